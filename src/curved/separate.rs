//! Bézier guarding of all input curves at once: split every curve until its pieces are
//! well guardable, then split until no two envelopes meet (seed 000 §4 Step 2; spec §3.3,
//! \[BG\] `splitIntersecting`).
//!
//! The loop runs on the pieces of every curve of every region of a patch together, so both
//! sides of a shared curve see the same pieces. Pieces are bisected at t = 1/2 only, so each
//! covers `[k/2ᵈ, (k+1)/2ᵈ]` of its input curve, exactly representable in f64.
//!
//! Envelopes that can never be separated mean curves that cross or touch (spec §1.4 (c)):
//! the split depth cap then reports them as [`CurvedError::CurvesIntersect`].

use glam::DVec2;

use super::bezier::BezierCurve;
use super::error::CurvedError;
use super::guard::{envelope, envelopes_meet, root_width, Guards};
use super::predicates::segments_meet_away_from_shared_end;

/// A guarded piece of an input curve.
#[derive(Debug, Clone)]
pub(crate) struct Piece {
    /// The input curve.
    pub curve: u32,
    /// Bisections from the input curve.
    pub depth: u32,
    /// The piece covers `[index/2^depth, (index+1)/2^depth]`.
    pub index: u64,
    /// Control points of the piece (de Casteljau from the input curve).
    pub ctrl: BezierCurve,
    pub guards: Guards,
}

impl Piece {
    /// `t₀` on the input curve (exact: a dyadic rational).
    pub fn t0(&self) -> f64 {
        self.index as f64 / (1u64 << self.depth) as f64
    }

    /// `t₁` on the input curve.
    pub fn t1(&self) -> f64 {
        (self.index + 1) as f64 / (1u64 << self.depth) as f64
    }

    /// A straight piece (degree 1): its own guard edge, with no curved triangle.
    pub fn is_linear(&self) -> bool {
        self.ctrl.degree() == 1
    }

    pub fn envelope(&self) -> [DVec2; 4] {
        envelope(self.ctrl.start(), self.ctrl.end(), &self.guards)
    }

    /// `|o_l − o_r|`, the envelope's size (seed 000 Def. 2.5), the split priority.
    pub fn size(&self) -> f64 {
        (self.guards.left - self.guards.right).length()
    }
}

/// Parameters of guarding shared by the initial split, the separation and the refinement's
/// curve bisections.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GuardParams {
    pub mu: f64,
    pub max_cone_deg: f64,
    pub max_depth: u32,
    pub max_pieces: u64,
}

/// The guarded pieces of the input curves.
#[derive(Debug, Clone)]
pub(crate) struct GuardedCurves {
    /// ŵ of every input curve (0 for curves not in use).
    pub root_width: Vec<f64>,
    /// Alive pieces; dead ones (split) are `None`.
    pub pieces: Vec<Option<Piece>>,
    pub params: GuardParams,
}

impl GuardedCurves {
    /// Splits `ctrl` (a piece of `curve` at `(depth, index)`) until every part is well
    /// guardable, appending the parts in curve order.
    fn guard_recursive(
        &mut self,
        curve: u32,
        depth: u32,
        index: u64,
        ctrl: BezierCurve,
        out: &mut Vec<u32>,
    ) -> Result<(), CurvedError> {
        let p = self.params;
        if let Some(guards) =
            Guards::of(&ctrl, self.root_width[curve as usize], p.mu, p.max_cone_deg)
        {
            if self.pieces.len() as u64 >= p.max_pieces {
                return Err(CurvedError::Budget {
                    what: "curve pieces",
                    option: "max_curve_pieces",
                    limit: p.max_pieces,
                    detail: format!("splitting curve {curve}"),
                });
            }
            out.push(self.pieces.len() as u32);
            self.pieces.push(Some(Piece {
                curve,
                depth,
                index,
                ctrl,
                guards,
            }));
            return Ok(());
        }
        if depth >= p.max_depth {
            let t = (index as f64 + 0.5) / (1u64 << depth) as f64;
            return Err(CurvedError::SingularCurve { curve, t });
        }
        let (a, b) = ctrl.split_half();
        self.guard_recursive(curve, depth + 1, 2 * index, a, out)?;
        self.guard_recursive(curve, depth + 1, 2 * index + 1, b, out)
    }

    /// Replaces piece `id` by its halves (each made well guardable), returning the new ids.
    pub fn split(&mut self, id: u32) -> Result<Vec<u32>, CurvedError> {
        let piece = self.pieces[id as usize]
            .take()
            .expect("splitting a dead piece");
        let (a, b) = piece.ctrl.split_half();
        let mut out = Vec::with_capacity(2);
        self.guard_recursive(piece.curve, piece.depth + 1, 2 * piece.index, a, &mut out)?;
        self.guard_recursive(
            piece.curve,
            piece.depth + 1,
            2 * piece.index + 1,
            b,
            &mut out,
        )?;
        Ok(out)
    }

    /// [`Self::split`] for the separation loop: `Err(None)` when a half cannot be guarded
    /// because it sits at the split depth cap (the caller reports why it was being split),
    /// `Err(Some(_))` for other errors. The piece is kept on `Err(None)`.
    pub fn split_checked(&mut self, id: u32) -> Result<Vec<u32>, Option<CurvedError>> {
        let depth = self.piece(id).depth;
        let saved = self.pieces[id as usize].clone();
        let before = self.pieces.len();
        match self.split(id) {
            Ok(v) => Ok(v),
            Err(CurvedError::SingularCurve { .. })
                if depth + 1 >= self.params.max_depth.saturating_sub(8) =>
            {
                self.pieces.truncate(before);
                self.pieces[id as usize] = saved;
                Err(None)
            }
            Err(e) => Err(Some(e)),
        }
    }

