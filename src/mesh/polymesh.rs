//! [`PolyMesh`]: positions and faces whose loops are an outer boundary plus holes.
//!
//! A face has one or more loops of vertex ids. The first loop is the outer boundary,
//! counter-clockwise seen from outside; further loops are holes, clockwise. This is the
//! B-rep face with a P loop and C loops of seed 001 (§1, §4), the shape CAD booleans produce.
//! Storage is flat (struct of arrays): `face_loop_offsets` indexes `loop_offsets`, which
//! indexes `corners`, so a million-face mesh is three allocations, not a million.

use glam::DVec3;

use super::attributes::Attributes;
use super::ids::{FaceId, LoopId, VertexId};
use super::validate;
use crate::error::{Error, Result};

/// A polygon mesh whose faces may have holes. Built only through validating constructors,
/// so every index is in range, every coordinate finite, and every loop has at least three
/// distinct vertices and no repeated vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct PolyMesh {
    positions: Vec<DVec3>,
    /// `F + 1` offsets into `loop_offsets`: face `f` has loops `face_loop_offsets[f]..face_loop_offsets[f+1]`.
    face_loop_offsets: Vec<u32>,
    /// `L + 1` offsets into `corners`: loop `l` is `corners[loop_offsets[l]..loop_offsets[l+1]]`.
    loop_offsets: Vec<u32>,
    /// The vertex of every corner of every loop, loop after loop.
    corners: Vec<VertexId>,
    pub(crate) attributes: Attributes,
}

/// The empty mesh, as [`PolyMesh::new`]: the offset arrays hold their leading 0, so every
/// count is 0.
impl Default for PolyMesh {
    fn default() -> Self {
        PolyMesh::new()
    }
}

impl PolyMesh {
    /// An empty mesh: no vertices, no faces (also [`PolyMesh::default`]).
    pub fn new() -> Self {
        PolyMesh {
            positions: Vec::new(),
            face_loop_offsets: vec![0],
            loop_offsets: vec![0],
            corners: Vec::new(),
            attributes: Attributes::default(),
        }
    }

