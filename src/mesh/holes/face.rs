//! One face with holes in local indices (its loops' vertices one after the other), projected
//! exactly onto a coordinate plane, and its validation.

use glam::DVec3;

use super::exact::*;
use crate::error::{Error, Result};
use crate::mesh::{FaceId, PolyMesh, VertexId};

pub(super) struct FaceGeom {
    pub(super) face: FaceId,
    /// Local vertex → mesh vertex.
    pub(super) vid: Vec<VertexId>,
    /// Local vertex → 3D position (for distances).
    pub(super) p3: Vec<DVec3>,
    /// Local vertex → position projected on the face's plane (an exact coordinate drop).
    pub(super) p2: Vec<P2>,
    /// Local vertex → its loop (0 = outer).
    pub(super) loop_of: Vec<u32>,
    /// Loop `k` is local vertices `loops[k].0 .. loops[k].1`.
    pub(super) loops: Vec<(usize, usize)>,
    /// Unit normal (Newell, outer loop), a point on the plane and the face size.
    pub(super) normal: DVec3,
    pub(super) origin: DVec3,
    pub(super) size: f64,
}

impl FaceGeom {
    pub(super) fn new(mesh: &PolyMesh, face: FaceId) -> Result<FaceGeom> {
        let mut vid = Vec::new();
        let mut loops = Vec::new();
        let mut loop_of = Vec::new();
        for (k, l) in mesh.face_loops(face).enumerate() {
            let start = vid.len();
            vid.extend_from_slice(mesh.loop_vertices(l));
            loop_of.resize(vid.len(), k as u32);
            loops.push((start, vid.len()));
        }
        let p3: Vec<DVec3> = vid.iter().map(|&v| mesh.position(v)).collect();
        let (lo, hi) = p3.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let size = (hi - lo).length();
        let outer = &p3[loops[0].0..loops[0].1];
        let origin = outer.iter().sum::<DVec3>() / outer.len() as f64;
        let mut n = DVec3::ZERO;
        for i in 0..outer.len() {
            let (a, b) = (outer[i] - origin, outer[(i + 1) % outer.len()] - origin);
            n += a.cross(b);
        }
        let area = 0.5 * n.length();
        let has_area = size > 0.0 && area > 1e-12 * size * size && area.is_finite();
        if !has_area {
            return Err(Error::InvalidFaceWithHoles {
                face: face.0,
                reason: "the outer loop (loop 0) has zero area, so the face has no plane".into(),
            });
        }
        let normal = n / n.length();
        // Drop the coordinate along which the normal is largest; keep the orientation.
        let na = normal.abs();
        let k = if na.x >= na.y && na.x >= na.z {
            0
        } else if na.y >= na.z {
            1
        } else {
            2
        };
        let (mut i, mut j) = ((k + 1) % 3, (k + 2) % 3);
        if normal[k] < 0.0 {
            std::mem::swap(&mut i, &mut j);
        }
        let p2 = p3.iter().map(|p| [p[i], p[j]]).collect();
        Ok(FaceGeom {
            face,
            vid,
            p3,
            p2,
            loop_of,
            loops,
            normal,
            origin,
            size,
        })
    }

    pub(super) fn n(&self) -> usize {
        self.vid.len()
    }

    /// The next local vertex along its loop (the loop edge `u → next(u)`).
    pub(super) fn next(&self, u: usize) -> usize {
        let (s, e) = self.loops[self.loop_of[u] as usize];
        if u + 1 == e {
            s
        } else {
            u + 1
        }
    }

    pub(super) fn prev(&self, u: usize) -> usize {
        let (s, e) = self.loops[self.loop_of[u] as usize];
        if u == s {
            e - 1
        } else {
            u - 1
        }
    }

    pub(super) fn loop_name(k: u32) -> String {
        if k == 0 {
            "the outer loop (loop 0)".to_string()
        } else {
            format!("hole (loop {k})")
        }
    }

    pub(super) fn edge_name(&self, u: usize) -> String {
        format!("{}-{}", self.vid[u], self.vid[self.next(u)])
    }

    pub(super) fn err(&self, message: String) -> Error {
        Error::InvalidFaceWithHoles {
            face: self.face.0,
            reason: message,
        }
    }

    // -----------------------------------------------------------------------------------------
    // Validation.

