//! Cutting a triangle mesh along a hand-drawn screen stroke (seed 002: Mitani, Suzuki, "A
//! method for cutting a mesh model by hand drawn stroke achieved by a simple implementation";
//! spec `spec/stroke_cut.md`).
//!
//! The paper trades exactness for robustness and mesh quality: model vertices near the
//! stroke move onto it (§3.2, Fig. 4), the stroke is simplified so that it meets every
//! triangle at most twice (§3.3, first and second normalization, Figs. 5-10) and is split at
//! sharp corners whose ends may lie inside a face (§3.4, Figs. 11-13); three split patterns
//! then do all the work, so no triangle is cut into more than 3 pieces (4 with a stroke end
//! inside it) and no sliver or near-duplicate vertex appears where a snap was possible.
//!
//! [`cut_by_stroke`] runs the paper's steps in order (§3.4's closing list, spec §4), one file
//! each:
//!
//! | seed 002 | step | file |
//! | --- | --- | --- |
//! | §2.1, spec §4 preprocessing | the stroke checked (finite, not crossing itself), near points dropped, a loop closed | `stroke_checks.rs` |
//! | spec §2-3 | the view; the region: the faces near the stroke, their adjacency, L | `view.rs`, `region.rs` |
//! | §3.2, Fig. 4 | model vertices snapped to stroke vertices, then onto stroke segments | `snap.rs` |
//! | §3.4, Fig. 11 | the stroke split into pieces at sharp corners | `stroke_checks.rs` |
//! | §3.3, Fig. 5; §3.4, Fig. 12 | first normalization: the array A of vertices and edge crossings, per piece and sheet; piece ends inside faces | `first_normalization.rs` |
//! | Fig. 2, spec §3 | visible-only mode: each crossing seen or hidden | `visibility.rs` |
//! | §3.3, Figs. 8-10 | second normalization: no triangle crossed twice | `second_normalization.rs` |
//! | Figs. 7, 13 | the split patterns: vertex + edge, edge + edge, end point inside | `split_patterns.rs` |
//! | spec §4 step 8 | the cut path made of edges, and its opening | `path_and_opening.rs` |
//! | — | the edits, the report, the new mesh; the cut in the input's own layout for hosts | `edits.rs`, `report.rs`, `assemble.rs`; `polygons.rs` |
//!
//! The corners are found on the stroke before snapping (it never changes them), so splitting
//! the stroke after the snap, as the spec orders, changes nothing. What the steps ask of
//! "what is near what" is answered by the speed machinery in `fast/` (a grid over the stroke,
//! SIMD whole-mesh passes, face buckets, radix sorts) behind a narrow interface;
//! [`cut_edits_plain`] runs the same steps on plain scans and gives the same edits.
//!
//! Gap-fills (the paper leaves these open; the spec's choices unless noted):
//! - L is the mean *screen* edge length of the faces the stroke meets (spec §4).
//! - Visible-only: front-facing faces, and a crossing is seen when no face under it is nearer
//!   by more than `depth_eps_rel` × the cut region's diagonal (spec §3: per crossing, a ray);
//!   a crossing that snapping did not move must also have been seen before snapping, so a
//!   snapped occluder sliding aside exposes nothing (katachi's choice).
//! - Second normalization runs to a fixed point, faces in ascending id (spec §4 step 6); the
//!   stretches of one piece that follow each other along the stroke (split by a silhouette
//!   or a hole) are normalized together, so a face left and re-entered is still crossed once
//!   (katachi's choice).
//! - A piece end within a third of the segment snap distance of an edge goes onto the edge
//!   (no sliver from the 1 → 3 split; reported in [`CutReport::ends_moved_to_edges`]), and a
//!   constructed point a rounding error from a vertex is that vertex (katachi's choice).
//! - Crossings of one edge by different chains get their own vertices; one crossing shared by
//!   chains (a silhouette, a corner) gets one (the spec's "once per edge", per crossing).
//! - Pieces are normalized apart, so two of them can cross one face on chords that cross;
//!   the later one then follows that face's edges ([`CutReport::rerouted`]).
//! - A closed stroke (last point within `min_stroke_px` of the first) without two sharp
//!   corners is cut as two halves meeting at points that hold model vertices when it can.
//! - Strokes that touch themselves, or come within 1e-9 × their size of doing so, are rejected.
//!
//! Cost: two streaming passes over the mesh (project each vertex into a grid cell about one
//! edge long; keep each face whose cell box meets the stroke's band), an exact distance test
//! on those candidates, local work on the faces within the snap distance of the stroke, and
//! one bulk copy for the output. Written by hand because no crate implements this paper;
//! predicates are `robust::orient2d`.
//!
//! ```
//! use katachi::cut::{cut_by_stroke, CutMode, CutOptions, Stroke, View};
//! use katachi::mesh::shapes;
//! use glam::{DMat4, DVec2, DVec3};
//!
//! // A 4 × 4 grid of unit quads (triangulated first), seen from above.
//! let grid = shapes::grid(4, 4).unwrap();
//! let view_proj = DMat4::orthographic_rh_gl(-0.5, 4.5, -0.5, 4.5, -10.0, 10.0)
//!     * DMat4::look_at_rh(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y);
//! let view = View::new(view_proj, [0.0, 0.0, 500.0, 500.0]);
//! let stroke = Stroke::new(vec![DVec2::new(20.0, 330.0), DVec2::new(480.0, 140.0)]);
//! let out = cut_by_stroke(&grid, &stroke, &view, &CutOptions::with_mode(CutMode::ThroughAll)).unwrap();
//! assert!(out.mesh.face_count() > 32); // the 32 triangles, some split
//! assert!(out.report.moved.iter().all(|m| m.pixels <= 0.3 * out.report.mean_edge_length_px));
//! assert_eq!(out.face_origin.len(), out.mesh.face_count() as usize);
//! assert_eq!(out.report.paths.len(), 1);
//! ```

