//! `katachi_curved_mesh`: curved anisotropic meshing of trimmed Bézier patches (seed 000)
//! through the C ABI. The caller builds the input with arrays (patches, curves, regions of
//! curve uses, a metric) on a `KatachiCurvedInput` handle, meshes it, and reads nodes,
//! elements, per-element data and the quality report from the `KatachiCurvedMesh` handle, or
//! writes MSH / VTK / OBJ. Conversion and error mapping only; the work is [`crate::curved`]'s.

use std::ffi::c_char;

use glam::{DVec2, DVec3};

use super::boundary::{
    c_str, check_ptr, deref, deref_mut, guard, guard_value, out_buffer, slice, write_sized,
    FfiError, FfiResult,
};
use super::status::KatachiStatus;
use crate::curved::{
    mesh, BezierCurve, BezierPatch, CurveUse, CurvedMesh, CurvedOptions, ElementKind, Grid2, Grid3,
    Metric2, Metric3, MetricField, PatchId, Region, SizeField, Space, TrimLoop, TrimmedPatches,
};
use crate::error::Error;

/// The input of `katachi_curved_mesh` under construction: patches, curves, regions and the
/// metric. Opaque; make it with `katachi_curved_input_new`, free it with
/// `katachi_curved_input_free`.
pub struct KatachiCurvedInput {
    input: TrimmedPatches,
}

/// The result of `katachi_curved_mesh`. Opaque; free it with `katachi_curved_mesh_free`.
pub struct KatachiCurvedMesh {
    mesh: CurvedMesh,
}

/// Where node coordinates live (`katachi_curved_mesh_copy_nodes`, `katachi_curved_mesh_write`).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiCurvedSpace {
    /// On the surface: `P(u, v)` of every node (3 values per node).
    Surface = 0,
    /// In the patch's parameter square: `(u, v, 0)` (3 values per node), where curved edges
    /// are the input curves exactly when the order is at least their degree.
    Parameter = 1,
}

/// Options of `katachi_curved_mesh`. Start from `katachi_curved_options_default()`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KatachiCurvedOptions {
    /// Set by the caller to `sizeof(KatachiCurvedOptions)`.
    pub struct_size: u32,
    /// Order of the elements, 1 to 10. Default 2.
    pub order: u32,
    /// Most bisections of one input curve, 1 to 52. Default 50.
    pub max_split_depth: u32,
    /// Lattice density of the points where angles are measured inside an element, 1 to 64.
    /// Default 4.
    pub angle_samples: u32,
    /// 1: measure every element over the lattice and in R³ as well; 0: only the
    /// vertex-metric angles (what the bound is on). Default 1.
    pub sampled_quality: u32,
    /// Guard offset μ (seed 000 §2.2), in (0, 1). Default 1e-2.
    pub mu: f64,
    /// A guarded curve piece is split while its control vectors spread over more than this
    /// many degrees, in (0, 180). Default 179.
    pub max_cone_degrees: f64,
    /// Refinement bound B on circumradius over shortest edge in the metric, ≥ √2: B = 2
    /// guarantees angles ≥ 14.48°. Default 2.
    pub radius_edge_bound: f64,
    /// Largest circumradius in metric units (> 0). Default 1/√3 (unit edges).
    pub size_bound: f64,
    /// Input corners below this angle in the metric are protected and their triangles
    /// exempt from the bound, in [0, 180). Default 60.
    pub small_angle_degrees: f64,
    /// Largest anisotropy a metric may ask for (≥ 1). Default 1000.
    pub max_anisotropy: f64,
    /// Smallest and largest edge length, in parameter units, a metric may ask for
    /// (0 < min < max). Defaults 1e-7 and 1.
    pub min_uv_size: f64,
    pub max_uv_size: f64,
    /// Most vertices; 0 means `10 × boundary vertices + 10⁶`. Exceeding it is
    /// `KATACHI_STATUS_BAD_INPUT` naming the budget. Default 0.
    pub max_sites: u64,
    /// Most refinement steps; 0 means `8 × max_sites`. Default 0.
    pub max_steps: u64,
    /// Most curve pieces after guarding (≥ 1). Default 1,000,000.
    pub max_curve_pieces: u64,
}

const OPTIONS_MIN_SIZE: usize = std::mem::size_of::<KatachiCurvedOptions>();

const OPTIONS_DEFAULT: KatachiCurvedOptions = KatachiCurvedOptions {
    struct_size: std::mem::size_of::<KatachiCurvedOptions>() as u32,
    order: 2,
    max_split_depth: 50,
    angle_samples: 4,
    sampled_quality: 1,
    mu: 1e-2,
    max_cone_degrees: 179.0,
    radius_edge_bound: 2.0,
    // 1/√3 (`CurvedOptions::default`; a unit test checks the two agree).
    size_bound: 0.577_350_269_189_625_8,
    small_angle_degrees: 60.0,
    max_anisotropy: 1e3,
    min_uv_size: 1e-7,
    max_uv_size: 1.0,
    max_sites: 0,
    max_steps: 0,
    max_curve_pieces: 1_000_000,
};

