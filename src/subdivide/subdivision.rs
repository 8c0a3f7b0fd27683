//! [`Subdivision`]: a subdivision kept whole for reading out as flat arrays — positions,
//! faces, edges with the creases left on them, where each face came from — the shape hosts
//! copy their meshes from (Blender's mesh arrays, MeshLab's faces, the C ABI's copy-out
//! calls), with the hierarchy through which their UVs and vertex data follow.
//!
//! Everything a host needs is here, so a front end copies arrays and rebuilds nothing:
//! faces with holes can be given back cut into simple polygons along bridge edges (for hosts
//! that store none), with each cut face's corners mapped to the refined corners they copy,
//! and the edge list comes with each corner's edge. Counts are stored, not recomputed; the
//! edges are computed on first request (a C caller that wants only faces does not pay for
//! them).

use std::collections::HashMap;
use std::sync::OnceLock;

use glam::DVec3;
use rayon::prelude::*;

use super::face_varying::FaceVarying;
use super::primvar::Primvar;
use super::refine;
use super::refiner::Refiner;
use super::{SubdivideOptions, SubdivideReport};
use crate::error::{Error, Result};
use crate::mesh::holes::bridge_face;
use crate::mesh::{FaceId, PolyMesh, VertexId};

/// The refined mesh's edges.
#[derive(Debug, Clone, PartialEq)]
pub struct Edges {
    /// The two vertices of each edge.
    pub verts: Vec<[u32; 2]>,
    /// Per face corner (in [`Subdivision::corners`] order), the edge from it to the next
    /// corner of its loop.
    pub corner_edges: Vec<u32>,
    /// Per edge, the sharpness left after refinement (the user's semi-sharp creases not yet
    /// spent and infinitely sharp ones; 0 elsewhere, boundaries included).
    pub sharpness: Vec<f32>,
}

/// A subdivision and its result, for reading out ([`Subdivision::new`]).
#[derive(Debug)]
pub struct Subdivision {
    refiner: Refiner,
    positions: Vec<DVec3>,
    /// Input face of each face (of the split faces when `split` is set), made on first request.
    face_origin: OnceLock<Vec<FaceId>>,
    split: Option<Split>,
    edges: OnceLock<Edges>,
    sharp_edge_count: u32,
    sharp_vertex_count: u32,
}

/// The refined mesh with its faces with holes cut into simple polygons.
#[derive(Debug)]
struct Split {
    /// `0..=F`: every face is one loop.
    face_loops: Vec<u32>,
    /// `F + 1` offsets into `corners`.
    offsets: Vec<u32>,
    corners: Vec<u32>,
    /// Per corner, the refined mesh's corner it copies.
    corner_origin: Vec<u32>,
    /// Refined face of each face.
    face_of: Vec<u32>,
    /// The refined mesh's creases by vertex pair (the split adds edges, so they are matched
    /// by their ends).
    creases: Vec<([u32; 2], f32)>,
}