    /// Builds a mesh from flat arrays, the layout of the C ABI.
    ///
    /// - `positions`: #V × 3 coordinates, `x0 y0 z0 x1 …`;
    /// - `loop_sizes`: the number of corners of each loop (#L values);
    /// - `face_loop_counts`: the number of loops of each face (#F values, each ≥ 1), outer first;
    /// - `corners`: the vertex of each corner, loop after loop (Σ `loop_sizes` values).
    pub fn from_flat(
        positions: &[f64],
        loop_sizes: &[u32],
        face_loop_counts: &[u32],
        corners: &[u32],
    ) -> Result<Self> {
        if !positions.len().is_multiple_of(3) {
            return Err(Error::InconsistentArrays {
                message: format!(
                    "positions has {} values, which is not a multiple of 3",
                    positions.len()
                ),
            });
        }
        let positions: Vec<DVec3> = positions
            .chunks_exact(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect();
        let loops_total: u64 = face_loop_counts.iter().map(|&c| c as u64).sum();
        if loops_total != loop_sizes.len() as u64 {
            return Err(Error::InconsistentArrays {
                message: format!(
                    "the faces' loop counts add up to {loops_total}, but {} loop sizes were given",
                    loop_sizes.len()
                ),
            });
        }
        let corners_total: u64 = loop_sizes.iter().map(|&c| c as u64).sum();
        if corners_total != corners.len() as u64 {
            return Err(Error::InconsistentArrays {
                message: format!(
                    "the loop sizes add up to {corners_total}, but {} corner indices were given",
                    corners.len()
                ),
            });
        }
        if corners.len() > u32::MAX as usize - 1 || positions.len() > u32::MAX as usize - 1 {
            return Err(Error::InconsistentArrays {
                message: "more than 2^32 - 2 vertices or corners".into(),
            });
        }
        let mut face_loop_offsets = Vec::with_capacity(face_loop_counts.len() + 1);
        face_loop_offsets.push(0u32);
        let mut acc = 0u32;
        for &c in face_loop_counts {
            acc += c;
            face_loop_offsets.push(acc);
        }
        let mut loop_offsets = Vec::with_capacity(loop_sizes.len() + 1);
        loop_offsets.push(0u32);
        let mut acc = 0u32;
        for &s in loop_sizes {
            acc += s;
            loop_offsets.push(acc);
        }
        let corners = corners.iter().map(|&v| VertexId(v)).collect();
        Self::from_parts(positions, face_loop_offsets, loop_offsets, corners)
    }

    /// Builds a mesh of simple polygons (one loop per face).
    pub fn from_polygons<F, I>(positions: Vec<DVec3>, faces: F) -> Result<Self>
    where
        F: IntoIterator<Item = I>,
        I: AsRef<[u32]>,
    {
        let mut face_loop_offsets = vec![0u32];
        let mut loop_offsets = vec![0u32];
        let mut corners = Vec::new();
        for face in faces {
            corners.extend(face.as_ref().iter().map(|&v| VertexId(v)));
            loop_offsets.push(to_u32(corners.len())?);
            face_loop_offsets.push(to_u32(loop_offsets.len() - 1)?);
        }
        Self::from_parts(positions, face_loop_offsets, loop_offsets, corners)
    }

    /// Builds a mesh whose faces are lists of loops: outer loop first, holes after.
    pub fn from_faces_with_holes<F, L, I>(positions: Vec<DVec3>, faces: F) -> Result<Self>
    where
        F: IntoIterator<Item = L>,
        L: IntoIterator<Item = I>,
        I: AsRef<[u32]>,
    {
        let mut face_loop_offsets = vec![0u32];
        let mut loop_offsets = vec![0u32];
        let mut corners = Vec::new();
        for face in faces {
            for lp in face {
                corners.extend(lp.as_ref().iter().map(|&v| VertexId(v)));
                loop_offsets.push(to_u32(corners.len())?);
            }
            face_loop_offsets.push(to_u32(loop_offsets.len() - 1)?);
        }
        Self::from_parts(positions, face_loop_offsets, loop_offsets, corners)
    }

    /// Validates and assembles the flat arrays; the single door every constructor goes through.
    pub(crate) fn from_parts(
        positions: Vec<DVec3>,
        face_loop_offsets: Vec<u32>,
        loop_offsets: Vec<u32>,
        corners: Vec<VertexId>,
    ) -> Result<Self> {
        validate::positions(&positions)?;
        validate::faces(positions.len(), &face_loop_offsets, &loop_offsets, &corners)?;
        let attributes = Attributes::new(positions.len(), face_loop_offsets.len() - 1);
        Ok(PolyMesh {
            positions,
            face_loop_offsets,
            loop_offsets,
            corners,
            attributes,
        })
    }

    /// Assembles arrays a kernel operation built and knows to be valid (checked in debug builds).
    pub(crate) fn from_parts_unchecked(
        positions: Vec<DVec3>,
        face_loop_offsets: Vec<u32>,
        loop_offsets: Vec<u32>,
        corners: Vec<VertexId>,
    ) -> Self {
        debug_assert!(validate::positions(&positions).is_ok());
        debug_assert!(validate::faces(
            positions.len(),
            &face_loop_offsets,
            &loop_offsets,
            &corners
        )
        .is_ok());
        let attributes = Attributes::new(positions.len(), face_loop_offsets.len() - 1);
        PolyMesh {
            positions,
            face_loop_offsets,
            loop_offsets,
            corners,
            attributes,
        }
    }

    /// Number of vertices, referenced or not.
    pub fn vertex_count(&self) -> u32 {
        self.positions.len() as u32
    }
    /// Number of faces.
    pub fn face_count(&self) -> u32 {
        (self.face_loop_offsets.len() - 1) as u32
    }
    /// Number of loops over all faces (outer loops plus holes).
    pub fn loop_count(&self) -> u32 {
        (self.loop_offsets.len() - 1) as u32
    }
    /// Number of corners over all loops (the length of the flat index array).
    pub fn corner_count(&self) -> u32 {
        self.corners.len() as u32
    }
    /// Whether the mesh has no faces.
    pub fn is_empty(&self) -> bool {
        self.face_count() == 0
    }

    /// All positions, #V.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// The position of one vertex.
    pub fn position(&self, v: VertexId) -> DVec3 {
        self.positions[v.idx()]
    }
    /// Replaces the positions, keeping faces and attributes (same count, finite values).
    pub fn set_positions(&mut self, positions: Vec<DVec3>) -> Result<()> {
        if positions.len() != self.positions.len() {
            return Err(Error::AttributeLength {
                attribute: "positions",
                per: "vertex",
                expected: self.positions.len(),
                got: positions.len(),
            });
        }
        validate::positions(&positions)?;
        self.positions = positions;
        Ok(())
    }

    /// The loops of face `f`, as ids into [`Self::loop_vertices`]; the first is the outer loop.
    pub fn face_loops(&self, f: FaceId) -> impl ExactSizeIterator<Item = LoopId> + Clone {
        let r = self.face_loop_offsets[f.idx()]..self.face_loop_offsets[f.idx() + 1];
        r.map(LoopId)
    }
    /// Number of loops of face `f` (1 + number of holes).
    pub fn face_loop_count(&self, f: FaceId) -> u32 {
        self.face_loop_offsets[f.idx() + 1] - self.face_loop_offsets[f.idx()]
    }
    /// The outer loop (P loop) of face `f`.
    pub fn face_outer(&self, f: FaceId) -> &[VertexId] {
        self.loop_vertices(LoopId(self.face_loop_offsets[f.idx()]))
    }
    /// The vertices of loop `l`, in order.
    pub fn loop_vertices(&self, l: LoopId) -> &[VertexId] {
        let (a, b) = (self.loop_offsets[l.idx()], self.loop_offsets[l.idx() + 1]);
        &self.corners[a as usize..b as usize]
    }
    /// The index of loop `l`'s first corner in [`Self::corners`].
    pub fn loop_first_corner(&self, l: LoopId) -> u32 {
        self.loop_offsets[l.idx()]
    }
    /// All faces' ids.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = FaceId> + Clone {
        (0..self.face_count()).map(FaceId)
    }
    /// All vertices' ids.
    pub fn vertices(&self) -> impl ExactSizeIterator<Item = VertexId> + Clone {
        (0..self.vertex_count()).map(VertexId)
    }

    /// Flat layout: `F + 1` offsets into the loop arrays.
    pub fn face_loop_offsets(&self) -> &[u32] {
        &self.face_loop_offsets
    }
    /// Flat layout: `L + 1` offsets into [`Self::corners`].
    pub fn loop_offsets(&self) -> &[u32] {
        &self.loop_offsets
    }
    /// Flat layout: the vertex of every corner, loop after loop.
    pub fn corners(&self) -> &[VertexId] {
        &self.corners
    }

    /// Fails with [`Error::EmptyMesh`] when the mesh has no faces; `what` names the operation.
    pub fn require_faces(&self, what: &'static str) -> Result<()> {
        if self.is_empty() {
            Err(Error::EmptyMesh {
                what,
                needs: "face",
            })
        } else {
            Ok(())
        }
    }

    /// Axis-aligned bounding box of the vertices, `None` for a mesh without vertices.
    pub fn bounding_box(&self) -> Option<(DVec3, DVec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }
}

pub(crate) fn to_u32(n: usize) -> Result<u32> {
    u32::try_from(n).map_err(|_| Error::InconsistentArrays {
        message: format!("{n} elements is more than katachi's 32-bit indices can address"),
    })
}