/// The kernel's option name as the caller's `KatachiCurvedOptions` field.
fn c_field(option: &str) -> &str {
    match option {
        "max_cone_deg" => "max_cone_degrees",
        "small_angle_deg" => "small_angle_degrees",
        other => other,
    }
}

#[allow(clippy::field_reassign_with_default)]
fn options_from(o: &KatachiCurvedOptions) -> FfiResult<CurvedOptions> {
    if (o.struct_size as usize) < OPTIONS_MIN_SIZE {
        return Err(FfiError::invalid(format!(
            "options->struct_size is {}, but KatachiCurvedOptions needs at least \
             {OPTIONS_MIN_SIZE} (start from katachi_curved_options_default())",
            o.struct_size
        )));
    }
    let sampled_quality = match o.sampled_quality {
        0 => false,
        1 => true,
        v => {
            return Err(FfiError::invalid(format!(
                "options->sampled_quality is {v}, which is not one of 0, 1"
            )))
        }
    };
    // Field by field: `CurvedOptions` is `#[non_exhaustive]` outside the crate.
    let mut c = CurvedOptions::default();
    c.order = o.order;
    c.max_split_depth = o.max_split_depth;
    c.angle_samples = o.angle_samples;
    c.sampled_quality = sampled_quality;
    c.mu = o.mu;
    c.max_cone_deg = o.max_cone_degrees;
    c.radius_edge_bound = o.radius_edge_bound;
    c.size_bound = o.size_bound;
    c.small_angle_deg = o.small_angle_degrees;
    c.max_anisotropy = o.max_anisotropy;
    c.min_uv_size = o.min_uv_size;
    c.max_uv_size = o.max_uv_size;
    c.max_sites = (o.max_sites != 0).then_some(o.max_sites);
    c.max_steps = (o.max_steps != 0).then_some(o.max_steps);
    c.max_curve_pieces = o.max_curve_pieces;
    c.validate().map_err(|e| match e {
        Error::InvalidOption { option, message } => {
            FfiError::invalid(format!("options->{}: {message}", c_field(option)))
        }
        other => FfiError::from(other),
    })?;
    Ok(c)
}

/// A `KatachiCurvedOptions` holding the defaults (order 2, the paper's μ = 1e-2 and B = 2,
/// unit edges in the metric) and its `struct_size`.
#[no_mangle]
pub extern "C" fn katachi_curved_options_default() -> KatachiCurvedOptions {
    guard_value("katachi_curved_options_default", OPTIONS_DEFAULT, || {
        OPTIONS_DEFAULT
    })
}

/// A new, empty input (no patches, curves or regions; metric: isotropic size 1). Free it
/// with `katachi_curved_input_free`. On failure `*out` is NULL.
///
/// # Safety
/// `out` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_new(
    out: *mut *mut KatachiCurvedInput,
) -> KatachiStatus {
    guard("katachi_curved_input_new", || {
        // SAFETY: the caller's promise above.
        let out = unsafe { deref_mut(out, "out") }?;
        *out = Box::into_raw(Box::new(KatachiCurvedInput {
            input: TrimmedPatches {
                patches: Vec::new(),
                curves: Vec::new(),
                regions: Vec::new(),
                metric: MetricField::isotropic(1.0),
            },
        }));
        Ok(())
    })
}

/// Frees an input. NULL is allowed and does nothing.
///
/// # Safety
/// `input` NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_free(input: *mut KatachiCurvedInput) {
    guard_value("katachi_curved_input_free", (), || {
        if !input.is_null() {
            // SAFETY: a live handle from katachi_curved_input_new (the caller's promise).
            drop(unsafe { Box::from_raw(input) });
        }
    })
}

/// # Safety
/// A non-NULL `p` must be a live handle that nothing else uses meanwhile.
unsafe fn input_mut<'a>(p: *mut KatachiCurvedInput) -> FfiResult<&'a mut TrimmedPatches> {
    // SAFETY: forwarded to the caller.
    Ok(&mut unsafe { deref_mut(p, "input") }?.input)
}

/// Writes `value` to `*out` when `out` is not NULL (ids are optional outputs).
///
/// # Safety
/// A non-NULL `out` must be writable.
unsafe fn put_id(out: *mut u32, value: u32) -> FfiResult {
    if !out.is_null() {
        check_ptr(out, "out_id")?;
        // SAFETY: non-NULL, aligned; writable by the caller's promise.
        unsafe { out.write(value) };
    }
    Ok(())
}

