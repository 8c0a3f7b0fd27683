//! `katachi_subdivide`: solid-aware Catmull-Clark subdivision (seed 001) through the C ABI,
//! its options, the result handle, and interpolation of the caller's data through it.
//! Conversion and error mapping only; the work is [`crate::subdivide`]'s.

use std::ffi::c_void;

use std::sync::OnceLock;

use super::boundary::{
    deref, guard, guard_value, out_buffer, slice, write_sized, FfiError, FfiResult,
};
use super::mesh::{mesh_ref, sharpness_scale, KatachiMesh};
use super::status::KatachiStatus;
use crate::subdivide::{
    merge_coplanar_regions, tag_feature_edges, BoundaryInterpolation, CreaseMethod, FaceVarying,
    HoleMethod, MergeOptions, Stencils, SubdivideOptions, Subdivision,
};

/// How faces with holes are subdivided (`KatachiSubdivideOptions::holes`).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiHoleMethod {
    /// Method `[a]`: bridge the loops, subdivide smoothly (the default).
    Smooth = 0,
    /// Method `[b]`: loop edges sharp, the face stays planar with its holes.
    Sharp = 1,
}

/// Boundary rule (`KatachiSubdivideOptions::boundary`), as OpenSubdiv's.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiBoundary {
    /// Boundary edges sharp; corners smoothed along the boundary (the default).
    EdgeOnly = 0,
    /// As EDGE_ONLY, and a boundary vertex with a single face is pinned.
    EdgeAndCorner = 1,
}

/// Semi-sharp crease rule (`KatachiSubdivideOptions::crease_method`), as OpenSubdiv's.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiCreaseMethod {
    /// Sharpness decreases by 1 per level (the default).
    Uniform = 0,
    /// Chaikin's rule: averaged with neighbouring creases.
    Chaikin = 1,
}

/// Face-varying (UV) interpolation, as OpenSubdiv's linear-interpolation options.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiFaceVarying {
    /// Smooth everywhere (Blender's UV Smooth "All").
    Smooth = 0,
    /// Smooth, UV corners pinned (Blender's "Keep Corners").
    LinearCornersOnly = 1,
    /// Linear along UV boundaries (Blender's "Keep Boundaries").
    LinearBoundaries = 2,
    /// Bilinear (Blender's "None").
    LinearAll = 3,
}

/// Options of `katachi_subdivide`. Start from `katachi_subdivide_options_default()`.
/// Enumerated fields are `uint32_t` holding the named constants; other values are rejected.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KatachiSubdivideOptions {
    /// Set by the caller to `sizeof(KatachiSubdivideOptions)`.
    pub struct_size: u32,
    /// Subdivision levels, 1 to 8. Default 1.
    pub levels: u32,
    /// A `KatachiHoleMethod`. Default `KATACHI_HOLE_METHOD_SMOOTH`.
    pub holes: u32,
    /// A `KatachiBoundary`. Default `KATACHI_BOUNDARY_EDGE_ONLY`.
    pub boundary: u32,
    /// A `KatachiCreaseMethod`. Default `KATACHI_CREASE_METHOD_UNIFORM`.
    pub crease_method: u32,
    /// 1: first turn coplanar regions (a boolean's triangles) back into faces with holes, as
    /// `katachi_merge_coplanar_regions` does. Default 0.
    pub recover_faces_with_holes: u32,
    /// Angle tolerance of that recovery, in radians, in [0, π/2). Default 1e-3.
    pub coplanar_angle_tolerance: f64,
    /// Tag edges whose dihedral angle exceeds this many degrees as infinitely sharp (0: off).
    /// Default 0.
    pub feature_angle_degrees: f64,
    /// 1: cut the result's faces with holes (method `[b]`'s, and those method `[a]` could not
    /// bridge) into simple polygons along bridge edges, for hosts that store no faces with
    /// holes; every count and copy of the result then describes the cut faces. Default 0.
    pub split_faces_with_holes: u32,
}

const OPTIONS_MIN_SIZE: usize = std::mem::size_of::<KatachiSubdivideOptions>();

const OPTIONS_DEFAULT: KatachiSubdivideOptions = KatachiSubdivideOptions {
    struct_size: std::mem::size_of::<KatachiSubdivideOptions>() as u32,
    levels: 1,
    holes: KatachiHoleMethod::Smooth as u32,
    boundary: KatachiBoundary::EdgeOnly as u32,
    crease_method: KatachiCreaseMethod::Uniform as u32,
    recover_faces_with_holes: 0,
    coplanar_angle_tolerance: 1e-3,
    feature_angle_degrees: 0.0,
    split_faces_with_holes: 0,
};

