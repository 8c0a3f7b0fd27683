//! Carrying the caller's per-corner data (UVs, corner colours) and per-vertex data (colours,
//! weights) through a cut, so front ends keep textures and paint (gap-fill: the paper cuts
//! geometry only; Blender's knife and MeshLab's filters carry such data the same way).
//!
//! Every output triangle lies inside one triangle of the (triangulated) input, its *source*:
//! slot `t` for the first piece, the recorded slot for appended pieces. An output corner at
//! an input vertex (or an opening copy of one) takes that vertex's value in the source face
//! exactly; a new vertex takes the linear blend of the source triangle's corner values at its
//! barycentric coordinates, measured on the output positions (the cut built it there, after
//! snapping moved the corners). Snapped vertices keep their values: the move is a small
//! slide along the surface that the paper accepts for geometry and that front ends expect for
//! UVs (Blender's knife does the same).

use glam::DVec3;
use rayon::prelude::*;

use super::edits::CutEdits;
use super::report::CutOutput;
use super::triangulate;
use crate::error::{Error, Result};
use crate::mesh::{PolyMesh, VertexId};

/// What the interpolation needs beyond the output mesh, derived from the edits when they are
/// applied ([`Provenance::of`]).
#[derive(Debug, Clone, Default)]
pub(crate) struct Provenance {
    /// Faces of the triangulated input (the output's first `tri_count` slots).
    pub tri_count: u32,
    /// Vertices of the input.
    pub input_vertices: u32,
    /// For each appended output face (ids from `tri_count` on), its source triangle.
    pub appended_from: Vec<u32>,
    /// Slots below `tri_count` whose triangle the cut rewrote, ascending.
    pub rewritten: Vec<u32>,
    /// The input triangle each rewritten slot held (parallel to `rewritten`).
    pub rewritten_sources: Vec<[u32; 3]>,
    /// Opening copies are vertices `first_copy..`; `copy_of[i]` is the vertex copied.
    pub first_copy: u32,
    pub copy_of: Vec<u32>,
    /// The input edges the cut split, as [`CutEdits::split_edges`] gives them.
    pub split: SplitEdges,
}

/// Input edges the cut split: `ends[i]`, with the new vertices `on[start[i]..start[i + 1]]`
/// on it from the first end to the second.
#[derive(Debug, Clone, Default)]
pub(crate) struct SplitEdges {
    pub ends: Vec<(u32, u32)>,
    pub start: Vec<u32>,
    pub on: Vec<u32>,
}

impl Provenance {
    /// From the edits and the triangulated input they were made on.
    pub fn of(e: &CutEdits, tris: &PolyMesh) -> Self {
        let c = tris.corners();
        Provenance {
            tri_count: e.input_triangle_count,
            input_vertices: e.input_vertex_count,
            appended_from: e.appended_faces.iter().map(|&(_, s)| s.0).collect(),
            rewritten: e.rewritten_faces.iter().map(|&(s, _)| s.0).collect(),
            rewritten_sources: (e.rewritten_faces.iter())
                .map(|&(s, _)| std::array::from_fn(|i| c[3 * s.idx() + i].0))
                .collect(),
            first_copy: e.first_copy,
            copy_of: e.copy_of.clone(),
            split: SplitEdges {
                ends: e.split_ends.iter().map(|&(u, w)| (u.0, w.0)).collect(),
                start: e.split_start.clone(),
                on: e.split_on.iter().map(|v| v.0).collect(),
            },
        }
    }

    /// The vertex an opening copy duplicates (itself otherwise).
    pub fn original(&self, v: u32) -> u32 {
        original(self.first_copy, &self.copy_of, v)
    }
}

/// The vertex `v` duplicates when opening copies are `first_copy..` with `copy_of[i]` the
/// vertex copied; `v` itself otherwise.
pub(crate) fn original(first_copy: u32, copy_of: &[u32], v: u32) -> u32 {
    match v.checked_sub(first_copy) {
        Some(i) if (i as usize) < copy_of.len() => copy_of[i as usize],
        _ => v,
    }
}