fn next_id(len: usize, what: &str) -> FfiResult<u32> {
    u32::try_from(len).map_err(|_| FfiError::invalid(format!("too many {what}")))
}

/// Adds a tensor-product Bézier patch of bidegree (`degree_u`, `degree_v`) with
/// `(degree_u + 1)(degree_v + 1)` control points, `points` holding 3 doubles `x y z` each,
/// u-major (point `i·(degree_v + 1) + j` is `Q_ij`, `i` along u). Its id (0, 1, … in the
/// order added) goes to `*out_id` when `out_id` is not NULL. Degrees and points are checked
/// by `katachi_curved_mesh`, which names the patch.
///
/// Statuses: `KATACHI_STATUS_NULL_POINTER` (`input`, or `points` with `point_count` > 0);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`point_count` is not `(degree_u + 1)(degree_v + 1)`).
///
/// # Safety
/// `input` NULL or a live handle; `points` NULL or readable for 3 × `point_count` doubles;
/// `out_id` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_add_patch(
    input: *mut KatachiCurvedInput,
    degree_u: u32,
    degree_v: u32,
    points: *const f64,
    point_count: u32,
    out_id: *mut u32,
) -> KatachiStatus {
    guard("katachi_curved_input_add_patch", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        let expected = (degree_u as u64 + 1) * (degree_v as u64 + 1);
        if point_count as u64 != expected {
            return Err(FfiError::invalid(format!(
                "point_count is {point_count}, but a patch of bidegree ({degree_u}, {degree_v}) \
                 has {expected} control points"
            )));
        }
        let xyz = unsafe {
            slice(
                points,
                3 * point_count as usize,
                "points",
                &format_args!("point_count is {point_count}"),
            )
        }?;
        let id = next_id(inp.patches.len(), "patches")?;
        let pts = xyz
            .chunks_exact(3)
            .map(|p| DVec3::new(p[0], p[1], p[2]))
            .collect();
        inp.patches
            .push(BezierPatch::new(degree_u as usize, degree_v as usize, pts));
        unsafe { put_id(out_id, id) }
    })
}

/// Adds a Bézier curve in a patch's parameter square `[0, 1]²`: `point_count` (≥ 2) control
/// points, `points_uv` holding 2 doubles `u v` each. Its id goes to `*out_id` when `out_id`
/// is not NULL. A curve between two regions is added once and used by both, in opposite
/// directions.
///
/// Statuses: `KATACHI_STATUS_NULL_POINTER`; `KATACHI_STATUS_INVALID_ARGUMENT` (fewer than
/// two points).
///
/// # Safety
/// `input` NULL or a live handle; `points_uv` NULL or readable for 2 × `point_count`
/// doubles; `out_id` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_add_curve(
    input: *mut KatachiCurvedInput,
    points_uv: *const f64,
    point_count: u32,
    out_id: *mut u32,
) -> KatachiStatus {
    guard("katachi_curved_input_add_curve", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        if point_count < 2 {
            return Err(FfiError::invalid(format!(
                "point_count is {point_count}; a Bézier curve needs at least 2 control points"
            )));
        }
        let uv = unsafe {
            slice(
                points_uv,
                2 * point_count as usize,
                "points_uv",
                &format_args!("point_count is {point_count}"),
            )
        }?;
        let id = next_id(inp.curves.len(), "curves")?;
        inp.curves.push(BezierCurve::new(
            uv.chunks_exact(2).map(|p| DVec2::new(p[0], p[1])).collect(),
        ));
        unsafe { put_id(out_id, id) }
    })
}