/// Summary of a subdivision, filled in by `katachi_subdivision_info` (stored counts: the
/// call costs nothing). Counts describe the result as the copy calls give it: with
/// `split_faces_with_holes`, the cut faces.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KatachiSubdivisionInfo {
    /// Set by the caller to `sizeof(KatachiSubdivisionInfo)`.
    pub struct_size: u32,
    /// Levels refined.
    pub levels: u32,
    /// Vertices of the result (`katachi_subdivision_refine_vertex_data` writes this many values).
    pub vertex_count: u32,
    /// Faces of the result.
    pub face_count: u32,
    /// Loops of the result: one per face, plus the holes of faces with holes (equal to
    /// `face_count` when there are none).
    pub loop_count: u32,
    /// Face corners of the result (`katachi_subdivision_refine_face_varying` writes this many).
    pub corner_count: u32,
    /// Edges of the result (`katachi_subdivision_copy_edges`).
    pub edge_count: u32,
    /// Edges with sharpness left after refinement.
    pub sharp_edge_count: u32,
    /// Vertices with sharpness left after refinement.
    pub sharp_vertex_count: u32,
    /// Vertices of the input (`katachi_subdivision_refine_vertex_data` reads this many values).
    pub input_vertex_count: u32,
    /// Faces of the input (`katachi_subdivision_carry_face_data` reads this many values).
    pub input_face_count: u32,
    /// Face corners of the input (face-varying indices expected).
    pub input_corner_count: u32,
    /// Faces with holes that method `[a]` could not bridge and that method `[b]` refined instead.
    pub fallback_face_count: u32,
}

const INFO_MIN_SIZE: usize = std::mem::size_of::<KatachiSubdivisionInfo>();

const INFO_DEFAULT: KatachiSubdivisionInfo = KatachiSubdivisionInfo {
    struct_size: std::mem::size_of::<KatachiSubdivisionInfo>() as u32,
    levels: 0,
    vertex_count: 0,
    face_count: 0,
    loop_count: 0,
    corner_count: 0,
    edge_count: 0,
    sharp_edge_count: 0,
    sharp_vertex_count: 0,
    input_vertex_count: 0,
    input_face_count: 0,
    input_corner_count: 0,
    fallback_face_count: 0,
};

/// The result of `katachi_subdivide`: the refined mesh, read out with the copy calls, and the
/// hierarchy through which the caller's vertex data and UVs follow. It keeps no copy of the
/// input. Opaque; free it with `katachi_subdivision_free`.
pub struct KatachiSubdivision {
    sub: Subdivision,
    /// The host's corner of each input corner, when the input mesh was made from a host's
    /// faces stored out of order (`katachi_mesh_create_polygons_f32`).
    host_corners: Option<Vec<u32>>,
    stencils: OnceLock<Stencils>,
}

/// A `KatachiSubdivideOptions` holding the defaults (1 level, method `[a]`, edge-only
/// boundaries, uniform creases) and its `struct_size`.
#[no_mangle]
pub extern "C" fn katachi_subdivide_options_default() -> KatachiSubdivideOptions {
    guard_value("katachi_subdivide_options_default", OPTIONS_DEFAULT, || {
        OPTIONS_DEFAULT
    })
}

/// A `KatachiSubdivisionInfo` with its `struct_size` set and counts 0.
#[no_mangle]
pub extern "C" fn katachi_subdivision_info_default() -> KatachiSubdivisionInfo {
    guard_value("katachi_subdivision_info_default", INFO_DEFAULT, || {
        INFO_DEFAULT
    })
}

fn options_from(o: &KatachiSubdivideOptions) -> FfiResult<SubdivideOptions> {
    if (o.struct_size as usize) < OPTIONS_MIN_SIZE {
        return Err(FfiError::invalid(format!(
            "options->struct_size is {}, but KatachiSubdivideOptions needs at least {OPTIONS_MIN_SIZE} \
             (start from katachi_subdivide_options_default())",
            o.struct_size
        )));
    }
    let bad = |field: &str, v: u32, allowed: &str| {
        FfiError::invalid(format!(
            "options->{field} is {v}, which is not one of {allowed}"
        ))
    };
    let mut s = SubdivideOptions::with_levels(o.levels);
    s.holes = match o.holes {
        0 => HoleMethod::Smooth,
        1 => HoleMethod::Sharp,
        v => {
            return Err(bad(
                "holes",
                v,
                "KATACHI_HOLE_METHOD_SMOOTH (0), KATACHI_HOLE_METHOD_SHARP (1)",
            ))
        }
    };
    s.boundary = match o.boundary {
        0 => BoundaryInterpolation::EdgeOnly,
        1 => BoundaryInterpolation::EdgeAndCorner,
        v => {
            return Err(bad(
                "boundary",
                v,
                "KATACHI_BOUNDARY_EDGE_ONLY (0), KATACHI_BOUNDARY_EDGE_AND_CORNER (1)",
            ))
        }
    };
    s.crease_method = match o.crease_method {
        0 => CreaseMethod::Uniform,
        1 => CreaseMethod::Chaikin,
        v => {
            return Err(bad(
                "crease_method",
                v,
                "KATACHI_CREASE_METHOD_UNIFORM (0), KATACHI_CREASE_METHOD_CHAIKIN (1)",
            ))
        }
    };
    s.recover_faces_with_holes = match o.recover_faces_with_holes {
        0 => false,
        1 => true,
        v => return Err(bad("recover_faces_with_holes", v, "0, 1")),
    };
    s.merge = MergeOptions::with_angle_tolerance(o.coplanar_angle_tolerance);
    s.feature_angle = (o.feature_angle_degrees != 0.0).then_some(o.feature_angle_degrees);
    s.split_faces_with_holes = match o.split_faces_with_holes {
        0 => false,
        1 => true,
        v => return Err(bad("split_faces_with_holes", v, "0, 1")),
    };
    Ok(s)
}

