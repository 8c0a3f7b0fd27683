//! A cut in the input's own layout (`katachi_cut_polygons`): the arrays a polygon host
//! stores, with where every face, edge and corner came from, so a host copies arrays and
//! rebuilds nothing. Conversion and error mapping only; the work is
//! [`crate::cut::CutPolygons`]'s.

use std::ffi::c_void;

use super::boundary::{
    deref, deref_mut, guard, guard_value, out_buffer, slice, write_sized, FfiError, FfiResult,
};
use super::cut::{cut_ref, KatachiCut};
use super::mesh::{mesh_ref, KatachiMesh};
use super::status::KatachiStatus;
use crate::cut::{CutPolygons, InputEdges, NONE};

/// A cut in the input's own layout. Opaque; free it with `katachi_cut_polygons_free`.
pub struct KatachiCutPolygons {
    polygons: CutPolygons,
    /// The host's corner order of the input (see `katachi_mesh_create_polygons_f32`).
    host_corners: Option<Vec<u32>>,
}

/// Sizes of a `KatachiCutPolygons`, filled in by `katachi_cut_polygons_info`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KatachiCutPolygonsInfo {
    /// Set by the caller to `sizeof(KatachiCutPolygonsInfo)`.
    pub struct_size: u32,
    /// Vertices of the result (the input's, then the new ones).
    pub vertex_count: u32,
    /// Faces of the result (the input's in their slots, then the appended triangles).
    pub face_count: u32,
    /// Corners of the result.
    pub corner_count: u32,
    /// Edges of the result (the host's in their slots, then the new ones).
    pub edge_count: u32,
    /// Input faces given back as the polygons they were.
    pub kept_face_count: u32,
    /// Edges of the result on the cut paths (`katachi_cut_polygons_copy_path_edges`).
    pub path_edge_count: u32,
}

const INFO_DEFAULT: KatachiCutPolygonsInfo = KatachiCutPolygonsInfo {
    struct_size: std::mem::size_of::<KatachiCutPolygonsInfo>() as u32,
    vertex_count: 0,
    face_count: 0,
    corner_count: 0,
    edge_count: 0,
    kept_face_count: 0,
    path_edge_count: 0,
};

/// A `KatachiCutPolygonsInfo` with its `struct_size` set and counts 0.
#[no_mangle]
pub extern "C" fn katachi_cut_polygons_info_default() -> KatachiCutPolygonsInfo {
    guard_value("katachi_cut_polygons_info_default", INFO_DEFAULT, || {
        INFO_DEFAULT
    })
}

