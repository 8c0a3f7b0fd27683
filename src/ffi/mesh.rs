//! `KatachiMesh`: the opaque mesh handle, its construction from flat arrays (faces with
//! holes included), counts, copy-out of its arrays, its sharpness attributes, and splitting
//! its faces with holes into simple polygons. Conversion and error mapping only; the work is
//! [`crate::PolyMesh`]'s and [`crate::mesh::holes`]'.

use super::boundary::{
    deref, deref_mut, guard, guard_value, out_buffer, slice, FfiError, FfiResult,
};
use super::status::KatachiStatus;
use crate::mesh::holes::split_faces_with_holes;
use crate::mesh::{PolyMesh, VertexId};

/// A polygon mesh whose faces may have holes, with its attributes (edge and vertex
/// sharpness). Opaque: create it with `katachi_mesh_create`, `katachi_mesh_clone` or
/// `katachi_mesh_read`, and free it with `katachi_mesh_free`.
///
/// A mesh may be read from several threads at once; a function that changes it (those taking
/// a non-const `KatachiMesh*`) must not run concurrently with any other call on the same mesh.
pub struct KatachiMesh {
    pub(crate) mesh: PolyMesh,
    /// When the mesh was made from a host's faces whose corners are not stored face after
    /// face (`katachi_mesh_create_polygons_f32` with scattered starts): the host's corner of
    /// each katachi corner, so per-corner data given in the host's order is read right.
    pub(crate) host_corners: Option<Vec<u32>>,
}

impl KatachiMesh {
    /// Moves `mesh` to the heap and hands it out as a C handle.
    pub(crate) fn into_raw(mesh: PolyMesh) -> *mut KatachiMesh {
        Box::into_raw(Box::new(KatachiMesh {
            mesh,
            host_corners: None,
        }))
    }
}

/// How sharpness is given or read in the `_f32` calls that take a `scale`.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KatachiSharpnessScale {
    /// OpenSubdiv's sharpness: 0 smooth, values in (0, 10) semi-sharp, ≥ 10 infinitely sharp.
    Sharpness = 0,
    /// A crease weight in [0, 1], Blender's: sharpness = 10 × crease² (the mapping Blender's
    /// Subdivision Surface modifier uses with OpenSubdiv), so crease 1 is infinitely sharp.
    Crease = 1,
}

/// The scale named by a `scale` argument.
pub(crate) fn sharpness_scale(scale: u32) -> FfiResult<KatachiSharpnessScale> {
    match scale {
        0 => Ok(KatachiSharpnessScale::Sharpness),
        1 => Ok(KatachiSharpnessScale::Crease),
        v => Err(FfiError::invalid(format!(
            "scale is {v}, which is not KATACHI_SHARPNESS_SCALE_SHARPNESS (0) or \
             KATACHI_SHARPNESS_SCALE_CREASE (1)"
        ))),
    }
}

impl KatachiSharpnessScale {
    /// A caller's value as sharpness; `element` names it in the error for a value outside
    /// the scale.
    pub(crate) fn to_sharpness(self, v: f32, element: impl FnOnce() -> String) -> FfiResult<f64> {
        let ok = match self {
            KatachiSharpnessScale::Sharpness => v.is_finite() && v >= 0.0,
            KatachiSharpnessScale::Crease => (0.0..=1.0).contains(&v),
        };
        if !ok {
            let range = match self {
                KatachiSharpnessScale::Sharpness => "finite and ≥ 0",
                KatachiSharpnessScale::Crease => "a crease in [0, 1]",
            };
            return Err(FfiError::new(
                KatachiStatus::BadInput,
                format!("{} is {v}, which is not {range}", element()),
            ));
        }
        let v = f64::from(v);
        Ok(match self {
            KatachiSharpnessScale::Sharpness => v,
            KatachiSharpnessScale::Crease => 10.0 * v * v,
        })
    }

    /// Sharpness in this scale (a crease is `sqrt(sharpness / 10)`, 1 from 10 up).
    pub(crate) fn of_sharpness(self, s: f32) -> f32 {
        match self {
            KatachiSharpnessScale::Sharpness => s,
            KatachiSharpnessScale::Crease => (s.clamp(0.0, 10.0) / 10.0).sqrt(),
        }
    }
}

/// The sizes of a mesh's arrays, filled in by `katachi_mesh_counts`.
///
/// Like every katachi struct that katachi fills in, it starts with `struct_size`: set it to
/// `sizeof(KatachiMeshCounts)` (or start from `katachi_mesh_counts_default()`) before the call.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KatachiMeshCounts {
    /// Set by the caller to `sizeof(KatachiMeshCounts)`; katachi leaves it unchanged.
    pub struct_size: u32,
    /// Vertices, referenced by a face or not (`positions` holds 3 × this many doubles).
    pub vertex_count: u32,
    /// Faces.
    pub face_count: u32,
    /// Loops over all faces: one outer loop per face plus its holes.
    pub loop_count: u32,
    /// Corners over all loops (the length of the `corners` array).
    pub corner_count: u32,
    /// Edges with sharpness > 0 (the length of `katachi_mesh_copy_sharp_edges`'s output).
    pub sharp_edge_count: u32,
    /// Vertices with sharpness > 0.
    pub sharp_vertex_count: u32,
}