/// Subdivides `mesh` (never changed) and returns the result handle in `*out`.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh`, `options` or `out`
/// NULL); `KATACHI_STATUS_INVALID_ARGUMENT` (a bad option: `struct_size`, an enumerated value,
/// `levels` outside 1..8); `KATACHI_STATUS_BAD_INPUT` (an empty mesh). On failure `*out` is NULL.
///
/// # Safety
/// `mesh` NULL or a live handle; `options` NULL or a readable `KatachiSubdivideOptions`;
/// `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivide(
    mesh: *const KatachiMesh,
    options: *const KatachiSubdivideOptions,
    out: *mut *mut KatachiSubdivision,
) -> KatachiStatus {
    guard("katachi_subdivide", || {
        // SAFETY: the caller's promises, passed on unchanged.
        unsafe { subdivide(mesh, options, &mut |_, _| {}, out) }
    })
}

/// Called by `katachi_subdivide_with_progress` on the calling thread after each level:
/// `done` levels of `total` are refined. `user` is the pointer given with the callback.
pub type KatachiProgressFn = Option<unsafe extern "C" fn(done: u32, total: u32, user: *mut c_void)>;

/// `katachi_subdivide`, calling `progress(done, total, user)` on the calling thread after
/// each level (for a progress bar; the work cannot be cancelled). `progress` may be NULL.
///
/// # Safety
/// As `katachi_subdivide`; `progress` NULL or a function safe to call with `user`.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivide_with_progress(
    mesh: *const KatachiMesh,
    options: *const KatachiSubdivideOptions,
    progress: KatachiProgressFn,
    user: *mut c_void,
    out: *mut *mut KatachiSubdivision,
) -> KatachiStatus {
    guard("katachi_subdivide_with_progress", || {
        let mut report = |done: u32, total: u32| {
            if let Some(f) = progress {
                // SAFETY: the caller's promise about `progress` and `user`.
                unsafe { f(done, total, user) }
            }
        };
        // SAFETY: the caller's promises, passed on unchanged.
        unsafe { subdivide(mesh, options, &mut report, out) }
    })
}

/// The body of both subdivide calls.
///
/// # Safety
/// As `katachi_subdivide`.
unsafe fn subdivide(
    mesh: *const KatachiMesh,
    options: *const KatachiSubdivideOptions,
    progress: &mut dyn FnMut(u32, u32),
    out: *mut *mut KatachiSubdivision,
) -> FfiResult {
    // SAFETY: the caller's promises above.
    let out = unsafe { super::boundary::deref_mut(out, "out") }?;
    *out = std::ptr::null_mut();
    let handle = unsafe { deref(mesh, "mesh") }?;
    let options = options_from(unsafe { deref(options, "options") }?)?;
    let result = KatachiSubdivision {
        sub: Subdivision::new(&handle.mesh, &options, progress)?,
        host_corners: handle.host_corners.clone(),
        stencils: OnceLock::new(),
    };
    *out = Box::into_raw(Box::new(result));
    Ok(())
}

/// Frees a result of `katachi_subdivide`. NULL is allowed and does nothing.
///
/// # Safety
/// `subdivision` NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_free(subdivision: *mut KatachiSubdivision) {
    guard_value("katachi_subdivision_free", (), || {
        if !subdivision.is_null() {
            // SAFETY: a live handle from katachi_subdivide (the caller's promise).
            drop(unsafe { Box::from_raw(subdivision) });
        }
    })
}

/// # Safety
/// A non-NULL `p` must be a live handle.
unsafe fn sub_ref<'a>(p: *const KatachiSubdivision) -> FfiResult<&'a KatachiSubdivision> {
    // SAFETY: forwarded to the caller.
    unsafe { deref(p, "subdivision") }
}

/// Fills `*info` with the result's counts. The caller sets `info->struct_size` first.
///
/// # Safety
/// `subdivision` NULL or a live handle; `info` NULL or writable for `info->struct_size` bytes.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_info(
    subdivision: *const KatachiSubdivision,
    info: *mut KatachiSubdivisionInfo,
) -> KatachiStatus {
    guard("katachi_subdivision_info", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        super::boundary::check_ptr(info, "info")?;
        let r = s.refiner();
        let value = KatachiSubdivisionInfo {
            struct_size: 0,
            levels: r.levels(),
            vertex_count: s.vertex_count(),
            face_count: s.face_count(),
            loop_count: s.loop_count(),
            corner_count: s.corner_count(),
            edge_count: s.edge_count(),
            sharp_edge_count: s.sharp_edge_count(),
            sharp_vertex_count: s.sharp_vertex_count(),
            input_vertex_count: r.input_vertex_count(),
            input_face_count: r.input_face_count(),
            input_corner_count: r.input_corner_count(),
            fallback_face_count: s.report().fell_back_to_sharp.len() as u32,
        };
        unsafe { write_sized(info, value, INFO_MIN_SIZE, "info", "KatachiSubdivisionInfo") }
    })
}

