//! `katachi_cut_by_stroke`: cutting a triangle mesh along a hand-drawn screen stroke (seed 002)
//! through the C ABI, its options, the result handle with its report, and carrying the
//! caller's per-corner and per-vertex data through the cut. Conversion and error mapping
//! only; the work is [`crate::cut`]'s.

use std::ffi::c_void;

use glam::{DMat4, DVec2};

use super::boundary::{
    check_ptr, deref, deref_mut, guard, guard_value, out_buffer, slice, write_sized, FfiError,
    FfiResult,
};
use super::mesh::{mesh_ref, reset_out, KatachiMesh};
use super::status::KatachiStatus;
use crate::cut::{cut_by_stroke_with_progress, CutMode, CutOptions, CutOutput, Stroke, View};
use crate::error::Error;
use crate::mesh::PolyMesh;

/// Which faces a stroke cuts (`KatachiCutOptions::mode`; seed 002 Fig. 2).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiCutMode {
    /// Only faces seen from the eye: front-facing and not hidden by nearer faces (the
    /// default).
    VisibleOnly = 0,
    /// Every face under the stroke, front and back sheets alike; each sheet gets its own path.
    ThroughAll = 1,
}

/// The stage of the cut that set a stroke point aside (`katachi_cut_copy_dropped_points`).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiCutStage {
    /// Closer than `min_stroke_px` to the previous kept point, or a closing point merged into
    /// the first.
    Preprocessing = 0,
    /// Inside a face: the cut passes it on a straight chord (seed 002 §3.3, first
    /// normalization).
    FirstNormalization = 1,
    /// On an edge or vertex, but removed so that no triangle is crossed twice (seed 002 §3.3,
    /// second normalization).
    SecondNormalization = 2,
    /// Over no face the cut may touch (background, hidden or back faces in visible-only mode,
    /// faces behind the eye).
    OffMesh = 3,
}

/// Options of `katachi_cut_by_stroke`. Start from `katachi_cut_options_default()`.
/// Enumerated fields are `uint32_t` holding the named constants; other values are rejected.
/// Distances "× L" are ratios of L, the mean on-screen edge length (in pixels) of the faces
/// the stroke passes over (`KatachiCutInfo::mean_edge_length_px`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KatachiCutOptions {
    /// Set by the caller to `sizeof(KatachiCutOptions)`.
    pub struct_size: u32,
    /// A `KatachiCutMode`. Default `KATACHI_CUT_MODE_VISIBLE_ONLY`.
    pub mode: u32,
    /// 1: open the cut (duplicate the path's vertices, so the mesh gets a slit, two
    /// boundaries or two components); 0: only insert the edge path. Default 0.
    pub open: u32,
    /// Refuse a cut that would split more triangles than this, with
    /// `KATACHI_STATUS_BAD_INPUT` ("the cut would split N faces, more than the limit ...") and
    /// nothing returned. Default `UINT32_MAX` (no limit).
    pub max_faces_split: u32,
    /// Snap a model vertex to a stroke point closer than this × L on screen (seed 002 §3.2),
    /// in [0, 0.5]. Default 0.3.
    pub snap_vertex_ratio: f64,
    /// Snap a model vertex onto a stroke segment closer than this × L (seed 002 §3.2,
    /// Fig. 4), in [0, 0.5]. Default 0.3.
    pub snap_segment_ratio: f64,
    /// Split the stroke where it turns by more than this many degrees (seed 002 §3.4), in
    /// [0, 180]. Default 60.
    pub corner_angle_degrees: f64,
    /// Drop stroke points closer than this many pixels to the previous kept point, and treat
    /// a stroke whose last point is this close to its first as closed (a loop); ≥ 0.
    /// Default 2.
    pub min_stroke_px: f64,
    /// Visible-only mode: a face hides a stroke crossing only if it is nearer than the
    /// crossing by more than this × the diagonal of the cut region's bounding box; ≥ 0.
    /// Default 1e-4.
    pub depth_eps_rel: f64,
}

const OPTIONS_MIN_SIZE: usize = std::mem::size_of::<KatachiCutOptions>();

const OPTIONS_DEFAULT: KatachiCutOptions = KatachiCutOptions {
    struct_size: std::mem::size_of::<KatachiCutOptions>() as u32,
    mode: KatachiCutMode::VisibleOnly as u32,
    open: 0,
    max_faces_split: u32::MAX,
    snap_vertex_ratio: 0.3,
    snap_segment_ratio: 0.3,
    corner_angle_degrees: 60.0,
    min_stroke_px: 2.0,
    depth_eps_rel: 1e-4,
};