impl Subdivision {
    /// Subdivides `mesh` (never changed) with `options`, as
    /// [`super::catmull_clark_with_progress`] does, and keeps what reading out needs. With
    /// `options.split_faces_with_holes`, faces with holes of the result are cut into simple
    /// polygons along bridge edges, and every array describes the cut faces. Same errors as
    /// [`super::catmull_clark`], and [`Error::InvalidFaceWithHoles`] for a face with holes
    /// of the result that cannot be cut.
    pub fn new(
        mesh: &PolyMesh,
        options: &SubdivideOptions,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<Subdivision> {
        let (refiner, positions) = Refiner::with_positions(mesh, options, progress)?;
        let last = refiner.level(refiner.levels() as usize);
        let sharp_vertex_count = if last.any_vertex_sharp {
            last.vertex_sharpness
                .iter()
                .zip(last.vertex_forced.iter())
                .filter(|&(&s, &forced)| s > 0.0 && !forced)
                .count() as u32
        } else {
            0
        };
        let sharp_edge_count = last.last_creases.len() as u32;
        let split = (options.split_faces_with_holes && !last.face_kept.is_empty())
            .then(|| split(&refiner, &positions))
            .transpose()?;
        Ok(Subdivision {
            refiner,
            positions,
            face_origin: OnceLock::new(),
            split,
            edges: OnceLock::new(),
            sharp_edge_count,
            sharp_vertex_count,
        })
    }

    /// The hierarchy (for the stencil matrix and vertex data).
    pub fn refiner(&self) -> &Refiner {
        &self.refiner
    }
    /// What was done differently from what was asked.
    pub fn report(&self) -> &SubdivideReport {
        self.refiner.report()
    }
    /// Number of vertices.
    pub fn vertex_count(&self) -> u32 {
        self.positions.len() as u32
    }
    /// Number of faces.
    pub fn face_count(&self) -> u32 {
        self.face_loop_offsets().len() as u32 - 1
    }
    /// Number of loops (one per face, plus the holes of faces with holes).
    pub fn loop_count(&self) -> u32 {
        self.loop_offsets().len() as u32 - 1
    }
    /// Number of face corners.
    pub fn corner_count(&self) -> u32 {
        self.corners().len() as u32
    }
    /// Number of edges (without computing them).
    pub fn edge_count(&self) -> u32 {
        if let Some(e) = self.edges.get() {
            return e.verts.len() as u32;
        }
        match (&self.split, self.parent_splits_all()) {
            (None, Some((step, parent))) => {
                (step.interior_edges + 2 * parent.edge_count() as usize) as u32
            }
            _ => self.edges().verts.len() as u32,
        }
    }
    /// Number of edges with sharpness left.
    pub fn sharp_edge_count(&self) -> u32 {
        self.sharp_edge_count
    }
    /// Number of vertices with sharpness left (the user's, not the topology's corners).
    pub fn sharp_vertex_count(&self) -> u32 {
        self.sharp_vertex_count
    }
    /// The positions, one per vertex.
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }
    /// Writes the positions as `x0 y0 z0 x1 …` into `out` (3 per vertex), each coordinate
    /// through `convert` (a host's precision), in parallel.
    ///
    /// Panics when `out` has another length (a bug of the caller's).
    pub fn write_positions<O: Send>(&self, out: &mut [O], convert: impl Fn(f64) -> O + Sync) {
        assert_eq!(out.len(), 3 * self.positions.len(), "position array length");
        out.par_chunks_exact_mut(3)
            .zip(self.positions.par_iter())
            .with_min_len(4096)
            .for_each(|(d, p)| {
                for (d, &x) in d.iter_mut().zip(&p.to_array()) {
                    *d = convert(x);
                }
            });
    }

    /// `F + 1` offsets into [`Self::loop_offsets`]: face `f` has loops
    /// `face_loop_offsets[f]..face_loop_offsets[f + 1]`, the outer loop first.
    pub fn face_loop_offsets(&self) -> &[u32] {
        match &self.split {
            Some(s) => &s.face_loops,
            None => &self.last().face_loops,
        }
    }
    /// `L + 1` offsets into [`Self::corners`].
    pub fn loop_offsets(&self) -> &[u32] {
        match &self.split {
            Some(s) => &s.offsets,
            None => &self.last().loop_offsets,
        }
    }
    /// The vertex of every corner, loop after loop.
    pub fn corners(&self) -> &[u32] {
        match &self.split {
            Some(s) => &s.corners,
            None => &self.last().corner_verts,
        }
    }
    /// Whether some face has holes (only without `split_faces_with_holes`).
    pub fn has_faces_with_holes(&self) -> bool {
        self.loop_count() != self.face_count()
    }
    /// For each face, the input face it comes from.
    pub fn face_origin(&self) -> &[FaceId] {
        self.face_origin.get_or_init(|| {
            let refined = self.refiner.face_origin();
            match &self.split {
                None => refined,
                Some(s) => s.face_of.iter().map(|&f| refined[f as usize]).collect(),
            }
        })
    }

    /// The edges, computed on first call.
    pub fn edges(&self) -> &Edges {
        self.edges
            .get_or_init(|| match (&self.split, self.parent_splits_all()) {
                (None, Some((step, parent))) => {
                    let (corner_edges, verts) = refine::child_edges(parent, step);
                    Edges {
                        verts,
                        corner_edges,
                        sharpness: refine::child_edge_sharpness(parent, step),
                    }
                }
                _ => {
                    let creases: &[([u32; 2], f32)] = match &self.split {
                        Some(s) => &s.creases,
                        None => &self.last().last_creases,
                    };
                    number_edges(self.loop_offsets(), self.corners(), creases)
                }
            })
    }