mod assemble;
mod edits;
mod fast;
mod first_normalization;
mod geom;
mod ids;
mod interpolate;
mod options;
mod path_and_opening;
mod polygons;
mod region;
mod report;
mod second_normalization;
mod snap;
mod split_patterns;
mod stroke_checks;
mod triangulate;
mod view;
mod visibility;

pub use edits::CutEdits;
pub use options::{CutMode, CutOptions};
pub use polygons::{CutPolygons, InputEdges, NONE};
pub use report::{CutOutput, CutPath, CutReport, DroppedPoints, VertexMove};
pub use view::{Stroke, View, SCREEN_RANGE_PX};

use crate::error::Result;
use crate::mesh::{PolyMesh, VertexId};
use fast::Machinery;
use ids::Lv;
use path_and_opening::PathEdges;
use split_patterns::Splitter;
use visibility::Visibility;

/// Cuts `mesh` along `stroke` drawn over `view` (seed 002; spec §4). Never changes `mesh`.
///
/// N-gons are triangulated first (faces with holes split by their bridges first), and
/// `face_origin` maps every output face to the input face it lies in.
///
/// Errors, all before anything is computed on the mesh: [`crate::Error::InvalidOption`],
/// [`crate::Error::NonFiniteStrokePoint`], [`crate::Error::StrokePointOutOfRange`] (beyond
/// ±[`SCREEN_RANGE_PX`]), [`crate::Error::StrokeTooShort`] (fewer than two points
/// `min_stroke_px` apart), [`crate::Error::StrokeSelfIntersects`],
/// [`crate::Error::NonFiniteMatrixEntry`], [`crate::Error::ViewProjectionOutOfRange`] (entries
/// whose determinant overflows), [`crate::Error::SingularViewProjection`],
/// [`crate::Error::InvalidViewport`], [`crate::Error::EmptyMesh`]; then
/// [`crate::Error::NonManifoldEdge`] or [`crate::Error::InconsistentOrientation`] for an edge
/// near the stroke and [`crate::Error::NonManifoldVertex`] for a bow-tie vertex within the
/// snap distance of it (the rest of the mesh is not inspected), and
/// [`crate::Error::InvalidFaceWithHoles`] for a face with holes that cannot be bridged;
/// [`crate::Error::CoordinateOverflow`] when a vertex the cut places has a coordinate f64
/// cannot hold (the input's coordinates near its limits).
pub fn cut_by_stroke(
    mesh: &PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
) -> Result<CutOutput> {
    cut_by_stroke_with_progress(mesh, stroke, view, options, &mut |_, _| true)
}

