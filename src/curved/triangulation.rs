//! The working triangulation of the linear domain Ω_lin (spec §4.2): the candidate dual of
//! the anisotropic Voronoi diagram of the sites, constrained to contain every guard edge.
//!
//! Triangles are counter-clockwise; half-edge `h = 3t + i` of triangle `t` runs from
//! `vert[h]` to `vert[next(h)]`, `twin[h]` is the opposite half-edge (or [`NONE`] on the
//! domain's boundary), and `cons[h]` names the constraint (a guard edge) it lies on. Dead
//! triangles are reused. Every combinatorial decision uses exact `orient2d`
//! ([`super::predicates`]); the metric decides only *which* valid triangulation is built.
//!
//! Insertion is the anisotropic Bowyer–Watson kernel (spec §4.2): the new site `p` takes
//! over every triangle whose Voronoi vertex it is nearer to, in its own metric, than the
//! triangle's sites are (`d_p(c) < r`); the cavity never crosses a constraint, is cut back
//! until it is star-shaped from `p` and swallows no vertex, and is refilled as a fan.

use glam::DVec2;

use super::predicates::orient;
use super::tensor::Metric2;
use super::voronoi::voronoi_vertex;

/// "No element".
pub(crate) const NONE: u32 = u32::MAX;

#[inline]
pub(crate) fn tri_of(h: u32) -> u32 {
    h / 3
}

#[inline]
pub(crate) fn next(h: u32) -> u32 {
    if h % 3 == 2 {
        h - 2
    } else {
        h + 1
    }
}

#[inline]
pub(crate) fn prev(h: u32) -> u32 {
    if h.is_multiple_of(3) {
        h + 2
    } else {
        h - 1
    }
}

/// A guard edge of Ω_lin that must stay an edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Constraint {
    /// Its vertices: the region is on the left of `a → b`.
    pub a: u32,
    pub b: u32,
    /// The half-edge `a → b` currently on it (its triangle is on the region's side).
    pub half: u32,
    /// The curve piece whose guard chain it belongs to.
    pub piece: u32,
    /// `false`: the piece's left guard chain; `true`: its right one.
    pub right_side: bool,
    /// The metric at its midpoint, for the encroachment test (spec §4.3 rule 1).
    pub metric: Metric2,
    pub alive: bool,
}

/// Where a walk ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Located {
    /// Strictly inside triangle `t`.
    Inside(u32),
    /// On the interior of the edge of half-edge `h`.
    OnEdge(u32),
    /// On vertex `v`.
    OnVertex(u32),
    /// Beyond the constraint or boundary half-edge `h`: the walk would have to cross it.
    Blocked(u32),
}

/// A cavity ready to be refilled.
#[derive(Debug, Default)]
pub(crate) struct Cavity {
    pub tris: Vec<u32>,
    /// Boundary half-edges (inside the cavity, twins outside), in no particular order.
    pub boundary: Vec<u32>,
}

#[derive(Debug, Default)]
pub(crate) struct Triangulation {
    pub pos: Vec<DVec2>,
    pub metric: Vec<Metric2>,
    /// Per half-edge.
    pub vert: Vec<u32>,
    pub twin: Vec<u32>,
    pub cons: Vec<u32>,
    /// Per triangle.
    pub alive: Vec<bool>,
    pub region: Vec<u32>,
    pub generation: Vec<u32>,
    pub center: Vec<DVec2>,
    pub radius2: Vec<f64>,
    pub exact_center: Vec<bool>,
    pub constraints: Vec<Constraint>,
    free: Vec<u32>,
    stamp: Vec<u32>,
    stamp_now: u32,
    rng: u64,
    pub alive_count: usize,
    /// Voronoi vertices that fell back to the mean-metric circumcentre.
    pub inexact_centers: u64,
}

impl Triangulation {
    pub fn new() -> Self {
        Triangulation {
            rng: 0x9E37_79B9_7F4A_7C15,
            ..Default::default()
        }
    }

