//! Solid-aware Catmull-Clark subdivision (seed 001: Yoshii, Tokuyama, Konno, "Generation of
//! Subdivision Surfaces based on Solid Model"), with DeRose et al.'s sharp and semi-sharp
//! creases and OpenSubdiv's boundary and non-manifold rules.
//!
//! [`catmull_clark`] refines any polygon mesh (triangles, quads, n-gons) and faces with holes
//! (a P loop and C loops, seed 001 §1, §4): method `[a]` bridges the loops and subdivides smoothly,
//! method `[b]` keeps the face planar with its loops as sharp crease curves.
//!
//! Written by hand because no Rust crate does Catmull-Clark with semi-sharp creases, and
//! none at all with faces with holes; OpenSubdiv is the reference it is tested against.

mod crease;
mod face_varying;
pub mod features;
mod level;
mod options;
mod prepare;
mod primvar;
mod refine;
mod refiner;
pub mod regions;
mod subdivision;

pub use face_varying::FaceVarying;
pub use features::{feature_edges, tag_feature_edges};
pub use options::{BoundaryInterpolation, CreaseMethod, HoleMethod, SubdivideOptions};
pub use primvar::{Primvar, SparseRow};
pub use refiner::{Refiner, Stencils};
pub use regions::{merge_coplanar_regions, MergeOptions, Merged};
pub use subdivision::{Edges, Subdivision};

use crate::error::Result;
use crate::mesh::{FaceId, PolyMesh};

/// What [`catmull_clark`] returns.
#[derive(Debug, Clone)]
pub struct Subdivided {
    /// The refined mesh. Vertex order at each level: children of vertices, then of faces,
    /// then of edges — OpenSubdiv's order — so the first #V vertices correspond to the
    /// input's (after `recover_faces_with_holes`, to the input vertices the recovery kept, in
    /// their order: vertices used only inside a merged region are gone).
    pub mesh: PolyMesh,
    /// For each output face, the input face it comes from (materials, face data follow);
    /// after `recover_faces_with_holes`, the lowest input face of its merged region.
    pub face_origin: Vec<FaceId>,
    /// What was done differently from what was asked, face by face.
    pub report: SubdivideReport,
}

/// Notes on a subdivision.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SubdivideReport {
    /// Faces with holes that method `[a]` could not bridge and that were refined with
    /// method `[b]` instead, each with the reason.
    pub fell_back_to_sharp: Vec<(FaceId, String)>,
}

/// Catmull-Clark subdivision, `options.levels` times.
///
/// Never changes `mesh`. Errors: [`crate::Error::EmptyMesh`] without faces,
/// [`crate::Error::InvalidOption`] for 0 levels or more than 8 (the face count grows 4× per
/// level), [`crate::Error::CoordinateOverflow`] for coordinates so near `f64::MAX` that the
/// subdivision's sums overflow. To carry other data (colours, UVs) or get the stencil matrix, use [`Refiner`].
pub fn catmull_clark(mesh: &PolyMesh, options: &SubdivideOptions) -> Result<Subdivided> {
    catmull_clark_with_progress(mesh, options, &mut |_, _| {})
}

/// [`catmull_clark`], calling `progress(levels_done, levels)` after each level, for front
/// ends that show progress on long work.
pub fn catmull_clark_with_progress(
    mesh: &PolyMesh,
    options: &SubdivideOptions,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Subdivided> {
    let (refiner, positions) = Refiner::with_positions(mesh, options, progress)?;
    let report = refiner.report().clone();
    let (mut mesh, mut face_origin) = refiner.into_parts(positions);
    if options.split_faces_with_holes && mesh.loop_count() != mesh.face_count() {
        let (split, origin) = crate::mesh::holes::split_faces_with_holes(&mesh)?;
        face_origin = origin.iter().map(|f| face_origin[f.idx()]).collect();
        mesh = split;
    }
    Ok(Subdivided {
        mesh,
        face_origin,
        report,
    })
}
