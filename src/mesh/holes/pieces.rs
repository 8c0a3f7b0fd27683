//! Cutting a face along all its holes' bridges into virtual faces (spec §5.2 step 3, A6),
//! and checking that the pieces are simple polygons.

use super::bridges::HolePlan;
use super::exact::*;
use super::face::FaceGeom;
use super::{BridgeFailure, Bridged, HoleBridges};

impl FaceGeom {
    /// Cuts the face along all holes' bridges, checks the pieces and assembles the result.
    pub(super) fn assemble(
        &self,
        plans: &[HolePlan],
    ) -> std::result::Result<Bridged, BridgeFailure> {
        let n = self.n();
        let p = &self.p2;
        // Bridges (s, l) in local indices, hole by hole.
        let mut bridges: Vec<(usize, usize)> = Vec::new();
        let mut bridge_hole: Vec<u32> = Vec::new();
        let mut holes = Vec::with_capacity(plans.len());
        for plan in plans {
            let first = bridges.len();
            let (ss, se) = self.loops[plan.s_loop];
            for (a, s) in (ss..se).enumerate() {
                bridges.push((s, plan.map[a]));
                bridge_hole.push(plan.hole as u32);
            }
            holes.push(HoleBridges {
                short_is_hole: plan.s_loop != 0,
                choice: plan.choice,
                first_bridge: first as u32,
                bridge_count: (se - ss) as u32,
            });
        }
        let nb = bridges.len();
        // No two bridges meet but at a shared end. (For one hole's bridges this follows from
        // the checks made when they were chosen; it is checked again, cheaply, all the same.)
        for i in 0..nb {
            for j in i + 1..nb {
                let ((a, b), (c, d)) = (bridges[i], bridges[j]);
                let meet = if a == c || a == d || b == c || b == d {
                    let (x, y, z) = if a == c {
                        (a, b, d)
                    } else if a == d {
                        (a, b, c)
                    } else if b == c {
                        (b, a, d)
                    } else {
                        (b, a, c)
                    };
                    overlap_at_shared(p[x], p[y], p[z])
                } else {
                    boxes_meet(p[a], p[b], p[c], p[d]) && segments_meet(p[a], p[b], p[c], p[d])
                };
                if meet && bridge_hole[i] != bridge_hole[j] {
                    return Err(BridgeFailure::BridgesCross {
                        first: bridge_hole[i],
                        second: bridge_hole[j],
                    });
                }
                if meet {
                    return Err(BridgeFailure::Degenerate(format!(
                        "bridges {}-{} and {}-{} of hole (loop {}) meet",
                        self.vid[a], self.vid[b], self.vid[c], self.vid[d], bridge_hole[i]
                    )));
                }
            }
        }
        // Bridges at each vertex, counter-clockwise from the outgoing loop edge.
        let mut at: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, &(s, l)) in bridges.iter().enumerate() {
            at[s].push(k);
            at[l].push(k);
        }
        let other = |k: usize, x: usize| {
            if bridges[k].0 == x {
                bridges[k].1
            } else {
                bridges[k].0
            }
        };
        for x in 0..n {
            if at[x].len() < 2 {
                continue;
            }
            let (px, r) = (p[x], p[self.next(x)]);
            let half = |d: P2| {
                let o = orient(px, r, d);
                if o > 0.0 || (o == 0.0 && same_direction(px, r, d)) {
                    0
                } else {
                    1
                }
            };
            let mut list = std::mem::take(&mut at[x]);
            let mut tie = None;
            list.sort_by(|&i, &j| {
                let (di, dj) = (p[other(i, x)], p[other(j, x)]);
                half(di).cmp(&half(dj)).then_with(|| {
                    let o = orient(px, di, dj);
                    if o > 0.0 {
                        std::cmp::Ordering::Less
                    } else if o < 0.0 {
                        std::cmp::Ordering::Greater
                    } else {
                        if i != j {
                            tie = Some((i, j));
                        }
                        i.cmp(&j)
                    }
                })
            });
            if let Some((i, j)) = tie {
                return Err(if bridge_hole[i] != bridge_hole[j] {
                    BridgeFailure::BridgesCross {
                        first: bridge_hole[i].min(bridge_hole[j]),
                        second: bridge_hole[i].max(bridge_hole[j]),
                    }
                } else {
                    BridgeFailure::Degenerate(format!(
                        "two bridges leave vertex {} in the same direction",
                        self.vid[x]
                    ))
                });
            }
            at[x] = list;
        }
        // Half-edges: loop edge u → next(u) is u; bridge k is n + 2k (s → l) and n + 2k + 1.
        let from = |h: usize| {
            if h < n {
                h
            } else {
                let (s, l) = bridges[(h - n) / 2];
                if (h - n).is_multiple_of(2) {
                    s
                } else {
                    l
                }
            }
        };
        let leave = |k: usize, x: usize| {
            if bridges[k].0 == x {
                n + 2 * k
            } else {
                n + 2 * k + 1
            }
        };
        let to = |h: usize| {
            if h < n {
                self.next(h)
            } else {
                let (s, l) = bridges[(h - n) / 2];
                if (h - n).is_multiple_of(2) {
                    l
                } else {
                    s
                }
            }
        };
        let next_he = |h: usize| {
            let x = to(h);
            let list = &at[x];
            if h < n {
                match list.last() {
                    Some(&k) => leave(k, x),
                    None => x,
                }
            } else {
                let k = (h - n) / 2;
                let pos = list.iter().position(|&b| b == k).unwrap_or(0);
                if pos > 0 {
                    leave(list[pos - 1], x)
                } else {
                    x
                }
            }
        };
        let total = n + 2 * nb;
        let mut piece_of = vec![usize::MAX; total];
        let mut pieces: Vec<Vec<usize>> = Vec::new();
        let mut corners: Vec<Vec<usize>> = Vec::new();
        for k in 0..nb {
            let h0 = next_he(n + 2 * k + 1);
            if piece_of[h0] != usize::MAX {
                continue;
            }
            let id = pieces.len();
            let (mut verts, mut corner) = (Vec::new(), Vec::new());
            let (mut h, mut prev_bridge) = (h0, true);
            loop {
                if piece_of[h] != usize::MAX || verts.len() > total {
                    return Err(BridgeFailure::Degenerate(
                        "walking a virtual face does not close".into(),
                    ));
                }
                piece_of[h] = id;
                let v = from(h);
                verts.push(v);
                if prev_bridge || h >= n {
                    corner.push(v);
                }
                prev_bridge = h >= n;
                h = next_he(h);
                if h == h0 {
                    break;
                }
            }
            pieces.push(verts);
            corners.push(corner);
        }
        if let Some(u) = (0..n).find(|&u| piece_of[u] == usize::MAX) {
            return Err(BridgeFailure::Degenerate(format!(
                "loop edge {} is in no virtual face",
                self.edge_name(u)
            )));
        }
        // Every piece a simple polygon turning left; their number B - H + 1 (Euler).
        let mut stamp = vec![usize::MAX; n];
        for (i, piece) in pieces.iter().enumerate() {
            for &v in piece {
                if stamp[v] == i {
                    return Err(BridgeFailure::Degenerate(format!(
                        "a virtual face passes vertex {} twice",
                        self.vid[v]
                    )));
                }
                stamp[v] = i;
            }
            let poly: Vec<P2> = piece.iter().map(|&v| p[v]).collect();
            if piece.len() < 3 || simple_polygon_turn(&poly) <= 0 {
                return Err(BridgeFailure::Degenerate(format!(
                    "the virtual face at vertex {} does not turn left",
                    self.vid[piece[0]]
                )));
            }
        }
        let hole_count = self.loops.len() - 1;
        if pieces.len() + hole_count != nb + 1 {
            return Err(BridgeFailure::Degenerate(format!(
                "{} virtual faces for {nb} bridges and {hole_count} holes",
                pieces.len()
            )));
        }
        // Spec A6: each hole keeps all its own virtual faces but the one that holds the other
        // holes (one of them if there is a single hole: none is lost).
        for plan in plans {
            let (ss, se) = self.loops[plan.s_loop];
            let q = se - ss;
            let (ls, le) = self.loops[plan.l_loop];
            let m = le - ls;
            let mut kept = 0;
            let mut foreign = None;
            for a in 0..q {
                let b = (a + 1) % q;
                let mut own = vec![ss + a, ss + b];
                let (x, y) = (plan.map[b], plan.map[a]);
                let mut v = x;
                own.push(v);
                while v != y && own.len() <= m + 2 {
                    v = self.next(v);
                    own.push(v);
                }
                let k = holes[plan.hole - 1].first_bridge as usize + a;
                let piece = &pieces[piece_of[n + 2 * k + 1]];
                let same = piece.len() == own.len() && {
                    let start = piece.iter().position(|&w| w == own[0]).unwrap_or(0);
                    (0..own.len()).all(|i| piece[(start + i) % piece.len()] == own[i])
                };
                if same {
                    kept += 1;
                } else if foreign.is_none() {
                    foreign = Some(piece_of[n + 2 * k + 1]);
                }
            }
            let expected = if hole_count == 1 { q } else { q - 1 };
            if kept != expected {
                if hole_count == 1 {
                    return Err(BridgeFailure::Degenerate(
                        "the virtual faces are not the ones the bridges define".into(),
                    ));
                }
                let me = plan.hole as u32;
                let second = foreign
                    .and_then(|f| {
                        pieces[f]
                            .iter()
                            .map(|&v| self.loop_of[v])
                            .find(|&k| k != 0 && k != me)
                    })
                    .unwrap_or(me);
                return Err(BridgeFailure::SharedArc { first: me, second });
            }
        }
        let ids = |list: &Vec<usize>| list.iter().map(|&v| self.vid[v]).collect::<Vec<_>>();
        Ok(Bridged {
            faces: pieces.iter().map(ids).collect(),
            face_point_vertices: corners.iter().map(ids).collect(),
            bridges: bridges
                .iter()
                .map(|&(s, l)| (self.vid[s], self.vid[l]))
                .collect(),
            holes,
        })
    }
}