    pub fn add_vertex(&mut self, p: DVec2, m: Metric2) -> u32 {
        self.pos.push(p);
        self.metric.push(m);
        self.pos.len() as u32 - 1
    }

    pub fn vertex_count(&self) -> usize {
        self.pos.len()
    }

    pub fn triangle_slots(&self) -> usize {
        self.alive.len()
    }

    /// The three vertices of triangle `t`.
    #[inline]
    pub fn tri(&self, t: u32) -> [u32; 3] {
        let h = 3 * t as usize;
        [self.vert[h], self.vert[h + 1], self.vert[h + 2]]
    }

    /// The three corner positions of triangle `t`.
    #[cfg(test)]
    pub fn tri_pos(&self, t: u32) -> [DVec2; 3] {
        self.tri(t).map(|v| self.pos[v as usize])
    }

    /// The end vertex of half-edge `h`.
    #[inline]
    pub fn dest(&self, h: u32) -> u32 {
        self.vert[next(h) as usize]
    }

    /// The vertex opposite half-edge `h` in its triangle.
    #[inline]
    pub fn apex(&self, h: u32) -> u32 {
        self.vert[prev(h) as usize]
    }

    fn next_rand(&mut self) -> u64 {
        // xorshift64: a fixed sequence, so runs repeat bit for bit.
        let mut x = self.rng;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.rng = x;
        x
    }

    /// A fresh triangle slot with vertices `(a, b, c)` (counter-clockwise), no twins, no
    /// constraints, its Voronoi vertex computed.
    pub fn new_triangle(&mut self, a: u32, b: u32, c: u32, region: u32) -> u32 {
        let t = match self.free.pop() {
            Some(t) => t,
            None => {
                let t = self.alive.len() as u32;
                self.vert.extend([NONE; 3]);
                self.twin.extend([NONE; 3]);
                self.cons.extend([NONE; 3]);
                self.alive.push(false);
                self.region.push(NONE);
                self.generation.push(0);
                self.center.push(DVec2::ZERO);
                self.radius2.push(0.0);
                self.exact_center.push(false);
                self.stamp.push(0);
                t
            }
        };
        let h = 3 * t as usize;
        self.vert[h] = a;
        self.vert[h + 1] = b;
        self.vert[h + 2] = c;
        self.twin[h..h + 3].fill(NONE);
        self.cons[h..h + 3].fill(NONE);
        self.alive[t as usize] = true;
        self.region[t as usize] = region;
        self.generation[t as usize] = self.generation[t as usize].wrapping_add(1);
        self.alive_count += 1;
        self.update_center(t);
        t
    }

    /// Recomputes the Voronoi vertex of `t` from its sites.
    pub fn update_center(&mut self, t: u32) {
        let v = self.tri(t);
        let p = v.map(|i| self.pos[i as usize]);
        let m = v.map(|i| self.metric[i as usize]);
        match voronoi_vertex(&p, &m) {
            Some(c) => {
                self.center[t as usize] = c.center;
                self.radius2[t as usize] = c.radius2;
                self.exact_center[t as usize] = c.exact;
                if !c.exact {
                    self.inexact_centers += 1;
                }
            }
            None => {
                // Collinear in the metric: a degenerate triangle takes part in every cavity
                // that reaches it.
                self.center[t as usize] = (p[0] + p[1] + p[2]) / 3.0;
                self.radius2[t as usize] = f64::INFINITY;
                self.exact_center[t as usize] = false;
            }
        }
    }

    pub fn kill_triangle(&mut self, t: u32) {
        debug_assert!(self.alive[t as usize]);
        self.alive[t as usize] = false;
        self.generation[t as usize] = self.generation[t as usize].wrapping_add(1);
        self.alive_count -= 1;
        self.free.push(t);
    }

    /// Makes `h` and `g` twins (either may be [`NONE`]).
    #[inline]
    pub fn link(&mut self, h: u32, g: u32) {
        if h != NONE {
            self.twin[h as usize] = g;
        }
        if g != NONE {
            self.twin[g as usize] = h;
        }
    }