/// The size of the first version of `KatachiMeshCounts`: smaller `struct_size`s are rejected.
const COUNTS_MIN_SIZE: usize = std::mem::size_of::<KatachiMeshCounts>();

const COUNTS_DEFAULT: KatachiMeshCounts = KatachiMeshCounts {
    struct_size: std::mem::size_of::<KatachiMeshCounts>() as u32,
    vertex_count: 0,
    face_count: 0,
    loop_count: 0,
    corner_count: 0,
    sharp_edge_count: 0,
    sharp_vertex_count: 0,
};

/// The mesh behind a `const KatachiMesh*` parameter named `mesh`.
///
/// # Safety
/// A non-NULL `p` must be a live handle from katachi, not being changed by another thread.
pub(crate) unsafe fn mesh_ref<'a>(p: *const KatachiMesh) -> FfiResult<&'a PolyMesh> {
    // SAFETY: forwarded to the caller.
    Ok(&unsafe { deref(p, "mesh") }?.mesh)
}

/// The mesh behind a `KatachiMesh*` parameter named `mesh`, for changing it.
///
/// # Safety
/// A non-NULL `p` must be a live handle from katachi that no other call is using.
unsafe fn mesh_mut<'a>(p: *mut KatachiMesh) -> FfiResult<&'a mut PolyMesh> {
    // SAFETY: forwarded to the caller.
    Ok(&mut unsafe { deref_mut(p, "mesh") }?.mesh)
}

/// Checks an out-parameter for a new handle and sets `*out = NULL`, so that it is NULL on
/// every failure after this point.
///
/// # Safety
/// A non-NULL `out` must point to writable storage for one pointer.
pub(crate) unsafe fn reset_out<'a>(
    out: *mut *mut KatachiMesh,
) -> FfiResult<&'a mut *mut KatachiMesh> {
    // SAFETY: forwarded to the caller.
    let out = unsafe { deref_mut(out, "out") }?;
    *out = std::ptr::null_mut();
    Ok(out)
}

/// Checks that `v` (the parameter `param`) is a vertex of `mesh`.
fn check_vertex(mesh: &PolyMesh, v: u32, param: &str) -> FfiResult<VertexId> {
    if v < mesh.vertex_count() {
        Ok(VertexId(v))
    } else {
        Err(FfiError::invalid(format!(
            "{param} = {v} is out of range (the mesh has {} vertices)",
            mesh.vertex_count()
        )))
    }
}

/// Checks an edge given as two vertices, the parameters (or array elements) `names`.
fn check_edge(
    mesh: &PolyMesh,
    a: u32,
    b: u32,
    names: [&str; 2],
) -> FfiResult<(VertexId, VertexId)> {
    let (va, vb) = (
        check_vertex(mesh, a, names[0])?,
        check_vertex(mesh, b, names[1])?,
    );
    if a == b {
        return Err(FfiError::invalid(format!(
            "{} and {} are both vertex {a}; an edge joins two different vertices",
            names[0], names[1]
        )));
    }
    Ok((va, vb))
}

