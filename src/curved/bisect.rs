//! Splitting a guarded curve piece during refinement (spec §4.3 rule 1, the guard-edge case;
//! the seed's "future work": smaller curved triangles where the straight ones are small).
//!
//! A guard edge is never split by a Steiner point: that would leave a hanging node on the
//! curved triangle. Instead the piece is bisected at t = 1/2 for every region at once, both
//! halves are guarded again, and on each side that bounds a region the old chain
//! `a → g → b` gives way to the new one `a → g₁ → m → g₂ → b`. The new chain lies between the
//! curve and the old one (checked exactly: every new vertex strictly right of the old chain),
//! so Ω_lin only grows: the strip between the chains is triangulated and joined to the
//! triangles along the old chain, whose edges stop being constraints, and the old guard
//! point becomes an interior site.

use super::domain::{Domain, VertexKind};
use super::error::CurvedError;
use super::guard::envelopes_meet;
use super::predicates::orient;
use super::triangulation::{ear_clip, next, prev, tri_of, Cavity, NONE};
use crate::error::Error;

/// What a bisection did.
pub(crate) enum Bisected {
    /// The piece was split; these triangles are new or changed.
    Split { touched: Vec<u32> },
    /// The piece is at the split depth cap.
    AtDepthCap,
}

/// The constraints on piece `id`'s chains: `[left a→g, left g→b, right a→g, right g→b]`
/// (in chain direction), found from the constraint records.
pub(crate) fn piece_constraints(d: &Domain, id: u32) -> [u32; 4] {
    let mut out = [NONE; 4];
    let list = &d.piece_cons[id as usize];
    for &c in list {
        let con = &d.tr.constraints[c as usize];
        if !con.alive {
            continue;
        }
        let chain = d.chain(id, con.right_side);
        let slot = if con.a == chain[0] { 0 } else { 1 };
        out[2 * con.right_side as usize + slot] = c;
    }
    out
}