    pub fn piece(&self, id: u32) -> &Piece {
        self.pieces[id as usize].as_ref().expect("a dead piece")
    }

    /// Alive pieces of each curve, in order along it.
    pub fn pieces_by_curve(&self, curve_count: usize) -> Vec<Vec<u32>> {
        let mut by: Vec<Vec<u32>> = vec![Vec::new(); curve_count];
        for (i, p) in self.pieces.iter().enumerate() {
            if let Some(p) = p {
                by[p.curve as usize].push(i as u32);
            }
        }
        for list in &mut by {
            list.sort_by(|&a, &b| self.piece(a).t0().total_cmp(&self.piece(b).t0()));
        }
        by
    }
}

/// An axis-aligned box.
#[derive(Debug, Clone, Copy)]
struct Box2 {
    lo: DVec2,
    hi: DVec2,
}

fn quad_box(q: &[DVec2; 4]) -> Box2 {
    let mut lo = q[0];
    let mut hi = q[0];
    for p in &q[1..] {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    Box2 { lo, hi }
}

/// Guards the curves `used` of `curves` and separates their envelopes (spec §3.1–3.3).
pub(crate) fn guard_and_separate(
    curves: &[BezierCurve],
    used: &[u32],
    params: GuardParams,
) -> Result<GuardedCurves, CurvedError> {
    let mut g = GuardedCurves {
        root_width: vec![0.0; curves.len()],
        pieces: Vec::new(),
        params,
    };
    for &c in used {
        g.root_width[c as usize] = root_width(&curves[c as usize]);
    }
    let mut dirty: Vec<bool> = Vec::new();
    for &c in used {
        let mut out = Vec::new();
        g.guard_recursive(c, 0, 0, curves[c as usize].clone(), &mut out)?;
    }
    dirty.resize(g.pieces.len(), true);
    loop {
        let pairs = meeting_pairs(&g, &dirty);
        dirty.iter_mut().for_each(|d| *d = false);
        if pairs.is_empty() {
            return Ok(g);
        }
        // Split the larger envelope of each pair (spec §3.3 step 3), each piece once a round.
        let mut to_split: Vec<u32> = Vec::new();
        for &(a, b) in &pairs {
            let (pa, pb) = (g.piece(a), g.piece(b));
            let pick = if (pa.size(), a) >= (pb.size(), b) {
                a
            } else {
                b
            };
            let other = if pick == a { b } else { a };
            if g.piece(pick).depth >= params.max_depth {
                return Err(unresolvable(&g, pick, other));
            }
            to_split.push(pick);
        }
        to_split.sort_unstable();
        to_split.dedup();
        for id in to_split {
            if g.pieces[id as usize].is_none() {
                continue;
            }
            let partner = pairs
                .iter()
                .find_map(|&(a, b)| {
                    if a == id {
                        Some(b)
                    } else if b == id {
                        Some(a)
                    } else {
                        None
                    }
                })
                .unwrap_or(id);
            let halves = match g.split_checked(id) {
                Ok(h) => h,
                // A half that rounding made unguardable at the depth cap: the curves meet.
                Err(Some(e)) => return Err(e),
                Err(None) => return Err(unresolvable(&g, id, partner)),
            };
            for new in halves {
                if new as usize >= dirty.len() {
                    dirty.resize(new as usize + 1, false);
                }
                dirty[new as usize] = true;
            }
        }
    }
}

/// The error for two pieces whose envelopes still meet at the depth cap: their control
/// polygons cross or touch (curves that meet, spec §1.4 (c)), or they are merely too close.
fn unresolvable(g: &GuardedCurves, a: u32, b: u32) -> CurvedError {
    let (pa, pb) = (g.piece(a), g.piece(b));
    let near = 0.5 * (pa.ctrl.eval(0.5) + pb.ctrl.eval(0.5));
    let (qa, qb) = (pa.ctrl.points(), pb.ctrl.points());
    let touch = qa.windows(2).any(|s| {
        qb.windows(2)
            .any(|t| segments_meet_away_from_shared_end(s[0], s[1], t[0], t[1]))
    });
    let (ca, cb) = (pa.curve.min(pb.curve), pa.curve.max(pb.curve));
    if touch {
        CurvedError::CurvesIntersect {
            a: ca,
            b: cb,
            near: near.to_array(),
        }
    } else {
        CurvedError::EnvelopeResolution {
            a: ca,
            b: cb,
            near: near.to_array(),
            depth: g.params.max_depth,
        }
    }
}

/// Pairs of alive pieces, at least one of them dirty, whose envelopes meet; by a sweep over
/// the boxes' x intervals and the exact test on overlapping boxes. Sorted, so the caller's
/// choices do not depend on hashing.
fn meeting_pairs(g: &GuardedCurves, dirty: &[bool]) -> Vec<(u32, u32)> {
    let mut items: Vec<(u32, [DVec2; 4], Box2)> = g
        .pieces
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            p.as_ref().map(|p| {
                let e = p.envelope();
                (i as u32, e, quad_box(&e))
            })
        })
        .collect();
    items.sort_by(|a, b| a.2.lo.x.total_cmp(&b.2.lo.x).then(a.0.cmp(&b.0)));
    let mut pairs = Vec::new();
    for i in 0..items.len() {
        let (ia, ea, ba) = &items[i];
        for (ib, eb, bb) in &items[i + 1..] {
            if bb.lo.x > ba.hi.x {
                break;
            }
            if !(dirty[*ia as usize] || dirty[*ib as usize]) {
                continue;
            }
            if bb.lo.y > ba.hi.y || bb.hi.y < ba.lo.y {
                continue;
            }
            if envelopes_meet(ea, eb) {
                pairs.push(((*ia).min(*ib), (*ia).max(*ib)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}