/// Adds a region of patch `patch` bounded by `loop_count` loops of curve uses: loop `k`
/// has `loop_sizes[k]` uses, taken in order from `curves` (curve ids) and `reversed`
/// (1: the curve runs backwards in this loop; NULL: all forwards); `use_count` is their
/// total. The first loop is the outer boundary, counter-clockwise; holes follow, clockwise
/// (the region is on the left of every loop); consecutive curves share their end point
/// exactly. Its id goes to `*out_id` when `out_id` is not NULL. The geometry is checked by
/// `katachi_curved_mesh`, which names the region, loop and curve at fault.
///
/// Statuses: `KATACHI_STATUS_NULL_POINTER`; `KATACHI_STATUS_INVALID_ARGUMENT` (no loops,
/// loop sizes that do not add up to `use_count`, a `reversed` value other than 0 or 1).
///
/// # Safety
/// `input` NULL or a live handle; `loop_sizes` readable for `loop_count` values; `curves`
/// and a non-NULL `reversed` readable for `use_count` values; `out_id` NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_add_region(
    input: *mut KatachiCurvedInput,
    patch: u32,
    loop_sizes: *const u32,
    loop_count: u32,
    curves: *const u32,
    reversed: *const u8,
    use_count: u32,
    out_id: *mut u32,
) -> KatachiStatus {
    guard("katachi_curved_input_add_region", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        if loop_count == 0 {
            return Err(FfiError::invalid(
                "loop_count is 0; a region needs an outer loop",
            ));
        }
        let sizes = unsafe {
            slice(
                loop_sizes,
                loop_count as usize,
                "loop_sizes",
                &format_args!("loop_count is {loop_count}"),
            )
        }?;
        let total: u64 = sizes.iter().map(|&s| s as u64).sum();
        if total != use_count as u64 {
            return Err(FfiError::invalid(format!(
                "the loop sizes add up to {total}, but use_count is {use_count}"
            )));
        }
        let why = format_args!("use_count is {use_count}");
        let ids = unsafe { slice(curves, use_count as usize, "curves", &why) }?;
        let rev: Option<&[u8]> = if reversed.is_null() {
            None
        } else {
            Some(unsafe { slice(reversed, use_count as usize, "reversed", &why) }?)
        };
        if let Some((k, v)) = rev.into_iter().flatten().enumerate().find(|(_, &v)| v > 1) {
            return Err(FfiError::invalid(format!(
                "reversed[{k}] is {v}, which is not one of 0, 1"
            )));
        }
        let id = next_id(inp.regions.len(), "regions")?;
        let mut at = 0usize;
        let loops = sizes
            .iter()
            .map(|&n| {
                let uses = (at..at + n as usize)
                    .map(|k| {
                        let backwards = rev.is_some_and(|r| r[k] == 1);
                        if backwards {
                            CurveUse::backward(ids[k])
                        } else {
                            CurveUse::forward(ids[k])
                        }
                    })
                    .collect();
                at += n as usize;
                TrimLoop::new(uses)
            })
            .collect();
        inp.regions.push(Region {
            patch: PatchId(patch),
            loops,
        });
        unsafe { put_id(out_id, id) }
    })
}

/// The metric: size `size` everywhere on the surface (edges about `size` long).
/// Checked by `katachi_curved_mesh` (a size that is not positive and finite is
/// `KATACHI_STATUS_BAD_INPUT`).
///
/// # Safety
/// `input` NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_set_metric_isotropic(
    input: *mut KatachiCurvedInput,
    size: f64,
) -> KatachiStatus {
    guard("katachi_curved_input_set_metric_isotropic", || {
        // SAFETY: the caller's promise above.
        let inp = unsafe { input_mut(input) }?;
        inp.metric = MetricField::isotropic(size);
        Ok(())
    })
}

/// The metric: edges `size_along` long along `direction` (3 doubles, in R³) and
/// `size_across` across it.
///
/// # Safety
/// `input` NULL or a live handle; `direction` NULL or readable for 3 doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_set_metric_directional(
    input: *mut KatachiCurvedInput,
    direction: *const f64,
    size_along: f64,
    size_across: f64,
) -> KatachiStatus {
    guard("katachi_curved_input_set_metric_directional", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        let d = unsafe { slice(direction, 3, "direction", &"3 values are needed") }?;
        let d = DVec3::new(d[0], d[1], d[2]);
        if !(d.is_finite() && d.length_squared() > 0.0) {
            return Err(FfiError::new(
                KatachiStatus::BadInput,
                format!("direction ({}, {}, {}) has no direction", d.x, d.y, d.z),
            ));
        }
        inp.metric = MetricField::Constant(Metric3::from_direction(d, size_along, size_across));
        Ok(())
    })
}

fn metric3(t: &[f64]) -> Metric3 {
    Metric3::new(t[0], t[1], t[2], t[3], t[4], t[5])
}

/// The metric: one symmetric tensor everywhere in R³, `tensor` holding 6 doubles
/// `xx xy xz yy yz zz` (`I/h²` asks for edges of length h).
///
/// # Safety
/// `input` NULL or a live handle; `tensor` NULL or readable for 6 doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_set_metric_tensor(
    input: *mut KatachiCurvedInput,
    tensor: *const f64,
) -> KatachiStatus {
    guard("katachi_curved_input_set_metric_tensor", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        let t = unsafe { slice(tensor, 6, "tensor", &"6 values are needed") }?;
        inp.metric = MetricField::Constant(metric3(t));
        Ok(())
    })
}