/// The cut `cut` of `mesh` (the mesh that was cut) in `mesh`'s own layout, for a host that
/// stores polygons and an edge list:
///
/// - faces: result face `f` below the input's face count comes from input face `f`: the
///   polygon it was when the cut left it alone and `keep_polygons` is 1 (faces with holes
///   come back as triangles), else its first triangle; the other triangles follow, each
///   with its input face (`katachi_cut_polygons_copy_origins`);
/// - edges: with the host's `edges` (2 × `edge_count` vertex indices) and `corner_edges`
///   (the host's edge of each corner, from it to the next corner of its face, in the order
///   the host gave the corners to `katachi_mesh_create_polygons_f32`), result edge `e` below
///   `edge_count` is the host's edge `e` (a split edge keeps its piece at its first vertex,
///   a loose edge stays as it is), and new edges follow, each with the host edge it lies on
///   or none. With `edges` and `corner_edges` NULL (`edge_count` 0), the input's edges are
///   numbered by first use in corner order.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER`;
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`mesh` is not the mesh that was cut, `corner_count`
/// not its corner count, a corner's edge out of range or not joining the corner to the next
/// one — the message names the corner —, `keep_polygons` not 0 or 1). On failure `*out` is
/// NULL.
///
/// # Safety
/// `cut` and `mesh` NULL or live handles; `edges` NULL or readable for 2 × `edge_count`
/// values, `corner_edges` NULL or readable for `corner_count`; `out` NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn katachi_cut_polygons(
    cut: *const KatachiCut,
    mesh: *const KatachiMesh,
    edges: *const u32,
    edge_count: u32,
    corner_edges: *const u32,
    corner_count: u32,
    keep_polygons: u32,
    out: *mut *mut KatachiCutPolygons,
) -> KatachiStatus {
    guard("katachi_cut_polygons", || {
        // SAFETY (all blocks): the caller's promises above.
        let out = unsafe { deref_mut(out, "out") }?;
        *out = std::ptr::null_mut();
        let c = unsafe { cut_ref(cut) }?;
        let m = unsafe { mesh_ref_handle(mesh) }?;
        let input = &m.mesh;
        if (
            input.vertex_count(),
            input.face_count(),
            input.corner_count(),
        ) != (
            c.input.vertex_count(),
            c.input.face_count(),
            c.input.corner_count(),
        ) {
            return Err(FfiError::invalid(format!(
                "mesh has {} vertices, {} faces and {} corners, but the mesh that was cut had \
                 {}, {} and {}: pass the mesh that was cut",
                input.vertex_count(),
                input.face_count(),
                input.corner_count(),
                c.input.vertex_count(),
                c.input.face_count(),
                c.input.corner_count()
            )));
        }
        let keep = match keep_polygons {
            0 => false,
            1 => true,
            v => {
                return Err(FfiError::invalid(format!(
                    "keep_polygons is {v}, which is not 0 or 1"
                )))
            }
        };
        let host_edges;
        let ordered;
        let given = if edges.is_null() && corner_edges.is_null() && edge_count == 0 {
            None
        } else {
            let pairs = unsafe {
                slice(
                    edges,
                    2 * edge_count as usize,
                    "edges",
                    &format_args!("edge_count is {edge_count}"),
                )
            }?;
            if corner_count != input.corner_count() {
                return Err(FfiError::invalid(format!(
                    "corner_count is {corner_count}, but the mesh has {} corners",
                    input.corner_count()
                )));
            }
            let ce = unsafe {
                slice(
                    corner_edges,
                    corner_count as usize,
                    "corner_edges",
                    &format_args!("corner_count is {corner_count}"),
                )
            }?;
            host_edges = pairs.as_chunks::<2>().0;
            // The kernel reads corners in its own order.
            let ce: &[u32] = match &m.host_corners {
                None => ce,
                Some(order) => {
                    ordered = order.iter().map(|&k| ce[k as usize]).collect::<Vec<u32>>();
                    &ordered
                }
            };
            Some(InputEdges {
                edges: host_edges,
                corner_edges: ce,
            })
        };
        let polygons = c.output.polygons(input, given, keep)?;
        *out = Box::into_raw(Box::new(KatachiCutPolygons {
            polygons,
            host_corners: m.host_corners.clone(),
        }));
        Ok(())
    })
}

/// # Safety
/// A non-NULL `p` must be a live handle.
unsafe fn mesh_ref_handle<'a>(p: *const KatachiMesh) -> FfiResult<&'a KatachiMesh> {
    // SAFETY: forwarded to the caller.
    let _ = unsafe { mesh_ref(p) }?;
    unsafe { deref(p, "mesh") }
}

/// # Safety
/// A non-NULL `p` must be a live handle.
unsafe fn polygons_ref<'a>(p: *const KatachiCutPolygons) -> FfiResult<&'a KatachiCutPolygons> {
    // SAFETY: forwarded to the caller.
    unsafe { deref(p, "polygons") }
}

/// Frees a `KatachiCutPolygons` (NULL is ignored).
///
/// # Safety
/// `polygons` NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_free(polygons: *mut KatachiCutPolygons) {
    guard_value("katachi_cut_polygons_free", (), || {
        if !polygons.is_null() {
            // SAFETY: the caller's promise: a live handle from `katachi_cut_polygons`.
            drop(unsafe { Box::from_raw(polygons) });
        }
    })
}

