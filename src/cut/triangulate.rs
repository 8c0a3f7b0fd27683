//! Input preparation: the paper cuts triangle meshes (seed 002 §2.1), so faces with holes are
//! first split by their bridges (`mesh::holes::split_faces_with_holes`) and polygons are
//! triangulated: a fan when convex, ear clipping otherwise (in the plane of the Newell
//! normal). Written here because the polygons are small and no approved crate does ear
//! clipping on 3D polygons; `spade` would need a constrained triangulation per face.

use std::borrow::Cow;

use glam::{DVec2, DVec3};

use crate::error::Result;
use crate::mesh::holes::split_faces_with_holes;
use crate::mesh::{FaceId, PolyMesh, VertexId};

/// The triangle mesh to cut and, when it differs from the input, each triangle's input face.
pub(crate) struct Triangles<'a> {
    pub mesh: Cow<'a, PolyMesh>,
    /// `None` when the input is already all triangles (triangle `t` is input face `t`).
    pub origin: Option<Vec<FaceId>>,
}

/// Whether every face is one loop of three vertices, in O(1): loops have ≥ 3 corners each
/// (validation), so #corners = 3·#loops means all have exactly 3.
pub(crate) fn is_triangle_mesh(mesh: &PolyMesh) -> bool {
    mesh.loop_count() == mesh.face_count()
        && mesh.corner_count() as u64 == 3 * mesh.loop_count() as u64
}

pub(crate) fn triangles(mesh: &PolyMesh) -> Result<Triangles<'_>> {
    if is_triangle_mesh(mesh) {
        return Ok(Triangles {
            mesh: Cow::Borrowed(mesh),
            origin: None,
        });
    }
    let (simple, split_origin) = split_faces_with_holes(mesh)?;
    let pos = simple.positions();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(simple.corner_count() as usize);
    let mut origin = Vec::with_capacity(simple.corner_count() as usize);
    let mut scratch = Vec::new();
    for f in simple.faces() {
        let lp = simple.face_outer(f);
        let before = tris.len();
        triangulate_polygon(pos, lp, &mut tris, &mut scratch);
        origin.extend(std::iter::repeat_n(
            split_origin[f.idx()],
            tris.len() - before,
        ));
    }
    let out = PolyMesh::from_polygons(pos.to_vec(), tris.iter())?;
    Ok(Triangles {
        mesh: Cow::Owned(out),
        origin: Some(origin),
    })
}

/// Appends the triangles of one simple polygon, keeping its winding.
fn triangulate_polygon(
    pos: &[DVec3],
    lp: &[VertexId],
    out: &mut Vec<[u32; 3]>,
    pts: &mut Vec<DVec2>,
) {
    let n = lp.len();
    if n == 3 {
        out.push([lp[0].0, lp[1].0, lp[2].0]);
        return;
    }
    // Newell normal, then a 2D frame in which the polygon winds counter-clockwise.
    let mut normal = DVec3::ZERO;
    for i in 0..n {
        let (a, b) = (pos[lp[i].idx()], pos[lp[(i + 1) % n].idx()]);
        normal += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let normal = normal.normalize_or_zero();
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    pts.clear();
    pts.extend(lp.iter().map(|&i| {
        let p = pos[i.idx()];
        DVec2::new(p.dot(u), p.dot(v))
    }));
    let turn = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - b);
    let convex = (0..n).all(|i| turn(pts[i], pts[(i + 1) % n], pts[(i + 2) % n]) > 0.0);
    if convex || normal == DVec3::ZERO {
        for i in 1..n - 1 {
            out.push([lp[0].0, lp[i].0, lp[i + 1].0]);
        }
        return;
    }
    // Ear clipping: O(n²) per polygon, fine for the polygons of modelling meshes.
    let mut idx: Vec<usize> = (0..n).collect();
    let mut guard = 0;
    while idx.len() > 3 && guard < 4 * n * n {
        guard += 1;
        let m = idx.len();
        let mut clipped = false;
        for k in 0..m {
            let (ia, ib, ic) = (idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m]);
            let (a, b, c) = (pts[ia], pts[ib], pts[ic]);
            if turn(a, b, c) <= 0.0 {
                continue;
            }
            let inside = idx.iter().any(|&j| {
                if j == ia || j == ib || j == ic {
                    return false;
                }
                let p = pts[j];
                turn(a, b, p) >= 0.0 && turn(b, c, p) >= 0.0 && (a - c).perp_dot(p - a) >= 0.0
            });
            if inside {
                continue;
            }
            out.push([lp[ia].0, lp[ib].0, lp[ic].0]);
            idx.remove(k);
            clipped = true;
            break;
        }
        if !clipped {
            break;
        }
    }
    // What is left (a triangle, or a degenerate remainder) becomes a fan.
    for i in 1..idx.len() - 1 {
        out.push([lp[idx[0]].0, lp[idx[i]].0, lp[idx[i + 1]].0]);
    }
}