/// Reads a 3D grid frame: `min`, `max` (3 doubles each), `counts` (3 values).
///
/// # Safety
/// As the caller of the exported functions promises.
unsafe fn grid3_frame(
    min: *const f64,
    max: *const f64,
    counts: *const u32,
) -> FfiResult<(DVec3, DVec3, [u32; 3], usize)> {
    // SAFETY (all blocks): forwarded to the caller.
    let lo = unsafe { slice(min, 3, "min", &"3 values are needed") }?;
    let hi = unsafe { slice(max, 3, "max", &"3 values are needed") }?;
    let n = unsafe { slice(counts, 3, "counts", &"3 values are needed") }?;
    let total = n
        .iter()
        .try_fold(1usize, |a, &c| a.checked_mul(c as usize))
        .ok_or_else(|| FfiError::invalid("counts: the grid has more samples than memory"))?;
    Ok((
        DVec3::new(lo[0], lo[1], lo[2]),
        DVec3::new(hi[0], hi[1], hi[2]),
        [n[0], n[1], n[2]],
        total,
    ))
}

/// The metric: edge sizes sampled on a regular grid in R³ over the box `min`–`max` (3
/// doubles each) with `counts` (3 values) samples per axis, `sizes` holding
/// `counts[0]·counts[1]·counts[2]` values, x fastest; interpolated trilinearly.
///
/// Statuses: `KATACHI_STATUS_INVALID_ARGUMENT` (`size_count` is not the product of `counts`).
///
/// # Safety
/// `input` NULL or a live handle; `min`, `max` readable for 3 doubles, `counts` for 3
/// values, `sizes` for `size_count` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_set_metric_size_grid(
    input: *mut KatachiCurvedInput,
    min: *const f64,
    max: *const f64,
    counts: *const u32,
    sizes: *const f64,
    size_count: usize,
) -> KatachiStatus {
    guard("katachi_curved_input_set_metric_size_grid", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        let (min, max, counts, total) = unsafe { grid3_frame(min, max, counts) }?;
        if size_count != total {
            return Err(FfiError::invalid(format!(
                "size_count is {size_count}, but the grid has {total} samples"
            )));
        }
        let why = format_args!("size_count is {size_count}");
        let values = unsafe { slice(sizes, size_count, "sizes", &why) }?.to_vec();
        inp.metric = MetricField::Isotropic(SizeField::Grid(Grid3 {
            min,
            max,
            counts,
            values,
        }));
        Ok(())
    })
}

/// The metric: tensors sampled on a regular grid in R³ (as
/// `katachi_curved_input_set_metric_size_grid`), `tensors` holding 6 doubles
/// `xx xy xz yy yz zz` per sample; interpolated entry by entry.
///
/// # Safety
/// As `katachi_curved_input_set_metric_size_grid`, with `tensors` readable for
/// 6 × `tensor_count` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_set_metric_tensor_grid(
    input: *mut KatachiCurvedInput,
    min: *const f64,
    max: *const f64,
    counts: *const u32,
    tensors: *const f64,
    tensor_count: usize,
) -> KatachiStatus {
    guard("katachi_curved_input_set_metric_tensor_grid", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        let (min, max, counts, total) = unsafe { grid3_frame(min, max, counts) }?;
        if tensor_count != total {
            return Err(FfiError::invalid(format!(
                "tensor_count is {tensor_count}, but the grid has {total} samples"
            )));
        }
        let n = tensor_count
            .checked_mul(6)
            .ok_or_else(|| FfiError::invalid("tensor_count is too large"))?;
        let why = format_args!("tensor_count is {tensor_count}");
        let t = unsafe { slice(tensors, n, "tensors", &why) }?;
        inp.metric = MetricField::Grid(Grid3 {
            min,
            max,
            counts,
            values: t.chunks_exact(6).map(metric3).collect(),
        });
        Ok(())
    })
}

/// The metric given in the parameter square (no pull-back): tensors `uu uv vv` (3 doubles
/// each) on a regular `counts[0] × counts[1]` grid over the box `min`–`max` (2 doubles
/// each), u fastest, interpolated bilinearly. One sample (`counts` 1, 1) is a constant.
///
/// # Safety
/// `input` NULL or a live handle; `min`, `max`, `counts` readable for 2 values; `tensors`
/// for 3 × `tensor_count` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_input_set_metric_uv_tensor_grid(
    input: *mut KatachiCurvedInput,
    min: *const f64,
    max: *const f64,
    counts: *const u32,
    tensors: *const f64,
    tensor_count: usize,
) -> KatachiStatus {
    guard("katachi_curved_input_set_metric_uv_tensor_grid", || {
        // SAFETY (all blocks): the caller's promises above.
        let inp = unsafe { input_mut(input) }?;
        let lo = unsafe { slice(min, 2, "min", &"2 values are needed") }?;
        let hi = unsafe { slice(max, 2, "max", &"2 values are needed") }?;
        let n = unsafe { slice(counts, 2, "counts", &"2 values are needed") }?;
        let total = (n[0] as usize)
            .checked_mul(n[1] as usize)
            .ok_or_else(|| FfiError::invalid("counts: the grid has more samples than memory"))?;
        if tensor_count != total {
            return Err(FfiError::invalid(format!(
                "tensor_count is {tensor_count}, but the grid has {total} samples"
            )));
        }
        let why = format_args!("tensor_count is {tensor_count}");
        let t = unsafe { slice(tensors, tensor_count.saturating_mul(3), "tensors", &why) }?;
        inp.metric = MetricField::ParameterGrid(Grid2 {
            min: DVec2::new(lo[0], lo[1]),
            max: DVec2::new(hi[0], hi[1]),
            counts: [n[0], n[1]],
            values: t
                .chunks_exact(3)
                .map(|m| Metric2::new(m[0], m[1], m[2]))
                .collect(),
        });
        Ok(())
    })
}