impl CutOutput {
    /// Per-corner data of `input` (`dim` values per corner, in `input.corners()` order)
    /// carried to the output's corners (module docs). `input` must be the mesh that was cut.
    ///
    /// Errors: [`Error::InvalidArgument`] when `input` is not the cut mesh (counts differ),
    /// `dim` is 0, or `values` does not hold `dim` × the input's corner count.
    pub fn interpolate_corner_data(
        &self,
        input: &PolyMesh,
        values: &[f64],
        dim: usize,
    ) -> Result<Vec<f64>> {
        self.check(input, values, dim, input.corner_count(), "corner")?;
        let src = Sources::new(self, input)?;
        let out_corners = self.mesh.corners();
        let mut out = vec![0.0; out_corners.len() * dim];
        out.par_chunks_mut(3 * dim)
            .enumerate()
            .for_each(|(t, face)| {
                let tri = src.tri_of(t as u32);
                let tri_v = src.tri_vertices(tri);
                let f = self.face_origin[t].idx();
                // The source triangle's corners as corners of the input face.
                let (lo, hi) = src.face_corner_range(f);
                let in_corner = |v: u32| {
                    (lo..hi)
                        .find(|&c| input.corners()[c].0 == v)
                        .expect("a source triangle's vertex is a corner of its input face")
                };
                let tri_c = tri_v.map(in_corner);
                for k in 0..3 {
                    let v = src.original(out_corners[3 * t + k].0);
                    let w = match tri_v.iter().position(|&u| u == v) {
                        Some(i) => unit(i),
                        None => src.weights(tri_v, out_corners[3 * t + k].0),
                    };
                    let o = &mut face[k * dim..(k + 1) * dim];
                    for (i, &c) in tri_c.iter().enumerate() {
                        if w[i] != 0.0 {
                            for (d, od) in o.iter_mut().enumerate() {
                                *od += w[i] * values[c * dim + d];
                            }
                        }
                    }
                }
            });
        Ok(out)
    }

    /// Per-vertex data of `input` (`dim` values per vertex) carried to the output's vertices:
    /// input vertices keep theirs, opening copies take their original's, split vertices the
    /// blend of their source triangle's vertices (module docs).
    ///
    /// Errors: as [`CutOutput::interpolate_corner_data`], with the vertex count.
    pub fn interpolate_vertex_data(
        &self,
        input: &PolyMesh,
        values: &[f64],
        dim: usize,
    ) -> Result<Vec<f64>> {
        self.check(input, values, dim, input.vertex_count(), "vertex")?;
        let src = Sources::new(self, input)?;
        let nv_in = src.p.input_vertices as usize;
        let nv_out = self.mesh.vertex_count() as usize;
        let mut out = Vec::with_capacity(nv_out * dim);
        out.extend_from_slice(values);
        out.resize(nv_out * dim, 0.0);
        // A face holding each split vertex: only rewritten slots and appended faces do.
        let mut host = vec![u32::MAX; nv_out - nv_in];
        let first_appended = src.p.tri_count;
        let faces = src
            .p
            .rewritten
            .iter()
            .copied()
            .chain(first_appended..self.mesh.face_count());
        let corners = self.mesh.corners();
        for t in faces {
            for k in 0..3 {
                let v = src.original(corners[3 * t as usize + k].0) as usize;
                if v >= nv_in && host[v - nv_in] == u32::MAX {
                    host[v - nv_in] = t;
                }
            }
        }
        for v in nv_in..nv_out {
            let o = src.original(v as u32) as usize;
            let (tri_v, w) = if o < nv_in {
                ([o as u32; 3], [1.0, 0.0, 0.0])
            } else {
                match host[o - nv_in] {
                    // A split vertex no face uses (not produced by a valid cut): zeros.
                    u32::MAX => continue,
                    t => {
                        let tri_v = src.tri_vertices(src.tri_of(t));
                        (tri_v, src.weights(tri_v, o as u32))
                    }
                }
            };
            for d in 0..dim {
                out[v * dim + d] = (0..3)
                    .filter(|&i| w[i] != 0.0)
                    .map(|i| w[i] * values[tri_v[i] as usize * dim + d])
                    .sum();
            }
        }
        Ok(out)
    }

    /// For each output vertex, the vertex it duplicates: an opened cut's copy of a path
    /// vertex gives that vertex (an input vertex or one the cut made), every other vertex
    /// itself. Front ends use it to give copies their original's data.
    pub fn vertex_original(&self) -> Vec<VertexId> {
        (0..self.mesh.vertex_count())
            .map(|v| VertexId(self.provenance.original(v)))
            .collect()
    }