/// Fills `*info` with the sizes of the arrays (O(1)). The caller sets `info->struct_size`.
///
/// # Safety
/// `polygons` NULL or a live handle; `info` NULL or writable for `info->struct_size` bytes.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_info(
    polygons: *const KatachiCutPolygons,
    info: *mut KatachiCutPolygonsInfo,
) -> KatachiStatus {
    guard("katachi_cut_polygons_info", || {
        // SAFETY: the caller's promises above.
        let p = &unsafe { polygons_ref(polygons) }?.polygons;
        let n = |x: usize| x as u32;
        let value = KatachiCutPolygonsInfo {
            struct_size: INFO_DEFAULT.struct_size,
            vertex_count: n(p.positions.len()),
            face_count: n(p.face_origin.len()),
            corner_count: n(p.corners.len()),
            edge_count: n(p.edges.len()),
            kept_face_count: p.kept_faces,
            path_edge_count: n(p.path_edges.len()),
        };
        let min = std::mem::size_of::<KatachiCutPolygonsInfo>();
        unsafe { write_sized(info, value, min, "info", "KatachiCutPolygonsInfo") }
    })
}

/// Copies the result's positions as floats (3 × `vertex_count`).
///
/// # Safety
/// `polygons` NULL or a live handle; `out` NULL or writable for `capacity` floats.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_copy_positions_f32(
    polygons: *const KatachiCutPolygons,
    out: *mut f32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_copy_positions_f32", || {
        // SAFETY: the caller's promises above.
        let p = &unsafe { polygons_ref(polygons) }?.polygons;
        let n = 3 * p.positions.len();
        let buf = unsafe { out_buffer(out, capacity, n, "out", &"3 × vertex_count") }?;
        for (d, v) in buf.as_chunks_mut::<3>().0.iter_mut().zip(&p.positions) {
            *d = v.as_vec3().to_array();
        }
        Ok(())
    })
}

/// Copies the result's positions as doubles (3 × `vertex_count`).
///
/// # Safety
/// `polygons` NULL or a live handle; `out` NULL or writable for `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_copy_positions(
    polygons: *const KatachiCutPolygons,
    out: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_copy_positions", || {
        // SAFETY: the caller's promises above.
        let p = &unsafe { polygons_ref(polygons) }?.polygons;
        let n = 3 * p.positions.len();
        let buf = unsafe { out_buffer(out, capacity, n, "out", &"3 × vertex_count") }?;
        for (d, v) in buf.as_chunks_mut::<3>().0.iter_mut().zip(&p.positions) {
            *d = v.to_array();
        }
        Ok(())
    })
}

/// Checks every non-NULL buffer's room before anything is written.
fn rooms(buffers: &[(bool, usize, usize, &str)]) -> FfiResult {
    for &(null, cap, need, name) in buffers {
        if !null && cap < need {
            return Err(FfiError::new(
                KatachiStatus::BufferTooSmall,
                format!("{name} has room for {cap} values, but {need} are needed"),
            ));
        }
    }
    Ok(())
}

/// Writes `values` into the caller's `p` (skipped when NULL; room checked by `rooms`).
///
/// # Safety
/// `p` NULL or writable for `capacity` values.
unsafe fn fill(
    p: *mut u32,
    capacity: usize,
    values: impl ExactSizeIterator<Item = u32>,
    name: &str,
) -> FfiResult {
    if p.is_null() {
        return Ok(());
    }
    // SAFETY: forwarded to the caller.
    let buf = unsafe { out_buffer(p, capacity, values.len(), name, &"see its count") }?;
    for (d, v) in buf.iter_mut().zip(values) {
        *d = v;
    }
    Ok(())
}

