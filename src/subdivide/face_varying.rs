//! Face-varying interpolation (UV maps), with OpenSubdiv's linear-interpolation choices,
//! which are also Blender's "UV Smooth" menu.
//!
//! The smooth modes refine the UV topology itself: a mesh whose vertices are the distinct
//! UV values (so seams are boundaries) and whose faces are the input faces, carrying the
//! input's creases. Its faces refine in the same order as the input's, so output corners
//! correspond one to one.

use super::level::Level;
use super::options::BoundaryInterpolation;
use super::primvar::Primvar;
use super::refiner::Refiner;
use crate::error::{Error, Result};
use crate::mesh::{LoopId, PolyMesh, Topology, TopologyOptions, VertexId, INFINITELY_SHARP};

/// How face-varying data is interpolated (OpenSubdiv `FVarLinearInterpolation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FaceVarying {
    /// Smooth everywhere; UV boundaries smoothed along themselves (OpenSubdiv
    /// `FVAR_LINEAR_NONE`; Blender "All").
    Smooth,
    /// Smooth, UV corners pinned (OpenSubdiv `FVAR_LINEAR_CORNERS_ONLY`; Blender "Keep Corners").
    LinearCornersOnly,
    /// Smooth inside UV islands, linear along their boundaries (OpenSubdiv
    /// `FVAR_LINEAR_BOUNDARIES`; Blender "Keep Boundaries").
    LinearBoundaries,
    /// Bilinear everywhere (OpenSubdiv `FVAR_LINEAR_ALL`; Blender "None").
    LinearAll,
}

pub(crate) fn refine<T: Primvar>(
    refiner: &Refiner,
    mesh: &PolyMesh,
    values: &[T],
    indices: &[u32],
    mode: FaceVarying,
) -> Result<Vec<T>> {
    if indices.len() != mesh.corner_count() as usize {
        return Err(Error::AttributeLength {
            attribute: "face-varying indices",
            per: "face corner",
            expected: mesh.corner_count() as usize,
            got: indices.len(),
        });
    }
    if let Some((k, &i)) = indices
        .iter()
        .enumerate()
        .find(|(_, &i)| i as usize >= values.len())
    {
        return Err(Error::InvalidArgument(format!(
            "face-varying index {i} at corner {k} is out of range ({} values)",
            values.len()
        )));
    }
    // Level 0 may differ from the input (recovered or bridged faces): follow its corners.
    let mapped: Vec<u32>;
    let indices = match refiner.corner_origin() {
        None => indices,
        Some(o) => {
            mapped = o.iter().map(|&k| indices[k as usize]).collect();
            &mapped
        }
    };
    let mesh = refiner.level0_mesh(mesh);
    match mode {
        FaceVarying::LinearAll => Ok(bilinear(refiner, values, indices)),
        _ => smooth(refiner, mesh, values, indices, mode),
    }
}

/// Bilinear: a child corner takes its parent corner's value, the average of the two corners
/// of its edge, or the face's average.
fn bilinear<T: Primvar>(refiner: &Refiner, values: &[T], indices: &[u32]) -> Vec<T> {
    let mut cur: Vec<T> = indices
        .iter()
        .map(|&i| values[i as usize].clone())
        .collect();
    for l in 0..refiner.levels() as usize {
        let parent: &Level = refiner.level(l);
        let mut next = Vec::with_capacity(cur.len() * 4);
        let mid = |a: &T, b: &T| {
            let mut m = a.scaled(0.5);
            m.add_scaled(b, 0.5);
            m
        };
        for f in 0..parent.face_count() as usize {
            let (l0, l1) = (
                parent.face_loops[f] as usize,
                parent.face_loops[f + 1] as usize,
            );
            if parent.is_kept(f) {
                for lp in l0..l1 {
                    let (a, b) = (
                        parent.loop_offsets[lp] as usize,
                        parent.loop_offsets[lp + 1] as usize,
                    );
                    for c in a..b {
                        let n = if c + 1 < b { c + 1 } else { a };
                        next.push(cur[c].clone());
                        next.push(mid(&cur[c], &cur[n]));
                    }
                }
                continue;
            }
            let cs = parent.face_corners(f);
            let mut centre = T::zero();
            let w = 1.0 / cs.len() as f64;
            for c in cs.clone() {
                centre.add_scaled(&cur[c], w);
            }
            let k = cs.len();
            for (j, c) in cs.clone().enumerate() {
                let n = if c + 1 < cs.end { c + 1 } else { cs.start };
                let p = if c == cs.start { cs.end - 1 } else { c - 1 };
                let mut quad = [
                    cur[c].clone(),
                    mid(&cur[c], &cur[n]),
                    centre.clone(),
                    mid(&cur[p], &cur[c]),
                ];
                if k == 4 {
                    quad.rotate_right(j); // as the child faces (see refine.rs)
                }
                next.extend(quad);
            }
        }
        cur = next;
    }
    cur
}