/// Summary of a cut, filled in by `katachi_cut_info`: the sizes of everything the copy
/// functions return, and the counts of the report.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KatachiCutInfo {
    /// Set by the caller to `sizeof(KatachiCutInfo)`.
    pub struct_size: u32,
    /// Vertices of the result.
    pub vertex_count: u32,
    /// Faces of the result (all triangles; `katachi_cut_copy_face_origin` writes this many).
    pub face_count: u32,
    /// Face corners of the result (3 × `face_count`).
    pub corner_count: u32,
    /// Vertices of the input mesh (`katachi_cut_interpolate_vertex_data` reads this many
    /// values per component).
    pub input_vertex_count: u32,
    /// Face corners of the input mesh (`katachi_cut_interpolate_corner_data` reads this many
    /// values per component).
    pub input_corner_count: u32,
    /// Vertices added: split vertices, then copies made by opening.
    pub new_vertex_count: u32,
    /// Faces added (result faces minus the triangles of the input).
    pub new_face_count: u32,
    /// Triangles of the input that were split.
    pub split_face_count: u32,
    /// Vertices moved onto the stroke by snapping (`katachi_cut_copy_moved_vertices`).
    pub moved_vertex_count: u32,
    /// Stroke pieces after splitting at sharp corners.
    pub piece_count: u32,
    /// Cut paths (one per piece and sheet or visible stretch; `katachi_cut_copy_paths`).
    pub path_count: u32,
    /// Vertices over all paths (the sum of their lengths).
    pub path_vertex_count: u32,
    /// Stroke points dropped in preprocessing (`KATACHI_CUT_STAGE_PREPROCESSING`).
    pub dropped_preprocessing_count: u32,
    /// Stroke points dropped by the first normalization.
    pub dropped_first_normalization_count: u32,
    /// Stroke points dropped by the second normalization.
    pub dropped_second_normalization_count: u32,
    /// Stroke points over no face the cut may touch.
    pub dropped_off_mesh_count: u32,
    /// Vertices within snapping distance kept in place because moving them would flip or
    /// flatten a face.
    pub snaps_refused_count: u32,
    /// Piece ends inside a face, close to one of its edges, moved onto that edge.
    pub ends_moved_to_edges_count: u32,
    /// Faces under the stroke with vertices both behind and in front of the eye: never cut.
    pub clipped_face_count: u32,
    /// Faces near the stroke with zero area: never split by a path.
    pub degenerate_face_count: u32,
    /// Path stretches that follow a face's edges because their chord crossed another
    /// piece's path.
    pub rerouted_count: u32,
    /// Path stretches that could not be made edges (0 for a sound cut).
    pub unjoined_count: u32,
    /// The largest snapping move, in world units (0 when none).
    pub max_move_world: f64,
    /// The largest snapping move, in pixels (0 when none).
    pub max_move_px: f64,
    /// L: the mean on-screen length, in pixels, of the edges of the faces the stroke passes
    /// over (0 when it meets none).
    pub mean_edge_length_px: f64,
    /// The same edges' mean length in world units.
    pub mean_edge_length_world: f64,
}

const INFO_MIN_SIZE: usize = std::mem::size_of::<KatachiCutInfo>();

const INFO_DEFAULT: KatachiCutInfo = KatachiCutInfo {
    struct_size: std::mem::size_of::<KatachiCutInfo>() as u32,
    vertex_count: 0,
    face_count: 0,
    corner_count: 0,
    input_vertex_count: 0,
    input_corner_count: 0,
    new_vertex_count: 0,
    new_face_count: 0,
    split_face_count: 0,
    moved_vertex_count: 0,
    piece_count: 0,
    path_count: 0,
    path_vertex_count: 0,
    dropped_preprocessing_count: 0,
    dropped_first_normalization_count: 0,
    dropped_second_normalization_count: 0,
    dropped_off_mesh_count: 0,
    snaps_refused_count: 0,
    ends_moved_to_edges_count: 0,
    clipped_face_count: 0,
    degenerate_face_count: 0,
    rerouted_count: 0,
    unjoined_count: 0,
    max_move_world: 0.0,
    max_move_px: 0.0,
    mean_edge_length_px: 0.0,
    mean_edge_length_world: 0.0,
};

