//! The linear domain Ω_lin and its first triangulation (seed 000 §4 Step 3: "the inner
//! guarding triangles form a polygon"; spec §3.4, §4.4).
//!
//! Every curve piece on a region's boundary is replaced by its two guard edges
//! `p₀ → o → p_d` on the region's side (left guard `o_l` for a curve run forwards, right
//! guard `o_r` for one run backwards), so Ω_lin is a polygon with holes whose boundary edges
//! are the constraints of the refinement. Its first triangulation inserts the boundary
//! vertices into a large triangle with the anisotropic kernel, recovers the constraints by
//! edge flips (Sloan 1993) and keeps, per region, the triangles reached from its boundary
//! without crossing a constraint.

use std::collections::HashMap;

use glam::DVec2;

use super::error::CurvedError;
use super::field::PatchMetric;
use super::input::TrimmedPatches;
use super::predicates::orient;
use super::separate::GuardedCurves;
use super::tensor::Metric2;
use super::triangulation::{next, prev, tri_of, Cavity, Constraint, Triangulation, NONE};
use crate::error::Error;

/// What a vertex of the triangulation is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum VertexKind {
    /// A point of input curve `curve` at parameter `t` (an end point of pieces).
    Curve { curve: u32, t: f64 },
    /// A guard point of a piece.
    Guard { piece: u32, right: bool },
    /// A refinement site.
    Steiner,
    /// A corner of the enclosing triangle of the first build (not output).
    Outer,
    /// A guard point of a piece that was bisected: no longer in the triangulation.
    Removed,
}

/// Ω_lin of every region of one patch, triangulated, with the bookkeeping the refinement,
/// the curve bisections and the output need.
pub(crate) struct Domain<'a> {
    pub input: &'a TrimmedPatches,
    pub metric: PatchMetric<'a>,
    pub guarded: GuardedCurves,
    pub tr: Triangulation,
    pub kind: Vec<VertexKind>,
    /// Per piece: `[p₀, p_d, left guard, right guard]` vertex ids (guards [`NONE`] where the
    /// side bounds no region).
    pub piece_verts: Vec<[u32; 4]>,
    /// Per input curve: the region on its left (run forwards) and on its right (run backwards).
    pub curve_regions: Vec<[u32; 2]>,
    /// Per piece: the constraints on its chains (alive or not).
    pub piece_cons: Vec<Vec<u32>>,
    /// Curve points by (position bits), so joints and shared curves get one vertex.
    point_vertex: HashMap<[u64; 2], u32>,
}

impl<'a> Domain<'a> {
    /// The vertex at curve point `p` of `curve` at `t`, created if new.
    pub fn curve_vertex(&mut self, p: DVec2, curve: u32, t: f64) -> Result<u32, CurvedError> {
        let key = [p.x.to_bits(), p.y.to_bits()];
        if let Some(&v) = self.point_vertex.get(&key) {
            return Ok(v);
        }
        let m = self.metric.at(p)?;
        let v = self.tr.add_vertex(p, m);
        self.kind.push(VertexKind::Curve { curve, t });
        self.point_vertex.insert(key, v);
        Ok(v)
    }

    /// The input curve a boundary vertex lies on or guards (a curve point or a guard point),
    /// `None` for sites.
    pub fn curve_of_vertex(&self, v: u32) -> Option<u32> {
        match self.kind.get(v as usize)? {
            VertexKind::Curve { curve, .. } => Some(*curve),
            VertexKind::Guard { piece, .. } => self.guarded.pieces[*piece as usize]
                .as_ref()
                .map(|p| p.curve),
            _ => None,
        }
    }

    /// The curve-point vertex at `p`, if any.
    pub fn vertex_at(&self, p: DVec2) -> Option<u32> {
        self.point_vertex
            .get(&[p.x.to_bits(), p.y.to_bits()])
            .copied()
    }

    /// A new vertex of another kind.
    pub fn add_vertex(&mut self, p: DVec2, kind: VertexKind) -> Result<u32, CurvedError> {
        let m = self.metric.at(p)?;
        Ok(self.add_vertex_with(p, m, kind))
    }