/// Copies the result's faces as a host stores polygons: each face's first corner
/// (`face_starts`, `face_count` values; faces are stored one after the other), its number
/// of corners (`face_sizes`, `face_count`) and every corner's vertex (`corner_vertices`,
/// `corner_count`). A NULL buffer is skipped; nothing is written when one is too small.
///
/// # Safety
/// `polygons` NULL or a live handle; each buffer NULL or writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_copy_polygons(
    polygons: *const KatachiCutPolygons,
    face_starts: *mut u32,
    face_starts_capacity: usize,
    face_sizes: *mut u32,
    face_sizes_capacity: usize,
    corner_vertices: *mut u32,
    corner_vertices_capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_copy_polygons", || {
        // SAFETY: the caller's promises above.
        let p = &unsafe { polygons_ref(polygons) }?.polygons;
        let fo = &p.face_offsets;
        let nf = fo.len() - 1;
        rooms(&[
            (
                face_starts.is_null(),
                face_starts_capacity,
                nf,
                "face_starts",
            ),
            (face_sizes.is_null(), face_sizes_capacity, nf, "face_sizes"),
            (
                corner_vertices.is_null(),
                corner_vertices_capacity,
                p.corners.len(),
                "corner_vertices",
            ),
        ])?;
        unsafe {
            fill(
                face_starts,
                face_starts_capacity,
                fo[..nf].iter().copied(),
                "face_starts",
            )?;
            fill(
                face_sizes,
                face_sizes_capacity,
                fo.windows(2).map(|w| w[1] - w[0]),
                "face_sizes",
            )?;
            fill(
                corner_vertices,
                corner_vertices_capacity,
                p.corners.iter().copied(),
                "corner_vertices",
            )?;
        }
        Ok(())
    })
}

/// Copies the result's edges: `edges` gets each edge's two vertices (2 × `edge_count`),
/// `corner_edges` each corner's edge (from it to the next corner of its face;
/// `corner_count`). A NULL buffer is skipped; nothing is written when one is too small.
///
/// # Safety
/// `polygons` NULL or a live handle; each buffer NULL or writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_copy_edges(
    polygons: *const KatachiCutPolygons,
    edges: *mut u32,
    edges_capacity: usize,
    corner_edges: *mut u32,
    corner_edges_capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_copy_edges", || {
        // SAFETY: the caller's promises above.
        let p = &unsafe { polygons_ref(polygons) }?.polygons;
        rooms(&[
            (edges.is_null(), edges_capacity, 2 * p.edges.len(), "edges"),
            (
                corner_edges.is_null(),
                corner_edges_capacity,
                p.corner_edges.len(),
                "corner_edges",
            ),
        ])?;
        unsafe {
            fill(
                edges,
                edges_capacity,
                p.edges.as_flattened().iter().copied(),
                "edges",
            )?;
            fill(
                corner_edges,
                corner_edges_capacity,
                p.corner_edges.iter().copied(),
                "corner_edges",
            )?;
        }
        Ok(())
    })
}

/// Copies where the result's elements come from: `face_origin` the input face of each
/// face (`face_count`), `edge_origin` the host edge each edge lies on (`edge_count`),
/// `corner_origin` the input corner of each corner (`corner_count`, in the host's corner
/// order), with `UINT32_MAX` for none (an edge made inside a face, a corner at a new
/// vertex). A NULL buffer is skipped; nothing is written when one is too small.
///
/// # Safety
/// `polygons` NULL or a live handle; each buffer NULL or writable for its capacity.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_copy_origins(
    polygons: *const KatachiCutPolygons,
    face_origin: *mut u32,
    face_origin_capacity: usize,
    edge_origin: *mut u32,
    edge_origin_capacity: usize,
    corner_origin: *mut u32,
    corner_origin_capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_copy_origins", || {
        // SAFETY: the caller's promises above.
        let h = unsafe { polygons_ref(polygons) }?;
        let p = &h.polygons;
        rooms(&[
            (
                face_origin.is_null(),
                face_origin_capacity,
                p.face_origin.len(),
                "face_origin",
            ),
            (
                edge_origin.is_null(),
                edge_origin_capacity,
                p.edge_origin.len(),
                "edge_origin",
            ),
            (
                corner_origin.is_null(),
                corner_origin_capacity,
                p.corner_origin.len(),
                "corner_origin",
            ),
        ])?;
        let host = |c: u32| match (&h.host_corners, c) {
            (Some(order), c) if c != NONE => order[c as usize],
            _ => c,
        };
        unsafe {
            fill(
                face_origin,
                face_origin_capacity,
                p.face_origin.iter().copied(),
                "face_origin",
            )?;
            fill(
                edge_origin,
                edge_origin_capacity,
                p.edge_origin.iter().copied(),
                "edge_origin",
            )?;
            fill(
                corner_origin,
                corner_origin_capacity,
                p.corner_origin.iter().map(|&c| host(c)),
                "corner_origin",
            )?;
        }
        Ok(())
    })
}