/// The result of `katachi_cut_by_stroke`: the cut mesh, where its faces come from, the cut
/// paths and what snapping and normalization did. Opaque; free it with `katachi_cut_free`.
pub struct KatachiCut {
    pub(super) input: PolyMesh,
    pub(super) output: CutOutput,
}

/// A `KatachiCutOptions` holding the defaults (visible-only, not opened, no limit, the
/// paper's snapping ratios 0.3, corners above 60°, 2 px between stroke points, depth
/// tolerance 1e-4) and its `struct_size`.
#[no_mangle]
pub extern "C" fn katachi_cut_options_default() -> KatachiCutOptions {
    guard_value("katachi_cut_options_default", OPTIONS_DEFAULT, || {
        OPTIONS_DEFAULT
    })
}

/// A `KatachiCutInfo` with its `struct_size` set and counts 0.
#[no_mangle]
pub extern "C" fn katachi_cut_info_default() -> KatachiCutInfo {
    guard_value("katachi_cut_info_default", INFO_DEFAULT, || INFO_DEFAULT)
}

/// The option of `CutOptions` (kernel name) as the caller's `KatachiCutOptions` field.
fn c_field(option: &str) -> &str {
    match option {
        "corner_angle_deg" => "corner_angle_degrees",
        other => other,
    }
}

#[allow(clippy::field_reassign_with_default)]
fn options_from(o: &KatachiCutOptions) -> FfiResult<CutOptions> {
    if (o.struct_size as usize) < OPTIONS_MIN_SIZE {
        return Err(FfiError::invalid(format!(
            "options->struct_size is {}, but KatachiCutOptions needs at least {OPTIONS_MIN_SIZE} \
             (start from katachi_cut_options_default())",
            o.struct_size
        )));
    }
    let bad = |field: &str, v: u32, allowed: &str| {
        FfiError::invalid(format!(
            "options->{field} is {v}, which is not one of {allowed}"
        ))
    };
    let mode = match o.mode {
        0 => CutMode::VisibleOnly,
        1 => CutMode::ThroughAll,
        v => {
            return Err(bad(
                "mode",
                v,
                "KATACHI_CUT_MODE_VISIBLE_ONLY (0), KATACHI_CUT_MODE_THROUGH_ALL (1)",
            ))
        }
    };
    let open = match o.open {
        0 => false,
        1 => true,
        v => return Err(bad("open", v, "0, 1")),
    };
    // Field by field from the default: `CutOptions` is `#[non_exhaustive]` outside the crate,
    // and this file is also compiled against the public API alone (tests/ffi-public).
    let mut c = CutOptions::default();
    c.mode = mode;
    c.open = open;
    c.max_faces_split = o.max_faces_split;
    c.snap_vertex_ratio = o.snap_vertex_ratio;
    c.snap_segment_ratio = o.snap_segment_ratio;
    c.corner_angle_deg = o.corner_angle_degrees;
    c.min_stroke_px = o.min_stroke_px;
    c.depth_eps_rel = o.depth_eps_rel;
    // The kernel checks the numeric fields; its message is given under the C field's name.
    c.validate().map_err(|e| match e {
        Error::InvalidOption { option, message } => {
            FfiError::invalid(format!("options->{}: {message}", c_field(option)))
        }
        other => FfiError::from(other),
    })?;
    Ok(c)
}

