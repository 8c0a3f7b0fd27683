//! Exact geometric predicates (spec §0): every combinatorial decision — orientation, segment
//! intersection, point in polygon — is Shewchuk's adaptive `orient2d` (`robust` crate) on the
//! f64 coordinates that are later written out. Constructions are plain f64.

use glam::DVec2;
use robust::{orient2d, Coord};

/// Twice the signed area of `abc`, exact in sign: > 0 when `a, b, c` turn counter-clockwise.
#[inline]
pub(crate) fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    orient2d(
        Coord { x: a.x, y: a.y },
        Coord { x: b.x, y: b.y },
        Coord { x: c.x, y: c.y },
    )
}

/// The sign of `a × b` for two vectors, exact.
#[inline]
pub(crate) fn cross_sign(a: DVec2, b: DVec2) -> f64 {
    orient(DVec2::ZERO, a, b)
}

/// For `p` collinear with `ab`: whether `p` lies on the closed segment `ab` (exact).
#[inline]
fn on_segment(a: DVec2, b: DVec2, p: DVec2) -> bool {
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
}

/// Whether the closed segments `ab` and `cd` meet somewhere other than at a point that is
/// an end point of both (`a` or `b` equal to `c` or `d`, bit for bit). This is the test of
/// two envelope edges that may share a curve end point (spec §3.3 step 2: edges are
/// half-open at shared end points).
pub(crate) fn segments_meet_away_from_shared_end(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let o1 = orient(a, b, c);
    let o2 = orient(a, b, d);
    let o3 = orient(c, d, a);
    let o4 = orient(c, d, b);
    let shared = |p: DVec2| p == c || p == d;
    if o1 == 0.0 && o2 == 0.0 {
        // Collinear: they overlap in a segment, a single shared point, or not at all.
        let lo_ab = if (a.x, a.y) <= (b.x, b.y) { a } else { b };
        let hi_ab = if (a.x, a.y) <= (b.x, b.y) { b } else { a };
        let lo_cd = if (c.x, c.y) <= (d.x, d.y) { c } else { d };
        let hi_cd = if (c.x, c.y) <= (d.x, d.y) { d } else { c };
        let lo = if (lo_ab.x, lo_ab.y) >= (lo_cd.x, lo_cd.y) {
            lo_ab
        } else {
            lo_cd
        };
        let hi = if (hi_ab.x, hi_ab.y) <= (hi_cd.x, hi_cd.y) {
            hi_ab
        } else {
            hi_cd
        };
        let cmp = (lo.x, lo.y).partial_cmp(&(hi.x, hi.y));
        return match cmp {
            Some(std::cmp::Ordering::Less) => true,
            Some(std::cmp::Ordering::Equal) => !((lo == a || lo == b) && shared(lo)),
            _ => false,
        };
    }
    // Proper crossing.
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    // Touching: an end point of one lies on the other.
    let touches = [
        (o1 == 0.0 && on_segment(a, b, c), c),
        (o2 == 0.0 && on_segment(a, b, d), d),
        (o3 == 0.0 && on_segment(c, d, a), a),
        (o4 == 0.0 && on_segment(c, d, b), b),
    ];
    touches
        .iter()
        .any(|&(t, p)| t && !((p == a || p == b) && shared(p)))
}

/// Where `p` lies against the closed polygon `poly` (any simple polygon, either
/// orientation): `Some(true)` strictly inside, `Some(false)` on its boundary, `None` outside.
/// Exact (winding number with `orient`).
pub(crate) fn in_polygon(poly: &[DVec2], p: DVec2) -> Option<bool> {
    let n = poly.len();
    let mut winding = 0i32;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let o = orient(a, b, p);
        if o == 0.0 && on_segment(a, b, p) {
            return Some(false);
        }
        if a.y <= p.y {
            if b.y > p.y && o > 0.0 {
                winding += 1;
            }
        } else if b.y <= p.y && o < 0.0 {
            winding -= 1;
        }
    }
    if winding != 0 {
        Some(true)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn shared_end_is_not_a_meeting() {
        let o = v(0.0, 0.0);
        assert!(!segments_meet_away_from_shared_end(
            o,
            v(1.0, 0.0),
            o,
            v(0.0, 1.0)
        ));
        // Collinear overlap from a shared end is a meeting.
        assert!(segments_meet_away_from_shared_end(
            o,
            v(1.0, 0.0),
            o,
            v(2.0, 0.0)
        ));
        // Collinear, opposite directions from the shared end: only the end.
        assert!(!segments_meet_away_from_shared_end(
            o,
            v(1.0, 0.0),
            o,
            v(-2.0, 0.0)
        ));
        // Crossing.
        assert!(segments_meet_away_from_shared_end(
            v(0.0, 0.0),
            v(1.0, 1.0),
            v(0.0, 1.0),
            v(1.0, 0.0)
        ));
        // T-junction on the interior.
        assert!(segments_meet_away_from_shared_end(
            v(0.0, 0.0),
            v(2.0, 0.0),
            v(1.0, 0.0),
            v(1.0, 1.0)
        ));
        // An end of one on the other's end, but not shared by both as an end: a is c.
        assert!(!segments_meet_away_from_shared_end(
            v(1.0, 0.0),
            v(2.0, 0.0),
            v(1.0, 0.0),
            v(1.0, 1.0)
        ));
    }

    #[test]
    fn polygon_membership() {
        let sq = [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)];
        assert_eq!(in_polygon(&sq, v(0.5, 0.5)), Some(true));
        assert_eq!(in_polygon(&sq, v(1.0, 0.5)), Some(false));
        assert_eq!(in_polygon(&sq, v(1.5, 0.5)), None);
        let cw: Vec<DVec2> = sq.iter().rev().copied().collect();
        assert_eq!(in_polygon(&cw, v(0.5, 0.5)), Some(true));
    }
}