/// Creates a mesh from flat arrays. Faces may have holes: each face has one or more loops,
/// the first its outer boundary (counter-clockwise seen from the front), any further loops
/// its holes (clockwise).
///
/// - `positions`: 3 × `vertex_count` doubles, `x0 y0 z0 x1 y1 z1 …`; every value finite.
/// - `loop_sizes`: `loop_count` values, the number of corners of each loop (each ≥ 3).
/// - `face_loop_counts`: `face_count` values, the number of loops of each face (each ≥ 1,
///   outer loop first); they add up to `loop_count`.
/// - `corners`: `corner_count` vertex indices, loop after loop; `loop_sizes` add up to
///   `corner_count`, and each index is below `vertex_count`.
///
/// A simple polygon mesh has `face_loop_counts` all 1 and `loop_sizes` the polygon sizes.
/// An array whose count is 0 may be NULL. The arrays are copied: the caller keeps them.
///
/// On success `*out` receives a new mesh, owned by the caller, to be freed with
/// `katachi_mesh_free`. On failure `*out` is set to NULL (when `out` is not NULL itself).
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`out` NULL, or an array NULL
/// with a nonzero count); `KATACHI_STATUS_BAD_INPUT` (a non-finite coordinate, counts that do
/// not add up, an index out of range, a loop with fewer than 3 distinct vertices or a repeated
/// vertex; the message names the face, loop and vertex); `KATACHI_STATUS_INVALID_ARGUMENT`
/// (a misaligned array).
///
/// # Safety
/// Each non-NULL array must hold the number of elements stated above; `out` must be NULL or
/// point to writable storage for one pointer.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn katachi_mesh_create(
    positions: *const f64,
    vertex_count: u32,
    loop_sizes: *const u32,
    loop_count: u32,
    face_loop_counts: *const u32,
    face_count: u32,
    corners: *const u32,
    corner_count: u32,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_mesh_create", || {
        // SAFETY (all blocks): the caller's promises above.
        let out = unsafe { reset_out(out) }?;
        let n_pos = (vertex_count as usize).checked_mul(3).ok_or_else(|| {
            FfiError::invalid(format!("vertex_count {vertex_count} is too large"))
        })?;
        let positions = unsafe {
            slice(
                positions,
                n_pos,
                "positions",
                &format_args!("vertex_count is {vertex_count}"),
            )
        }?;
        let loop_sizes = unsafe {
            slice(
                loop_sizes,
                loop_count as usize,
                "loop_sizes",
                &format_args!("loop_count is {loop_count}"),
            )
        }?;
        let face_loop_counts = unsafe {
            slice(
                face_loop_counts,
                face_count as usize,
                "face_loop_counts",
                &format_args!("face_count is {face_count}"),
            )
        }?;
        let corners = unsafe {
            slice(
                corners,
                corner_count as usize,
                "corners",
                &format_args!("corner_count is {corner_count}"),
            )
        }?;
        let mesh = PolyMesh::from_flat(positions, loop_sizes, face_loop_counts, corners)?;
        *out = KatachiMesh::into_raw(mesh);
        Ok(())
    })
}

/// Frees a mesh made by katachi. NULL is allowed and does nothing. The handle must not be
/// used afterwards, and must not be freed twice.
///
/// # Safety
/// `mesh` must be NULL or a live handle from katachi that no other call is using.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_free(mesh: *mut KatachiMesh) {
    guard_value("katachi_mesh_free", (), || {
        if !mesh.is_null() {
            // SAFETY: a live handle made by `KatachiMesh::into_raw` (the caller's promise).
            drop(unsafe { Box::from_raw(mesh) });
        }
    })
}

/// Copies a mesh with its attributes. On success `*out` receives a new mesh owned by the
/// caller (free it with `katachi_mesh_free`); on failure `*out` is set to NULL.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` or `out` NULL).
///
/// # Safety
/// `mesh` must be NULL or a live handle; `out` NULL or writable storage for one pointer.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_clone(
    mesh: *const KatachiMesh,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_mesh_clone", || {
        // SAFETY: the caller's promises above.
        let out = unsafe { reset_out(out) }?;
        let m = unsafe { deref(mesh, "mesh") }?;
        *out = Box::into_raw(Box::new(KatachiMesh {
            mesh: m.mesh.clone(),
            host_corners: m.host_corners.clone(),
        }));
        Ok(())
    })
}

/// A `KatachiMeshCounts` with `struct_size = sizeof(KatachiMeshCounts)` and every count 0,
/// ready to pass to `katachi_mesh_counts`.
#[no_mangle]
pub extern "C" fn katachi_mesh_counts_default() -> KatachiMeshCounts {
    guard_value("katachi_mesh_counts_default", COUNTS_DEFAULT, || {
        COUNTS_DEFAULT
    })
}

/// Fills `*counts` with the sizes of the mesh's arrays, which are the sizes the copy-out
/// functions need. The caller sets `counts->struct_size` first.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` or `counts` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`counts->struct_size` smaller than the first version of
/// the struct). On failure `*counts` is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle; `counts` NULL or a writable `KatachiMeshCounts` of
/// at least `counts->struct_size` bytes.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_counts(
    mesh: *const KatachiMesh,
    counts: *mut KatachiMeshCounts,
) -> KatachiStatus {
    guard("katachi_mesh_counts", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let value = KatachiMeshCounts {
            struct_size: 0, // not written: the caller's value stays
            vertex_count: mesh.vertex_count(),
            face_count: mesh.face_count(),
            loop_count: mesh.loop_count(),
            corner_count: mesh.corner_count(),
            sharp_edge_count: mesh.sharp_edges().len() as u32,
            sharp_vertex_count: mesh.vertex_sharpness().iter().filter(|&&s| s > 0.0).count() as u32,
        };
        unsafe {
            super::boundary::write_sized(
                counts,
                value,
                COUNTS_MIN_SIZE,
                "counts",
                "KatachiMeshCounts",
            )
        }
    })
}