/// The smooth modes: refine the UV topology as a mesh of its own.
fn smooth<T: Primvar>(
    refiner: &Refiner,
    mesh: &PolyMesh,
    values: &[T],
    indices: &[u32],
    mode: FaceVarying,
) -> Result<Vec<T>> {
    let loops: Vec<u32> = (0..mesh.loop_count())
        .map(|l| mesh.loop_vertices(LoopId(l)).len() as u32)
        .collect();
    let faces: Vec<u32> = mesh.faces().map(|f| mesh.face_loop_count(f)).collect();
    let zeros = vec![0.0; 3 * values.len()];
    let mut uv = PolyMesh::from_flat(&zeros, &loops, &faces, indices).map_err(|e| {
        Error::InvalidArgument(format!("face-varying indices do not form valid faces: {e}"))
    })?;
    // Creases of the mesh carry over to the UV edges along them.
    let corners = mesh.corners();
    let mut creases = Vec::new();
    for l in 0..mesh.loop_count() {
        let (a, b) = (
            mesh.loop_offsets()[l as usize] as usize,
            mesh.loop_offsets()[l as usize + 1] as usize,
        );
        for k in a..b {
            let n = if k + 1 < b { k + 1 } else { a };
            let s = mesh.edge_sharpness(corners[k], corners[n]);
            if s > 0.0 {
                creases.push((VertexId(indices[k]), VertexId(indices[n]), s));
            }
        }
    }
    uv.set_edge_sharpnesses(creases)?;
    let mut vertex_sharpness = vec![0.0f64; values.len()];
    for (k, &i) in indices.iter().enumerate() {
        let s = mesh.vertex_sharpness()[corners[k].idx()];
        vertex_sharpness[i as usize] = vertex_sharpness[i as usize].max(s);
    }
    if mode == FaceVarying::LinearBoundaries {
        let topo = Topology::build(&uv, &TopologyOptions::tolerant())?;
        for v in uv.vertices() {
            if topo.is_boundary_vertex(v) {
                vertex_sharpness[v.idx()] = INFINITELY_SHARP;
            }
        }
    }
    uv.set_all_vertex_sharpness(vertex_sharpness)?;
    let mut options = refiner.options().clone();
    // The UV topology is refined as level 0 is: no recovery or tagging again, faces with
    // holes that level 0 kept stay whole.
    options.recover_faces_with_holes = false;
    options.feature_angle = None;
    options.holes = super::options::HoleMethod::Sharp;
    // Level 0's faces with holes passed their checks; the UV mesh's positions are zeros.
    options.holes_checked = true;
    options.boundary = match mode {
        FaceVarying::LinearCornersOnly => BoundaryInterpolation::EdgeAndCorner,
        _ => BoundaryInterpolation::EdgeOnly,
    };
    let uv_refiner = Refiner::new(&uv, &options)?;
    let refined = uv_refiner.refine_vertex_data(values)?;
    let last = uv_refiner.level(uv_refiner.levels() as usize);
    debug_assert_eq!(last.corner_verts.len(), refiner.corner_count() as usize);
    Ok(last
        .corner_verts
        .iter()
        .map(|&v| refined[v as usize].clone())
        .collect())
}