/// Cuts `mesh` (never changed) along a stroke drawn over a view of it (seed 002: Mitani and
/// Suzuki's stroke cut) and returns the result handle in `*out`. N-gons and faces with holes
/// are triangulated first; the result is all triangles. Input vertex `v` is result vertex `v`
/// (possibly moved onto the stroke by snapping), new vertices follow; triangle `t` of the
/// triangulated input keeps slot `t`, pieces of split triangles are appended.
///
/// - `stroke_px`: 2 × `point_count` doubles `x0 y0 x1 y1 …`, in pixels, drawing order.
/// - `view_proj`: 16 doubles, the view-projection matrix in column-major order (OpenGL's
///   and glam's layout): `clip = view_proj · [x, y, z, 1]`.
/// - `viewport`: 4 doubles `x0, y0, width, height` in pixels, in the stroke's convention.
///
/// Conventions:
/// - A point is in front of the eye iff `clip.w > 0`, and `ndc = clip.xyz / clip.w`.
/// - OpenGL-style NDC: x right, y up, depth growing away from the eye (z in [-1, 1]). A
///   D3D-style matrix (z in [0, 1], y up) works unchanged: only the depth order is used. A
///   Vulkan-style matrix (y down in NDC) shows the mesh upside down against the stroke and
///   turns front faces into back faces: negate its second row first. A reversed-Z matrix
///   (near at z = 1) inverts visibility: pass a forward-Z one.
/// - Pixels: origin at the viewport's TOP-LEFT corner, y DOWN (Blender's region coordinates
///   and OpenGL window coordinates must be flipped: `y = height - y_up`):
///   `s = (x0 + (ndc.x + 1)/2 · W, y0 + (1 − ndc.y)/2 · H)`.
/// - Perspective and orthographic matrices go through the same formula.
///
/// A stroke that meets no face succeeds with nothing cut (`path_count` 0 in
/// `katachi_cut_info`).
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh`, `view_proj`,
/// `viewport`, `options` or `out` NULL, or `stroke_px` NULL with `point_count` > 0);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (a bad option: `struct_size`, `mode`, `open`, a ratio,
/// angle or distance out of its range); `KATACHI_STATUS_BAD_INPUT` (a NaN or infinite stroke
/// point or matrix entry, a stroke point or viewport value beyond ±2^40 pixels, matrix
/// entries so large that its determinant overflows, fewer than two stroke points
/// `min_stroke_px` apart, a stroke that crosses itself, a singular matrix, a viewport without
/// area, an empty mesh, a cut that would split more than `max_faces_split` triangles, a
/// vertex the cut would place beyond what a double holds); `KATACHI_STATUS_BAD_TOPOLOGY` (a
/// non-manifold or inconsistently oriented edge near the stroke, a bow-tie vertex within the
/// snap distance of it). On failure `*out` is NULL.
///
/// # Safety
/// `mesh` NULL or a live handle; `stroke_px` NULL or readable for 2 × `point_count` doubles;
/// `view_proj` NULL or readable for 16 doubles, `viewport` for 4; `options` NULL or a readable
/// `KatachiCutOptions`; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_by_stroke(
    mesh: *const KatachiMesh,
    stroke_px: *const f64,
    point_count: u32,
    view_proj: *const f64,
    viewport: *const f64,
    options: *const KatachiCutOptions,
    out: *mut *mut KatachiCut,
) -> KatachiStatus {
    guard("katachi_cut_by_stroke", || {
        let args = CutArgs {
            mesh,
            stroke_px,
            point_count,
            view_proj,
            viewport,
            options,
        };
        // SAFETY: the caller's promises, passed on unchanged.
        unsafe { cut_body(args, &mut |_, _| true, out) }
    })
}

/// Called by `katachi_cut_by_stroke_with_progress` on the calling thread after each step of
/// the cut: `done` steps of `total` are finished. Return 0 to go on, any other value to
/// cancel the cut. `user` is the pointer given with the callback.
pub type KatachiCutProgressFn =
    Option<unsafe extern "C" fn(done: u32, total: u32, user: *mut c_void) -> u32>;

/// `katachi_cut_by_stroke`, calling `progress(done, total, user)` on the calling thread after
/// each step of the cut (`total` steps; no step takes long whatever the stroke's length: a
/// 200,000-point stroke is checked in linear time). When `progress` returns non-zero the cut
/// stops: `KATACHI_STATUS_CANCELLED`, `*out` NULL, the mesh unchanged. `progress` may be NULL
/// (then this is `katachi_cut_by_stroke`). Other statuses as `katachi_cut_by_stroke`.
///
/// # Safety
/// As `katachi_cut_by_stroke`; `progress` NULL or a function safe to call with `user`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn katachi_cut_by_stroke_with_progress(
    mesh: *const KatachiMesh,
    stroke_px: *const f64,
    point_count: u32,
    view_proj: *const f64,
    viewport: *const f64,
    options: *const KatachiCutOptions,
    progress: KatachiCutProgressFn,
    user: *mut c_void,
    out: *mut *mut KatachiCut,
) -> KatachiStatus {
    guard("katachi_cut_by_stroke_with_progress", || {
        let args = CutArgs {
            mesh,
            stroke_px,
            point_count,
            view_proj,
            viewport,
            options,
        };
        let mut go_on = |done: u32, total: u32| match progress {
            // SAFETY: the caller's promise about `progress` and `user`.
            Some(f) => (unsafe { f(done, total, user) }) == 0,
            None => true,
        };
        // SAFETY: the caller's promises, passed on unchanged.
        unsafe { cut_body(args, &mut go_on, out) }
    })
}

/// The caller's arguments of both cut calls but the result.
struct CutArgs {
    mesh: *const KatachiMesh,
    stroke_px: *const f64,
    point_count: u32,
    view_proj: *const f64,
    viewport: *const f64,
    options: *const KatachiCutOptions,
}

/// The body of both cut calls.
///
/// # Safety
/// As `katachi_cut_by_stroke`.
unsafe fn cut_body(
    a: CutArgs,
    progress: &mut dyn FnMut(u32, u32) -> bool,
    out: *mut *mut KatachiCut,
) -> FfiResult {
    // SAFETY (all blocks): the caller's promises above.
    let out = unsafe { deref_mut(out, "out") }?;
    *out = std::ptr::null_mut();
    let mesh = unsafe { mesh_ref(a.mesh) }?;
    let point_count = a.point_count;
    let n = point_count as usize * 2;
    let stroke = unsafe {
        slice(
            a.stroke_px,
            n,
            "stroke_px",
            &format_args!("point_count is {point_count}"),
        )
    }?;
    let view_proj = unsafe { slice(a.view_proj, 16, "view_proj", &"16 values are needed") }?;
    let viewport = unsafe { slice(a.viewport, 4, "viewport", &"4 values are needed") }?;
    let options = options_from(unsafe { deref(a.options, "options") }?)?;
    let stroke = Stroke::new(
        stroke
            .chunks_exact(2)
            .map(|p| DVec2::new(p[0], p[1]))
            .collect(),
    );
    let matrix = DMat4::from_cols_slice(view_proj);
    let view = View::new(matrix, [viewport[0], viewport[1], viewport[2], viewport[3]]);
    let output = cut_by_stroke_with_progress(mesh, &stroke, &view, &options, progress)?;
    *out = Box::into_raw(Box::new(KatachiCut {
        input: mesh.clone(),
        output,
    }));
    Ok(())
}

/// Frees a result of `katachi_cut_by_stroke`. NULL is allowed and does nothing.
///
/// # Safety
/// `cut` NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_free(cut: *mut KatachiCut) {
    guard_value("katachi_cut_free", (), || {
        if !cut.is_null() {
            // SAFETY: a live handle from katachi_cut_by_stroke (the caller's promise).
            drop(unsafe { Box::from_raw(cut) });
        }
    })
}

/// # Safety
/// A non-NULL `p` must be a live handle.
pub(super) unsafe fn cut_ref<'a>(p: *const KatachiCut) -> FfiResult<&'a KatachiCut> {
    // SAFETY: forwarded to the caller.
    unsafe { deref(p, "cut") }
}

/// Fills `*info` with the result's counts and the report's numbers. The caller sets
/// `info->struct_size` first.
///
/// # Safety
/// `cut` NULL or a live handle; `info` NULL or writable for `info->struct_size` bytes.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_info(
    cut: *const KatachiCut,
    info: *mut KatachiCutInfo,
) -> KatachiStatus {
    guard("katachi_cut_info", || {
        // SAFETY: the caller's promises above.
        let c = unsafe { cut_ref(cut) }?;
        check_ptr(info, "info")?;
        let (m, r) = (&c.output.mesh, &c.output.report);
        let n = |len: usize| len as u32;
        let value = KatachiCutInfo {
            struct_size: 0,
            vertex_count: m.vertex_count(),
            face_count: m.face_count(),
            corner_count: m.corner_count(),
            input_vertex_count: c.input.vertex_count(),
            input_corner_count: c.input.corner_count(),
            new_vertex_count: r.new_vertices,
            new_face_count: r.new_faces,
            split_face_count: r.split_faces,
            moved_vertex_count: n(r.moved.len()),
            piece_count: r.pieces,
            path_count: n(r.paths.len()),
            path_vertex_count: n(r.paths.iter().map(|p| p.vertices.len()).sum()),
            dropped_preprocessing_count: n(r.dropped.preprocessing.len()),
            dropped_first_normalization_count: n(r.dropped.first_normalization.len()),
            dropped_second_normalization_count: n(r.dropped.second_normalization.len()),
            dropped_off_mesh_count: n(r.dropped.off_mesh.len()),
            snaps_refused_count: n(r.snaps_refused.len()),
            ends_moved_to_edges_count: n(r.ends_moved_to_edges.len()),
            clipped_face_count: n(r.clipped_faces.len()),
            degenerate_face_count: n(r.degenerate_faces.len()),
            rerouted_count: n(r.rerouted.len()),
            unjoined_count: n(r.unjoined.len()),
            max_move_world: r.max_move_world,
            max_move_px: r.max_move_px,
            mean_edge_length_px: r.mean_edge_length_px,
            mean_edge_length_world: r.mean_edge_length_world,
        };
        unsafe { write_sized(info, value, INFO_MIN_SIZE, "info", "KatachiCutInfo") }
    })
}

/// A new mesh handle holding the cut mesh (all triangles); the caller frees it with
/// `katachi_mesh_free`. On failure `*out` is NULL.
///
/// # Safety
/// `cut` NULL or a live handle; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_mesh(
    cut: *const KatachiCut,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_cut_mesh", || {
        // SAFETY: the caller's promises above.
        let out = unsafe { reset_out(out) }?;
        let c = unsafe { cut_ref(cut) }?;
        *out = KatachiMesh::into_raw(c.output.mesh.clone());
        Ok(())
    })
}

/// Copies, for each face of the result, the face of the INPUT mesh it lies in (before
/// triangulation), so materials and face data follow: `face_count` values.
///
/// # Safety
/// `cut` NULL or a live handle; `faces` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_copy_face_origin(
    cut: *const KatachiCut,
    faces: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_copy_face_origin", || {
        // SAFETY: the caller's promises above.
        let c = unsafe { cut_ref(cut) }?;
        let origin = &c.output.face_origin;
        let buf = unsafe {
            out_buffer(
                faces,
                capacity,
                origin.len(),
                "faces",
                &"one per result face",
            )
        }?;
        for (o, f) in buf.iter_mut().zip(origin) {
            *o = f.0;
        }
        Ok(())
    })
}

/// Copies, for each vertex of the result, the vertex it duplicates: an opened cut's copy of
/// a path vertex gives that vertex, every other vertex itself (`vertex_count` values). Vertex
/// data of a copy is its original's.
///
/// # Safety
/// `cut` NULL or a live handle; `vertices` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_copy_vertex_original(
    cut: *const KatachiCut,
    vertices: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_copy_vertex_original", || {
        // SAFETY: the caller's promises above.
        let c = unsafe { cut_ref(cut) }?;
        let original = c.output.vertex_original();
        let buf = unsafe {
            out_buffer(
                vertices,
                capacity,
                original.len(),
                "vertices",
                &"one per result vertex",
            )
        }?;
        for (o, v) in buf.iter_mut().zip(&original) {
            *o = v.0;
        }
        Ok(())
    })
}

/// Copies the cut paths in compressed rows: `offsets` gets `path_count + 1` values (path `i`
/// is `vertices[offsets[i] .. offsets[i + 1]]`), `vertices` gets `path_vertex_count` result
/// vertex ids in stroke order; consecutive ones share an edge of the result. A closed path
/// does not repeat its first vertex (its last edge joins last and first). When the cut was
/// opened these are the ids before opening: the faces on one side of each path vertex kept
/// the id, the others' corners moved to copies.
///
/// # Safety
/// `cut` NULL or a live handle; `offsets` and `vertices` NULL or writable for their
/// capacities.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_copy_paths(
    cut: *const KatachiCut,
    offsets: *mut u32,
    offsets_capacity: usize,
    vertices: *mut u32,
    vertices_capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_copy_paths", || {
        // SAFETY: the caller's promises above.
        let c = unsafe { cut_ref(cut) }?;
        let paths = &c.output.report.paths;
        let total: usize = paths.iter().map(|p| p.vertices.len()).sum();
        let o = unsafe {
            out_buffer(
                offsets,
                offsets_capacity,
                paths.len() + 1,
                "offsets",
                &"path_count + 1",
            )
        }?;
        let v = unsafe {
            out_buffer(
                vertices,
                vertices_capacity,
                total,
                "vertices",
                &"path_vertex_count",
            )
        }?;
        let mut at = 0usize;
        o[0] = 0;
        for (i, p) in paths.iter().enumerate() {
            for (d, s) in v[at..at + p.vertices.len()].iter_mut().zip(&p.vertices) {
                *d = s.0;
            }
            at += p.vertices.len();
            o[i + 1] = at as u32;
        }
        Ok(())
    })
}

/// Copies, for each cut path, the stroke piece it belongs to (the stroke is split into
/// pieces at sharp corners) into `pieces` and 1 if the path is closed (0 otherwise) into
/// `closed`: `path_count` values each.
///
/// # Safety
/// `cut` NULL or a live handle; `pieces` and `closed` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_copy_path_pieces(
    cut: *const KatachiCut,
    pieces: *mut u32,
    closed: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_copy_path_pieces", || {
        // SAFETY: the caller's promises above.
        let c = unsafe { cut_ref(cut) }?;
        let paths = &c.output.report.paths;
        let p = unsafe { out_buffer(pieces, capacity, paths.len(), "pieces", &"path_count") }?;
        let cl = unsafe { out_buffer(closed, capacity, paths.len(), "closed", &"path_count") }?;
        for ((dp, dc), path) in p.iter_mut().zip(cl.iter_mut()).zip(paths) {
            *dp = path.piece;
            *dc = path.closed as u32;
        }
        Ok(())
    })
}

/// Copies the vertices snapping moved onto the stroke (seed 002 §3.2), ascending id:
/// `moved_vertex_count` ids into `vertices`, their positions before and after into
/// `from_xyz` and `to_xyz` (3 doubles each, so 3 × `capacity` room), and the distance each
/// moved on screen, in pixels, into `pixels`. A vertex moves parallel to the screen: its
/// clip-space w and NDC depth are kept.
///
/// # Safety
/// `cut` NULL or a live handle; `vertices` and `pixels` NULL or writable for `capacity`
/// values, `from_xyz` and `to_xyz` for 3 × `capacity`.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_copy_moved_vertices(
    cut: *const KatachiCut,
    vertices: *mut u32,
    from_xyz: *mut f64,
    to_xyz: *mut f64,
    pixels: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_copy_moved_vertices", || {
        // SAFETY: the caller's promises above.
        let c = unsafe { cut_ref(cut) }?;
        let moved = &c.output.report.moved;
        let n = moved.len();
        let what = &"moved_vertex_count";
        let v = unsafe { out_buffer(vertices, capacity, n, "vertices", what) }?;
        let from = unsafe {
            out_buffer(
                from_xyz,
                capacity.saturating_mul(3),
                3 * n,
                "from_xyz",
                &"3 × moved_vertex_count",
            )
        }?;
        let to = unsafe {
            out_buffer(
                to_xyz,
                capacity.saturating_mul(3),
                3 * n,
                "to_xyz",
                &"3 × moved_vertex_count",
            )
        }?;
        let px = unsafe { out_buffer(pixels, capacity, n, "pixels", what) }?;
        for (i, m) in moved.iter().enumerate() {
            v[i] = m.vertex.0;
            from[3 * i..3 * i + 3].copy_from_slice(&m.from.to_array());
            to[3 * i..3 * i + 3].copy_from_slice(&m.to.to_array());
            px[i] = m.pixels;
        }
        Ok(())
    })
}

/// Copies the stroke points (indices into the caller's stroke, ascending) that the stage
/// `stage` (a `KatachiCutStage`) set aside; the counts are in `katachi_cut_info`
/// (`dropped_preprocessing_count` and so on).
///
/// # Safety
/// `cut` NULL or a live handle; `points` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_copy_dropped_points(
    cut: *const KatachiCut,
    stage: u32,
    points: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_copy_dropped_points", || {
        // SAFETY: the caller's promises above.
        let c = unsafe { cut_ref(cut) }?;
        let d = &c.output.report.dropped;
        let list = match stage {
            0 => &d.preprocessing,
            1 => &d.first_normalization,
            2 => &d.second_normalization,
            3 => &d.off_mesh,
            v => {
                return Err(FfiError::invalid(format!(
                    "stage is {v}, which is not one of KATACHI_CUT_STAGE_PREPROCESSING (0), \
                     KATACHI_CUT_STAGE_FIRST_NORMALIZATION (1), \
                     KATACHI_CUT_STAGE_SECOND_NORMALIZATION (2), KATACHI_CUT_STAGE_OFF_MESH (3)"
                )))
            }
        };
        let buf = unsafe {
            out_buffer(
                points,
                capacity,
                list.len(),
                "points",
                &"the stage's dropped point count",
            )
        }?;
        buf.copy_from_slice(list);
        Ok(())
    })
}

/// `count × dim`, or an error when `dim` is 0 or the product overflows.
fn data_size(count: u32, dim: u32, what: &str) -> FfiResult<usize> {
    if dim == 0 {
        return Err(FfiError::invalid(format!(
            "dim is 0; {what} data needs at least one value per {what}"
        )));
    }
    (count as usize)
        .checked_mul(dim as usize)
        .ok_or_else(|| FfiError::invalid(format!("dim {dim} is too large")))
}

/// Carries per-corner data of the INPUT mesh (UVs, corner colours: `dim` doubles per corner,
/// corner after corner in `katachi_mesh_copy_faces` order, so `value_count` =
/// `input_corner_count` × `dim`) to the result's corners (`corner_count` × `dim` doubles into
/// `out`). A result corner at an input vertex takes that vertex's value in the face it lies
/// in, exactly; a new vertex takes the linear blend of its source triangle's corner values.
/// Snapped vertices keep their values.
///
/// Statuses: `KATACHI_STATUS_INVALID_ARGUMENT` when `dim` is 0 or `value_count` is not
/// `input_corner_count` × `dim`; `KATACHI_STATUS_BUFFER_TOO_SMALL` when `capacity` is short
/// (`(NULL, 0)` asks the size).
///
/// # Safety
/// `cut` NULL or a live handle; `values` NULL or readable for `value_count` doubles; `out`
/// NULL or writable for `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_interpolate_corner_data(
    cut: *const KatachiCut,
    values: *const f64,
    value_count: usize,
    dim: u32,
    out: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_interpolate_corner_data", || {
        // SAFETY: the caller's promises above.
        unsafe { interpolate(cut, values, value_count, dim, out, capacity, Per::Corner) }
    })
}