/// Copies the vertex positions into `positions`, a caller's buffer of `capacity` doubles:
/// 3 × vertex_count values, `x0 y0 z0 x1 y1 z1 …`, are written.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL, or `positions`
/// NULL when the mesh has vertices); `KATACHI_STATUS_BUFFER_TOO_SMALL` (`capacity` below
/// 3 × vertex_count; the message says how many are needed, and nothing is written).
///
/// # Safety
/// `mesh` must be NULL or a live handle; `positions` NULL or `capacity` writable doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_copy_positions(
    mesh: *const KatachiMesh,
    positions: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_mesh_copy_positions", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let nv = mesh.vertex_count();
        let out = unsafe {
            out_buffer(
                positions,
                capacity,
                3 * nv as usize,
                "positions",
                &format_args!("3 doubles for each of {nv} vertices"),
            )
        }?;
        for (dst, p) in out.chunks_exact_mut(3).zip(mesh.positions()) {
            dst.copy_from_slice(&p.to_array());
        }
        Ok(())
    })
}

/// Copies the face-loop layout, in the form `katachi_mesh_create` takes, into three caller's
/// buffers:
///
/// - `loop_sizes` (capacity `loop_sizes_capacity`): loop_count values, the corners of each loop;
/// - `face_loop_counts` (capacity `face_loop_counts_capacity`): face_count values, the loops of
///   each face (outer loop first, then holes);
/// - `corners` (capacity `corners_capacity`): corner_count vertex indices, loop after loop.
///
/// The counts come from `katachi_mesh_counts`. A buffer whose needed count is 0 may be NULL.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL, or a buffer NULL
/// with a nonzero need); `KATACHI_STATUS_BUFFER_TOO_SMALL` (a capacity below its count; the
/// message names the buffer and the count). On failure nothing is written.
///
/// # Safety
/// `mesh` must be NULL or a live handle; each buffer NULL or holding its capacity of
/// writable `uint32_t`s.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_copy_faces(
    mesh: *const KatachiMesh,
    loop_sizes: *mut u32,
    loop_sizes_capacity: usize,
    face_loop_counts: *mut u32,
    face_loop_counts_capacity: usize,
    corners: *mut u32,
    corners_capacity: usize,
) -> KatachiStatus {
    guard("katachi_mesh_copy_faces", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let (nl, nf, nc) = (mesh.loop_count(), mesh.face_count(), mesh.corner_count());
        let loop_sizes = unsafe {
            out_buffer(
                loop_sizes,
                loop_sizes_capacity,
                nl as usize,
                "loop_sizes",
                &format_args!("one per loop; the mesh has {nl} loops"),
            )
        }?;
        let face_loop_counts = unsafe {
            out_buffer(
                face_loop_counts,
                face_loop_counts_capacity,
                nf as usize,
                "face_loop_counts",
                &format_args!("one per face; the mesh has {nf} faces"),
            )
        }?;
        let corners = unsafe {
            out_buffer(
                corners,
                corners_capacity,
                nc as usize,
                "corners",
                &format_args!("one per corner; the mesh has {nc} corners"),
            )
        }?;
        for (dst, w) in loop_sizes.iter_mut().zip(mesh.loop_offsets().windows(2)) {
            *dst = w[1] - w[0];
        }
        for (dst, w) in face_loop_counts
            .iter_mut()
            .zip(mesh.face_loop_offsets().windows(2))
        {
            *dst = w[1] - w[0];
        }
        for (dst, v) in corners.iter_mut().zip(mesh.corners()) {
            *dst = v.0;
        }
        Ok(())
    })
}

/// Reads the sharpness of the edge between vertices `a` and `b` (either order) into
/// `*sharpness`: 0 is smooth, values in (0, 10) are semi-sharp, ≥ 10 infinitely sharp
/// (OpenSubdiv semantics). A pair of vertices not joined by any edge reads 0.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` or `sharpness` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`a` or `b` out of range, or `a == b`). On failure
/// `*sharpness` is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle; `sharpness` NULL or a writable double.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_edge_sharpness(
    mesh: *const KatachiMesh,
    a: u32,
    b: u32,
    sharpness: *mut f64,
) -> KatachiStatus {
    guard("katachi_mesh_edge_sharpness", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let out = unsafe { deref_mut(sharpness, "sharpness") }?;
        let (a, b) = check_edge(mesh, a, b, ["a", "b"])?;
        *out = mesh.edge_sharpness(a, b);
        Ok(())
    })
}

/// Sets the sharpness of the edge between vertices `a` and `b` (either order): finite and
/// ≥ 0; 0 makes it smooth again. The edge must be a side of some face's loop.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`a` or `b` out of range, or `a == b`);
/// `KATACHI_STATUS_BAD_INPUT` (no edge joins `a` and `b`, or `sharpness` is negative or not
/// finite). On failure the mesh is unchanged.
///
/// Cost: O(corners) per call; use `katachi_mesh_set_edge_sharpnesses` for many edges.
///
/// # Safety
/// `mesh` must be NULL or a live handle that no other call is using.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_set_edge_sharpness(
    mesh: *mut KatachiMesh,
    a: u32,
    b: u32,
    sharpness: f64,
) -> KatachiStatus {
    guard("katachi_mesh_set_edge_sharpness", || {
        // SAFETY: the caller's promise above.
        let mesh = unsafe { mesh_mut(mesh) }?;
        let (a, b) = check_edge(mesh, a, b, ["a", "b"])?;
        mesh.set_edge_sharpness(a, b, sharpness)?;
        Ok(())
    })
}

