//! Screen-space predicates (spec §5): every side and crossing decision is Shewchuk's adaptive
//! exact `orient2d` (`robust` crate); constructions are plain f64 and never re-decide.

use glam::{DVec2, DVec3};
use robust::{orient2d, Coord};

/// `t.map(f)` for a face's three corners, always inlined (`[T; 3]::map` with a closure that
/// can panic stays a call that returns its array through memory).
#[inline(always)]
pub(crate) fn map3<T: Copy, U>(t: [T; 3], mut f: impl FnMut(T) -> U) -> [U; 3] {
    [f(t[0]), f(t[1]), f(t[2])]
}

/// Twice the signed area of abc: > 0 when a, b, c turn counter-clockwise in a y-up frame
/// (clockwise on the y-down screen), exact in sign.
///
/// The `robust` crate's first step, its floating-point filter (Ozaki et al. 2016, the bound
/// θ·|l + r| on the error of l − r), is taken here as one comparison of the magnitude: the
/// crate compares `det` and `−det` in turn, two branches that go either way with the side of
/// the point. Where the filter passes, this is the value the crate returns; otherwise the
/// crate decides.
#[inline]
pub(crate) fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    /// θ of the filter, as in `robust` 1.2 (3.33e-16, about 3u for the unit roundoff u).
    const THETA: f64 = 3.330_669_062_177_372_2e-16;
    let left = (a.x - c.x) * (b.y - c.y);
    let right = (a.y - c.y) * (b.x - c.x);
    let det = left - right;
    if det.abs() >= THETA * (left + right).abs() {
        return det;
    }
    orient2d(
        Coord { x: a.x, y: a.y },
        Coord { x: b.x, y: b.y },
        Coord { x: c.x, y: c.y },
    )
}

/// For p collinear with ab (checked by the caller): whether p lies on the closed segment ab.
/// Exact: compares coordinates only.
#[inline]
pub(crate) fn on_segment(a: DVec2, b: DVec2, p: DVec2) -> bool {
    (p.x >= a.x.min(b.x)) & (p.x <= a.x.max(b.x)) & (p.y >= a.y.min(b.y)) & (p.y <= a.y.max(b.y))
}

/// Where p lies against triangle abc of orientation sign `sign` (±1): `Some(true)` strictly
/// inside, `Some(false)` on its boundary, `None` outside.
#[inline]
pub(crate) fn in_triangle(a: DVec2, b: DVec2, c: DVec2, sign: f64, p: DVec2) -> Option<bool> {
    let mut strict = true;
    for (u, v) in [(a, b), (b, c), (c, a)] {
        let o = orient(u, v, p);
        if o * sign < 0.0 {
            return None;
        }
        strict &= o != 0.0;
    }
    Some(strict)
}

/// Screen barycentric coordinates of p in abc (constructed, f64).
pub(crate) fn barycentric(a: DVec2, b: DVec2, c: DVec2, p: DVec2) -> [f64; 3] {
    let area = (b - a).perp_dot(c - a);
    if area == 0.0 {
        return [1.0 / 3.0; 3];
    }
    let la = (b - p).perp_dot(c - p) / area;
    let lb = (c - p).perp_dot(a - p) / area;
    [la, lb, 1.0 - la - lb]
}

/// The cosine of triangle abc's smallest corner angle in 3D (1 at a degenerate corner), from
/// its corners and side lengths `|ab|`, `|bc|`, `|ca|` (a flip compares four triangles with
/// six sides among them: each length is taken once). Arc cosine is monotone, so the
/// smallest angle of several triangles is the arc cosine of their largest `max_cos_sides`:
/// one `acos` per comparison instead of one per corner.
pub(crate) fn max_cos_sides(a: DVec3, b: DVec3, c: DVec3, [ab, bc, ca]: [f64; 3]) -> f64 {
    let cos = |p: DVec3, q: DVec3, r: DVec3, d: f64| {
        if d == 0.0 {
            1.0
        } else {
            ((q - p).dot(r - p) / d).clamp(-1.0, 1.0)
        }
    };
    cos(a, b, c, ab * ca)
        .max(cos(b, c, a, bc * ab))
        .max(cos(c, a, b, ca * bc))
}