/// Bisects piece `id` on every side that bounds a region.
pub(crate) fn bisect(d: &mut Domain, id: u32) -> Result<Bisected, Error> {
    let max_depth = d.guarded.params.max_depth;
    if d.guarded.piece(id).depth >= max_depth {
        return Ok(Bisected::AtDepthCap);
    }
    if d.guarded.piece(id).is_linear() {
        return bisect_linear(d, id);
    }
    let old_cons = piece_constraints(d, id);
    let old_chains = [d.chain(id, false), d.chain(id, true)];
    let curve = d.guarded.piece(id).curve;
    let sides = d.curve_regions[curve as usize];
    // Split until the new pieces' envelopes meet no other envelope and their chain vertices
    // lie strictly on the curve's side of the old chains.
    let mut new_ids = d.guarded.split(id)?;
    let mut rounds = 0;
    loop {
        rounds += 1;
        let mut bad: Option<u32> = None;
        'pieces: for &n in &new_ids {
            let p = d.guarded.piece(n);
            let e = p.envelope();
            for (k, side) in [false, true].into_iter().enumerate() {
                if sides[k] == NONE {
                    continue;
                }
                let [a, g, b] = old_chains[k];
                let (pa, pg, pb) = (
                    d.tr.pos[a as usize],
                    d.tr.pos[g as usize],
                    d.tr.pos[b as usize],
                );
                let guard = if side { p.guards.right } else { p.guards.left };
                for q in [guard, p.ctrl.start(), p.ctrl.end()] {
                    if q == pa || q == pb {
                        continue;
                    }
                    if !(orient(pa, pg, q) < 0.0 && orient(pg, pb, q) < 0.0) {
                        bad = Some(n);
                        break 'pieces;
                    }
                }
            }
            for (j, other) in d.guarded.pieces.iter().enumerate() {
                let Some(o) = other else { continue };
                if new_ids.contains(&(j as u32)) {
                    continue;
                }
                if envelopes_meet(&e, &o.envelope()) {
                    bad = Some(n);
                    break 'pieces;
                }
            }
        }
        let Some(n) = bad else { break };
        if d.guarded.piece(n).depth >= max_depth || rounds > 4 * max_depth as usize {
            let p = d.guarded.piece(n);
            return Err(CurvedError::EnvelopeResolution {
                a: curve,
                b: curve,
                near: p.ctrl.eval(0.5).to_array(),
                depth: max_depth,
            }
            .into());
        }
        let halves = d.guarded.split(n)?;
        let pos = new_ids.iter().position(|&x| x == n).expect("a new piece");
        new_ids.splice(pos..pos + 1, halves);
    }
    new_ids.sort_by(|&a, &b| d.guarded.piece(a).t0().total_cmp(&d.guarded.piece(b).t0()));
    for &n in &new_ids {
        d.make_piece_vertices(n)?;
    }
    let mut touched = Vec::new();
    for (k, right) in [false, true].into_iter().enumerate() {
        let region = sides[k];
        if region == NONE {
            continue;
        }
        let [a, g, b] = old_chains[k];
        let (c1, c2) = (old_cons[2 * k], old_cons[2 * k + 1]);
        if c1 == NONE || c2 == NONE {
            return Err(Error::Internal(format!(
                "curved meshing: piece {id} has no guard edges on its {} side",
                if right { "right" } else { "left" }
            )));
        }
        // The new chain from a to b, in the side's direction.
        let order: Vec<u32> = if right {
            new_ids.iter().rev().copied().collect()
        } else {
            new_ids.clone()
        };
        let mut chain: Vec<u32> = vec![a];
        let mut chain_edges: Vec<(u32, u32, u32)> = Vec::new();
        for &n in &order {
            let [x, y, z] = d.chain(n, right);
            debug_assert_eq!(x, *chain.last().unwrap());
            chain.push(y);
            chain.push(z);
            chain_edges.push((x, y, n));
            chain_edges.push((y, z, n));
        }
        debug_assert_eq!(*chain.last().unwrap(), b);
        // The old guard g goes: its fan of triangles (from the edge a → g round to g → b)
        // and the strip between the chains become one polygon, new chain a → … → b then
        // g's link back from b to a, triangulated afresh. Left in place, g would sit a
        // hair's breadth from the new chain and force ever finer pieces.
        let (h_first, h_last) = (
            d.tr.constraints[c1 as usize].half,
            d.tr.constraints[c2 as usize].half,
        );
        let mut fan: Vec<u32> = Vec::new();
        let mut h = h_first;
        loop {
            fan.push(h);
            if next(h) == h_last {
                break;
            }
            let g2 = d.tr.twin[next(h) as usize];
            if g2 == NONE || fan.len() > d.tr.triangle_slots() {
                return Err(Error::Internal(format!(
                    "curved meshing: the triangles around guard point {g} of piece {id} do not close"
                )));
            }
            h = g2;
        }
        // Link edges (opposite g), from b's side back to a's: prev of each fan half-edge.
        let link: Vec<(u32, u32, u32, u32)> = fan
            .iter()
            .rev()
            .map(|&h| {
                let e = prev(h);
                (
                    d.tr.vert[e as usize],
                    d.tr.dest(e),
                    d.tr.twin[e as usize],
                    d.tr.cons[e as usize],
                )
            })
            .collect();
        let mut poly = chain.clone();
        for &(x, _, _, _) in &link[1..] {
            poly.push(x);
        }
        debug_assert_eq!(link[0].0, b);
        let tris = ear_clip(&poly, &d.tr.pos, Some(&d.tr.metric)).ok_or_else(|| {
            Error::Internal(format!(
                "curved meshing: the polygon left by bisecting piece {id} of curve {curve} is not simple"
            ))
        })?;
        for &c in &[c1, c2] {
            d.tr.constraints[c as usize].alive = false;
        }
        for &h in &fan {
            let t = tri_of(h);
            for k in 0..3 {
                let e = 3 * t + k;
                d.tr.cons[e as usize] = NONE;
            }
            d.tr.kill_triangle(t);
        }
        let new_cons: Vec<u32> = chain_edges
            .iter()
            .map(|&(x, y, n)| d.new_constraint(x, y, n, right))
            .collect::<Result<_, CurvedError>>()?;
        let first = touched.len();
        for tv in &tris {
            let t = d.tr.new_triangle(tv[0], tv[1], tv[2], region);
            touched.push(t);
        }
        let made: Vec<u32> = touched[first..].to_vec();
        for &t in &made {
            for k in 0..3u32 {
                let h = 3 * t + k;
                if d.tr.twin[h as usize] != NONE || d.tr.cons[h as usize] != NONE {
                    continue;
                }
                let (x, y) = (d.tr.vert[h as usize], d.tr.dest(h));
                if let Some(i) = chain_edges.iter().position(|&(p, q, _)| p == x && q == y) {
                    d.tr.set_cons(h, new_cons[i]);
                    continue;
                }
                if let Some(&(_, _, tw, c)) = link.iter().find(|e| e.0 == x && e.1 == y) {
                    d.tr.link(h, tw);
                    d.tr.set_cons(h, c);
                    if tw != NONE {
                        touched.push(tri_of(tw));
                    }
                    continue;
                }
                let mate = made
                    .iter()
                    .flat_map(|&u| [3 * u, 3 * u + 1, 3 * u + 2])
                    .find(|&e| d.tr.vert[e as usize] == y && d.tr.dest(e) == x);
                match mate {
                    Some(e) => d.tr.link(h, e),
                    None => {
                        return Err(Error::Internal(format!(
                            "curved meshing: bisecting piece {id}: edge {x}→{y} has no neighbour"
                        )))
                    }
                }
            }
        }
        d.kind[g as usize] = VertexKind::Removed;
    }
    Ok(Bisected::Split { touched })
}