/// A new mesh handle holding a copy of the refined mesh (with its remaining creases); the
/// caller frees it with `katachi_mesh_free`. On failure `*out` is NULL. To copy the result's
/// arrays, the copy calls on the subdivision need no mesh in between.
///
/// # Safety
/// `subdivision` NULL or a live handle; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_mesh(
    subdivision: *const KatachiSubdivision,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_subdivision_mesh", || {
        // SAFETY: the caller's promises above.
        let out = unsafe { super::mesh::reset_out(out) }?;
        let s = unsafe { sub_ref(subdivision) }?;
        *out = KatachiMesh::into_raw(s.sub.mesh());
        Ok(())
    })
}

/// Copies, for each face of the result, the input face it comes from (materials and face data
/// follow it): `face_count` values (see `katachi_subdivision_info`).
///
/// # Safety
/// `subdivision` NULL or a live handle; `faces` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_face_origin(
    subdivision: *const KatachiSubdivision,
    faces: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_face_origin", || {
        // SAFETY: the caller's promises above.
        let s = unsafe { sub_ref(subdivision) }?;
        let origin = s.sub.face_origin();
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

/// Copies the faces with holes that method `[a]` could not bridge (refined with method `[b]`
/// instead): `fallback_face_count` input face ids.
///
/// # Safety
/// `subdivision` NULL or a live handle; `faces` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_fallback_faces(
    subdivision: *const KatachiSubdivision,
    faces: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_fallback_faces", || {
        // SAFETY: the caller's promises above.
        let s = unsafe { sub_ref(subdivision) }?;
        let fb = &s.sub.report().fell_back_to_sharp;
        let buf =
            unsafe { out_buffer(faces, capacity, fb.len(), "faces", &"one per fallback face") }?;
        for (o, (f, _)) in buf.iter_mut().zip(fb) {
            *o = f.0;
        }
        Ok(())
    })
}

/// The `KatachiFaceVarying` named by `mode`.
fn face_varying_mode(mode: u32) -> FfiResult<FaceVarying> {
    Ok(match mode {
        0 => FaceVarying::Smooth,
        1 => FaceVarying::LinearCornersOnly,
        2 => FaceVarying::LinearBoundaries,
        3 => FaceVarying::LinearAll,
        v => {
            return Err(FfiError::invalid(format!(
                "mode is {v}, which is not a KatachiFaceVarying (0 to 3)"
            )))
        }
    })
}

/// Indexed face-varying values of `k` components, all components in one refinement (up to
/// 4; more go one at a time), as `k` values per result corner.
fn refine_face_varying_flat(
    s: &Subdivision,
    values: &[f64],
    k: usize,
    indices: &[u32],
    mode: FaceVarying,
) -> FfiResult<Vec<f64>> {
    fn run<const N: usize>(
        s: &Subdivision,
        values: &[f64],
        indices: &[u32],
        mode: FaceVarying,
    ) -> FfiResult<Vec<f64>> {
        let v: Vec<[f64; N]> = values
            .chunks_exact(N)
            .map(|c| c.try_into().expect("N values"))
            .collect();
        Ok(s.refine_face_varying(&v, indices, mode)?
            .into_iter()
            .flatten()
            .collect())
    }
    match k {
        1 => run::<1>(s, values, indices, mode),
        2 => run::<2>(s, values, indices, mode),
        3 => run::<3>(s, values, indices, mode),
        4 => run::<4>(s, values, indices, mode),
        _ => {
            let mut out = vec![0.0; s.corner_count() as usize * k];
            for c in 0..k {
                let column: Vec<f64> = values.iter().skip(c).step_by(k).copied().collect();
                for (i, v) in s
                    .refine_face_varying(&column, indices, mode)?
                    .into_iter()
                    .enumerate()
                {
                    out[i * k + c] = v;
                }
            }
            Ok(out)
        }
    }
}

/// Writes `values` into an optional caller's buffer: NULL skips it.
///
/// # Safety
/// A non-NULL `p` must point to `capacity` writable `T`s.
unsafe fn copy_optional<T: Copy>(
    p: *mut T,
    capacity: usize,
    values: impl ExactSizeIterator<Item = T>,
    param: &str,
    what: &dyn std::fmt::Display,
) -> FfiResult {
    if p.is_null() {
        return Ok(());
    }
    // SAFETY: forwarded to the caller.
    let buf = unsafe { out_buffer(p, capacity, values.len(), param, what) }?;
    for (d, v) in buf.iter_mut().zip(values) {
        *d = v;
    }
    Ok(())
}

/// Computes the stencil matrix (kept in the subdivision; the first call costs as much as
/// refining `input_vertex_count` sparse rows) and writes its number of entries to `*count`
/// (the size `katachi_subdivision_copy_stencils` needs for `sources` and `weights`).
///
/// # Safety
/// `subdivision` NULL or a live handle; `count` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_stencil_entry_count(
    subdivision: *const KatachiSubdivision,
    count: *mut u32,
) -> KatachiStatus {
    guard("katachi_subdivision_stencil_entry_count", || {
        // SAFETY: the caller's promises above.
        let s = unsafe { sub_ref(subdivision) }?;
        let out = unsafe { super::boundary::deref_mut(count, "count") }?;
        let n = s
            .stencils
            .get_or_init(|| s.sub.refiner().stencils())
            .weights
            .len();
        *out = u32::try_from(n).map_err(|_| {
            FfiError::invalid(format!(
                "the stencil matrix has {n} entries, more than 2^32 - 1"
            ))
        })?;
        Ok(())
    })
}