/// Meshes `input` (never changed; seed 000: the metric pulled back to each patch's parameter
/// square, trim curves guarded, anisotropic Voronoi refinement with a minimum angle in the
/// metric, curved elements whose edges are the trim curves) and returns the result handle in
/// `*out`. Regions that share a curve get bitwise identical nodes along it.
///
/// Statuses: `KATACHI_STATUS_NULL_POINTER`; `KATACHI_STATUS_INVALID_ARGUMENT` (a bad option);
/// `KATACHI_STATUS_BAD_INPUT` (the message names the curve, loop, region, patch or metric
/// sample at fault: a loop not closed, wrong orientation, curves that cross, a degenerate
/// patch, a metric that is not positive definite; or a budget that ran out). On failure
/// `*out` is NULL.
///
/// # Safety
/// `input` NULL or a live handle; `options` NULL or a readable `KatachiCurvedOptions`; `out`
/// NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_mesh(
    input: *const KatachiCurvedInput,
    options: *const KatachiCurvedOptions,
    out: *mut *mut KatachiCurvedMesh,
) -> KatachiStatus {
    guard("katachi_curved_mesh", || {
        // SAFETY (all blocks): the caller's promises above.
        let out = unsafe { deref_mut(out, "out") }?;
        *out = std::ptr::null_mut();
        let inp = &unsafe { deref(input, "input") }?.input;
        let options = options_from(unsafe { deref(options, "options") }?)?;
        let m = mesh(inp, &options)?;
        *out = Box::into_raw(Box::new(KatachiCurvedMesh { mesh: m }));
        Ok(())
    })
}

/// Frees a result of `katachi_curved_mesh`. NULL is allowed and does nothing.
///
/// # Safety
/// `mesh` NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_mesh_free(mesh: *mut KatachiCurvedMesh) {
    guard_value("katachi_curved_mesh_free", (), || {
        if !mesh.is_null() {
            // SAFETY: a live handle from katachi_curved_mesh (the caller's promise).
            drop(unsafe { Box::from_raw(mesh) });
        }
    })
}

/// # Safety
/// A non-NULL `p` must be a live handle.
unsafe fn mesh_ref<'a>(p: *const KatachiCurvedMesh) -> FfiResult<&'a CurvedMesh> {
    // SAFETY: forwarded to the caller.
    Ok(&unsafe { deref(p, "mesh") }?.mesh)
}

/// Counts and quality of a curved mesh, filled in by `katachi_curved_mesh_info`. Angles are
/// in degrees, measured in the metric (seed 000 §5.1).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KatachiCurvedInfo {
    /// Set by the caller to `sizeof(KatachiCurvedInfo)`.
    pub struct_size: u32,
    /// The element order.
    pub order: u32,
    /// Nodes per element, `(order + 1)(order + 2) / 2`.
    pub nodes_per_element: u32,
    /// Nodes (`katachi_curved_mesh_copy_nodes` writes 3 values per node).
    pub node_count: u32,
    /// Elements (`katachi_curved_mesh_copy_elements` writes `nodes_per_element` per element).
    pub element_count: u32,
    /// Elements with an edge on a trim curve.
    pub curved_element_count: u32,
    /// Straight elements at small input angles: no bound applies.
    pub exempt_element_count: u32,
    /// The bound the refinement guarantees on straight, non-exempt elements.
    pub guaranteed_angle_degrees: f64,
    /// Per straight, non-exempt element, its smallest angle in its vertices' metrics: the
    /// smallest, the median, and the share (0 to 1) below 14.48° and below 20°.
    pub min_angle_degrees: f64,
    pub median_min_angle_degrees: f64,
    pub share_below_14_48: f64,
    pub share_below_20: f64,
    /// Every corner angle of the straight elements: min, max, mean, median (the statistics
    /// of the seed's Tables 1 and 2).
    pub corner_angle_min_degrees: f64,
    pub corner_angle_max_degrees: f64,
    pub corner_angle_mean_degrees: f64,
    pub corner_angle_median_degrees: f64,
    /// The smallest scaled Jacobian (> 0: all elements valid), in parameter space and on the
    /// surface (along each element's corners' normal, as Gmsh checks).
    pub min_scaled_jacobian: f64,
    pub min_scaled_jacobian_surface: f64,
    /// Seconds spent meshing.
    pub seconds: f64,
}