/// Copies the result's edges on the cut paths (both sides of an opened cut), ascending:
/// `path_edge_count` values.
///
/// # Safety
/// `polygons` NULL or a live handle; `out` NULL or writable for `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_copy_path_edges(
    polygons: *const KatachiCutPolygons,
    out: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_copy_path_edges", || {
        // SAFETY: the caller's promises above.
        let p = &unsafe { polygons_ref(polygons) }?.polygons;
        let n = p.path_edges.len();
        let buf = unsafe { out_buffer(out, capacity, n, "out", &"path_edge_count") }?;
        buf.copy_from_slice(&p.path_edges);
        Ok(())
    })
}

/// What per-element data is carried over.
#[derive(Clone, Copy)]
enum Element {
    Face,
    Edge,
    Vertex,
}

/// Carries per-face data of the input to the result's faces: `values` holds one value of
/// `value_size` bytes (1, 2, 4 or 8) per input face (materials, smooth flags), and each
/// result face gets its input face's (`face_count` values into `out`). Bytes are copied as
/// they are.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER`;
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`value_size` not 1, 2, 4 or 8, `value_count` not the
/// input's face count); `KATACHI_STATUS_BUFFER_TOO_SMALL` (`capacity`, in values).
///
/// # Safety
/// `polygons` NULL or a live handle; `values` NULL or readable for `value_count` values of
/// `value_size` bytes; `out` NULL or writable for `capacity` such values.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_carry_face_data(
    polygons: *const KatachiCutPolygons,
    values: *const c_void,
    value_count: usize,
    value_size: u32,
    out: *mut c_void,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_carry_face_data", || {
        // SAFETY: the caller's promises above.
        unsafe {
            carry(
                polygons,
                Element::Face,
                values,
                value_count,
                value_size,
                out,
                capacity,
            )
        }
    })
}

/// Carries per-edge data of the host's edges to the result's edges, as
/// `katachi_cut_polygons_carry_face_data` (one value per host edge in, `edge_count` out): an
/// edge on a host edge (a piece of a split one, an opened cut's copy) takes its value, an
/// edge made inside a face gets zero bytes.
///
/// # Safety
/// As `katachi_cut_polygons_carry_face_data`.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_carry_edge_data(
    polygons: *const KatachiCutPolygons,
    values: *const c_void,
    value_count: usize,
    value_size: u32,
    out: *mut c_void,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_carry_edge_data", || {
        // SAFETY: the caller's promises above.
        unsafe {
            carry(
                polygons,
                Element::Edge,
                values,
                value_count,
                value_size,
                out,
                capacity,
            )
        }
    })
}

/// Carries per-vertex data of the input to the result's vertices, as
/// `katachi_cut_polygons_carry_face_data` (one value per input vertex in, `vertex_count`
/// out): input vertices keep theirs, an opened cut's copy of an input vertex takes its
/// original's, other new vertices get zero bytes (creases, flags; blend weights with
/// `katachi_cut_interpolate_vertex_data`).
///
/// # Safety
/// As `katachi_cut_polygons_carry_face_data`.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_carry_vertex_data(
    polygons: *const KatachiCutPolygons,
    values: *const c_void,
    value_count: usize,
    value_size: u32,
    out: *mut c_void,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_carry_vertex_data", || {
        // SAFETY: the caller's promises above.
        unsafe {
            carry(
                polygons,
                Element::Vertex,
                values,
                value_count,
                value_size,
                out,
                capacity,
            )
        }
    })
}