    /// Puts constraint `c` (or none) on half-edge `h`, keeping the constraint's record in step.
    #[inline]
    pub fn set_cons(&mut self, h: u32, c: u32) {
        self.cons[h as usize] = c;
        if c != NONE && self.vert[h as usize] == self.constraints[c as usize].a {
            self.constraints[c as usize].half = h;
        }
    }

    /// Walks from triangle `start` to `p` (a randomized visibility walk, which ends on any
    /// triangulation; Devillers, Pion & Teillaud 2002), never crossing a constraint or the
    /// boundary.
    pub fn locate(&mut self, p: DVec2, start: u32) -> Located {
        let mut t = start;
        let limit = 4 * self.alive_count + 64;
        for _ in 0..limit {
            let r = (self.next_rand() % 3) as u32;
            let mut moved = false;
            for k in 0..3 {
                let h = 3 * t + (r + k) % 3;
                let a = self.pos[self.vert[h as usize] as usize];
                let b = self.pos[self.dest(h) as usize];
                if orient(a, b, p) < 0.0 {
                    let g = self.twin[h as usize];
                    if g == NONE || self.cons[h as usize] != NONE {
                        return Located::Blocked(h);
                    }
                    t = tri_of(g);
                    moved = true;
                    break;
                }
            }
            if !moved {
                let mut zeros = [NONE; 3];
                let mut n = 0;
                for i in 0..3 {
                    let h = 3 * t + i;
                    let a = self.pos[self.vert[h as usize] as usize];
                    let b = self.pos[self.dest(h) as usize];
                    if orient(a, b, p) == 0.0 {
                        zeros[n] = h;
                        n += 1;
                    }
                }
                return match n {
                    0 => Located::Inside(t),
                    1 => Located::OnEdge(zeros[0]),
                    _ => {
                        // On two edges: their common vertex.
                        let (h0, h1) = (zeros[0], zeros[1]);
                        let v = if self.vert[h0 as usize] == self.dest(h1) {
                            self.vert[h0 as usize]
                        } else {
                            self.vert[h1 as usize]
                        };
                        Located::OnVertex(v)
                    }
                };
            }
        }
        // Unreachable on a valid triangulation; report the last triangle's first edge.
        Located::Blocked(3 * t)
    }