const INFO_MIN_SIZE: usize = std::mem::size_of::<KatachiCurvedInfo>();

const INFO_DEFAULT: KatachiCurvedInfo = KatachiCurvedInfo {
    struct_size: std::mem::size_of::<KatachiCurvedInfo>() as u32,
    order: 0,
    nodes_per_element: 0,
    node_count: 0,
    element_count: 0,
    curved_element_count: 0,
    exempt_element_count: 0,
    guaranteed_angle_degrees: 0.0,
    min_angle_degrees: 0.0,
    median_min_angle_degrees: 0.0,
    share_below_14_48: 0.0,
    share_below_20: 0.0,
    corner_angle_min_degrees: 0.0,
    corner_angle_max_degrees: 0.0,
    corner_angle_mean_degrees: 0.0,
    corner_angle_median_degrees: 0.0,
    min_scaled_jacobian: 0.0,
    min_scaled_jacobian_surface: 0.0,
    seconds: 0.0,
};

/// A `KatachiCurvedInfo` with its `struct_size` set and everything else 0.
#[no_mangle]
pub extern "C" fn katachi_curved_info_default() -> KatachiCurvedInfo {
    guard_value("katachi_curved_info_default", INFO_DEFAULT, || INFO_DEFAULT)
}

/// Fills `*info` with the mesh's counts and quality. The caller sets `info->struct_size`.
///
/// # Safety
/// `mesh` NULL or a live handle; `info` NULL or writable for `info->struct_size` bytes.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_mesh_info(
    mesh: *const KatachiCurvedMesh,
    info: *mut KatachiCurvedInfo,
) -> KatachiStatus {
    guard("katachi_curved_mesh_info", || {
        // SAFETY: the caller's promises above.
        let m = unsafe { mesh_ref(mesh) }?;
        check_ptr(info, "info")?;
        let q = &m.quality;
        let s = &m.stats;
        let count = |f: &dyn Fn(&crate::curved::ElementInfo) -> bool| {
            m.info.iter().filter(|i| f(i)).count() as u32
        };
        let value = KatachiCurvedInfo {
            struct_size: 0,
            order: m.order,
            nodes_per_element: m.nodes_per_element() as u32,
            node_count: m.nodes_uv.len() as u32,
            element_count: m.element_count() as u32,
            curved_element_count: count(&|i| i.kind == ElementKind::Curved),
            exempt_element_count: count(&|i| i.exempt),
            guaranteed_angle_degrees: q.guaranteed_angle_deg,
            min_angle_degrees: q.straight_min_vertex.min,
            median_min_angle_degrees: q.straight_min_vertex.median,
            share_below_14_48: q.straight_min_vertex.below_14_48,
            share_below_20: q.straight_min_vertex.below_20,
            corner_angle_min_degrees: q.straight_angles.min,
            corner_angle_max_degrees: q.straight_angles.max,
            corner_angle_mean_degrees: q.straight_angles.mean,
            corner_angle_median_degrees: q.straight_angles.median,
            min_scaled_jacobian: q.min_scaled_jacobian,
            min_scaled_jacobian_surface: q.min_scaled_jacobian_surface,
            seconds: s.seconds_validate + s.seconds_guard + s.seconds_refine + s.seconds_output,
        };
        unsafe { write_sized(info, value, INFO_MIN_SIZE, "info", "KatachiCurvedInfo") }
    })
}

fn space_from(space: u32) -> FfiResult<Space> {
    match space {
        0 => Ok(Space::Surface),
        1 => Ok(Space::Parameter),
        v => Err(FfiError::invalid(format!(
            "space is {v}, which is not one of KATACHI_CURVED_SPACE_SURFACE (0), \
             KATACHI_CURVED_SPACE_PARAMETER (1)"
        ))),
    }
}