    pub fn add_vertex_with(&mut self, p: DVec2, m: Metric2, kind: VertexKind) -> u32 {
        let v = self.tr.add_vertex(p, m);
        self.kind.push(kind);
        v
    }

    /// Vertices for piece `id` (its end points and the guards on used sides).
    pub fn make_piece_vertices(&mut self, id: u32) -> Result<(), CurvedError> {
        let piece = self.guarded.piece(id).clone();
        let p0 = self.curve_vertex(piece.ctrl.start(), piece.curve, piece.t0())?;
        let pd = self.curve_vertex(piece.ctrl.end(), piece.curve, piece.t1())?;
        let sides = self.curve_regions[piece.curve as usize];
        let linear = piece.is_linear();
        let left = if sides[0] != NONE && !linear {
            self.add_vertex(
                piece.guards.left,
                VertexKind::Guard {
                    piece: id,
                    right: false,
                },
            )?
        } else {
            NONE
        };
        let right = if sides[1] != NONE && !linear {
            self.add_vertex(
                piece.guards.right,
                VertexKind::Guard {
                    piece: id,
                    right: true,
                },
            )?
        } else {
            NONE
        };
        if self.piece_verts.len() <= id as usize {
            self.piece_verts.resize(id as usize + 1, [NONE; 4]);
        }
        self.piece_verts[id as usize] = [p0, pd, left, right];
        Ok(())
    }

    /// The guard chain's edges of piece `id` on one side, directed with the region on its
    /// left: `p₀ → o_l → p_d` (left) or `p_d → o_r → p₀` (right); a straight piece's chain is
    /// the piece itself.
    pub fn chain_edges(&self, id: u32, right: bool) -> Vec<(u32, u32)> {
        let [a, g, b] = self.chain(id, right);
        if g == NONE {
            vec![(a, b)]
        } else {
            vec![(a, g), (g, b)]
        }
    }

    /// The guard chain of piece `id` on one side, directed with the region on its left:
    /// `p₀ → o_l → p_d` (left) or `p_d → o_r → p₀` (right); the middle is [`NONE`] for a
    /// straight piece.
    pub fn chain(&self, id: u32, right: bool) -> [u32; 3] {
        let [p0, pd, l, r] = self.piece_verts[id as usize];
        if right {
            [pd, r, p0]
        } else {
            [p0, l, pd]
        }
    }

    /// A new constraint on the directed edge `a → b` of piece `piece`'s chain.
    pub fn new_constraint(
        &mut self,
        a: u32,
        b: u32,
        piece: u32,
        right: bool,
    ) -> Result<u32, CurvedError> {
        let mid = 0.5 * (self.tr.pos[a as usize] + self.tr.pos[b as usize]);
        let metric = self.metric.at(mid)?;
        self.tr.constraints.push(Constraint {
            a,
            b,
            half: NONE,
            piece,
            right_side: right,
            metric,
            alive: true,
        });
        let c = self.tr.constraints.len() as u32 - 1;
        if self.piece_cons.len() <= piece as usize {
            self.piece_cons.resize(piece as usize + 1, Vec::new());
        }
        self.piece_cons[piece as usize].push(c);
        Ok(c)
    }
}