    pub(super) fn check(&self, tolerance: f64) -> Result<()> {
        // Coplanarity.
        let limit = tolerance * self.size;
        for u in 0..self.n() {
            let d = (self.p3[u] - self.origin).dot(self.normal).abs();
            if d > limit || !d.is_finite() {
                let k = self.loop_of[u];
                let what = if k == 0 {
                    "the outer loop (loop 0) is not planar".to_string()
                } else {
                    format!("hole (loop {k}) is not coplanar with the face")
                };
                return Err(self.err(format!(
                    "{what}: vertex {} is {} from its plane (face size {}, tolerance {})",
                    self.vid[u],
                    num(d),
                    num(self.size),
                    num(limit)
                )));
            }
        }
        // Loops sharing a vertex touch.
        let mut ids: Vec<(VertexId, u32)> = self
            .vid
            .iter()
            .copied()
            .zip(self.loop_of.iter().copied())
            .collect();
        ids.sort_unstable();
        for w in ids.windows(2) {
            if w[0].0 == w[1].0 {
                return Err(self.err(format!(
                    "{} and {} share vertex {}; \
                     a hole must not touch the outer loop or another hole",
                    Self::loop_name(w[0].1),
                    Self::loop_name(w[1].1),
                    w[0].0
                )));
            }
        }
        // No loop edge meets another except adjacent ones at their shared vertex.
        if let Some((u, v)) = self.first_crossing() {
            let (ku, kv) = (self.loop_of[u], self.loop_of[v]);
            let (u, v, ku, kv) = if (ku, u) <= (kv, v) {
                (u, v, ku, kv)
            } else {
                (v, u, kv, ku)
            };
            let what = if ku == kv {
                format!("{} crosses or touches itself", Self::loop_name(ku))
            } else if ku == 0 {
                format!("hole (loop {kv}) crosses or touches the outer loop")
            } else {
                format!("holes (loops {ku} and {kv}) cross or touch")
            };
            return Err(self.err(format!(
                "{what}: edge {} meets edge {}",
                self.edge_name(u),
                self.edge_name(v)
            )));
        }
        // Holes run clockwise (the loops are simple now, so the turn at an extreme vertex
        // gives the orientation); the outer loop is counter-clockwise by the choice of normal.
        let polys: Vec<Vec<P2>> = self
            .loops
            .iter()
            .map(|&(s, e)| self.p2[s..e].to_vec())
            .collect();
        for (k, poly) in polys.iter().enumerate().skip(1) {
            if simple_polygon_turn(poly) > 0 {
                return Err(self.err(format!(
                    "hole (loop {k}) runs the same way as the outer loop \
                     (counter-clockwise seen from the face's front); holes must run the other way"
                )));
            }
        }
        // Holes inside the outer loop, and not inside each other (spec A9).
        for k in 1..polys.len() {
            if winding(&polys[0], polys[k][0]) == 0 {
                return Err(self.err(format!("hole (loop {k}) lies outside the outer loop")));
            }
            for (j, other) in polys.iter().enumerate().skip(1) {
                if j != k && winding(other, polys[k][0]) != 0 {
                    return Err(self.err(format!(
                        "hole (loop {k}) lies inside hole (loop {j}); nested loops are not \
                         a valid face (an island inside a hole is a face of its own)"
                    )));
                }
            }
        }
        Ok(())
    }

    /// The first pair of loop edges (by their first local vertex) that meet other than at the
    /// shared vertex of two consecutive edges. Sweep and prune along x.
    pub(super) fn first_crossing(&self) -> Option<(usize, usize)> {
        let n = self.n();
        let xmin = |u: usize| self.p2[u][0].min(self.p2[self.next(u)][0]);
        let xmax = |u: usize| self.p2[u][0].max(self.p2[self.next(u)][0]);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| xmin(a).total_cmp(&xmin(b)).then(a.cmp(&b)));
        for (i, &u) in order.iter().enumerate() {
            let hi = xmax(u);
            for &v in &order[i + 1..] {
                if xmin(v) > hi {
                    break;
                }
                if self.edges_meet(u, v) {
                    return Some((u.min(v), u.max(v)));
                }
            }
        }
        None
    }

    /// Whether loop edges `u → next(u)` and `v → next(v)` (u ≠ v) meet improperly.
    pub(super) fn edges_meet(&self, u: usize, v: usize) -> bool {
        let (nu, nv) = (self.next(u), self.next(v));
        let p = &self.p2;
        if !boxes_meet(p[u], p[nu], p[v], p[nv]) {
            return false;
        }
        if nu == v {
            overlap_at_shared(p[v], p[u], p[nv])
        } else if nv == u {
            overlap_at_shared(p[u], p[nu], p[v])
        } else {
            segments_meet(p[u], p[nu], p[v], p[nv])
        }
    }

    // -----------------------------------------------------------------------------------------
    // Bridges.

    /// Direction `x → toward` lies strictly inside the face's angle at loop vertex `x`
    /// (counter-clockwise from the outgoing to the reversed incoming loop edge).
    pub(super) fn in_sector(&self, x: usize, toward: usize) -> bool {
        let p = &self.p2;
        let (px, a, b, d) = (p[x], p[self.next(x)], p[self.prev(x)], p[toward]);
        let turn = orient(px, a, b);
        let o1 = orient(px, a, d);
        let o2 = orient(px, d, b);
        if turn > 0.0 {
            o1 > 0.0 && o2 > 0.0
        } else if turn < 0.0 {
            !(o1 <= 0.0 && o2 <= 0.0)
        } else if !same_direction(px, a, b) {
            o1 > 0.0
        } else {
            !(o1 == 0.0 && same_direction(px, a, d))
        }
    }

    /// A bridge from `s` to `l` (vertices of different loops) lies inside the face: it leaves
    /// both ends into the face and meets no loop edge elsewhere.
    pub(super) fn bridge_ok(&self, s: usize, l: usize) -> bool {
        if !self.in_sector(s, l) || !self.in_sector(l, s) {
            return false;
        }
        let (a, b) = (self.p2[s], self.p2[l]);
        for u in 0..self.n() {
            let nu = self.next(u);
            if u == s || u == l || nu == s || nu == l {
                continue;
            }
            if boxes_meet(a, b, self.p2[u], self.p2[nu])
                && segments_meet(a, b, self.p2[u], self.p2[nu])
            {
                return false;
            }
        }
        true
    }

    /// Two consecutive bridges `s_a → x`, `s_{a+1} → y` bound a proper virtual face between
    /// them: they do not meet, or (A3) they share `x = y` and the triangle turns left.
    pub(super) fn consecutive_ok(&self, sa: usize, x: usize, sb: usize, y: usize) -> bool {
        let p = &self.p2;
        if x == y {
            orient(p[sa], p[sb], p[x]) > 0.0
        } else {
            !(boxes_meet(p[sa], p[x], p[sb], p[y]) && segments_meet(p[sa], p[x], p[sb], p[y]))
        }
    }
}