    fn bump_stamp(&mut self) -> u32 {
        self.stamp_now = self.stamp_now.wrapping_add(1);
        if self.stamp_now == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.stamp_now = 1;
        }
        self.stamp_now
    }

    /// Whether `p` with metric `m` takes over triangle `t`'s Voronoi vertex.
    #[inline]
    fn conflicts(&self, t: u32, p: DVec2, m: &Metric2) -> bool {
        m.norm_sq(self.center[t as usize] - p) < self.radius2[t as usize]
    }

    /// The cavity of a new site `p` (metric `m`) whose location `seeds` are the triangle(s)
    /// holding it: conflicting triangles reachable from the seeds without crossing a
    /// constraint, cut back to a star-shaped polygon around `p` that swallows no vertex.
    ///
    /// `skip` is a constraint half-edge `p` lies on (a guard edge being split at `p`), or
    /// [`NONE`]: it stays on the cavity's boundary and the refill leaves it out.
    pub fn cavity(&mut self, p: DVec2, m: &Metric2, seeds: &[u32], skip: u32, out: &mut Cavity) {
        out.tris.clear();
        out.boundary.clear();
        let mut mark = self.bump_stamp();
        for &s in seeds {
            self.stamp[s as usize] = mark;
            out.tris.push(s);
        }
        let mut i = 0;
        while i < out.tris.len() {
            let t = out.tris[i];
            i += 1;
            for k in 0..3 {
                let h = 3 * t + k;
                let g = self.twin[h as usize];
                if g == NONE || self.cons[h as usize] != NONE {
                    continue;
                }
                let u = tri_of(g);
                if self.stamp[u as usize] != mark && self.conflicts(u, p, m) {
                    self.stamp[u as usize] = mark;
                    out.tris.push(u);
                }
            }
        }
        // Cut back until star-shaped and no vertex is swallowed.
        loop {
            let mut remove: Option<u32> = None;
            out.boundary.clear();
            for &t in &out.tris {
                for k in 0..3 {
                    let h = 3 * t + k;
                    let g = self.twin[h as usize];
                    if g == NONE || self.stamp[tri_of(g) as usize] != mark {
                        out.boundary.push(h);
                    }
                }
            }
            for &h in &out.boundary {
                let t = tri_of(h);
                if h == skip || seeds.contains(&t) {
                    continue;
                }
                let a = self.pos[self.vert[h as usize] as usize];
                let b = self.pos[self.dest(h) as usize];
                if orient(a, b, p) <= 0.0 {
                    remove = Some(t);
                    break;
                }
            }
            if remove.is_none() {
                remove = self.swallowing_triangle(&out.tris, &out.boundary, seeds);
            }
            let Some(r) = remove else {
                return;
            };
            // Drop r and keep what stays connected to the seeds.
            let cand = self.bump_stamp();
            for &t in &out.tris {
                if t != r {
                    self.stamp[t as usize] = cand;
                }
            }
            out.tris.clear();
            mark = self.bump_stamp();
            for &s in seeds {
                self.stamp[s as usize] = mark;
                out.tris.push(s);
            }
            let mut i = 0;
            while i < out.tris.len() {
                let t = out.tris[i];
                i += 1;
                for k in 0..3 {
                    let h = 3 * t + k;
                    let g = self.twin[h as usize];
                    if g == NONE || self.cons[h as usize] != NONE {
                        continue;
                    }
                    let u = tri_of(g);
                    if self.stamp[u as usize] == cand {
                        self.stamp[u as usize] = mark;
                        out.tris.push(u);
                    }
                }
            }
        }
    }

    /// A non-seed cavity triangle around a vertex that is on no boundary edge (it would be
    /// lost by the refill), if any.
    fn swallowing_triangle(&self, tris: &[u32], boundary: &[u32], seeds: &[u32]) -> Option<u32> {
        if tris.len() < 3 {
            return None;
        }
        let on_boundary = |v: u32| boundary.iter().any(|&h| self.vert[h as usize] == v);
        for &t in tris {
            for v in self.tri(t) {
                if !on_boundary(v) {
                    // Remove a non-seed triangle around v: the first in cavity order.
                    return tris
                        .iter()
                        .copied()
                        .find(|&u| !seeds.contains(&u) && self.tri(u).contains(&v));
                }
            }
        }
        None
    }

    /// Replaces the cavity by a fan of triangles around the new vertex `v` (inside it, or on
    /// the boundary half-edge `skip`, which gets no triangle). Returns the new triangles.
    pub fn fill(&mut self, v: u32, cav: &Cavity, skip: u32, out: &mut Vec<u32>) {
        out.clear();
        // Save each boundary edge before its triangle is reused.
        let edges: Vec<(u32, u32, u32, u32, u32)> = cav
            .boundary
            .iter()
            .filter(|&&h| h != skip)
            .map(|&h| {
                (
                    self.vert[h as usize],
                    self.dest(h),
                    self.twin[h as usize],
                    self.cons[h as usize],
                    self.region[tri_of(h) as usize],
                )
            })
            .collect();
        for &t in &cav.tris {
            self.kill_triangle(t);
        }
        for &(a, b, tw, c, region) in &edges {
            let t = self.new_triangle(a, b, v, region);
            let h = 3 * t;
            self.link(h, tw);
            self.set_cons(h, c);
            out.push(t);
        }
        // Fan edges: (b → v) of the triangle on edge (a, b) meets (v → b) of the one on (b, c).
        for i in 0..out.len() {
            let t = out[i];
            let b = self.vert[3 * t as usize + 1];
            // Around a skipped edge the fan is open: (b → v) stays a boundary.
            if let Some(j) = (0..out.len()).find(|&j| self.vert[3 * out[j] as usize] == b) {
                let u = out[j];
                self.link(3 * t + 1, 3 * u + 2);
            }
        }
    }

    /// Inserts vertex `v` (already added) at its located position: the common path of
    /// refinement and of the initial build.
    pub fn insert_located(
        &mut self,
        v: u32,
        loc: Located,
        cav: &mut Cavity,
        out: &mut Vec<u32>,
    ) -> bool {
        let seeds: Vec<u32> = match loc {
            Located::Inside(t) => vec![t],
            Located::OnEdge(h) => {
                if self.cons[h as usize] != NONE {
                    return false;
                }
                let g = self.twin[h as usize];
                if g == NONE {
                    return false;
                }
                vec![tri_of(h), tri_of(g)]
            }
            Located::OnVertex(_) | Located::Blocked(_) => return false,
        };
        let p = self.pos[v as usize];
        let m = self.metric[v as usize];
        self.cavity(p, &m, &seeds, NONE, cav);
        self.fill(v, cav, NONE, out);
        true
    }

    /// Flips the edge of half-edge `h` (its quadrilateral must be strictly convex; checked
    /// by the caller). Returns the half-edge on the new diagonal in `h`'s old triangle.
    pub fn flip(&mut self, h: u32) -> u32 {
        let g = self.twin[h as usize];
        debug_assert!(g != NONE && self.cons[h as usize] == NONE);
        let (t1, t2) = (tri_of(h), tri_of(g));
        let (h1, h2) = (next(h), prev(h));
        let (g1, g2) = (next(g), prev(g));
        let a = self.vert[h as usize];
        let b = self.vert[g as usize];
        let c = self.vert[h2 as usize];
        let d = self.vert[g2 as usize];
        // Outer half-edges: (b→c), (c→a), (a→d), (d→b).
        let outer = |s: &Self, x: u32| (s.twin[x as usize], s.cons[x as usize]);
        let (bc, ca, ad, db) = (
            outer(self, h1),
            outer(self, h2),
            outer(self, g1),
            outer(self, g2),
        );
        let (r1, r2) = (self.region[t1 as usize], self.region[t2 as usize]);
        // t1 becomes (a, d, c), t2 becomes (d, b, c).
        for (t, vs, reg) in [(t1, [a, d, c], r1), (t2, [d, b, c], r2)] {
            let base = 3 * t as usize;
            self.vert[base..base + 3].copy_from_slice(&vs);
            self.region[t as usize] = reg;
            self.generation[t as usize] = self.generation[t as usize].wrapping_add(1);
        }
        let (e0, e1, e2) = (3 * t1, 3 * t1 + 1, 3 * t1 + 2);
        let (f0, f1, f2) = (3 * t2, 3 * t2 + 1, 3 * t2 + 2);
        self.link(e0, ad.0);
        self.set_cons(e0, ad.1);
        self.link(e2, ca.0);
        self.set_cons(e2, ca.1);
        self.link(f0, db.0);
        self.set_cons(f0, db.1);
        self.link(f1, bc.0);
        self.set_cons(f1, bc.1);
        self.link(e1, f2);
        self.set_cons(e1, NONE);
        self.set_cons(f2, NONE);
        self.update_center(t1);
        self.update_center(t2);
        e1
    }

    /// Whether the edge of `h` should flip: the vertex across it lies inside the circumcircle
    /// of `h`'s triangle, both measured in the mean metric of the four vertices (a symmetric
    /// test, so repeated flips end as Lawson's do). Constraints never flip.
    pub fn should_flip(&self, h: u32) -> bool {
        let g = self.twin[h as usize];
        if g == NONE || self.cons[h as usize] != NONE {
            return false;
        }
        let v = [
            self.vert[h as usize],
            self.dest(h),
            self.apex(h),
            self.apex(g),
        ];
        let m = v.iter().fold(Metric2::new(0.0, 0.0, 0.0), |acc, &i| {
            acc.add(&self.metric[i as usize])
        });
        let Some(f) = m.cholesky() else { return false };
        let o = self.pos[v[0] as usize];
        let q = v.map(|i| f.apply(self.pos[i as usize] - o));
        let c = |p: DVec2| robust::Coord { x: p.x, y: p.y };
        robust::incircle(c(q[0]), c(q[1]), c(q[2]), c(q[3])) > 0.0
    }

    /// Lawson's flips from the edges `stack` (half-edges with their triangle's generation):
    /// flips every edge that [`Self::should_flip`] and can, then checks the four edges around
    /// the new diagonal, at most `limit` flips. Changed triangles go to `touched`.
    pub fn legalize(&mut self, stack: &mut Vec<(u32, u32)>, touched: &mut Vec<u32>, limit: usize) {
        let mut flips = 0;
        while let Some((h, gen)) = stack.pop() {
            let t = tri_of(h);
            if !self.alive[t as usize] || self.generation[t as usize] != gen {
                continue;
            }
            if !self.should_flip(h) || !self.flippable(h) {
                continue;
            }
            if flips >= limit {
                stack.clear();
                return;
            }
            flips += 1;
            let g = self.twin[h as usize];
            let (t1, t2) = (tri_of(h), tri_of(g));
            self.flip(h);
            touched.push(t1);
            touched.push(t2);
            for t in [t1, t2] {
                for k in 0..3 {
                    stack.push((3 * t + k, self.generation[t as usize]));
                }
            }
        }
    }

    /// Whether the quadrilateral around the edge of `h` is strictly convex (so it can flip).
    pub fn flippable(&self, h: u32) -> bool {
        let g = self.twin[h as usize];
        if g == NONE || self.cons[h as usize] != NONE {
            return false;
        }
        let a = self.pos[self.vert[h as usize] as usize];
        let b = self.pos[self.vert[g as usize] as usize];
        let c = self.pos[self.apex(h) as usize];
        let d = self.pos[self.apex(g) as usize];
        orient(c, d, b) > 0.0 && orient(d, c, a) > 0.0
    }
}