    /// Writes the edges into the caller's arrays (`verts`: [`Self::edge_count`] pairs;
    /// `corner_edges`: one per corner), either of which may be left out: when every face of
    /// the last level's parent split, computed straight into them (the edges are then not
    /// kept: a host copies them once), else copied from [`Self::edges`].
    ///
    /// Panics when an array has another length (a bug of the caller's).
    pub fn write_edges(&self, verts: Option<&mut [[u32; 2]]>, corner_edges: Option<&mut [u32]>) {
        if let (None, None, Some((step, parent))) =
            (&self.split, self.edges.get(), self.parent_splits_all())
        {
            let (nc, ne) = refine::child_edge_counts(parent, step);
            assert!(
                verts.as_ref().is_none_or(|v| v.len() == ne),
                "edge array length"
            );
            assert!(
                corner_edges.as_ref().is_none_or(|c| c.len() == nc),
                "corner array length"
            );
            refine::child_edges_into(parent, step, corner_edges, verts);
            return;
        }
        let e = self.edges();
        if let Some(v) = verts {
            v.copy_from_slice(&e.verts);
        }
        if let Some(c) = corner_edges {
            c.copy_from_slice(&e.corner_edges);
        }
    }

    /// The sharpness left on each edge, in [`Self::write_edges`]' order.
    pub fn edge_sharpness(&self) -> Vec<f32> {
        let mut out = vec![0.0; self.edge_count() as usize];
        self.write_edge_sharpness(&mut out, |s| s);
        out
    }

    /// [`Self::edge_sharpness`] written into `out` ([`Self::edge_count`] values), each
    /// nonzero value through `map` (a host's scale; 0 stays 0).
    ///
    /// Panics when `out` has another length (a bug of the caller's).
    pub fn write_edge_sharpness(&self, out: &mut [f32], map: impl Fn(f32) -> f32) {
        assert_eq!(out.len(), self.edge_count() as usize, "edge array length");
        if let (None, None, Some((step, parent))) =
            (&self.split, self.edges.get(), self.parent_splits_all())
        {
            out.fill(0.0);
            refine::for_each_child_edge_sharpness(parent, step, |e, s| out[e] = map(s));
            return;
        }
        for (d, &s) in out.iter_mut().zip(&self.edges().sharpness) {
            *d = if s > 0.0 { map(s) } else { 0.0 };
        }
    }

    /// The sharpness left on each vertex (0 where none is left; topology's corners are not
    /// the user's).
    pub fn vertex_sharpness(&self) -> Vec<f32> {
        let last = self.last();
        if !last.any_vertex_sharp {
            return vec![0.0; self.positions.len()];
        }
        last.vertex_sharpness
            .iter()
            .zip(last.vertex_forced.iter())
            .map(|(&s, &forced)| if forced { 0.0 } else { s })
            .collect()
    }

    /// Interpolates face-varying data (UVs) as [`Refiner::refine_face_varying`] does, one
    /// value per corner of this result (the cut faces' corners copy the refined corners).
    pub fn refine_face_varying<T: Primvar>(
        &self,
        values: &[T],
        indices: &[u32],
        mode: FaceVarying,
    ) -> Result<Vec<T>> {
        let refined = self.refiner.refine_face_varying(values, indices, mode)?;
        Ok(self.to_result_corners(refined))
    }

    /// Interpolates per-corner data of `components` values (`values`: that many per input
    /// corner, in the input's corner order) as face-varying data: corners at the same vertex
    /// with the same values (bit for bit) share them, so seams are where the values differ,
    /// as in a host's UV map. Returns `components` values per corner of this result.
    ///
    /// Errors: [`Error::AttributeLength`] when `values` is not `components` per input corner;
    /// [`Error::InvalidArgument`] for 0 components.
    pub fn refine_corner_data(
        &self,
        values: &[f64],
        components: usize,
        mode: FaceVarying,
    ) -> Result<Vec<f64>> {
        let mut out = vec![0.0; self.corner_count() as usize * components.max(1)];
        self.refine_corner_data_into(values, components, mode, &mut out, |x| x)?;
        Ok(out)
    }