/// Sets the sharpness of `count` edges at once, all or nothing.
///
/// - `edges`: 2 × `count` vertex indices, `a0 b0 a1 b1 …`, each pair an edge of the mesh;
/// - `sharpness`: `count` values, finite and ≥ 0 (0 makes an edge smooth).
///
/// With `count == 0` both arrays may be NULL.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL, or an array NULL
/// with `count > 0`); `KATACHI_STATUS_INVALID_ARGUMENT` (an index out of range or a pair with
/// twice the same vertex; the message gives its position in `edges`);
/// `KATACHI_STATUS_BAD_INPUT` (a pair that is no edge, a negative or non-finite value). On
/// failure the mesh is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle that no other call is using; non-NULL arrays must
/// hold the counts above.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_set_edge_sharpnesses(
    mesh: *mut KatachiMesh,
    edges: *const u32,
    sharpness: *const f64,
    count: usize,
) -> KatachiStatus {
    guard("katachi_mesh_set_edge_sharpnesses", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_mut(mesh) }?;
        let n_idx = count
            .checked_mul(2)
            .ok_or_else(|| FfiError::invalid(format!("count {count} is too large")))?;
        let edges = unsafe { slice(edges, n_idx, "edges", &format_args!("count is {count}")) }?;
        let values = unsafe {
            slice(
                sharpness,
                count,
                "sharpness",
                &format_args!("count is {count}"),
            )
        }?;
        let mut batch = Vec::with_capacity(count);
        for (i, (pair, &s)) in edges.chunks_exact(2).zip(values).enumerate() {
            let names = [format!("edges[{}]", 2 * i), format!("edges[{}]", 2 * i + 1)];
            let (a, b) = check_edge(mesh, pair[0], pair[1], [&names[0], &names[1]])?;
            batch.push((a, b, s));
        }
        mesh.set_edge_sharpnesses(batch)?;
        Ok(())
    })
}

/// Copies every edge with sharpness > 0, sorted by (smaller vertex, larger vertex):
///
/// - `edges`: 2 × n vertex indices `a0 b0 a1 b1 …` with `a < b`;
/// - `sharpness`: n values;
///
/// where n is `sharp_edge_count` from `katachi_mesh_counts` and `capacity` is the number of
/// edges both buffers have room for (`edges` holds 2 × `capacity` `uint32_t`s).
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL, or a buffer NULL
/// when n > 0); `KATACHI_STATUS_BUFFER_TOO_SMALL` (`capacity` < n; nothing is written).
///
/// # Safety
/// `mesh` must be NULL or a live handle; `edges` NULL or 2 × `capacity` writable `uint32_t`s;
/// `sharpness` NULL or `capacity` writable doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_copy_sharp_edges(
    mesh: *const KatachiMesh,
    edges: *mut u32,
    sharpness: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_mesh_copy_sharp_edges", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let n = mesh.sharp_edges().len();
        if capacity < n {
            return Err(FfiError::new(
                KatachiStatus::BufferTooSmall,
                format!("capacity is {capacity} edges, but the mesh has {n} sharp edges"),
            ));
        }
        let what = format_args!("the mesh has {n} sharp edges");
        let edges = unsafe { out_buffer(edges, 2 * n, 2 * n, "edges", &what) }?;
        let values = unsafe { out_buffer(sharpness, n, n, "sharpness", &what) }?;
        for ((pair, value), (a, b, s)) in edges
            .chunks_exact_mut(2)
            .zip(values)
            .zip(mesh.sharp_edges())
        {
            pair[0] = a.0;
            pair[1] = b.0;
            *value = s;
        }
        Ok(())
    })
}

/// Reads the sharpness of vertex `vertex` (a corner crease; 0 smooth, ≥ 10 infinitely
/// sharp) into `*sharpness`.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` or `sharpness` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`vertex` out of range). On failure `*sharpness` is
/// unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle; `sharpness` NULL or a writable double.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_vertex_sharpness(
    mesh: *const KatachiMesh,
    vertex: u32,
    sharpness: *mut f64,
) -> KatachiStatus {
    guard("katachi_mesh_vertex_sharpness", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let out = unsafe { deref_mut(sharpness, "sharpness") }?;
        let v = check_vertex(mesh, vertex, "vertex")?;
        *out = mesh.vertex_sharpness()[v.idx()];
        Ok(())
    })
}