/// Triangulates the simple counter-clockwise polygon `poly` (vertex ids, positions in
/// `pos`) by ear clipping with exact predicates; returns triangles as vertex triples, or
/// `None` if the polygon is not simple. With `metric`, each step clips the ear whose
/// anisotropic Voronoi vertex no other polygon vertex is nearer to (the ear a Voronoi
/// refinement would keep), or failing that the ear of smallest radius.
pub(crate) fn ear_clip(
    poly: &[u32],
    pos: &[DVec2],
    metric: Option<&[Metric2]>,
) -> Option<Vec<[u32; 3]>> {
    let mut ring: Vec<u32> = poly.to_vec();
    let mut out = Vec::with_capacity(ring.len().saturating_sub(2));
    let p = |v: u32| pos[v as usize];
    while ring.len() > 3 {
        let n = ring.len();
        // (empty, radius², index) of the best ear so far.
        let mut best: Option<(bool, f64, usize)> = None;
        for i in 0..n {
            let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            if orient(p(a), p(b), p(c)) <= 0.0 {
                continue;
            }
            let blocked = ring.iter().any(|&v| {
                v != a
                    && v != b
                    && v != c
                    && orient(p(a), p(b), p(v)) >= 0.0
                    && orient(p(b), p(c), p(v)) >= 0.0
                    && orient(p(c), p(a), p(v)) >= 0.0
            });
            if blocked {
                continue;
            }
            let Some(m) = metric else {
                best = Some((true, 0.0, i));
                break;
            };
            let vv = voronoi_vertex(
                &[p(a), p(b), p(c)],
                &[m[a as usize], m[b as usize], m[c as usize]],
            );
            let (empty, r2) = match vv {
                Some(x) => (
                    ring.iter().all(|&w| {
                        w == a
                            || w == b
                            || w == c
                            || m[w as usize].norm_sq(x.center - p(w)) >= x.radius2
                    }),
                    x.radius2,
                ),
                None => (false, f64::INFINITY),
            };
            let better = match best {
                None => true,
                Some((be, br, _)) => (empty && !be) || (empty == be && r2 < br),
            };
            if better {
                best = Some((empty, r2, i));
            }
        }
        let (_, _, i) = best?;
        let n = ring.len();
        out.push([ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]]);
        ring.remove(i);
    }
    if orient(p(ring[0]), p(ring[1]), p(ring[2])) <= 0.0 {
        return None;
    }
    out.push([ring[0], ring[1], ring[2]]);
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks twins, orientation and constraint records of every live triangle.
    pub(crate) fn check(tr: &Triangulation) {
        for t in 0..tr.triangle_slots() as u32 {
            if !tr.alive[t as usize] {
                continue;
            }
            let [a, b, c] = tr.tri_pos(t);
            assert!(
                orient(a, b, c) > 0.0,
                "triangle {t} is not counter-clockwise"
            );
            for k in 0..3 {
                let h = 3 * t + k;
                let g = tr.twin[h as usize];
                if g != NONE {
                    assert!(tr.alive[tri_of(g) as usize]);
                    assert_eq!(tr.twin[g as usize], h);
                    assert_eq!(tr.vert[g as usize], tr.dest(h));
                    assert_eq!(tr.dest(g), tr.vert[h as usize]);
                }
                let c = tr.cons[h as usize];
                if c != NONE {
                    assert_eq!(tr.constraints[c as usize].half, h);
                }
            }
        }
    }

    #[test]
    fn insert_into_a_square() {
        let mut tr = Triangulation::new();
        let m = Metric2::IDENTITY;
        let v: Vec<u32> = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .iter()
            .map(|&(x, y)| tr.add_vertex(DVec2::new(x, y), m))
            .collect();
        let t0 = tr.new_triangle(v[0], v[1], v[2], 0);
        let t1 = tr.new_triangle(v[0], v[2], v[3], 0);
        tr.link(3 * t0 + 2, 3 * t1);
        let mut cav = Cavity::default();
        let mut out = Vec::new();
        let mut state = 12345u64;
        for _ in 0..200 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let x = ((state >> 11) as f64) / (1u64 << 53) as f64;
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let y = ((state >> 11) as f64) / (1u64 << 53) as f64;
            let p = DVec2::new(0.01 + 0.98 * x, 0.01 + 0.98 * y);
            let start = (0..tr.triangle_slots() as u32)
                .find(|&t| tr.alive[t as usize])
                .unwrap();
            let loc = tr.locate(p, start);
            let nv = tr.add_vertex(p, m);
            assert!(tr.insert_located(nv, loc, &mut cav, &mut out));
            check(&tr);
        }
        assert_eq!(tr.alive_count, 2 + 2 * 200);
        // Euclidean metric: the result is Delaunay (no vertex inside a circumcircle).
        for t in 0..tr.triangle_slots() as u32 {
            if !tr.alive[t as usize] {
                continue;
            }
            for (i, q) in tr.pos.iter().enumerate() {
                if tr.tri(t).contains(&(i as u32)) {
                    continue;
                }
                assert!(
                    (*q - tr.center[t as usize]).length_squared()
                        >= tr.radius2[t as usize] * (1.0 - 1e-9)
                );
            }
        }
    }

    #[test]
    fn ear_clipping_a_comb() {
        let pts: Vec<DVec2> = [
            (0.0, 0.0),
            (4.0, 0.0),
            (4.0, 2.0),
            (3.0, 1.0),
            (2.0, 2.0),
            (1.0, 1.0),
            (0.0, 2.0),
        ]
        .iter()
        .map(|&(x, y)| DVec2::new(x, y))
        .collect();
        let poly: Vec<u32> = (0..pts.len() as u32).collect();
        let tris = ear_clip(&poly, &pts, None).unwrap();
        assert_eq!(tris.len(), 5);
        let area: f64 = tris
            .iter()
            .map(|t| orient(pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]) / 2.0)
            .sum();
        assert!((area - 6.0).abs() < 1e-12);
    }
}
