//! Screen-space predicates (spec §5): every side and crossing decision is Shewchuk's adaptive
//! exact `orient2d` (`robust` crate); constructions are plain f64 and never re-decide.

use glam::{DVec2, DVec3};
use robust::{orient2d, Coord};

/// `t.map(f)` for a face's three corners, always inlined: `[T; 3]::map` with a closure
/// that can panic (an index, an `expect`) stayed a call that returned its array through
/// memory, and the loads right after waited on it (snapping −7% to −20% side by side).
#[inline(always)]
pub(crate) fn map3<T: Copy, U>(t: [T; 3], mut f: impl FnMut(T) -> U) -> [U; 3] {
    [f(t[0]), f(t[1]), f(t[2])]
}

/// Twice the signed area of abc: > 0 when a, b, c turn counter-clockwise in a y-up frame
/// (clockwise on the y-down screen), exact in sign.
#[inline]
pub(crate) fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
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
    p.x >= a.x.min(b.x) && p.x <= a.x.max(b.x) && p.y >= a.y.min(b.y) && p.y <= a.y.max(b.y)
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