    /// [`Subdivision::refine_corner_data`] written into `out` (`components` per result
    /// corner, each converted by `convert`: a host's precision), without an intermediate
    /// array. `out` must have exactly that length.
    pub fn refine_corner_data_into<O: Send>(
        &self,
        values: &[f64],
        components: usize,
        mode: FaceVarying,
        out: &mut [O],
        convert: impl Fn(f64) -> O + Sync,
    ) -> Result<()> {
        let corners = self.refiner.input_corner_count() as usize;
        if components == 0 {
            return Err(Error::InvalidArgument(
                "per-corner data needs at least one component".into(),
            ));
        }
        if values.len() != corners * components {
            return Err(Error::AttributeLength {
                attribute: "per-corner data",
                per: "input corner × component",
                expected: corners * components,
                got: values.len(),
            });
        }
        if out.len() != self.corner_count() as usize * components {
            return Err(Error::AttributeLength {
                attribute: "refined per-corner data",
                per: "result corner × component",
                expected: self.corner_count() as usize * components,
                got: out.len(),
            });
        }
        let k = components;
        let (unique, indices) = super::face_varying::weld(&self.refiner, values, k);
        // The refined corner each result corner reads.
        let source = |c: usize| match &self.split {
            None => c,
            Some(s) => s.corner_origin[c] as usize,
        };
        fn run<const N: usize, O: Send>(
            s: &Subdivision,
            unique: &[f64],
            indices: &[u32],
            mode: FaceVarying,
            out: &mut [O],
            source: &(dyn Fn(usize) -> usize + Sync),
            convert: &(dyn Fn(f64) -> O + Sync),
        ) -> Result<()> {
            let vals: Vec<[f64; N]> = unique
                .chunks_exact(N)
                .map(|c| c.try_into().expect("N values"))
                .collect();
            let refined = super::face_varying::refine_level0(&s.refiner, &vals, indices, mode)?;
            out.par_chunks_mut(N)
                .with_min_len(4096)
                .enumerate()
                .for_each(|(c, o)| {
                    for (d, &x) in o.iter_mut().zip(refined.at(source(c))) {
                        *d = convert(x);
                    }
                });
            Ok(())
        }
        match k {
            1 => run::<1, O>(self, &unique, &indices, mode, out, &source, &convert),
            2 => run::<2, O>(self, &unique, &indices, mode, out, &source, &convert),
            3 => run::<3, O>(self, &unique, &indices, mode, out, &source, &convert),
            4 => run::<4, O>(self, &unique, &indices, mode, out, &source, &convert),
            _ => {
                for c in 0..k {
                    let column: Vec<f64> = unique.iter().skip(c).step_by(k).copied().collect();
                    let refined =
                        super::face_varying::refine_level0(&self.refiner, &column, &indices, mode)?;
                    for (i, o) in out.chunks_mut(k).enumerate() {
                        o[c] = convert(*refined.at(source(i)));
                    }
                }
                Ok(())
            }
        }
    }

    /// Refined-corner values as values of this result's corners.
    fn to_result_corners<T: Clone>(&self, refined: Vec<T>) -> Vec<T> {
        match &self.split {
            None => refined,
            Some(s) => s
                .corner_origin
                .iter()
                .map(|&k| refined[k as usize].clone())
                .collect(),
        }
    }

    /// The result as a [`PolyMesh`] (a copy), with its creases.
    pub fn mesh(&self) -> PolyMesh {
        let mut mesh = match &self.split {
            None => {
                return self
                    .refiner
                    .mesh(self.positions.clone())
                    .expect("the refined positions passed with_positions' checks")
            }
            Some(s) => PolyMesh::from_parts_unchecked(
                self.positions.clone(),
                s.face_loops.clone(),
                s.offsets.clone(),
                s.corners.iter().map(|&v| VertexId(v)).collect(),
            ),
        };
        let split = self.split.as_ref().expect("split");
        mesh.attributes.edge_sharpness = split
            .creases
            .iter()
            .map(|&([a, b], s)| ((a.min(b), a.max(b)), s as f64))
            .collect();
        if self.sharp_vertex_count > 0 {
            mesh.attributes.vertex_sharpness =
                self.vertex_sharpness().iter().map(|&s| s as f64).collect();
        }
        mesh
    }

    fn last(&self) -> &super::level::Level {
        self.refiner.level(self.refiner.levels() as usize)
    }