/// Splits a straight piece at its midpoint `m`: on each side, `m` is inserted on the guard
/// edge with the refinement's kernel (the edge stays on the cavity's boundary and gets no
/// triangle), and `a → b` becomes `a → m → b` (Ruppert's segment split).
fn bisect_linear(d: &mut Domain, id: u32) -> Result<Bisected, Error> {
    let old_cons = piece_constraints(d, id);
    let curve = d.guarded.piece(id).curve;
    let sides = d.curve_regions[curve as usize];
    let new_ids = d.guarded.split(id)?;
    for &n in &new_ids {
        d.make_piece_vertices(n)?;
    }
    let (first, second) = (new_ids[0], new_ids[1]);
    let m = d.piece_verts[first as usize][1];
    let (pm, mm) = (d.tr.pos[m as usize], d.tr.metric[m as usize]);
    let mut touched = Vec::new();
    let mut cav = Cavity::default();
    let mut out = Vec::new();
    for (k, right) in [false, true].into_iter().enumerate() {
        if sides[k] == NONE {
            continue;
        }
        let c = old_cons[2 * k];
        if c == NONE {
            return Err(Error::Internal(format!(
                "curved meshing: straight piece {id} has no guard edge"
            )));
        }
        let con = d.tr.constraints[c as usize];
        let h = con.half;
        d.tr.constraints[c as usize].alive = false;
        d.tr.cavity(pm, &mm, &[tri_of(h)], h, &mut cav);
        d.tr.fill(m, &cav, h, &mut out);
        let (pa, pb) = if right {
            (second, first)
        } else {
            (first, second)
        };
        let c1 = d.new_constraint(con.a, m, pa, right)?;
        let c2 = d.new_constraint(m, con.b, pb, right)?;
        for &t in &out {
            for e in [3 * t, 3 * t + 1, 3 * t + 2] {
                let (x, y) = (d.tr.vert[e as usize], d.tr.dest(e));
                if x == con.a && y == m {
                    d.tr.set_cons(e, c1);
                } else if x == m && y == con.b {
                    d.tr.set_cons(e, c2);
                }
            }
        }
        if d.tr.constraints[c1 as usize].half == NONE || d.tr.constraints[c2 as usize].half == NONE
        {
            return Err(Error::Internal(format!(
                "curved meshing: splitting straight piece {id} lost a guard edge"
            )));
        }
        touched.extend_from_slice(&out);
    }
    Ok(Bisected::Split { touched })
}
