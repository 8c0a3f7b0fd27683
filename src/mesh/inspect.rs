//! [`inspect`]: what a user wants to know about a mesh before working on it — counts,
//! boundaries, components, manifoldness, defects — without failing on defects.

use std::collections::BTreeMap;

use glam::DVec3;

use super::ids::{FaceId, VertexId};
use super::polymesh::PolyMesh;
use super::topology::{Defects, Topology, TopologyOptions};
use crate::error::Result;

/// The facts [`inspect`] gathers. Defects are listed, not raised.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshReport {
    /// All vertices, referenced or not.
    pub vertices: u32,
    /// Vertices no face uses.
    pub unreferenced_vertices: u32,
    /// All faces.
    pub faces: u32,
    /// Faces by the size of their outer loop: `{3: triangles, 4: quads, …}`.
    pub faces_by_size: BTreeMap<u32, u32>,
    /// Faces with at least one hole.
    pub faces_with_holes: u32,
    /// Undirected edges.
    pub edges: u32,
    /// Edges with a face on one side only.
    pub boundary_edges: u32,
    /// Boundary curves: connected components of the boundary edges, joined at shared
    /// vertices. Equals the number of boundary half-edge cycles on a manifold mesh; where
    /// two boundary cycles touch at a non-manifold vertex they count as one curve.
    pub boundary_loops: u32,
    /// Connected components of faces.
    pub components: u32,
    /// Non-manifold edges, inconsistent edges and non-manifold vertices.
    pub defects: Defects,
    /// Vertices at the same position (to 1e-9) as an earlier vertex.
    pub coincident_vertices: u32,
    /// Faces whose area is below 1e-12 × the bounding box diagonal squared.
    pub zero_area_faces: Vec<FaceId>,
    /// V − E + F over referenced vertices, faces with h holes counting 1 − h.
    pub euler_characteristic: i64,
    /// Genus, when the surface is closed and manifold: (2 × components − χ) / 2.
    pub genus: Option<i64>,
    /// Axis-aligned bounding box, `None` without vertices.
    pub bounding_box: Option<(DVec3, DVec3)>,
    /// Edges with sharpness > 0.
    pub sharp_edges: u32,
    /// Vertices with sharpness > 0.
    pub sharp_vertices: u32,
}

impl MeshReport {
    /// No boundary edge.
    pub fn is_closed(&self) -> bool {
        self.boundary_edges == 0
    }
    /// No non-manifold edge or vertex and consistent orientation.
    pub fn is_manifold(&self) -> bool {
        self.defects.is_empty()
    }
}

/// Gathers a [`MeshReport`]. Never fails on defects: they are tolerated and listed.
pub fn inspect(mesh: &PolyMesh) -> Result<MeshReport> {
    let topo = Topology::build(mesh, &TopologyOptions::tolerant())?;
    let mut faces_by_size = BTreeMap::new();
    let mut faces_with_holes = 0;
    for f in mesh.faces() {
        *faces_by_size
            .entry(mesh.face_outer(f).len() as u32)
            .or_insert(0) += 1;
        if mesh.face_loop_count(f) > 1 {
            faces_with_holes += 1;
        }
    }
    let boundary_edges = (0..topo.edge_count())
        .filter(|&e| topo.is_boundary_edge(super::EdgeId(e)))
        .count() as u32;
    let (components, _) = topo.face_components();
    let euler = topo.euler_characteristic(mesh);
    let defects = topo.defects().clone();
    let genus = (boundary_edges == 0 && defects.is_empty() && components > 0)
        .then(|| (2 * components as i64 - euler) / 2);
    let bounding_box = mesh.bounding_box();
    Ok(MeshReport {
        vertices: mesh.vertex_count(),
        unreferenced_vertices: mesh.vertex_count() - topo.referenced_vertex_count(),
        faces: mesh.face_count(),
        faces_by_size,
        faces_with_holes,
        edges: topo.edge_count(),
        boundary_edges,
        boundary_loops: boundary_curves(&topo),
        components,
        defects,
        coincident_vertices: coincident_vertices(mesh.positions()),
        zero_area_faces: zero_area_faces(mesh, bounding_box),
        euler_characteristic: euler,
        genus,
        bounding_box,
        sharp_edges: mesh.sharp_edges().len() as u32,
        sharp_vertices: mesh.vertex_sharpness().iter().filter(|&&s| s > 0.0).count() as u32,
    })
}

fn boundary_curves(topo: &Topology) -> u32 {
    let n = topo.vertex_count() as usize;
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let mut on_boundary = vec![false; n];
    fn root(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for e in 0..topo.edge_count() {
        let e = super::EdgeId(e);
        if topo.is_boundary_edge(e) {
            let [a, b] = topo.edge_vertices(e);
            on_boundary[a.idx()] = true;
            on_boundary[b.idx()] = true;
            let (ra, rb) = (root(&mut parent, a.0), root(&mut parent, b.0));
            parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
    (0..n as u32)
        .filter(|&v| on_boundary[v as usize] && root(&mut parent, v) == v)
        .count() as u32
}

fn coincident_vertices(positions: &[DVec3]) -> u32 {
    let mut keys: Vec<[i64; 3]> = positions
        .iter()
        .map(|p| [p.x, p.y, p.z].map(|c| (c * 1e9).round() as i64))
        .collect();
    keys.sort_unstable();
    keys.windows(2).filter(|w| w[0] == w[1]).count() as u32
}

/// Area vector of a face by Newell's formula over all its loops (holes, wound clockwise,
/// subtract themselves), relative to the face's first vertex so that precision does not
/// depend on the distance from the origin.
pub(crate) fn face_area_vector(mesh: &PolyMesh, f: FaceId) -> DVec3 {
    let origin = mesh.position(mesh.face_outer(f)[0]);
    let mut n = DVec3::ZERO;
    for l in mesh.face_loops(f) {
        let lp = mesh.loop_vertices(l);
        for (i, &a) in lp.iter().enumerate() {
            let b: VertexId = lp[(i + 1) % lp.len()];
            n += (mesh.position(a) - origin).cross(mesh.position(b) - origin);
        }
    }
    0.5 * n
}

fn zero_area_faces(mesh: &PolyMesh, bbox: Option<(DVec3, DVec3)>) -> Vec<FaceId> {
    let Some((lo, hi)) = bbox else {
        return Vec::new();
    };
    let eps = 1e-12 * (hi - lo).length_squared();
    mesh.faces()
        .filter(|&f| face_area_vector(mesh, f).length() <= eps)
        .collect()
}
