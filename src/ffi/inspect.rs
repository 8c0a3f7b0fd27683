//! `katachi_mesh_inspect`: what a caller wants to know about a mesh before working on it.
//! Conversion only; the work is [`crate::mesh::inspect`]'s.

use super::boundary::{guard, guard_value, write_sized};
use super::mesh::{mesh_ref, KatachiMesh};
use super::status::KatachiStatus;

/// Facts about a mesh, filled in by `katachi_mesh_inspect`. Defects are counted, not raised.
///
/// Like every katachi struct that katachi fills in, it starts with `struct_size`: set it to
/// `sizeof(KatachiMeshInfo)` (or start from `katachi_mesh_info_default()`) before the call.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KatachiMeshInfo {
    /// Set by the caller to `sizeof(KatachiMeshInfo)`; katachi leaves it unchanged.
    pub struct_size: u32,
    /// All vertices, referenced or not.
    pub vertex_count: u32,
    /// Vertices no face uses.
    pub unreferenced_vertex_count: u32,
    /// All faces.
    pub face_count: u32,
    /// Faces with at least one hole.
    pub faces_with_holes_count: u32,
    /// Undirected edges.
    pub edge_count: u32,
    /// Edges with a face on one side only.
    pub boundary_edge_count: u32,
    /// Boundary loops (the holes of the surface, not of single faces).
    pub boundary_loop_count: u32,
    /// Connected components of faces.
    pub component_count: u32,
    /// Edges shared by more than two face sides.
    pub non_manifold_edge_count: u32,
    /// Edges that two faces traverse in the same direction (inconsistent orientation).
    pub inconsistent_edge_count: u32,
    /// Vertices whose faces form more than one fan (e.g. two cones touching at the tip).
    pub non_manifold_vertex_count: u32,
    /// Vertices at the same position (to 1e-9) as an earlier vertex.
    pub coincident_vertex_count: u32,
    /// Faces whose area is below 1e-12 × the bounding box diagonal squared.
    pub zero_area_face_count: u32,
    /// Edges with sharpness > 0.
    pub sharp_edge_count: u32,
    /// Vertices with sharpness > 0.
    pub sharp_vertex_count: u32,
    /// V − E + F over referenced vertices, a face with h holes counting 1 − h.
    pub euler_characteristic: i64,
    /// (2 × components − χ) / 2 when the surface is closed and manifold; −1 otherwise.
    pub genus: i64,
    /// No boundary edge.
    pub is_closed: bool,
    /// No non-manifold edge or vertex and consistent orientation.
    pub is_manifold: bool,
    /// Whether the mesh has vertices, and so a bounding box.
    pub has_bounding_box: bool,
    /// Smallest x, y, z over all vertices (0 without vertices).
    pub bounding_box_min: [f64; 3],
    /// Largest x, y, z over all vertices (0 without vertices).
    pub bounding_box_max: [f64; 3],
}

/// The size of the first version of `KatachiMeshInfo`: smaller `struct_size`s are rejected.
const INFO_MIN_SIZE: usize = std::mem::size_of::<KatachiMeshInfo>();

const INFO_DEFAULT: KatachiMeshInfo = KatachiMeshInfo {
    struct_size: std::mem::size_of::<KatachiMeshInfo>() as u32,
    vertex_count: 0,
    unreferenced_vertex_count: 0,
    face_count: 0,
    faces_with_holes_count: 0,
    edge_count: 0,
    boundary_edge_count: 0,
    boundary_loop_count: 0,
    component_count: 0,
    non_manifold_edge_count: 0,
    inconsistent_edge_count: 0,
    non_manifold_vertex_count: 0,
    coincident_vertex_count: 0,
    zero_area_face_count: 0,
    sharp_edge_count: 0,
    sharp_vertex_count: 0,
    euler_characteristic: 0,
    genus: -1,
    is_closed: false,
    is_manifold: false,
    has_bounding_box: false,
    bounding_box_min: [0.0; 3],
    bounding_box_max: [0.0; 3],
};

/// A `KatachiMeshInfo` with `struct_size = sizeof(KatachiMeshInfo)`, counts 0, `genus` −1 and
/// flags false, ready to pass to `katachi_mesh_inspect`.
#[no_mangle]
pub extern "C" fn katachi_mesh_info_default() -> KatachiMeshInfo {
    guard_value("katachi_mesh_info_default", INFO_DEFAULT, || INFO_DEFAULT)
}

/// Gathers facts about a mesh into `*info`: counts, edges, boundary loops, components,
/// Euler characteristic, genus, manifoldness and defects. Never fails on defects: they are
/// counted. The caller sets `info->struct_size` first.
///
/// Statuses: `KATACHI_STATUS_OK`; `KATACHI_STATUS_NULL_POINTER` (`mesh` or `info` NULL);
/// `KATACHI_STATUS_INVALID_ARGUMENT` (`info->struct_size` smaller than the first version of the
/// struct). On failure `*info` is unchanged.
///
/// # Safety
/// `mesh` must be NULL or a live handle; `info` NULL or a writable `KatachiMeshInfo` of at
/// least `info->struct_size` bytes.
#[no_mangle]
pub unsafe extern "C" fn katachi_mesh_inspect(
    mesh: *const KatachiMesh,
    info: *mut KatachiMeshInfo,
) -> KatachiStatus {
    guard("katachi_mesh_inspect", || {
        // SAFETY: the caller's promises above.
        let mesh = unsafe { mesh_ref(mesh) }?;
        // Check `info` before the (linear-time) work.
        super::boundary::check_ptr(info, "info")?;
        let r = crate::mesh::inspect(mesh)?;
        let (lo, hi) = r.bounding_box.unwrap_or_default();
        let value = KatachiMeshInfo {
            struct_size: 0, // not written: the caller's value stays
            vertex_count: r.vertices,
            unreferenced_vertex_count: r.unreferenced_vertices,
            face_count: r.faces,
            faces_with_holes_count: r.faces_with_holes,
            edge_count: r.edges,
            boundary_edge_count: r.boundary_edges,
            boundary_loop_count: r.boundary_loops,
            component_count: r.components,
            non_manifold_edge_count: r.defects.non_manifold_edges.len() as u32,
            inconsistent_edge_count: r.defects.inconsistent_edges.len() as u32,
            non_manifold_vertex_count: r.defects.non_manifold_vertices.len() as u32,
            coincident_vertex_count: r.coincident_vertices,
            zero_area_face_count: r.zero_area_faces.len() as u32,
            sharp_edge_count: r.sharp_edges,
            sharp_vertex_count: r.sharp_vertices,
            euler_characteristic: r.euler_characteristic,
            genus: r.genus.unwrap_or(-1),
            is_closed: r.is_closed(),
            is_manifold: r.is_manifold(),
            has_bounding_box: r.bounding_box.is_some(),
            bounding_box_min: lo.to_array(),
            bounding_box_max: hi.to_array(),
        };
        unsafe { write_sized(info, value, INFO_MIN_SIZE, "info", "KatachiMeshInfo") }
    })
}
