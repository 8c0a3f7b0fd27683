//! Solid-aware Catmull-Clark subdivision (seed 001: Yoshii, Tokuyama, Konno, "Generation of
//! Subdivision Surfaces based on Solid Model"), with DeRose et al.'s sharp and semi-sharp
//! creases and OpenSubdiv's boundary and non-manifold rules.
//!
//! [`catmull_clark`] refines any polygon mesh (triangles, quads, n-gons) and faces with holes
//! (a P loop and C loops, seed 001 §2): method [a] bridges the loops and subdivides smoothly,
//! method [b] keeps the face planar with its loops as sharp crease curves.
//!
//! Written by hand because no Rust crate does Catmull-Clark with semi-sharp creases, and
//! none at all with faces with holes; OpenSubdiv is the reference it is tested against.

mod crease;
pub mod features;
pub mod holes;
mod level;
mod options;
mod refine;
pub mod regions;

use std::collections::BTreeMap;

pub use options::{BoundaryInterpolation, CreaseMethod, HoleMethod, SubdivideOptions};

use crate::error::{Error, Result};
use crate::mesh::{FaceId, PolyMesh, VertexId};
use level::Level;

/// What [`catmull_clark`] returns.
#[derive(Debug, Clone)]
pub struct Subdivided {
    /// The refined mesh. Vertex order at each level: children of vertices (so the first #V
    /// vertices correspond to the input's), then of faces, then of edges — OpenSubdiv's order.
    pub mesh: PolyMesh,
    /// For each output face, the input face it comes from (materials, face data follow).
    pub face_origin: Vec<FaceId>,
    /// What was done differently from what was asked, face by face.
    pub report: SubdivideReport,
}

/// Notes on a subdivision.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SubdivideReport {
    /// Faces with holes that method [a] could not bridge and that were refined with
    /// method [b] instead, each with the reason.
    pub fell_back_to_sharp: Vec<(FaceId, String)>,
}

/// Catmull-Clark subdivision, `options.levels` times.
///
/// Never changes `mesh`. Errors: [`Error::EmptyMesh`] without faces, [`Error::InvalidOption`]
/// for 0 levels or more than 8 (the face count grows 4× per level).
pub fn catmull_clark(mesh: &PolyMesh, options: &SubdivideOptions) -> Result<Subdivided> {
    mesh.require_faces("subdivision")?;
    if options.levels == 0 || options.levels > 8 {
        return Err(Error::InvalidOption {
            option: "levels",
            message: format!("{} is outside 1..=8", options.levels),
        });
    }
    let mut report = SubdivideReport::default();
    let keep = |f: u32| mesh.face_loop_count(FaceId(f)) > 1;
    if options.holes == HoleMethod::Smooth {
        for f in mesh.faces().filter(|&f| mesh.face_loop_count(f) > 1) {
            report.fell_back_to_sharp.push((
                f,
                "method [a] bridging is not available yet; method [b] was used".into(),
            ));
        }
    }
    let mut level = Level::from_mesh(mesh, options, &keep)?;
    let mut pos = mesh.positions().to_vec();
    for l in 0..options.levels {
        let last = l + 1 == options.levels;
        let (child, child_pos) = refine::refine(&level, &pos, options.crease_method, None, last);
        level = child;
        pos = child_pos;
    }
    let face_origin = level.face_origin.iter().map(|&f| FaceId(f)).collect();
    Ok(Subdivided {
        mesh: to_mesh(level, pos),
        face_origin,
        report,
    })
}

/// The last level as a [`PolyMesh`], keeping the user's remaining sharpness.
fn to_mesh(level: Level, pos: Vec<DVec3>) -> PolyMesh {
    let edge_sharpness: BTreeMap<(u32, u32), f64> = level
        .last_creases
        .iter()
        .map(|&([a, b], s)| ((a.min(b), a.max(b)), s as f64))
        .collect();
    let vertex_sharpness = level
        .vertex_sharpness
        .iter()
        .zip(&level.vertex_forced)
        .map(|(&s, &forced)| if forced { 0.0 } else { s as f64 })
        .collect();
    let corners = level.corner_verts.into_iter().map(VertexId).collect();
    let mut mesh =
        PolyMesh::from_parts_unchecked(pos, level.face_loops, level.loop_offsets, corners);
    mesh.attributes.edge_sharpness = edge_sharpness;
    mesh.attributes.vertex_sharpness = vertex_sharpness;
    mesh
}

use glam::DVec3;