/// Copies the result's positions: 3 × `vertex_count` doubles, `x0 y0 z0 x1 …`.
///
/// # Safety
/// `subdivision` NULL or a live handle; `positions` NULL or writable for `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_positions(
    subdivision: *const KatachiSubdivision,
    positions: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_positions", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let p = s.positions();
        let buf = unsafe {
            out_buffer(
                positions,
                capacity,
                3 * p.len(),
                "positions",
                &"3 per vertex",
            )
        }?;
        s.write_positions(buf, |x| x);
        Ok(())
    })
}

/// Copies the result's positions as floats (a host's own precision, such as Blender's):
/// 3 × `vertex_count` values, each the nearest float to katachi's double.
///
/// # Safety
/// `subdivision` NULL or a live handle; `positions` NULL or writable for `capacity` floats.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_positions_f32(
    subdivision: *const KatachiSubdivision,
    positions: *mut f32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_positions_f32", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let p = s.positions();
        let buf = unsafe {
            out_buffer(
                positions,
                capacity,
                3 * p.len(),
                "positions",
                &"3 per vertex",
            )
        }?;
        s.write_positions(buf, |x| x as f32);
        Ok(())
    })
}

/// Copies the result's faces in the form `katachi_mesh_copy_faces` gives (loop sizes, loops
/// per face, corners), with the counts of `katachi_subdivision_info` (`loop_count`,
/// `face_count`, `corner_count`). A buffer whose count is 0 may be NULL.
///
/// # Safety
/// `subdivision` NULL or a live handle; each buffer NULL or writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_faces(
    subdivision: *const KatachiSubdivision,
    loop_sizes: *mut u32,
    loop_sizes_capacity: usize,
    face_loop_counts: *mut u32,
    face_loop_counts_capacity: usize,
    corners: *mut u32,
    corners_capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_faces", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let (lo, fl, c) = (s.loop_offsets(), s.face_loop_offsets(), s.corners());
        let a = unsafe {
            out_buffer(
                loop_sizes,
                loop_sizes_capacity,
                lo.len() - 1,
                "loop_sizes",
                &"one per loop",
            )
        }?;
        let b = unsafe {
            out_buffer(
                face_loop_counts,
                face_loop_counts_capacity,
                fl.len() - 1,
                "face_loop_counts",
                &"one per face",
            )
        }?;
        let d = unsafe {
            out_buffer(
                corners,
                corners_capacity,
                c.len(),
                "corners",
                &"one per corner",
            )
        }?;
        for (x, w) in a.iter_mut().zip(lo.windows(2)) {
            *x = w[1] - w[0];
        }
        for (x, w) in b.iter_mut().zip(fl.windows(2)) {
            *x = w[1] - w[0];
        }
        d.copy_from_slice(c);
        Ok(())
    })
}

