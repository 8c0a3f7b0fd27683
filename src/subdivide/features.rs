//! Sharp edges from a feature angle, for CAD meshes such as fandisk.
//!
//! A triangulated CAD part has no crease data, but its creases are where the surface folds:
//! where the dihedral angle — the angle between the normals of the two faces of an edge —
//! exceeds a threshold. Tagging those edges infinitely sharp ([`INFINITELY_SHARP`], seed 001
//! formulas (3) and (4), DeRose et al. 1998) makes Catmull-Clark keep them as creases.
//!
//! [`feature_edges`] lists the edges; [`tag_feature_edges`] returns a copy of the mesh with
//! them tagged. Face normals are Newell normals (the area vector of all the face's loops,
//! holes subtracting themselves), so polygons and faces with holes get their best-fit plane's
//! normal, not the normal of one corner.
//!
//! ```
//! use katachi::mesh::{shapes, INFINITELY_SHARP};
//! use katachi::subdivide::features::tag_feature_edges;
//! let cube = tag_feature_edges(&shapes::cube(1.0).unwrap(), 30.0).unwrap();
//! assert_eq!(cube.sharp_edges().len(), 12);
//! assert!(cube.sharp_edges().all(|(_, _, s)| s == INFINITELY_SHARP));
//! ```

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{EdgeId, FaceId, PolyMesh, VertexId, INFINITELY_SHARP};

/// The edges whose dihedral angle exceeds `angle_degrees`, as `(min, max)` vertex pairs,
/// sorted.
///
/// The dihedral angle of an edge is the angle between the unit Newell normals of its two
/// faces: 0° where the surface is flat, 90° at a cube's edge. An edge is listed when its
/// angle is strictly greater than `angle_degrees`.
///
/// Not listed: boundary edges (one face; they are sharp already by the boundary rule, spec
/// §4.1), and edges next to a face without a normal (zero area: the angle is undefined).
///
/// Errors: [`Error::InvalidOption`] when `angle_degrees` is NaN or outside (0, 180);
/// [`Error::EmptyMesh`] without faces; [`Error::NonManifoldEdge`] and
/// [`Error::InconsistentOrientation`] from [`PolyMesh::connectivity`], naming the edge
/// (dihedral angles need a consistent orientation).
pub fn feature_edges(mesh: &PolyMesh, angle_degrees: f64) -> Result<Vec<(VertexId, VertexId)>> {
    if !(angle_degrees > 0.0 && angle_degrees < 180.0) {
        return Err(Error::InvalidOption {
            option: "feature angle",
            message: format!("{angle_degrees} degrees is outside (0, 180)"),
        });
    }
    mesh.require_faces("feature-edge detection")?;
    let topo = mesh.connectivity()?;
    let normals: Vec<Option<DVec3>> = mesh.faces().map(|f| face_normal(mesh, f)).collect();
    let threshold = angle_degrees.to_radians();
    let mut edges = Vec::new();
    for e in 0..topo.edge_count() {
        let [h0, h1] = topo.edge_halfedges(EdgeId(e));
        let (f, g) = (topo.face(h0), topo.face(h1));
        if !f.is_valid() || !g.is_valid() || f == g {
            continue;
        }
        let (Some(a), Some(b)) = (normals[f.idx()], normals[g.idx()]) else {
            continue;
        };
        if angle_between(a, b) > threshold {
            let [u, v] = topo.edge_vertices(EdgeId(e));
            edges.push((u.min(v), u.max(v)));
        }
    }
    edges.sort_unstable();
    Ok(edges)
}

/// A copy of `mesh` whose feature edges ([`feature_edges`]) are infinitely sharp
/// ([`INFINITELY_SHARP`]). Sharpness already set is kept: untagged edges keep theirs, and a
/// tagged edge keeps a value above [`INFINITELY_SHARP`] if it had one.
///
/// Errors as [`feature_edges`]; `mesh` is never changed.
pub fn tag_feature_edges(mesh: &PolyMesh, angle_degrees: f64) -> Result<PolyMesh> {
    let edges = feature_edges(mesh, angle_degrees)?;
    let mut out = mesh.clone();
    out.set_edge_sharpnesses(
        edges
            .into_iter()
            .map(|(a, b)| (a, b, mesh.edge_sharpness(a, b).max(INFINITELY_SHARP))),
    )?;
    Ok(out)
}

/// The area vector of face `f` by Newell's formula over all its loops (holes, wound
/// clockwise, subtract themselves), computed relative to the face's first vertex so that
/// meshes far from the origin keep their precision. Its length is the face's area.
pub(crate) fn face_area_vector(mesh: &PolyMesh, f: FaceId) -> DVec3 {
    let origin = mesh.position(mesh.face_outer(f)[0]);
    let mut n = DVec3::ZERO;
    for l in mesh.face_loops(f) {
        n += loop_area_vector(mesh.positions(), mesh.loop_vertices(l), origin);
    }
    0.5 * n
}

/// Twice the area vector of one closed loop (Newell), relative to `origin`.
pub(crate) fn loop_area_vector(positions: &[DVec3], lp: &[VertexId], origin: DVec3) -> DVec3 {
    let mut n = DVec3::ZERO;
    let mut prev = positions[lp[lp.len() - 1].idx()] - origin;
    for v in lp {
        let p = positions[v.idx()] - origin;
        n += prev.cross(p);
        prev = p;
    }
    n
}

/// The unit Newell normal of face `f`, `None` when the face has (numerically) no area.
pub(crate) fn face_normal(mesh: &PolyMesh, f: FaceId) -> Option<DVec3> {
    face_area_vector(mesh, f).try_normalize()
}

/// The angle between two unit vectors, in radians, accurate near 0 and π (atan2 form).
pub(crate) fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}
