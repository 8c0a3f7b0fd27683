//! Exact 2D predicates in the plane of a face (Shewchuk's adaptive `orient2d` from the `robust`
//! crate), and the number format of error messages.

use robust::{orient2d, Coord};

pub(super) type P2 = [f64; 2];

/// Twice the signed area of triangle `abc`, exact in sign: > 0 when `abc` turns left.
pub(super) fn orient(a: P2, b: P2, c: P2) -> f64 {
    orient2d(
        Coord { x: a[0], y: a[1] },
        Coord { x: b[0], y: b[1] },
        Coord { x: c[0], y: c[1] },
    )
}

pub(super) fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Whether `(b - a)` and `(c - a)` point the same way (only meaningful when collinear).
/// Exact for collinear vectors: all products in the sum have the same sign.
pub(super) fn same_direction(a: P2, b: P2, c: P2) -> bool {
    (b[0] - a[0]) * (c[0] - a[0]) + (b[1] - a[1]) * (c[1] - a[1]) > 0.0
}

/// `p`, collinear with `a` and `b`, lies on the closed segment `ab`.
pub(super) fn on_segment(a: P2, b: P2, p: P2) -> bool {
    a[0].min(b[0]) <= p[0]
        && p[0] <= a[0].max(b[0])
        && a[1].min(b[1]) <= p[1]
        && p[1] <= a[1].max(b[1])
}

/// Whether the closed segments `ab` and `cd` have a point in common.
pub(super) fn segments_meet(a: P2, b: P2, c: P2, d: P2) -> bool {
    let o1 = sign(orient(a, b, c));
    let o2 = sign(orient(a, b, d));
    let o3 = sign(orient(c, d, a));
    let o4 = sign(orient(c, d, b));
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    (o1 == 0 && on_segment(a, b, c))
        || (o2 == 0 && on_segment(a, b, d))
        || (o3 == 0 && on_segment(c, d, a))
        || (o4 == 0 && on_segment(c, d, b))
}

/// Two segments `xy` and `xz` sharing the end `x` overlap beyond it.
pub(super) fn overlap_at_shared(x: P2, y: P2, z: P2) -> bool {
    orient(x, y, z) == 0.0 && same_direction(x, y, z)
}

/// Whether the axis-aligned boxes of segments `ab` and `cd` overlap.
pub(super) fn boxes_meet(a: P2, b: P2, c: P2, d: P2) -> bool {
    a[0].max(b[0]) >= c[0].min(d[0])
        && c[0].max(d[0]) >= a[0].min(b[0])
        && a[1].max(b[1]) >= c[1].min(d[1])
        && c[1].max(d[1]) >= a[1].min(b[1])
}

/// Winding number of the closed polygon `poly` around `p` (Sunday's crossing rule, exact);
/// `p` must not lie on the polygon.
pub(super) fn winding(poly: &[P2], p: P2) -> i32 {
    let mut w = 0;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        if a[1] <= p[1] {
            if b[1] > p[1] && orient(a, b, p) > 0.0 {
                w += 1;
            }
        } else if b[1] <= p[1] && orient(a, b, p) < 0.0 {
            w -= 1;
        }
    }
    w
}

/// Orientation of a simple polygon, exact: the turn at its lowest-leftmost vertex.
pub(super) fn simple_polygon_turn(poly: &[P2]) -> i8 {
    let n = poly.len();
    let mut k = 0;
    for i in 1..n {
        if (poly[i][0], poly[i][1]) < (poly[k][0], poly[k][1]) {
            k = i;
        }
    }
    sign(orient(poly[(k + n - 1) % n], poly[k], poly[(k + 1) % n]))
}

/// A number with about four significant digits, for messages.
pub(super) fn num(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{x}");
    }
    if (1e-3..1e6).contains(&a) {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.3e}")
    }
}
