//! One hole's bridges (spec §5.2 steps 1–3, A2, A3, A5, A8): the seed's nearest-vertex map
//! when it is valid, otherwise the shortest valid set by dynamic programming.

use super::face::FaceGeom;
use super::{BridgeChoice, BridgeFailure, DP_BUDGET};

pub(super) struct HolePlan {
    /// The hole's loop index in the face.
    pub(super) hole: usize,
    /// S and L as loop indices (one of them is the hole, the other 0).
    pub(super) s_loop: usize,
    pub(super) l_loop: usize,
    /// For each vertex `a` of S (in order), the local vertex `l(a)` of L.
    pub(super) map: Vec<usize>,
    pub(super) choice: BridgeChoice,
}

/// A candidate target of one vertex of S in the dynamic programme.
#[derive(Clone, Copy)]
struct Cand {
    /// Local vertex of L.
    v: usize,
    len: f64,
    nearest: bool,
}

pub(super) fn bridge_hole(
    g: &FaceGeom,
    hole: usize,
) -> std::result::Result<HolePlan, BridgeFailure> {
    let (cs, ce) = g.loops[hole];
    let (ps, pe) = g.loops[0];
    // Spec §5.2 step 1 and A8: S has fewer vertices, the hole on ties.
    let (s_loop, l_loop) = if ce - cs <= pe - ps {
        (hole, 0)
    } else {
        (0, hole)
    };
    let (ss, se) = g.loops[s_loop];
    let (ls, le) = g.loops[l_loop];
    let (q, m) = (se - ss, le - ls);
    // Spec A5: count L from its lowest vertex id.
    let first = (ls..le).min_by_key(|&v| g.vid[v]).unwrap_or(ls);
    let rank = |v: usize| (v + m - first) % m;
    let dist2 = |s: usize, v: usize| (g.p3[s] - g.p3[v]).length_squared();
    // Step 2: the nearest vertex of L to each s_a.
    let nearest: Vec<usize> = (ss..se)
        .map(|s| {
            (ls..le)
                .min_by(|&a, &b| {
                    dist2(s, a)
                        .total_cmp(&dist2(s, b))
                        .then(rank(a).cmp(&rank(b)))
                })
                .unwrap_or(ls)
        })
        .collect();
    // Going along S, l(a) must step backwards along L (G_a walks L forwards from l(a+1) to
    // l(a)), by 0..m-1 vertices each time and by exactly m in all (once round the hole).
    let back = |from: usize, to: usize| (from + m - to) % m;
    let turns: usize = (0..q).map(|a| back(nearest[a], nearest[(a + 1) % q])).sum();
    let ok = turns == m
        && (0..q).all(|a| g.bridge_ok(ss + a, nearest[a]))
        && (0..q).all(|a| {
            let b = (a + 1) % q;
            g.consecutive_ok(ss + a, nearest[a], ss + b, nearest[b])
        });
    if ok {
        return Ok(HolePlan {
            hole,
            s_loop,
            l_loop,
            map: nearest,
            choice: BridgeChoice::Nearest,
        });
    }
    // Spec A2: the shortest monotone set of valid, pairwise non-crossing bridges.
    let k_max = ((DP_BUDGET / q as f64).cbrt() as usize).max(8).min(m);
    let mut by_distance: Vec<usize> = (ls..le).collect();
    let mut cands: Vec<Vec<Cand>> = Vec::with_capacity(q);
    for (a, &near) in nearest.iter().enumerate() {
        let s = ss + a;
        by_distance.sort_by(|&x, &y| {
            dist2(s, x)
                .total_cmp(&dist2(s, y))
                .then(rank(x).cmp(&rank(y)))
        });
        let list: Vec<Cand> = by_distance
            .iter()
            .filter(|&&v| g.bridge_ok(s, v))
            .take(k_max)
            .map(|&v| Cand {
                v,
                len: dist2(s, v).sqrt(),
                nearest: v == near,
            })
            .collect();
        if list.is_empty() {
            return Err(BridgeFailure::NoBridgeSet { hole: hole as u32 });
        }
        cands.push(list);
    }
    // Start the cycle at the vertex of S with the fewest candidates.
    let r = (0..q).min_by_key(|&a| cands[a].len()).unwrap_or(0);
    let row = |i: usize| (r + i) % q;
    // compat[i][x * |C(i)| + y]: candidate x of row i-1 and y of row i may be consecutive
    // (for i = 0: row q-1 then row 0, closing the cycle).
    let compat: Vec<Vec<bool>> = (0..q)
        .map(|i| {
            let (a0, a1) = (row((i + q - 1) % q), row(i));
            let (c0, c1) = (&cands[a0], &cands[a1]);
            let mut t = Vec::with_capacity(c0.len() * c1.len());
            for x in c0 {
                for y in c1 {
                    t.push(g.consecutive_ok(ss + a0, x.v, ss + a1, y.v));
                }
            }
            t
        })
        .collect();
    #[derive(Clone, Copy)]
    struct State {
        cand: usize,
        /// Steps backwards along L from the start target, 0..=m.
        t: usize,
        len: f64,
        dev: u32,
        pred: usize,
    }
    let better = |len: f64, dev: u32, than: Option<(f64, u32)>| match than {
        None => true,
        Some((l, d)) => len < l || (len == l && dev < d),
    };
    let mut best: Option<(f64, u32, Vec<usize>)> = None;
    for (c0, start) in cands[row(0)].iter().enumerate() {
        let mut table: Vec<Vec<State>> = Vec::with_capacity(q);
        table.push(vec![State {
            cand: c0,
            t: 0,
            len: start.len,
            dev: u32::from(!start.nearest),
            pred: usize::MAX,
        }]);
        for i in 1..q {
            let a = row(i);
            let width = cands[a].len();
            let mut states: Vec<State> = Vec::with_capacity(width + 1);
            for (ci, c) in cands[a].iter().enumerate() {
                let t = back(start.v, c.v);
                states.push(State {
                    cand: ci,
                    t,
                    len: f64::INFINITY,
                    dev: 0,
                    pred: usize::MAX,
                });
                if c.v == start.v {
                    states.push(State {
                        cand: ci,
                        t: m,
                        len: f64::INFINITY,
                        dev: 0,
                        pred: usize::MAX,
                    });
                }
            }
            let prev = &table[i - 1];
            for st in states.iter_mut() {
                let c = cands[a][st.cand];
                let mut found: Option<(f64, u32)> = None;
                for (pi, ps) in prev.iter().enumerate() {
                    if ps.pred == usize::MAX && i > 1 {
                        continue; // unreachable
                    }
                    if ps.t > st.t || st.t - ps.t >= m || !compat[i][ps.cand * width + st.cand] {
                        continue;
                    }
                    let (len, dev) = (ps.len + c.len, ps.dev + u32::from(!c.nearest));
                    if better(len, dev, found) {
                        found = Some((len, dev));
                        st.len = len;
                        st.dev = dev;
                        st.pred = pi;
                    }
                }
            }
            table.push(states);
        }
        // Close the cycle: the last step backwards, m - t, must be 0..m-1.
        let width0 = cands[row(0)].len();
        let last = &table[q - 1];
        for (li, st) in last.iter().enumerate() {
            let reachable = q == 1 || st.pred != usize::MAX;
            if !reachable || st.t == 0 || !compat[0][st.cand * width0 + c0] {
                continue;
            }
            if better(st.len, st.dev, best.as_ref().map(|b| (b.0, b.1))) {
                let mut chosen = vec![0usize; q];
                let mut idx = li;
                for i in (0..q).rev() {
                    let s = table[i][idx];
                    chosen[row(i)] = cands[row(i)][s.cand].v;
                    idx = s.pred;
                }
                best = Some((st.len, st.dev, chosen));
            }
        }
    }
    match best {
        Some((_, _, map)) => Ok(HolePlan {
            hole,
            s_loop,
            l_loop,
            map,
            choice: BridgeChoice::Optimised,
        }),
        None => Err(BridgeFailure::NoBridgeSet { hole: hole as u32 }),
    }
}