/// Sets the sharpness of vertex `vertex`: finite and ≥ 0 (0 smooth, ≥ 10 infinitely sharp).
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`vertex` out of range); `KATACHI_STATUS_BAD_INPUT`
/// (`sharpness` negative or not finite). On failure the mesh is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle that no other call is using.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_set_vertex_sharpness(
    mesh: *mut KatachiMesh,
    vertex: u32,
    sharpness: f64,
) -> KatachiStatus {
    guard("katachi_mesh_set_vertex_sharpness", || {
        // SAFETY: the caller's promise above.
        let mesh = unsafe { mesh_mut(mesh) }?;
        let v = check_vertex(mesh, vertex, "vertex")?;
        mesh.set_vertex_sharpness(v, sharpness)?;
        Ok(())
    })
}

/// Copies the sharpness of every vertex (vertex_count doubles) into `sharpness`, a caller's
/// buffer of `capacity` doubles.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL, or `sharpness`
/// NULL when the mesh has vertices); `KATACHI_STATUS_BUFFER_TOO_SMALL` (`capacity` below
/// vertex_count; nothing is written).
///
/// # Safety
/// `mesh` must be NULL or a live handle; `sharpness` NULL or `capacity` writable doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_copy_vertex_sharpness(
    mesh: *const KatachiMesh,
    sharpness: *mut f64,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_mesh_copy_vertex_sharpness", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        let values = mesh.vertex_sharpness();
        let out = unsafe {
            out_buffer(
                sharpness,
                capacity,
                values.len(),
                "sharpness",
                &format_args!("one per vertex; the mesh has {} vertices", values.len()),
            )
        }?;
        out.copy_from_slice(values);
        Ok(())
    })
}

/// Replaces the sharpness of every vertex, all or nothing: `sharpness` holds `count` values,
/// one per vertex, each finite and ≥ 0; `count` must equal the mesh's vertex count.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL, or `sharpness`
/// NULL with `count > 0`); `KATACHI_STATUS_INVALID_ARGUMENT` (`count` is not the vertex count);
/// `KATACHI_STATUS_BAD_INPUT` (a negative or non-finite value; the message names the vertex).
/// On failure the mesh is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle that no other call is using; a non-NULL `sharpness`
/// must hold `count` doubles.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_set_all_vertex_sharpness(
    mesh: *mut KatachiMesh,
    sharpness: *const f64,
    count: usize,
) -> KatachiStatus {
    guard("katachi_mesh_set_all_vertex_sharpness", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_mut(mesh) }?;
        let nv = mesh.vertex_count() as usize;
        if count != nv {
            return Err(FfiError::invalid(format!(
                "count is {count}, but the mesh has {nv} vertices (one value per vertex)"
            )));
        }
        let values = unsafe {
            slice(
                sharpness,
                count,
                "sharpness",
                &format_args!("count is {count}"),
            )
        }?;
        mesh.set_all_vertex_sharpness(values.to_vec())?;
        Ok(())
    })
}