    /// The last level's parent and its step, when every parent face was split (then the
    /// last level's edges follow by index, [`refine::child_edges`]).
    fn parent_splits_all(&self) -> Option<(&refine::Step, &super::level::Level)> {
        let l = self.refiner.levels() as usize - 1;
        let parent = self.refiner.level(l);
        parent
            .face_kept
            .is_empty()
            .then(|| (self.refiner.step(l), parent))
    }
}

/// Cuts the last level's faces with holes into the simple polygons their bridges make.
fn split(refiner: &Refiner, positions: &[DVec3]) -> Result<Split> {
    let last = refiner.level(refiner.levels() as usize);
    let nf = last.face_count() as usize;
    let mut offsets = Vec::with_capacity(nf + 1);
    offsets.push(0u32);
    let mut corners = Vec::with_capacity(last.corner_verts.len());
    let mut corner_origin = Vec::with_capacity(last.corner_verts.len());
    let mut face_of = Vec::with_capacity(nf);
    for f in 0..nf {
        let (l0, l1) = (last.face_loops[f] as usize, last.face_loops[f + 1] as usize);
        let (c0, c1) = (
            last.loop_offsets[l0] as usize,
            last.loop_offsets[l1] as usize,
        );
        if l1 - l0 == 1 {
            corners.extend_from_slice(&last.corner_verts[c0..c1]);
            corner_origin.extend(c0 as u32..c1 as u32);
            offsets.push(corners.len() as u32);
            face_of.push(f as u32);
            continue;
        }
        // The face alone, on its own vertices, for bridging.
        let face_verts: Vec<u32> = last.corner_verts[c0..c1].to_vec();
        let loops: Vec<Vec<u32>> = (l0..l1)
            .map(|l| {
                let (a, b) = (
                    last.loop_offsets[l] as usize,
                    last.loop_offsets[l + 1] as usize,
                );
                (a..b).map(|c| (c - c0) as u32).collect()
            })
            .collect();
        let pts: Vec<DVec3> = face_verts.iter().map(|&v| positions[v as usize]).collect();
        let single = PolyMesh::from_faces_with_holes(pts, [loops])?;
        let bridged =
            bridge_face(&single, FaceId(0)).map_err(|why| Error::InvalidFaceWithHoles {
                face: refiner.face_origin()[f].0,
                reason: format!(
                    "a face of its subdivision cannot be split into simple polygons: {why}"
                ),
            })?;
        // Loop vertices are distinct within a face, so a vertex names its corner.
        let corner_of: HashMap<u32, u32> = face_verts
            .iter()
            .enumerate()
            .map(|(i, &v)| (v, (c0 + i) as u32))
            .collect();
        for vf in &bridged.faces {
            for v in vf {
                let g = face_verts[v.idx()];
                corners.push(g);
                corner_origin.push(corner_of[&g]);
            }
            offsets.push(corners.len() as u32);
            face_of.push(f as u32);
        }
    }
    Ok(Split {
        face_loops: (0..offsets.len() as u32).collect(),
        offsets,
        corners,
        corner_origin,
        face_of,
        creases: last.last_creases.clone(),
    })
}

/// Numbers the edges of faces given as loops (`loop_offsets` into `corners`) by first use in
/// corner order; `creases` (vertex pairs, either order) give their sharpness.
fn number_edges(loop_offsets: &[u32], corners: &[u32], creases: &[([u32; 2], f32)]) -> Edges {
    let key = |a: u32, b: u32| (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
    let mut ids: HashMap<u64, u32> = HashMap::with_capacity(corners.len() / 2 + 8);
    let mut verts = Vec::with_capacity(corners.len() / 2 + 8);
    let mut corner_edges = vec![0u32; corners.len()];
    for w in loop_offsets.windows(2) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        for c in a..b {
            let (u, v) = (corners[c], corners[if c + 1 < b { c + 1 } else { a }]);
            let next = verts.len() as u32;
            let e = *ids.entry(key(u, v)).or_insert(next);
            if e == next {
                verts.push([u, v]);
            }
            corner_edges[c] = e;
        }
    }
    let mut sharpness = vec![0.0f32; verts.len()];
    for &([a, b], s) in creases {
        if let Some(&e) = ids.get(&key(a, b)) {
            sharpness[e as usize] = s;
        }
    }
    Edges {
        verts,
        corner_edges,
        sharpness,
    }
}