/// Copies the result's faces as a host of simple polygons stores them (Blender): each
/// face's first corner (`face_starts`, `face_count` values), its number of corners
/// (`face_sizes`, `face_count` values) and the vertex of every corner (`corner_vertices`,
/// `corner_count` values). A NULL buffer is skipped. The result must have no faces with
/// holes (subdivide with `split_faces_with_holes`).
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER`;
/// `KATACHI_STATUS_BUFFER_TOO_SMALL`; `KATACHI_STATUS_INVALID_ARGUMENT` (the result has faces
/// with holes). On failure nothing is written.
///
/// # Safety
/// `subdivision` NULL or a live handle; each buffer NULL or writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_polygons(
    subdivision: *const KatachiSubdivision,
    face_starts: *mut u32,
    face_starts_capacity: usize,
    face_sizes: *mut u32,
    face_sizes_capacity: usize,
    corner_vertices: *mut u32,
    corner_vertices_capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_polygons", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        if s.has_faces_with_holes() {
            return Err(FfiError::invalid(format!(
                "the result has {} faces with holes, which are no simple polygons; subdivide \
                 with split_faces_with_holes = 1, or copy them with katachi_subdivision_copy_faces",
                s.loop_count() - s.face_count()
            )));
        }
        let lo = s.loop_offsets();
        let nf = lo.len() - 1;
        let check = |p: *mut u32, cap: usize, need: usize, name: &str| -> FfiResult {
            if !p.is_null() && cap < need {
                return Err(FfiError::new(
                    KatachiStatus::BufferTooSmall,
                    format!("{name} has room for {cap} values, but {need} are needed"),
                ));
            }
            Ok(())
        };
        check(face_starts, face_starts_capacity, nf, "face_starts")?;
        check(face_sizes, face_sizes_capacity, nf, "face_sizes")?;
        check(
            corner_vertices,
            corner_vertices_capacity,
            s.corners().len(),
            "corner_vertices",
        )?;
        let per_face = &"one per face";
        unsafe {
            copy_optional(
                face_starts,
                face_starts_capacity,
                lo[..nf].iter().copied(),
                "face_starts",
                per_face,
            )?;
            copy_optional(
                face_sizes,
                face_sizes_capacity,
                lo.windows(2).map(|w| w[1] - w[0]),
                "face_sizes",
                per_face,
            )?;
            copy_optional(
                corner_vertices,
                corner_vertices_capacity,
                s.corners().iter().copied(),
                "corner_vertices",
                &"one per corner",
            )?;
        }
        Ok(())
    })
}

/// Copies the result's edges (computed on the first call, then kept): `edges` gets their
/// two vertices (2 × `edge_count` values), `corner_edges` the edge of each corner (the edge
/// from it to the next corner of its loop; `corner_count` values). A NULL buffer is skipped.
///
/// # Safety
/// `subdivision` NULL or a live handle; each buffer NULL or writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_edges(
    subdivision: *const KatachiSubdivision,
    edges: *mut u32,
    edges_capacity: usize,
    corner_edges: *mut u32,
    corner_edges_capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_edges", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let (ne, nc) = (s.edge_count() as usize, s.corner_count() as usize);
        let verts = if edges.is_null() {
            None
        } else {
            let b = unsafe { out_buffer(edges, edges_capacity, 2 * ne, "edges", &"2 per edge") }?;
            Some(b.as_chunks_mut::<2>().0)
        };
        let corners = if corner_edges.is_null() {
            None
        } else {
            Some(unsafe {
                out_buffer(
                    corner_edges,
                    corner_edges_capacity,
                    nc,
                    "corner_edges",
                    &"one per corner",
                )
            }?)
        };
        s.write_edges(verts, corners);
        Ok(())
    })
}

/// Copies the sharpness left on each edge (`edge_count` floats, in `katachi_subdivision_copy_edges`'
/// order) in `scale` (a `KatachiSharpnessScale`; Blender's creases with
/// `KATACHI_SHARPNESS_SCALE_CREASE`): the user's creases not yet spent, 0 elsewhere.
///
/// # Safety
/// `subdivision` NULL or a live handle; `values` NULL or writable for `capacity` floats.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_edge_sharpness_f32(
    subdivision: *const KatachiSubdivision,
    values: *mut f32,
    capacity: usize,
    scale: u32,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_edge_sharpness_f32", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let scale = sharpness_scale(scale)?;
        let e = s.edges();
        let buf = unsafe {
            out_buffer(
                values,
                capacity,
                e.sharpness.len(),
                "values",
                &"one per edge",
            )
        }?;
        for (d, &x) in buf.iter_mut().zip(&e.sharpness) {
            *d = scale.of_sharpness(x);
        }
        Ok(())
    })
}

/// Copies the sharpness left on each vertex (`vertex_count` floats) in `scale` (a
/// `KatachiSharpnessScale`): the user's corner sharpness not yet spent, 0 elsewhere.
///
/// # Safety
/// `subdivision` NULL or a live handle; `values` NULL or writable for `capacity` floats.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_vertex_sharpness_f32(
    subdivision: *const KatachiSubdivision,
    values: *mut f32,
    capacity: usize,
    scale: u32,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_vertex_sharpness_f32", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let scale = sharpness_scale(scale)?;
        let v = s.vertex_sharpness();
        let buf = unsafe { out_buffer(values, capacity, v.len(), "values", &"one per vertex") }?;
        for (d, &x) in buf.iter_mut().zip(&v) {
            *d = scale.of_sharpness(x);
        }
        Ok(())
    })
}

/// Carries per-face data of the input to the result's faces: `values` holds `value_count`
/// values of `value_size` bytes (1, 2, 4 or 8; one per input face: materials, smooth flags,
/// selections), and each result face gets its input face's value in `out` (`face_count`
/// values of `value_size` bytes). The bytes are copied as they are.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER`;
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`value_size` not 1, 2, 4 or 8, `value_count` not the
/// input's face count); `KATACHI_STATUS_BUFFER_TOO_SMALL` (`capacity`, in values).
///
/// # Safety
/// `subdivision` NULL or a live handle; `values` NULL or readable for `value_count` values
/// of `value_size` bytes; `out` NULL or writable for `capacity` such values.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_carry_face_data(
    subdivision: *const KatachiSubdivision,
    values: *const c_void,
    value_count: usize,
    value_size: u32,
    out: *mut c_void,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_carry_face_data", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let nin = s.refiner().input_face_count() as usize;
        if value_count != nin {
            return Err(FfiError::invalid(format!(
                "value_count is {value_count}, but the input has {nin} faces (one value per face)"
            )));
        }
        let origin = s.face_origin();
        /// # Safety
        /// As the caller's, for values of type `T`.
        unsafe fn carry<T: Copy>(
            origin: &[crate::mesh::FaceId],
            values: *const c_void,
            n: usize,
            out: *mut c_void,
            capacity: usize,
        ) -> FfiResult {
            // SAFETY: forwarded (the caller's promises, `T` of `value_size` bytes).
            let vals = unsafe { slice(values.cast::<T>(), n, "values", &"value_count > 0") }?;
            let buf = unsafe {
                out_buffer(
                    out.cast::<T>(),
                    capacity,
                    origin.len(),
                    "out",
                    &"one per result face",
                )
            }?;
            for (d, f) in buf.iter_mut().zip(origin) {
                *d = vals[f.idx()];
            }
            Ok(())
        }
        unsafe {
            match value_size {
                1 => carry::<u8>(origin, values, nin, out, capacity),
                2 => carry::<u16>(origin, values, nin, out, capacity),
                4 => carry::<u32>(origin, values, nin, out, capacity),
                8 => carry::<u64>(origin, values, nin, out, capacity),
                v => Err(FfiError::invalid(format!(
                    "value_size is {v}; it must be 1, 2, 4 or 8 bytes"
                ))),
            }
        }
    })
}