/// A copy of `mesh` whose faces with holes are cut along bridge edges into simple polygons
/// (for hosts that store no faces with holes), in `*out`; `face_origin`, when not NULL, gets
/// the source face of each new face (`capacity` values, at least the new face count, which
/// `katachi_mesh_counts` on the result gives; pass NULL to skip).
///
/// # Safety
/// `mesh` NULL or a live handle; `out` NULL or writable; `face_origin` NULL or writable for
/// `capacity` values.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_split_faces_with_holes(
    mesh: *const KatachiMesh,
    out: *mut *mut KatachiMesh,
    face_origin: *mut u32,
    capacity: usize,
) -> KatachiStatus {
    guard("katachi_mesh_split_faces_with_holes", || {
        // SAFETY: the caller's promises above.
        let out = unsafe { reset_out(out) }?;
        let mesh = unsafe { mesh_ref(mesh) }?;
        let (split, origin) = split_faces_with_holes(mesh)?;
        if !face_origin.is_null() {
            let buf = unsafe {
                out_buffer(
                    face_origin,
                    capacity,
                    origin.len(),
                    "face_origin",
                    &"one per new face",
                )
            }?;
            for (d, f) in buf.iter_mut().zip(&origin) {
                *d = f.0;
            }
        }
        *out = KatachiMesh::into_raw(split);
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------
// Meshes from a host's arrays (Blender's layout: f32 positions, faces by their first corner)

/// Creates a mesh of simple polygons from a host's arrays, as Blender stores a mesh:
///
/// - `positions`: 3 × `vertex_count` floats, `x0 y0 z0 x1 …` (kept as doubles); every value finite;
/// - `face_starts`: `face_count` values, the index of each face's first corner in
///   `corner_vertices`;
/// - `face_sizes`: `face_count` values, the corners of each face (each ≥ 3), or NULL when the
///   faces are stored one after the other: then `face_starts` ascends and each face ends
///   where the next one starts (the last at `corner_count`);
/// - `corner_vertices`: `corner_count` vertex indices; the faces' corners add up to
///   `corner_count`.
///
/// When the faces' corners are not stored face after face, katachi reads them in face order
/// and remembers the host's order: the per-corner calls on results of this mesh
/// (`katachi_subdivision_refine_corner_data_f32`) then read values in the host's order too.
/// The arrays are copied. On success `*out` receives a new mesh (free it with
/// `katachi_mesh_free`); on failure `*out` is NULL.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`out` NULL, or an array NULL
/// with a nonzero count); `KATACHI_STATUS_INVALID_ARGUMENT` (a face's corners outside
/// `corner_vertices`, sizes that do not add up to `corner_count`, starts that do not ascend
/// when `face_sizes` is NULL; the message names the face); `KATACHI_STATUS_BAD_INPUT` (as
/// `katachi_mesh_create`: a non-finite coordinate, an index out of range, a face with fewer
/// than 3 distinct vertices or a repeated vertex).
///
/// # Safety
/// Each non-NULL array must hold the number of elements stated above; `out` must be NULL or
/// point to writable storage for one pointer.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn katachi_mesh_create_polygons_f32(
    positions: *const f32,
    vertex_count: u32,
    face_starts: *const u32,
    face_sizes: *const u32,
    face_count: u32,
    corner_vertices: *const u32,
    corner_count: u32,
    out: *mut *mut KatachiMesh,
) -> KatachiStatus {
    guard("katachi_mesh_create_polygons_f32", || {
        // SAFETY (all blocks): the caller's promises above.
        let out = unsafe { reset_out(out) }?;
        let positions = unsafe {
            slice(
                positions,
                3 * vertex_count as usize,
                "positions",
                &format_args!("vertex_count is {vertex_count}"),
            )
        }?;
        let nf = face_count as usize;
        let starts = unsafe {
            slice(
                face_starts,
                nf,
                "face_starts",
                &format_args!("face_count is {face_count}"),
            )
        }?;
        let sizes = if face_sizes.is_null() {
            None
        } else {
            Some(unsafe { slice(face_sizes, nf, "face_sizes", &"it is not NULL") }?)
        };
        let corners = unsafe {
            slice(
                corner_vertices,
                corner_count as usize,
                "corner_vertices",
                &format_args!("corner_count is {corner_count}"),
            )
        }?;
        let size = |f: usize| -> FfiResult<u32> {
            match sizes {
                Some(s) => Ok(s[f]),
                None => {
                    let end = if f + 1 < nf {
                        starts[f + 1]
                    } else {
                        corner_count
                    };
                    end.checked_sub(starts[f]).ok_or_else(|| {
                        FfiError::invalid(format!(
                            "face_sizes is NULL, so face_starts must ascend, but face {f} starts \
                             at corner {} and face {} at {end}",
                            starts[f],
                            f + 1
                        ))
                    })
                }
            }
        };
        let mut loop_sizes = Vec::with_capacity(nf);
        let mut contiguous = true;
        let mut total = 0u64;
        for (f, &start) in starts.iter().enumerate() {
            let n = size(f)?;
            let end = u64::from(start) + u64::from(n);
            if end > u64::from(corner_count) {
                return Err(FfiError::invalid(format!(
                    "face {f} has corners {start}..{end}, beyond corner_count ({corner_count})"
                )));
            }
            contiguous &= u64::from(start) == total;
            total += u64::from(n);
            loop_sizes.push(n);
        }
        if total != u64::from(corner_count) {
            return Err(FfiError::invalid(format!(
                "the faces have {total} corners in all, but corner_count is {corner_count}"
            )));
        }
        let gathered: Vec<u32>;
        let (corners, host_corners) = if contiguous {
            (corners, None)
        } else {
            let order: Vec<u32> = starts
                .iter()
                .zip(&loop_sizes)
                .flat_map(|(&s, &n)| s..s + n)
                .collect();
            gathered = order.iter().map(|&k| corners[k as usize]).collect();
            (&gathered[..], Some(order))
        };
        let points: Vec<f64> = positions.iter().map(|&x| f64::from(x)).collect();
        let mesh = PolyMesh::from_flat(&points, &loop_sizes, &vec![1; nf], corners)?;
        *out = Box::into_raw(Box::new(KatachiMesh { mesh, host_corners }));
        Ok(())
    })
}

/// Sets edge sharpness from a host's edge list, all or nothing, and counts the host's loose
/// edges:
///
/// - `edges`: 2 × `edge_count` vertex indices (`a0 b0 a1 b1 …`), the host's edges;
/// - `values`: `edge_count` values in `scale` (a `KatachiSharpnessScale`), or NULL to set
///   nothing. Edges whose value is 0 are skipped, and so is an edge that is no side of any
///   face (a loose edge); other edges keep their sharpness;
/// - `corner_edges`: `corner_count` values, the host's edge of each corner (in any order of
///   the corners), or NULL;
/// - `*loose_edges` (when not NULL): how many of the host's edges are no side of any face —
///   counted exactly with `corner_edges` (the edges no corner names), otherwise only among
///   the edges with a nonzero value.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` NULL, or `edges` NULL
/// with `edge_count > 0`); `KATACHI_STATUS_INVALID_ARGUMENT` (a vertex index out of range or
/// an edge with twice the same vertex, named by its position; a corner's edge out of range;
/// `corner_count` not the mesh's; a bad `scale`); `KATACHI_STATUS_BAD_INPUT` (a value outside
/// the scale, named by its edge). On failure the mesh is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle that no other call is using; non-NULL arrays must
/// hold the counts above; `loose_edges` NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn katachi_mesh_set_edge_sharpness_f32(
    mesh: *mut KatachiMesh,
    edges: *const u32,
    values: *const f32,
    edge_count: u32,
    corner_edges: *const u32,
    corner_count: u32,
    scale: u32,
    loose_edges: *mut u32,
) -> KatachiStatus {
    guard("katachi_mesh_set_edge_sharpness_f32", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_mut(mesh) }?;
        let scale = sharpness_scale(scale)?;
        let n = edge_count as usize;
        let why = format_args!("edge_count is {edge_count}");
        let edges = unsafe { slice(edges, 2 * n, "edges", &why) }?;
        let values = if values.is_null() {
            None
        } else {
            Some(unsafe { slice(values, n, "values", &why) }?)
        };
        let corner_edges = if corner_edges.is_null() {
            None
        } else {
            if corner_count != mesh.corner_count() {
                return Err(FfiError::invalid(format!(
                    "corner_count is {corner_count}, but the mesh has {} corners",
                    mesh.corner_count()
                )));
            }
            let c = unsafe {
                slice(
                    corner_edges,
                    corner_count as usize,
                    "corner_edges",
                    &"it is not NULL",
                )
            }?;
            if let Some((k, &e)) = c.iter().enumerate().find(|(_, &e)| e >= edge_count) {
                return Err(FfiError::invalid(format!(
                    "corner_edges[{k}] is {e}, but there are {edge_count} edges"
                )));
            }
            Some(c)
        };
        let mut wanted: Vec<((u32, u32), f64)> = Vec::new();
        let nv = mesh.vertex_count();
        for (i, pair) in edges.chunks_exact(2).enumerate() {
            if pair[0] >= nv || pair[1] >= nv || pair[0] == pair[1] {
                let names = [format!("edges[{}]", 2 * i), format!("edges[{}]", 2 * i + 1)];
                check_edge(mesh, pair[0], pair[1], [&names[0], &names[1]])?;
            }
            if let Some(values) = values {
                let s = scale.to_sharpness(values[i], || {
                    format!("values[{i}] (edge {}-{})", pair[0], pair[1])
                })?;
                if s > 0.0 {
                    wanted.push(((pair[0].min(pair[1]), pair[0].max(pair[1])), s));
                }
            }
        }
        let loose_out = if loose_edges.is_null() {
            None
        } else {
            // Checked before the mesh changes, so a bad pointer leaves it untouched.
            Some(unsafe { deref_mut(loose_edges, "loose_edges") }?)
        };
        let skipped = mesh.set_sharpness_of_existing_edges(
            wanted
                .into_iter()
                .map(|((a, b), s)| (VertexId(a), VertexId(b), s)),
        )?;
        let loose = match corner_edges {
            Some(c) => {
                let mut used = vec![false; n];
                for &e in c {
                    used[e as usize] = true;
                }
                used.iter().filter(|&&u| !u).count() as u32
            }
            None => skipped,
        };
        if let Some(out) = loose_out {
            *out = loose;
        }
        Ok(())
    })
}

