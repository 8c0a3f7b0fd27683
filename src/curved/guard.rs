//! Guard points and envelopes of guardable curve pieces (seed 000 §2.2, Defs. 2.3–2.5;
//! spec §3.1–3.2; Mandad & Campen's Bézier Guarding).
//!
//! A piece whose control vectors lie in a cone `[s⁻, s⁺]` narrower than 180° lies in the
//! quadrilateral `p₀, x_r, p_d, x_l` (the lines through the end points along `s⁺` and `s⁻`
//! meet at `x_l` on its left and `x_r` on its right). Moving `x_l` and `x_r` outwards by
//! `μ w²/ŵ` along the axis normal gives the guard points `o_l`, `o_r`; the curve is then
//! strictly inside the envelope `E = (p₀, o_r, p_d, o_l)` except at its end points, and
//! `T_l = (c, p_d→o_l, o_l→p₀)` is a triangle with one curved edge.

use glam::DVec2;

use super::bezier::BezierCurve;
use super::cone::Cone;
use super::predicates::{in_polygon, segments_meet_away_from_shared_end};

/// The guard points of a well-guardable piece.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Guards {
    /// `o_l`, left of the directed curve (seed 000 §2.2: `o_l = x + μ (w²/ŵ) n`).
    pub left: DVec2,
    /// `o_r`, right of it.
    pub right: DVec2,
}

impl Guards {
    /// Guard points of `c`, or `None` when the piece must be split first: not guardable
    /// (seed 000 Def. 2.1) or its cone wider than `max_cone_deg` (\[BG\] `isWellGuardable`).
    /// `root_width` is ŵ, the width of the unsplit input curve (seed 000 §2.2: "constant
    /// under splitting").
    pub fn of(c: &BezierCurve, root_width: f64, mu: f64, max_cone_deg: f64) -> Option<Guards> {
        let p = c.points();
        if p.len() == 2 {
            // A straight piece is its own guard edge [DESIGN]: no curved triangle, and its
            // "envelope" is the segment (both guards at the midpoint, no μ shift).
            let mid = 0.5 * (p[0] + p[1]);
            return (p[0] != p[1]).then_some(Guards {
                left: mid,
                right: mid,
            });
        }
        let s: Vec<DVec2> = p.windows(2).map(|w| w[1] - w[0]).collect();
        let cone = Cone::of(&s)?;
        if cone.spread_deg() > max_cone_deg {
            return None;
        }
        let (p0, pd) = (c.start(), c.end());
        let axis = cone.axis();
        let n = axis.perp() / axis.length();
        let w = (pd - p0).length();
        let shift = mu * w * w / root_width;
        let (xl, xr) = apexes(p0, pd, cone);
        Some(Guards {
            left: xl + shift * n,
            right: xr - shift * n,
        })
    }
}

/// `x_l` and `x_r`: `x_l` where the line through `p₀` along `s⁺` meets the line through
/// `p_d` along `s⁻`, `x_r` with the roles swapped; both the chord's midpoint when the lines
/// are (numerically) parallel, i.e. the piece is straight (seed 000 §2.2).
fn apexes(p0: DVec2, pd: DVec2, cone: Cone) -> (DVec2, DVec2) {
    let mid = 0.5 * (p0 + pd);
    let (sp, sm) = (cone.plus, cone.minus);
    let den = sp.perp_dot(sm);
    if den.abs() <= 1e-12 * sp.length() * sm.length() {
        return (mid, mid);
    }
    let chord = pd - p0;
    // p₀ + α s⁺ = p_d + β s⁻  ⇒  α = (chord × s⁻) / (s⁺ × s⁻).
    let alpha_l = chord.perp_dot(sm) / den;
    let alpha_r = chord.perp_dot(sp) / -den;
    // The chord is a positive combination of the control vectors, so both α are ≥ 0; a
    // negative one is rounding on a nearly straight piece.
    let xl = if alpha_l >= 0.0 {
        p0 + alpha_l * sp
    } else {
        mid
    };
    let xr = if alpha_r >= 0.0 {
        p0 + alpha_r * sm
    } else {
        mid
    };
    (xl, xr)
}

/// The width ŵ of an input curve: its chord, or the control box's diagonal when the curve
/// nearly closes on itself (the chord then says nothing about its size) \[DESIGN\].
pub(crate) fn root_width(c: &BezierCurve) -> f64 {
    let chord = (c.end() - c.start()).length();
    let (lo, hi) = c.control_box();
    let diag = (hi - lo).length();
    if chord >= 1e-3 * diag {
        chord
    } else {
        diag
    }
}