/// Builds Ω_lin of the regions `regions` of one patch and its first triangulation.
pub(crate) fn build<'a>(
    input: &'a TrimmedPatches,
    regions: &[u32],
    metric: PatchMetric<'a>,
    guarded: GuardedCurves,
) -> Result<Domain<'a>, Error> {
    let mut curve_regions = vec![[NONE; 2]; input.curves.len()];
    for &r in regions {
        for lp in &input.regions[r as usize].loops {
            for u in &lp.uses {
                curve_regions[u.curve.idx()][u.reversed as usize] = r;
            }
        }
    }
    let mut d = Domain {
        input,
        metric,
        guarded,
        tr: Triangulation::new(),
        kind: Vec::new(),
        piece_verts: Vec::new(),
        curve_regions,
        piece_cons: Vec::new(),
        point_vertex: HashMap::new(),
    };
    let by_curve = d.guarded.pieces_by_curve(input.curves.len());
    // Chain edges, per region, in loop order, as constraints.
    let mut chains: Vec<(u32, Vec<u32>)> = Vec::new();
    for &r in regions {
        let mut edges = Vec::new();
        for lp in &input.regions[r as usize].loops {
            for u in &lp.uses {
                let list = &by_curve[u.curve.idx()];
                let ordered: Vec<u32> = if u.reversed {
                    list.iter().rev().copied().collect()
                } else {
                    list.clone()
                };
                for id in ordered {
                    if d.piece_verts.get(id as usize).is_none_or(|v| v[0] == NONE) {
                        d.make_piece_vertices(id)?;
                    }
                    for (a, b) in d.chain_edges(id, u.reversed) {
                        edges.push(d.new_constraint(a, b, id, u.reversed)?);
                    }
                }
            }
        }
        chains.push((r, edges));
    }
    triangulate(&mut d, &chains)?;
    Ok(d)
}