    fn check(
        &self,
        input: &PolyMesh,
        values: &[f64],
        dim: usize,
        count: u32,
        what: &str,
    ) -> Result<()> {
        let p = &self.provenance;
        if input.vertex_count() != p.input_vertices {
            return Err(Error::InvalidArgument(format!(
                "the mesh given has {} vertices, but the cut mesh had {}: pass the mesh that \
                 was cut",
                input.vertex_count(),
                p.input_vertices
            )));
        }
        if dim == 0 {
            return Err(Error::InvalidArgument(format!(
                "{what} data needs at least one value per {what} (dim is 0)"
            )));
        }
        let want = count as usize * dim;
        if values.len() != want {
            return Err(Error::InvalidArgument(format!(
                "{what} data holds {} values, but {count} {what}s × {dim} = {want} were expected",
                values.len()
            )));
        }
        Ok(())
    }
}

fn unit(i: usize) -> [f64; 3] {
    let mut w = [0.0; 3];
    w[i] = 1.0;
    w
}

/// The source triangles, rebuilt from the input (the triangulation is deterministic).
struct Sources<'a> {
    out: &'a CutOutput,
    input: &'a PolyMesh,
    p: &'a Provenance,
    tris: triangulate::Triangles<'a>,
}

impl<'a> Sources<'a> {
    fn new(out: &'a CutOutput, input: &'a PolyMesh) -> Result<Self> {
        let tris = triangulate::triangles(input)?;
        if tris.mesh.face_count() != out.provenance.tri_count {
            return Err(Error::InvalidArgument(format!(
                "the mesh given triangulates into {} triangles, but the cut mesh gave {}: pass \
                 the mesh that was cut",
                tris.mesh.face_count(),
                out.provenance.tri_count
            )));
        }
        Ok(Sources {
            out,
            input,
            p: &out.provenance,
            tris,
        })
    }

    fn tri_of(&self, t: u32) -> u32 {
        if t < self.p.tri_count {
            t
        } else {
            self.p.appended_from[(t - self.p.tri_count) as usize]
        }
    }

    fn tri_vertices(&self, tri: u32) -> [u32; 3] {
        let c = &self.tris.mesh.corners()[3 * tri as usize..3 * tri as usize + 3];
        [c[0].0, c[1].0, c[2].0]
    }

    fn face_corner_range(&self, f: usize) -> (usize, usize) {
        let flo = self.input.face_loop_offsets();
        let lo = self.input.loop_offsets();
        (
            lo[flo[f] as usize] as usize,
            lo[flo[f + 1] as usize] as usize,
        )
    }

    fn original(&self, v: u32) -> u32 {
        self.p.original(v)
    }

    /// Barycentric weights of output vertex `v` in the triangle `tri_v` (output positions),
    /// clamped to the triangle; a degenerate triangle uses its longest edge.
    fn weights(&self, tri_v: [u32; 3], v: u32) -> [f64; 3] {
        let pos = self.out.mesh.positions();
        let [a, b, c] = tri_v.map(|u| pos[u as usize]);
        barycentric(pos[v as usize], a, b, c)
    }
}

pub(crate) fn barycentric(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> [f64; 3] {
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let denom = d00 * d11 - d01 * d01;
    if denom > 1e-12 * d00 * d11 && denom > 0.0 {
        let beta = (d11 * d20 - d01 * d21) / denom;
        let gamma = (d00 * d21 - d01 * d20) / denom;
        let w = [1.0 - beta - gamma, beta, gamma].map(|x| x.max(0.0));
        let s: f64 = w.iter().sum();
        return w.map(|x| x / s);
    }
    // Degenerate: the point's parameter along the longest edge.
    let edges = [(0, 1, a, b), (1, 2, b, c), (2, 0, c, a)];
    let &(i, j, p0, p1) = edges
        .iter()
        .max_by(|x, y| {
            (x.3 - x.2)
                .length_squared()
                .total_cmp(&(y.3 - y.2).length_squared())
        })
        .expect("three edges");
    let d = p1 - p0;
    let t = if d.length_squared() > 0.0 {
        ((p - p0).dot(d) / d.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut w = [0.0; 3];
    w[i] = 1.0 - t;
    w[j] += t;
    w
}