/// The body of the carry calls.
///
/// # Safety
/// As those functions.
unsafe fn carry(
    polygons: *const KatachiCutPolygons,
    element: Element,
    values: *const c_void,
    value_count: usize,
    value_size: u32,
    out: *mut c_void,
    capacity: usize,
) -> FfiResult {
    // SAFETY: forwarded to the caller.
    let p = &unsafe { polygons_ref(polygons) }?.polygons;
    let nv_in = p.input_vertex_count as usize;
    let (n_in, n_out, what) = match element {
        Element::Face => (p.input_face_count as usize, p.face_origin.len(), "face"),
        Element::Edge => (p.input_edge_count as usize, p.edge_origin.len(), "edge"),
        Element::Vertex => (nv_in, p.positions.len(), "vertex"),
    };
    if value_count != n_in {
        return Err(FfiError::invalid(format!(
            "value_count is {value_count}, but the input has {n_in} {what} values (one per \
             {what})"
        )));
    }
    let source = |i: usize| -> Option<usize> {
        let o = match element {
            Element::Face => p.face_origin[i],
            Element::Edge => p.edge_origin[i],
            Element::Vertex if i < nv_in => i as u32,
            Element::Vertex => p.new_vertex_original[i - nv_in],
        };
        (o != NONE).then_some(o as usize)
    };
    /// # Safety
    /// As the caller's, for values of type `T`.
    unsafe fn typed<T: Copy + Default>(
        source: &dyn Fn(usize) -> Option<usize>,
        values: *const c_void,
        n_in: usize,
        out: *mut c_void,
        capacity: usize,
        n_out: usize,
    ) -> FfiResult {
        // SAFETY: forwarded (the caller's promises, `T` of `value_size` bytes).
        let vals = unsafe { slice(values.cast::<T>(), n_in, "values", &"value_count > 0") }?;
        let buf = unsafe {
            out_buffer(
                out.cast::<T>(),
                capacity,
                n_out,
                "out",
                &"one per result element",
            )
        }?;
        for (i, d) in buf.iter_mut().enumerate() {
            *d = source(i).map_or_else(T::default, |o| vals[o]);
        }
        Ok(())
    }
    unsafe {
        match value_size {
            1 => typed::<u8>(&source, values, n_in, out, capacity, n_out),
            2 => typed::<u16>(&source, values, n_in, out, capacity, n_out),
            4 => typed::<u32>(&source, values, n_in, out, capacity, n_out),
            8 => typed::<u64>(&source, values, n_in, out, capacity, n_out),
            v => Err(FfiError::invalid(format!(
                "value_size is {v}; it must be 1, 2, 4 or 8 bytes"
            ))),
        }
    }
}

/// Carries per-corner data given as floats, as a host stores UV maps: `values` holds
/// `components` floats per input corner (in the host's corner order), and each result
/// corner gets its input corner's, or, at a new vertex, the blend of the corners of the
/// input triangle it lies in (`components` floats per result corner into `out`).
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER`;
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`components` not 1 to 64, `value_count` not input
/// corners × components); `KATACHI_STATUS_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `polygons` NULL or a live handle; `values` NULL or readable for `value_count` floats;
/// `out` NULL or writable for `capacity` floats.
#[no_mangle]
pub unsafe extern "C" fn katachi_cut_polygons_carry_corner_data_f32(
    polygons: *const KatachiCutPolygons,
    values: *const f32,
    value_count: usize,
    components: u32,
    out: *mut f32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_cut_polygons_carry_corner_data_f32", || {
        // SAFETY: the caller's promises above.
        let h = unsafe { polygons_ref(polygons) }?;
        let p = &h.polygons;
        if components == 0 || components > 64 {
            return Err(FfiError::invalid(format!(
                "components is {components}; it must be 1 to 64"
            )));
        }
        let k = components as usize;
        let nin = p.input_corner_count as usize * k;
        if value_count != nin {
            return Err(FfiError::invalid(format!(
                "value_count is {value_count}, but the input has {} corners × {k} components \
                 = {nin}",
                p.input_corner_count
            )));
        }
        let values = unsafe { slice(values, value_count, "values", &"value_count > 0") }?;
        let buf = unsafe {
            out_buffer(
                out,
                capacity,
                p.corners.len() * k,
                "out",
                &"corner_count × components",
            )
        }?;
        let ordered: Vec<f32>;
        let values = match &h.host_corners {
            None => values,
            Some(order) => {
                ordered = order
                    .iter()
                    .flat_map(|&c| values[k * c as usize..k * c as usize + k].iter().copied())
                    .collect();
                &ordered
            }
        };
        buf.copy_from_slice(&p.carry_corner_data(values, k)?);
        Ok(())
    })
}