/// Carries per-vertex data of the INPUT mesh (colours, weights: `dim` doubles per vertex, so
/// `value_count` = `input_vertex_count` × `dim`) to the result's vertices (`vertex_count` ×
/// `dim` doubles into `out`): input vertices keep theirs, opening copies take their
/// original's, new vertices the linear blend of their source triangle's vertices.
///
/// Statuses: as `katachi_cut_interpolate_corner_data`, with vertex counts.
///
/// # Safety
/// `cut` NULL or a live handle; `values` NULL or readable for `value_count` doubles; `out`
/// NULL or writable for `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_interpolate_vertex_data(
    cut: *const KatachiCut,
    values: *const f64,
    value_count: usize,
    dim: u32,
    out: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_interpolate_vertex_data", || {
        // SAFETY: the caller's promises above.
        unsafe { interpolate(cut, values, value_count, dim, out, capacity, Per::Vertex) }
    })
}

/// What the data given to the interpolation calls is attached to.
#[derive(Clone, Copy)]
enum Per {
    Corner,
    Vertex,
}

/// The body of `katachi_cut_interpolate_corner_data` and `_vertex_data`.
///
/// # Safety
/// As those functions.
unsafe fn interpolate(
    cut: *const KatachiCut,
    values: *const f64,
    value_count: usize,
    dim: u32,
    out: *mut f64,
    capacity: usize,
    per: Per,
) -> FfiResult<()> {
    // SAFETY: forwarded to the caller.
    let c = unsafe { cut_ref(cut) }?;
    let (n_in, n_out, what, plural) = match per {
        Per::Corner => (
            c.input.corner_count(),
            c.output.mesh.corner_count(),
            "corner",
            "corners",
        ),
        Per::Vertex => (
            c.input.vertex_count(),
            c.output.mesh.vertex_count(),
            "vertex",
            "vertices",
        ),
    };
    let nout = data_size(n_out, dim, what)?;
    let nin = data_size(n_in, dim, what)?;
    if value_count != nin {
        return Err(FfiError::invalid(format!(
            "value_count is {value_count}, but the input mesh has {n_in} {plural} × dim {dim} = \
             {nin}"
        )));
    }
    let values = unsafe { slice(values, value_count, "values", &"value_count > 0") }?;
    let expected = format!("{what}_count × dim");
    let buf = unsafe { out_buffer(out, capacity, nout, "out", &expected) }?;
    let result = match per {
        Per::Corner => c
            .output
            .interpolate_corner_data(&c.input, values, dim as usize)?,
        Per::Vertex => c
            .output
            .interpolate_vertex_data(&c.input, values, dim as usize)?,
    };
    buf.copy_from_slice(&result);
    Ok(())
}