/// Copies the node coordinates, 3 doubles per node: `P(u, v)` for
/// `KATACHI_CURVED_SPACE_SURFACE`, `(u, v, 0)` for `KATACHI_CURVED_SPACE_PARAMETER`.
/// `(NULL, 0)` asks the size (`KATACHI_STATUS_BUFFER_TOO_SMALL` naming it).
///
/// # Safety
/// `mesh` NULL or a live handle; `coords` NULL or writable for `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_mesh_copy_nodes(
    mesh: *const KatachiCurvedMesh,
    space: u32,
    coords: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_curved_mesh_copy_nodes", || {
        // SAFETY: the caller's promises above.
        let m = unsafe { mesh_ref(mesh) }?;
        let space = space_from(space)?;
        let n = m.nodes_uv.len();
        let buf = unsafe { out_buffer(coords, capacity, 3 * n, "coords", &"3 per node") }?;
        for (k, o) in buf.chunks_exact_mut(3).enumerate() {
            let p = match space {
                Space::Surface => m.nodes_xyz[k],
                Space::Parameter => m.nodes_uv[k].extend(0.0),
            };
            o.copy_from_slice(&p.to_array());
        }
        Ok(())
    })
}

/// Copies the elements' node ids, `nodes_per_element` per element in Gmsh's order for
/// triangles of the mesh's order: the three corners (counter-clockwise in the parameter
/// square), then each edge's inner nodes (edges 0-1, 1-2, 2-0), then the inner nodes.
///
/// # Safety
/// `mesh` NULL or a live handle; `nodes` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_mesh_copy_elements(
    mesh: *const KatachiCurvedMesh,
    nodes: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_curved_mesh_copy_elements", || {
        // SAFETY: the caller's promises above.
        let m = unsafe { mesh_ref(mesh) }?;
        let buf = unsafe {
            out_buffer(
                nodes,
                capacity,
                m.elements.len(),
                "nodes",
                &"nodes_per_element per element",
            )
        }?;
        buf.copy_from_slice(&m.elements);
        Ok(())
    })
}

/// Copies one value per element: its region id, its kind (0 straight, 1 curved), and its
/// smallest angle in degrees in its vertices' metrics (the quantity the bound is on; the
/// MSH view "min metric angle (deg)"). Any of the three buffers may be NULL (with capacity 0)
/// to skip it.
///
/// # Safety
/// `mesh` NULL or a live handle; each non-NULL buffer writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_mesh_copy_element_data(
    mesh: *const KatachiCurvedMesh,
    regions: *mut u32,
    regions_capacity: usize,
    kinds: *mut u32,
    kinds_capacity: usize,
    min_angles_degrees: *mut f64,
    min_angles_capacity: usize,
) -> KatachiStatus {
    guard("katachi_curved_mesh_copy_element_data", || {
        // SAFETY (all blocks): the caller's promises above.
        let m = unsafe { mesh_ref(mesh) }?;
        let n = m.info.len();
        let what = &"one per element";
        if !regions.is_null() {
            let b = unsafe { out_buffer(regions, regions_capacity, n, "regions", what) }?;
            for (o, i) in b.iter_mut().zip(&m.info) {
                *o = i.region.0;
            }
        }
        if !kinds.is_null() {
            let b = unsafe { out_buffer(kinds, kinds_capacity, n, "kinds", what) }?;
            for (o, i) in b.iter_mut().zip(&m.info) {
                *o = (i.kind == ElementKind::Curved) as u32;
            }
        }
        if !min_angles_degrees.is_null() {
            let b = unsafe {
                out_buffer(
                    min_angles_degrees,
                    min_angles_capacity,
                    n,
                    "min_angles_degrees",
                    what,
                )
            }?;
            for (o, i) in b.iter_mut().zip(&m.info) {
                *o = i.quality.min_angle_vertex;
            }
        }
        Ok(())
    })
}

/// Writes the mesh to `path`: Gmsh MSH 4.1 (`.msh`, high-order triangles with the views
/// "min metric angle (deg)" and "region"), legacy VTK with Lagrange triangles (`.vtk`), or
/// an OBJ preview (`.obj`), by the extension; nodes as `space` says. The file is replaced
/// whole or left as it was.
///
/// Statuses: `KATACHI_STATUS_NULL_POINTER`; `KATACHI_STATUS_INVALID_ARGUMENT` (`space`, a
/// path that is not UTF-8, an unknown extension); `KATACHI_STATUS_IO_ERROR` (a write that
/// failed).
///
/// # Safety
/// `mesh` NULL or a live handle; `path` NULL or a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn katachi_curved_mesh_write(
    mesh: *const KatachiCurvedMesh,
    path: *const c_char,
    space: u32,
) -> KatachiStatus {
    guard("katachi_curved_mesh_write", || {
        // SAFETY: the caller's promises above.
        let m = unsafe { mesh_ref(mesh) }?;
        let path = unsafe { c_str(path, "path") }?;
        let space = space_from(space)?;
        m.write(std::path::Path::new(path), space)?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_defaults_are_the_kernels() {
        assert_eq!(options_from(&OPTIONS_DEFAULT), Ok(CurvedOptions::default()));
    }
}