/// How many times [`cut_by_stroke_with_progress`] reports progress: after each step of the
/// cut (stroke checks, region, snap, first normalization, split patterns, path and opening,
/// edits) and once the new mesh is built.
pub const CUT_STEPS: u32 = 8;

/// [`cut_by_stroke`], calling `progress(done, CUT_STEPS)` on the calling thread after each
/// step (a progress bar; no call takes long between two of them, whatever the stroke's
/// length). When `progress` returns `false` the cut stops there with
/// [`crate::Error::Cancelled`] (kind [`crate::ErrorKind::Cancelled`]); `mesh` is unchanged
/// either way. Same errors otherwise.
pub fn cut_by_stroke_with_progress(
    mesh: &PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
    progress: &mut dyn FnMut(u32, u32) -> bool,
) -> Result<CutOutput> {
    let mut steps = Steps { done: 0, progress };
    let (edits, tris) = plan(mesh, stroke, view, options, Machinery::Fast, &mut steps)?;
    let output = edits.apply_to(mesh, &tris)?;
    steps.next()?;
    Ok(output)
}

/// The steps done, told to the caller's progress function, which may cancel.
struct Steps<'p> {
    done: u32,
    progress: &'p mut dyn FnMut(u32, u32) -> bool,
}

impl Steps<'_> {
    /// One more step done: `Err(Cancelled)` when the caller says stop.
    fn next(&mut self) -> Result<()> {
        self.done += 1;
        if (self.progress)(self.done, CUT_STEPS) {
            Ok(())
        } else {
            Err(crate::Error::Cancelled {
                operation: "the stroke cut",
            })
        }
    }
}

/// [`cut_by_stroke`] without building the new mesh: what the cut changes, as edits to the
/// triangulated input ([`CutEdits`]), for callers that keep their own mesh and apply them
/// in O(changes). [`CutEdits::apply`] gives [`cut_by_stroke`]'s result. Same errors.
pub fn cut_edits(
    mesh: &PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
) -> Result<CutEdits> {
    let mut steps = Steps {
        done: 0,
        progress: &mut |_, _| true,
    };
    Ok(plan(mesh, stroke, view, options, Machinery::Fast, &mut steps)?.0)
}

/// [`cut_edits`] on the plain path: no candidate grid, SIMD passes, buckets, windows or radix
/// sorts, but linear scans of every face and stroke segment and the standard library's
/// sorts (O(faces × stroke points)). The same edits bit for bit; for checking the fast path.
pub fn cut_edits_plain(
    mesh: &PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
) -> Result<CutEdits> {
    let mut steps = Steps {
        done: 0,
        progress: &mut |_, _| true,
    };
    Ok(plan(mesh, stroke, view, options, Machinery::Plain, &mut steps)?.0)
}