/// Replaces the sharpness of every vertex from a host's array, all or nothing: `values`
/// holds `count` values in `scale` (a `KatachiSharpnessScale`), one per vertex; `count` must
/// equal the vertex count.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER`;
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`count` is not the vertex count, a bad `scale`);
/// `KATACHI_STATUS_BAD_INPUT` (a value outside the scale, named by its vertex). On failure
/// the mesh is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle that no other call is using; a non-NULL `values`
/// must hold `count` floats.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_set_vertex_sharpness_f32(
    mesh: *mut KatachiMesh,
    values: *const f32,
    count: u32,
    scale: u32,
) -> KatachiStatus {
    guard("katachi_mesh_set_vertex_sharpness_f32", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_mut(mesh) }?;
        let scale = sharpness_scale(scale)?;
        let nv = mesh.vertex_count();
        if count != nv {
            return Err(FfiError::invalid(format!(
                "count is {count}, but the mesh has {nv} vertices (one value per vertex)"
            )));
        }
        let values = unsafe {
            slice(
                values,
                count as usize,
                "values",
                &format_args!("count is {count}"),
            )
        }?;
        let sharpness = values
            .iter()
            .enumerate()
            .map(|(v, &x)| scale.to_sharpness(x, || format!("values[{v}] (vertex {v})")))
            .collect::<FfiResult<Vec<f64>>>()?;
        mesh.set_all_vertex_sharpness(sharpness)?;
        Ok(())
    })
}