/// The distance from `p` to segment `ab` (plain f64).
pub(crate) fn point_segment_distance(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

/// Whether a segment and a triangle on screen meet (touching counts), f64.
pub(crate) fn segment_meets_triangle(a: DVec2, b: DVec2, t: [DVec2; 3]) -> bool {
    let cross = |o: DVec2, p: DVec2, q: DVec2| (p - o).perp_dot(q - o);
    let inside = |p: DVec2| {
        let o = [
            cross(t[0], t[1], p),
            cross(t[1], t[2], p),
            cross(t[2], t[0], p),
        ];
        !(o.iter().any(|&v| v > 0.0) && o.iter().any(|&v| v < 0.0))
    };
    if inside(a) || inside(b) {
        return true;
    }
    (0..3).any(|i| {
        let (p, q) = (t[i], t[(i + 1) % 3]);
        let (o1, o2) = (cross(a, b, p), cross(a, b, q));
        let (o3, o4) = (cross(p, q, a), cross(p, q, b));
        o1 * o2 <= 0.0 && o3 * o4 <= 0.0 && (o1 != 0.0 || o2 != 0.0)
    })
}

/// `None` when segment `ab` and triangle `t` meet ([`segment_meets_triangle`]), else the
/// square of the gap between them (plain f64: callers compare it with a slack). A shortcut
/// for the common case of a triangle that lies across the segment's slab (every corner
/// projects strictly inside the segment) and clearly off its line or clearly across it:
/// off, the nearest points are a corner and its foot on the segment; across, the line's
/// chord through the triangle is inside the slab, so the segment meets it. A corner within
/// a billionth of the squared length of the line takes the general tests (rounding would
/// decide it). One gap, not a yes/no at a radius: the region keeps faces by it at two radii
/// (the first guess's margin, then the snap distance) from one walk over the grid.
pub(crate) fn segment_triangle_gap2(a: DVec2, b: DVec2, t: [DVec2; 3]) -> Option<f64> {
    let ab = b - a;
    let len2 = ab.length_squared();
    let mut slab = true;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in t {
        let ap = p - a;
        let u = ap.dot(ab);
        slab &= (u > 0.0) & (u < len2);
        let c = ab.perp_dot(ap);
        lo = lo.min(c);
        hi = hi.max(c);
    }
    let tiny = 1e-9 * len2;
    // `&` and `|`, not `&&` and `||`: the comparisons are cheap, and short-circuiting would
    // make a branch of each that goes either way from face to face.
    if slab & ((lo > tiny) | (hi < -tiny)) {
        let c = if lo > 0.0 { lo } else { hi };
        return Some(c * c / len2);
    }
    if (slab & (lo < -tiny) & (hi > tiny)) || segment_meets_triangle(a, b, t) {
        return None;
    }
    // Apart: the nearest pair has an end point of one on the other.
    let mut gap2 = f64::INFINITY;
    for i in 0..3 {
        let (p, q) = (t[i], t[(i + 1) % 3]);
        gap2 = gap2
            .min(distance2(a, p, q))
            .min(distance2(b, p, q))
            .min(distance2(p, a, b));
    }
    Some(gap2)
}

/// The squared distance from `p` to segment `ab` (plain f64).
#[inline]
fn distance2(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let (ab, ap) = (b - a, p - a);
    let t = ap.dot(ab);
    if t <= 0.0 {
        return ap.length_squared();
    }
    let len2 = ab.length_squared();
    if t >= len2 {
        return (p - b).length_squared();
    }
    let c = ab.perp_dot(ap);
    c * c / len2
}

#[cfg(test)]
mod tests {
    use super::orient;
    use glam::DVec2;
    use robust::{orient2d, Coord};

    /// The same values as `robust::orient2d`, bit for bit: random points, points on lines
    /// through them (where the filter fails and the crate's exact stages decide), repeated
    /// points, huge, tiny, infinite and NaN coordinates.
    #[test]
    fn orient_is_robusts_orient2d() {
        let mut bits = crate::cut::fast::radix::tests::xorshift(0x2545_f491_4f6c_dd1d);
        let mut next = || (bits() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
        let mut cases: Vec<[DVec2; 3]> = Vec::new();
        for _ in 0..20_000 {
            let (a, b) = (DVec2::new(next(), next()), DVec2::new(next(), next()));
            let t = next();
            cases.push([a, b, DVec2::new(next(), next())]);
            cases.push([a, b, a + (b - a) * t]);
            cases.push([a, b, a]);
            cases.push([a * 1e300, b * 1e-300, a + (b - a) * t]);
        }
        for x in [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
        ] {
            cases.push([
                DVec2::new(x, 1.0),
                DVec2::new(0.5, x),
                DVec2::new(-0.25, 2.0),
            ]);
        }
        let c = |p: DVec2| Coord { x: p.x, y: p.y };
        for [a, b, p] in cases {
            let (ours, theirs) = (orient(a, b, p), orient2d(c(a), c(b), c(p)));
            assert_eq!(ours.to_bits(), theirs.to_bits(), "{a} {b} {p}");
        }
    }
}