/// The cut's steps (seed 002 §3.4's list, spec §4), up to the edits.
fn plan<'a>(
    mesh: &'a PolyMesh,
    stroke: &Stroke,
    view: &View,
    options: &CutOptions,
    machinery: Machinery,
    steps: &mut Steps<'_>,
) -> Result<(CutEdits, triangulate::Triangles<'a>)> {
    let mut trace = fast::trace::Trace::start();
    options.validate()?;
    let proj = view::Projector::new(view)?;
    let prep = stroke_checks::prepare(stroke, options)?;
    mesh.require_faces("a stroke cut")?;
    let tris = triangulate::triangles(mesh)?;
    let segments = prep.segments();
    trace.mark("prepare");
    steps.next()?;

    // The faces near the stroke, and L.
    let region::Around {
        mut region,
        length,
        reach,
        segments: index,
        clipped,
    } = region::around_stroke(&tris.mesh, &segments, &proj, options, machinery)?;
    trace.mark("region");
    steps.next()?;

    // Seed 002 §3.2: model vertices near the stroke move onto it.
    let mut visibility = (options.mode == CutMode::VisibleOnly)
        .then(|| Visibility::new(&region, &index, options.depth_eps_rel, reach));
    let snapped = snap::snap(
        &mut region,
        &prep,
        &segments,
        &index,
        length.px,
        reach,
        options,
        &proj,
        visibility.as_mut(),
    );
    trace.mark("snap");
    steps.next()?;

    // §3.4: the stroke split at its sharp corners; §3.3: the first normalization of each
    // piece, one array per sheet.
    let pieces = stroke_checks::pieces(&prep, &snapped);
    let elements = first_normalization::first_normalization(
        &region,
        &snapped,
        prep.closed,
        &pieces,
        &index,
        visibility.as_ref(),
        first_normalization::EndReach {
            edge: options.snap_segment_ratio * length.px / 3.0,
            silhouette: 1e-9 * length.px.max(1.0),
        },
        machinery,
    );
    trace.mark("first normalization");
    steps.next()?;

    // §3.3: the second normalization of each array, then the split patterns along it
    // (Figs. 7, 13).
    let mut sp = Splitter::new(&region, length.px);
    let mut placed = vec![false; elements.occ.len()];
    let mut paths = Vec::new();
    for (piece, array) in &elements.arrays {
        for nz in second_normalization::normalize(&region, &elements.occ, array) {
            paths.extend(split_patterns::split_along(
                &mut sp,
                &elements.occ,
                &nz,
                *piece,
                &mut placed,
            ));
        }
    }
    trace.mark("split");
    steps.next()?;

    // Spec §4 step 8: the cut path, made of edges, and its opening.
    let (rerouted, unjoined) = path_and_opening::join_steps(&mut sp, &mut paths);
    let path_edges = PathEdges::new(&paths, region.vertex_count() + sp.new_pos.len());
    sp.improve(&|a, b| path_edges.contains(a, b));
    let split_faces = sp
        .touched
        .iter()
        .filter(|&&f| sp.pieces_of(f).is_some_and(|s| s.len() > 1))
        .count() as u32;
    if split_faces > options.max_faces_split {
        return Err(crate::Error::CutTooLarge {
            split_faces,
            limit: options.max_faces_split,
        });
    }
    let copies = if options.open && !path_edges.is_empty() {
        path_and_opening::open(&mut sp, &paths, &path_edges)
    } else {
        Vec::new()
    };
    trace.mark("path");
    steps.next()?;

    // Output ids: the region's vertices keep their mesh ids, new vertices follow.
    let nv_in = tris.mesh.vertex_count();
    let n0 = region.vertex_count() as u32;
    let gid = |v: Lv| {
        VertexId(if v.0 < n0 {
            region.global(v)
        } else {
            nv_in + v.0 - n0
        })
    };
    let report = report::build(&report::Parts {
        prep: &prep,
        snapped: &snapped,
        pieces: &pieces,
        elements: &elements,
        placed: &placed,
        paths: &paths,
        rerouted: &rerouted,
        unjoined: &unjoined,
        clipped: &clipped,
        length: &length,
        tris: &tris,
        region: &region,
        gid: &gid,
    });
    let report = CutReport {
        pieces: pieces.count() as u32,
        split_faces,
        mean_edge_length_px: length.px,
        mean_edge_length_world: length.world,
        ..report
    };
    let counts = (mesh.vertex_count(), tris.mesh.face_count());
    let edits = CutEdits::collect(counts, &region, sp, &copies, &gid, report);
    // No vertex placed where f64 cannot hold it (coordinates near its limits).
    let placed: Vec<glam::DVec3> = (edits.new_vertices.iter().copied())
        .chain(edits.report.moved.iter().map(|m| m.to))
        .collect();
    crate::mesh::validate::result_positions("the stroke cut", mesh.positions(), &placed)?;
    trace.mark("edits");
    steps.next()?;
    Ok((edits, tris))
}