/// Interpolates per-corner data given as floats, as a host stores UV maps: `values` holds
/// `components` floats per input corner (`value_count` = input corners × `components`), in
/// the order of the corners of the mesh that was subdivided — for a mesh made by
/// `katachi_mesh_create_polygons_f32`, the host's own corner order. Corners at the same
/// vertex with the same values share them, so the data's seams are where values differ.
/// Writes `components` floats per result corner with the interpolation `mode` (a
/// `KatachiFaceVarying`).
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER`;
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`components` not 1 to 64, `value_count` not input
/// corners × components, a bad `mode`); `KATACHI_STATUS_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `subdivision` NULL or a live handle; `values` NULL or readable for `value_count` floats;
/// `out` NULL or writable for `capacity` floats.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_refine_corner_data_f32(
    subdivision: *const KatachiSubdivision,
    values: *const f32,
    value_count: usize,
    components: u32,
    mode: u32,
    out: *mut f32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_refine_corner_data_f32", || {
        // SAFETY: the caller's promises above.
        let h = unsafe { sub_ref(subdivision) }?;
        let s = &h.sub;
        let k = check_components(components)?;
        let mode = face_varying_mode(mode)?;
        let corners = s.refiner().input_corner_count() as usize;
        if value_count != corners * k {
            return Err(FfiError::invalid(format!(
                "value_count is {value_count}, but the input has {corners} corners × {k} \
                 components = {}",
                corners * k
            )));
        }
        let values = unsafe { slice(values, value_count, "values", &"value_count > 0") }?;
        let nout = s.corner_count() as usize * k;
        let buf =
            unsafe { out_buffer(out, capacity, nout, "out", &"result corners × components") }?;
        let ordered: Vec<f64> = match &h.host_corners {
            None => values.iter().map(|&x| f64::from(x)).collect(),
            Some(order) => order
                .iter()
                .flat_map(|&c| values[k * c as usize..k * c as usize + k].iter())
                .map(|&x| f64::from(x))
                .collect(),
        };
        s.refine_corner_data_into(&ordered, k, mode, buf, |x| x as f32)?;
        Ok(())
    })
}

fn check_components(components: u32) -> FfiResult<usize> {
    if components == 0 || components > 64 {
        return Err(FfiError::invalid(format!(
            "components is {components}; it must be 1 to 64"
        )));
    }
    Ok(components as usize)
}

/// Interpolates per-vertex data (colours, weights, any `components` doubles per vertex) with
/// the subdivision rules: reads `input_vertex_count × components` doubles (vertex after
/// vertex), writes `vertex_count × components`.
///
/// # Safety
/// `subdivision` NULL or a live handle; `values` NULL or readable for `value_count` doubles;
/// `out` NULL or writable for `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_refine_vertex_data(
    subdivision: *const KatachiSubdivision,
    values: *const f64,
    value_count: usize,
    components: u32,
    out: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_refine_vertex_data", || {
        // SAFETY: the caller's promises above.
        let s = &unsafe { sub_ref(subdivision) }?.sub;
        let k = check_components(components)?;
        let input_vertices = s.refiner().input_vertex_count();
        let nin = input_vertices as usize * k;
        if value_count != nin {
            return Err(FfiError::invalid(format!(
                "value_count is {value_count}, but the input has {input_vertices} vertices × {k} \
                 components = {nin}"
            )));
        }
        let values = unsafe { slice(values, value_count, "values", &"value_count > 0") }?;
        let nout = s.vertex_count() as usize * k;
        let buf =
            unsafe { out_buffer(out, capacity, nout, "out", &"result vertices × components") }?;
        for c in 0..k {
            let column: Vec<f64> = values.iter().skip(c).step_by(k).copied().collect();
            let refined = s.refiner().refine_vertex_data(&column)?;
            for (i, v) in refined.into_iter().enumerate() {
                buf[i * k + c] = v;
            }
        }
        Ok(())
    })
}

/// Interpolates face-varying data (UVs): `values` holds `value_count / components` values of
/// `components` doubles, `indices` one value index per input face corner (in the corner
/// order of `katachi_mesh_copy_faces`); writes `corner_count × components` doubles, one value
/// per result corner, with the interpolation `mode` (a `KatachiFaceVarying`).
///
/// # Safety
/// `subdivision` NULL or a live handle; `values`, `indices` NULL or readable for their counts;
/// `out` NULL or writable for `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_refine_face_varying(
    subdivision: *const KatachiSubdivision,
    values: *const f64,
    value_count: usize,
    components: u32,
    indices: *const u32,
    index_count: usize,
    mode: u32,
    out: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_refine_face_varying", || {
        // SAFETY: the caller's promises above.
        let s = unsafe { sub_ref(subdivision) }?;
        let k = check_components(components)?;
        if !value_count.is_multiple_of(k) {
            return Err(FfiError::invalid(format!(
                "value_count {value_count} is not a multiple of components ({k})"
            )));
        }
        let mode = face_varying_mode(mode)?;
        let values = unsafe { slice(values, value_count, "values", &"value_count > 0") }?;
        let indices = unsafe { slice(indices, index_count, "indices", &"index_count > 0") }?;
        let s = &s.sub;
        let nout = s.corner_count() as usize * k;
        let buf =
            unsafe { out_buffer(out, capacity, nout, "out", &"result corners × components") }?;
        let result = refine_face_varying_flat(s, values, k, indices, mode)?;
        buf.copy_from_slice(&result);
        Ok(())
    })
}