/// The envelope quadrilateral `(p₀, o_r, p_d, o_l)`, counter-clockwise (seed 000 Def. 2.5).
#[inline]
pub(crate) fn envelope(p0: DVec2, pd: DVec2, g: &Guards) -> [DVec2; 4] {
    [p0, g.right, pd, g.left]
}

/// Whether two envelopes meet anywhere but at shared curve end points (spec §3.3 step 2):
/// an edge pair meets away from a shared end, or a vertex of one lies in the other. Exact.
pub(crate) fn envelopes_meet(a: &[DVec2; 4], b: &[DVec2; 4]) -> bool {
    for i in 0..4 {
        let (a0, a1) = (a[i], a[(i + 1) % 4]);
        for j in 0..4 {
            if segments_meet_away_from_shared_end(a0, a1, b[j], b[(j + 1) % 4]) {
                return true;
            }
        }
    }
    let inside = |p: &[DVec2; 4], q: &[DVec2; 4]| {
        p.iter()
            .any(|v| !q.contains(v) && in_polygon(q, *v).is_some())
    };
    inside(a, b) || inside(b, a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curved::predicates::orient;

    fn arch() -> BezierCurve {
        BezierCurve::new(vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(0.5, 0.5),
            DVec2::new(1.0, 0.0),
        ])
    }

    #[test]
    fn guards_sit_on_each_side() {
        let c = arch();
        let g = Guards::of(&c, 1.0, 1e-2, 179.0).unwrap();
        // x_l = (0.5, 0.5) shifted up by μ w²/ŵ = 0.01; x_r = (0.5, -0.5) shifted down.
        assert!((g.left - DVec2::new(0.5, 0.51)).length() < 1e-15);
        assert!((g.right - DVec2::new(0.5, -0.51)).length() < 1e-15);
    }

    #[test]
    fn samples_are_strictly_inside_the_envelope() {
        let curves = [
            arch(),
            BezierCurve::new(vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(0.3, -0.25),
                DVec2::new(0.7, -0.25),
                DVec2::new(1.0, 0.0),
            ]),
        ];
        for c in &curves {
            let g = Guards::of(c, 1.0, 1e-2, 179.0).unwrap();
            let e = envelope(c.start(), c.end(), &g);
            for k in 1..1000 {
                let p = c.eval(k as f64 / 1000.0);
                assert_eq!(in_polygon(&e, p), Some(true), "{c:?} t = {k}");
                // Left of p₀→o_l→p_d means right of its reverse: check each side.
                assert!(orient(c.start(), g.left, p) < 0.0);
                assert!(orient(g.left, c.end(), p) < 0.0);
                assert!(orient(c.start(), g.right, p) > 0.0);
                assert!(orient(g.right, c.end(), p) > 0.0);
            }
        }
    }

    #[test]
    fn a_straight_piece_is_its_own_guard() {
        let c = BezierCurve::line(DVec2::new(0.2, 0.1), DVec2::new(0.9, 0.7));
        let g = Guards::of(&c, 1.0, 1e-2, 179.0).unwrap();
        assert_eq!(g.left, 0.5 * (c.start() + c.end()));
        assert_eq!(g.right, g.left);
    }

    #[test]
    fn s_curve_needs_splitting() {
        let s = BezierCurve::new(vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(-0.5, 1.0),
            DVec2::new(0.5, 0.0),
        ]);
        assert!(Guards::of(&s, 1.0, 1e-2, 179.0).is_none());
        let (a, b) = s.split_half();
        let (a1, a2) = a.split_half();
        let (b1, b2) = b.split_half();
        for p in [a1, a2, b1, b2] {
            assert!(Guards::of(&p, 1.0, 1e-2, 179.0).is_some());
        }
    }

    #[test]
    fn envelope_meeting() {
        let a = [
            DVec2::new(0.0, 0.0),
            DVec2::new(0.5, -0.1),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.5, 0.1),
        ];
        // Shares the end (1, 0), goes on to the right: only the shared point.
        let b = a.map(|p| p + DVec2::new(1.0, 0.0));
        assert!(!envelopes_meet(&a, &b));
        // Shifted by less than its length: overlaps.
        let c = a.map(|p| p + DVec2::new(0.7, 0.0));
        assert!(envelopes_meet(&a, &c));
        // Nested.
        let d = a.map(|p| 0.25 * p + DVec2::new(0.3, 0.0));
        assert!(envelopes_meet(&a, &d));
    }
}