/// The first triangulation: vertices into an enclosing triangle, constraints by flips,
/// regions by flood fill (spec §4.4).
fn triangulate(d: &mut Domain, chains: &[(u32, Vec<u32>)]) -> Result<(), Error> {
    let n = d.tr.vertex_count() as u32;
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for p in &d.tr.pos {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let c = 0.5 * (lo + hi);
    let r = (hi - lo).length().max(1e-300) * 8.0;
    let m = Metric2::isotropic(r);
    let s: Vec<u32> = [
        DVec2::new(-1.0, -1.0),
        DVec2::new(3.0, -1.0),
        DVec2::new(-1.0, 3.0),
    ]
    .iter()
    .map(|&dir| d.add_vertex_with(c + r * dir, m, VertexKind::Outer))
    .collect();
    let mut last = d.tr.new_triangle(s[0], s[1], s[2], NONE);
    let mut cav = Cavity::default();
    let mut out = Vec::new();
    for v in 0..n {
        let p = d.tr.pos[v as usize];
        let loc = d.tr.locate(p, last);
        if !d.tr.insert_located(v, loc, &mut cav, &mut out) {
            return Err(Error::Internal(format!(
                "curved meshing: boundary vertex {v} at ({}, {}) could not be inserted ({loc:?})",
                p.x, p.y
            )));
        }
        last = out[0];
    }
    let mut out_half = OutgoingCache::default();
    for (_, edges) in chains {
        for &c in edges {
            let con = d.tr.constraints[c as usize];
            recover(&mut d.tr, &mut out_half, con.a, con.b, c)?;
        }
    }
    label_regions(d, chains)
}

/// A half-edge leaving each vertex, rebuilt by one scan when an entry has gone stale (the
/// first build only: flips there are few).
#[derive(Default)]
struct OutgoingCache {
    half: Vec<u32>,
}

impl OutgoingCache {
    fn set(&mut self, v: u32, h: u32) {
        if let Some(x) = self.half.get_mut(v as usize) {
            *x = h;
        }
    }

    fn get(&mut self, tr: &Triangulation, v: u32) -> Option<u32> {
        let fresh = |h: u32| h != NONE && tr.alive[tri_of(h) as usize] && tr.vert[h as usize] == v;
        if let Some(&h) = self.half.get(v as usize) {
            if fresh(h) {
                return Some(h);
            }
        }
        self.half = vec![NONE; tr.vertex_count()];
        for t in 0..tr.triangle_slots() as u32 {
            if tr.alive[t as usize] {
                for h in [3 * t, 3 * t + 1, 3 * t + 2] {
                    self.half[tr.vert[h as usize] as usize] = h;
                }
            }
        }
        let h = self.half[v as usize];
        fresh(h).then_some(h)
    }
}

/// The half-edge `x → y`, by turning around `x` from a cached outgoing half-edge.
fn find_half(tr: &Triangulation, cache: &mut OutgoingCache, x: u32, y: u32) -> Option<u32> {
    let start = cache.get(tr, x)?;
    let mut h = start;
    // Counter-clockwise around x: twin(prev(h)) leaves x too.
    loop {
        if tr.dest(h) == y {
            return Some(h);
        }
        let g = tr.twin[prev(h) as usize];
        if g == NONE {
            break;
        }
        h = g;
        if h == start {
            return None;
        }
    }
    // Hit a boundary: go clockwise from the start instead.
    let mut h = start;
    loop {
        let g = tr.twin[h as usize];
        if g == NONE {
            return None;
        }
        h = next(g);
        if tr.dest(h) == y {
            return Some(h);
        }
        if h == start {
            return None;
        }
    }
}

/// Makes `a → b` an edge carrying constraint `c`: Sloan's algorithm (1993) — list the edges
/// the segment crosses, flip each whose quadrilateral is convex, put back the others and the
/// new diagonals that still cross. Every decision is exact.
fn recover(
    tr: &mut Triangulation,
    cache: &mut OutgoingCache,
    a: u32,
    b: u32,
    c: u32,
) -> Result<(), Error> {
    let pa = tr.pos[a as usize];
    let pb = tr.pos[b as usize];
    let internal = |what: &str| {
        Error::Internal(format!(
            "curved meshing: guard edge {a}→{b} from ({}, {}) to ({}, {}): {what}",
            pa.x, pa.y, pb.x, pb.y
        ))
    };
    let mark = |tr: &mut Triangulation, h: u32| {
        tr.cons[h as usize] = c;
        let g = tr.twin[h as usize];
        if g != NONE {
            tr.cons[g as usize] = c;
        }
        tr.constraints[c as usize].half = h;
    };
    if let Some(h) = find_half(tr, cache, a, b) {
        mark(tr, h);
        return Ok(());
    }
    // The wedge at a the segment enters.
    let start = cache
        .get(tr, a)
        .ok_or_else(|| internal("its first vertex is in no triangle"))?;
    let mut h = start;
    let mut e = NONE;
    loop {
        let (x, y) = (tr.dest(h), tr.apex(h));
        let ox = orient(pa, tr.pos[x as usize], pb);
        let oy = orient(pa, tr.pos[y as usize], pb);
        if (ox == 0.0 && (tr.pos[x as usize] - pa).dot(pb - pa) > 0.0)
            || (oy == 0.0 && (tr.pos[y as usize] - pa).dot(pb - pa) > 0.0)
        {
            return Err(internal("a vertex lies on it"));
        }
        if ox > 0.0 && oy < 0.0 {
            e = next(h);
            break;
        }
        let g = tr.twin[prev(h) as usize];
        if g == NONE || g == start {
            break;
        }
        h = g;
    }
    if e == NONE {
        return Err(internal(
            "no triangle around its first vertex points at its second",
        ));
    }
    // The crossed edges, from a to b, as vertex pairs (half-edges move when flipped).
    let mut crossed: std::collections::VecDeque<(u32, u32)> = std::collections::VecDeque::new();
    loop {
        if tr.cons[e as usize] != NONE {
            return Err(internal("it crosses another guard edge"));
        }
        crossed.push_back((tr.vert[e as usize], tr.dest(e)));
        let g = tr.twin[e as usize];
        if g == NONE {
            return Err(internal("it leaves the triangulation"));
        }
        let z = tr.apex(g);
        if z == b {
            break;
        }
        let oz = orient(pa, tr.pos[z as usize], pb);
        if oz == 0.0 {
            return Err(internal("a vertex lies on it"));
        }
        e = if oz > 0.0 { prev(g) } else { next(g) };
    }
    let limit = 64 * crossed.len() * crossed.len() + 1024;
    let mut steps = 0;
    while let Some((x, y)) = crossed.pop_front() {
        steps += 1;
        if steps > limit {
            return Err(internal("the flips do not end"));
        }
        let h = find_half(tr, cache, x, y).ok_or_else(|| internal("a crossed edge vanished"))?;
        if !tr.flippable(h) {
            crossed.push_back((x, y));
            continue;
        }
        let g = tr.twin[h as usize];
        let (t1, t2) = (tri_of(h), tri_of(g));
        tr.flip(h);
        // t1 = (a', d, c'), t2 = (d, b', c') after the flip: refresh the cache of all four.
        for t in [t1, t2] {
            for k in 0..3 {
                let e = 3 * t + k;
                cache.set(tr.vert[e as usize], e);
            }
        }
        let e1 = 3 * t1 + 1;
        let (u, w) = (tr.vert[e1 as usize], tr.dest(e1));
        let (pu, pw) = (tr.pos[u as usize], tr.pos[w as usize]);
        let crosses = u != a && u != b && w != a && w != b && {
            let o1 = orient(pa, pb, pu);
            let o2 = orient(pa, pb, pw);
            let o3 = orient(pu, pw, pa);
            let o4 = orient(pu, pw, pb);
            o1 * o2 < 0.0 && o3 * o4 < 0.0
        };
        if crosses {
            crossed.push_back((u, w));
        }
    }
    let h = find_half(tr, cache, a, b).ok_or_else(|| internal("still missing after the flips"))?;
    mark(tr, h);
    Ok(())
}

/// Flood-fills each region from its chain edges without crossing constraints; anything a
/// region reaches beyond its own chains (another region's chain, a chain from outside, the
/// enclosing triangle) means overlapping regions or loops that bound nothing. Unreached
/// triangles go.
fn label_regions(d: &mut Domain, chains: &[(u32, Vec<u32>)]) -> Result<(), Error> {
    let patch = d.metric.patch_id;
    let tr = &mut d.tr;
    let mut owner: Vec<u32> = vec![NONE; tr.triangle_slots()];
    let mut stack: Vec<u32> = Vec::new();
    for (r, edges) in chains {
        let r = *r;
        stack.extend(
            edges
                .iter()
                .map(|&c| tri_of(tr.constraints[c as usize].half)),
        );
        while let Some(t) = stack.pop() {
            let o = owner[t as usize];
            if o == r {
                continue;
            }
            if o != NONE {
                return Err(CurvedError::RegionsOverlap {
                    a: o.min(r),
                    b: o.max(r),
                    patch,
                }
                .into());
            }
            if tr
                .tri(t)
                .iter()
                .any(|&v| d.kind[v as usize] == VertexKind::Outer)
            {
                return Err(CurvedError::LoopsDoNotBound { region: r }.into());
            }
            owner[t as usize] = r;
            for k in 0..3 {
                let h = 3 * t + k;
                let c = tr.cons[h as usize];
                if c != NONE {
                    let con = tr.constraints[c as usize];
                    let side = d.curve_regions[d.guarded.piece(con.piece).curve as usize]
                        [con.right_side as usize];
                    if side != r {
                        return Err(CurvedError::RegionsOverlap {
                            a: side.min(r),
                            b: side.max(r),
                            patch,
                        }
                        .into());
                    }
                    if con.half != h {
                        // This region's own chain, reached from outside.
                        return Err(CurvedError::LoopsDoNotBound { region: r }.into());
                    }
                    continue;
                }
                let g = tr.twin[h as usize];
                if g != NONE {
                    stack.push(tri_of(g));
                }
            }
        }
    }
    for t in 0..tr.triangle_slots() as u32 {
        if !tr.alive[t as usize] {
            continue;
        }
        if owner[t as usize] == NONE {
            for k in 0..3 {
                let h = 3 * t + k;
                let g = tr.twin[h as usize];
                if g != NONE {
                    tr.twin[g as usize] = NONE;
                }
                tr.cons[h as usize] = NONE;
            }
            tr.kill_triangle(t);
        } else {
            tr.region[t as usize] = owner[t as usize];
        }
    }
    Ok(())
}