/// Copies the stencil matrix (result vertex i = Σ weights × input vertices) in compressed
/// rows: `offsets` gets `vertex_count + 1` values, `sources` and `weights` each the count
/// `katachi_subdivision_stencil_entry_count` gives.
///
/// # Safety
/// `subdivision` NULL or a live handle; each buffer NULL or writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_copy_stencils(
    subdivision: *const KatachiSubdivision,
    offsets: *mut u32,
    offsets_capacity: usize,
    sources: *mut u32,
    sources_capacity: usize,
    weights: *mut f64,
    weights_capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_copy_stencils", || {
        // SAFETY: the caller's promises above.
        let s = unsafe { sub_ref(subdivision) }?;
        let st = s.stencils.get_or_init(|| s.sub.refiner().stencils());
        let o = unsafe {
            out_buffer(
                offsets,
                offsets_capacity,
                st.offsets.len(),
                "offsets",
                &"result vertices + 1",
            )
        }?;
        let so = unsafe {
            out_buffer(
                sources,
                sources_capacity,
                st.sources.len(),
                "sources",
                &"stencil entries",
            )
        }?;
        let w = unsafe {
            out_buffer(
                weights,
                weights_capacity,
                st.weights.len(),
                "weights",
                &"stencil entries",
            )
        }?;
        o.copy_from_slice(&st.offsets);
        for (d, v) in so.iter_mut().zip(&st.sources) {
            *d = v.0;
        }
        w.copy_from_slice(&st.weights);
        Ok(())
    })
}

/// Copies the reason method `[a]` could not bridge fallback face number `index` (0 to
/// `fallback_face_count` − 1) as a NUL-terminated UTF-8 string into `buffer`
/// (`capacity` bytes, terminator included; `(NULL, 0)` asks the size, reported as
/// `KATACHI_STATUS_BUFFER_TOO_SMALL` with the size in the message).
///
/// # Safety
/// `subdivision` NULL or a live handle; `buffer` NULL or writable for `capacity` bytes.
#[no_mangle]
pub unsafe extern "C" fn katachi_subdivision_fallback_reason(
    subdivision: *const KatachiSubdivision,
    index: u32,
    buffer: *mut std::ffi::c_char,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_subdivision_fallback_reason", || {
        // SAFETY: the caller's promises above.
        let s = unsafe { sub_ref(subdivision) }?;
        let fb = &s.sub.report().fell_back_to_sharp;
        let (_, why) = fb.get(index as usize).ok_or_else(|| {
            FfiError::invalid(format!(
                "index {index} is out of range ({} fallback faces)",
                fb.len()
            ))
        })?;
        let bytes = why.as_bytes();
        let buf = unsafe {
            out_buffer(
                buffer,
                capacity,
                bytes.len() + 1,
                "buffer",
                &"bytes with the terminating NUL",
            )
        }?;
        for (d, &b) in buf.iter_mut().zip(bytes) {
            *d = b as std::ffi::c_char;
        }
        buf[bytes.len()] = 0;
        Ok(())
    })
}

/// Turns coplanar regions of `mesh` (a boolean's triangles or n-gon fans) into faces with
/// holes; `angle_tolerance` in radians, in [0, π/2) (1e-3 is the default of the subdivision
/// option). The new mesh goes to `*out` (free it with `katachi_mesh_free`); `mesh` is unchanged.
///
/// # Safety
/// `mesh` NULL or a live handle; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_merge_coplanar_regions(
    mesh: *const KatachiMesh,
    angle_tolerance: f64,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_merge_coplanar_regions", || {
        // SAFETY: the caller's promises above.
        let out = unsafe { super::mesh::reset_out(out) }?;
        let mesh = unsafe { mesh_ref(mesh) }?;
        let merged =
            merge_coplanar_regions(mesh, &MergeOptions::with_angle_tolerance(angle_tolerance))?;
        *out = KatachiMesh::into_raw(merged.mesh);
        Ok(())
    })
}

/// A copy of `mesh` whose edges with a dihedral angle above `angle_degrees` (in (0, 180))
/// are infinitely sharp, in `*out` (free it with `katachi_mesh_free`).
///
/// # Safety
/// `mesh` NULL or a live handle; `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_tag_feature_edges(
    mesh: *const KatachiMesh,
    angle_degrees: f64,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_tag_feature_edges", || {
        // SAFETY: the caller's promises above.
        let out = unsafe { super::mesh::reset_out(out) }?;
        let mesh = unsafe { mesh_ref(mesh) }?;
        *out = KatachiMesh::into_raw(tag_feature_edges(mesh, angle_degrees)?);
        Ok(())
    })
}
