//! Which polyline segments may meet an edge or pass through a vertex, for the first
//! normalization's exact tests: each prepared stroke segment's line, with the polyline
//! points a segment snap inserted on it a few ulps off, dismisses most of the region's edges
//! by two cross products, and a window of parameters along the line narrows the rest to
//! one or two polyline segments. The plain path tests every polyline segment.

use glam::DVec2;

use super::Machinery;
use crate::cut::geom::orient;

/// No polyline point.
const NONE: u32 = u32::MAX;

/// The polyline segments that may meet an edge or pass through a vertex.
pub(crate) enum PolylineIndex<'a> {
    Windows {
        pts: &'a [DVec2],
        /// The polyline segments `a..b` making up each prepared segment.
        seg_range: &'a [(u32, u32)],
        /// Each polyline point's parameter along its prepared segment ([`along`]).
        tpar: Vec<f64>,
        /// Each prepared segment's line.
        strips: Vec<Strip>,
    },
    /// Every segment, `0..last`.
    All { last: u32 },
}

impl<'a> PolylineIndex<'a> {
    /// The index of the polyline `pts` made of the prepared segments `seg_range`.
    pub fn new(machinery: Machinery, pts: &'a [DVec2], seg_range: &'a [(u32, u32)]) -> Self {
        match machinery {
            Machinery::Fast => PolylineIndex::Windows {
                pts,
                seg_range,
                tpar: along(pts, seg_range),
                strips: seg_range
                    .iter()
                    .map(|&(j0, j1)| Strip::new(pts[j0 as usize], pts[j1 as usize]))
                    .collect(),
            },
            Machinery::Plain => PolylineIndex::All {
                last: pts.len() as u32 - 1,
            },
        }
    }

    /// Calls `f` on each polyline segment that may hold screen point `x`: a vertex that sits
    /// exactly on polyline point `on` (a snapped one: it is on that point and on no other
    /// segment, as the stroke checks keep non-adjacent segments apart), or on no point
    /// (`NONE`). `near`: the prepared segments that may lie within the margin of `x`.
    #[inline]
    pub fn for_vertex(&self, x: DVec2, on: u32, near: &[u32], mut f: impl FnMut(u32)) {
        match self {
            PolylineIndex::Windows {
                pts,
                seg_range,
                tpar,
                strips,
            } => {
                if on != NONE {
                    debug_assert_eq!(pts[on as usize], x, "a snapped vertex on its point");
                    f(if on as usize == pts.len() - 1 {
                        on - 1
                    } else {
                        on
                    });
                    return;
                }
                for &si in near {
                    let Some(w) = strips[si as usize].window(x, x) else {
                        continue;
                    };
                    for k in in_window(tpar, seg_range[si as usize], w) {
                        f(k);
                    }
                }
            }
            PolylineIndex::All { last } => (0..*last).for_each(f),
        }
    }

    /// Calls `f` on each polyline segment that may meet edge `a`-`b`, whose ends sit exactly
    /// on polyline points `ja` and `jb` (`NONE`: not on one). `near`: the prepared segments
    /// that may lie within the margin of the edge. An edge whose ends sit on consecutive
    /// points is that polyline segment, which no other one meets, so it meets the polyline
    /// only at its ends (the vertices' own occurrences).
    #[inline]
    pub fn for_edge(
        &self,
        (a, b): (DVec2, DVec2),
        (ja, jb): (u32, u32),
        near: &[u32],
        mut f: impl FnMut(u32),
    ) {
        match self {
            PolylineIndex::Windows {
                pts,
                seg_range,
                tpar,
                strips,
            } => {
                if ja != NONE && jb != NONE && ja.abs_diff(jb) == 1 {
                    return;
                }
                for &si in near {
                    let Some(w) = strips[si as usize].window(a, b) else {
                        continue;
                    };
                    // Most edges that pass the window have an end snapped onto the polyline:
                    // skipped when they meet it only there.
                    let range = seg_range[si as usize];
                    if meets_only_at(tpar, pts, range, w, ja, b)
                        || meets_only_at(tpar, pts, range, w, jb, a)
                    {
                        debug_assert!(in_window(tpar, range, w).all(|k| {
                            let (p, q) = (pts[k as usize], pts[k as usize + 1]);
                            let (o1, o2) = (orient(p, q, a), orient(p, q, b));
                            o1 * o2 >= 0.0 && (o1 != 0.0 || o2 != 0.0)
                        }));
                        continue;
                    }
                    for k in in_window(tpar, range, w) {
                        f(k);
                    }
                }
            }
            PolylineIndex::All { last } => (0..*last).for_each(f),
        }
    }
}

/// The line through a prepared segment. Every polyline point of the segment lies on it up
/// to rounding (a snap inserts its foot `a + t·(b − a)`, a few ulps off), so points clearly
/// on one side of it cannot meet any of those polyline segments: most edges of the region
/// are dismissed by two cross products, before the exact tests.
pub(crate) struct Strip {
    a: DVec2,
    d: DVec2,
    /// `1e-12 · |d|`, and the largest coordinate of the segment's ends.
    unit: f64,
    extent: f64,
    /// `1 / |d|²`, so a window costs one division.
    inv_len2: f64,
}

impl Strip {
    fn new(a: DVec2, b: DVec2) -> Self {
        let d = b - a;
        Strip {
            a,
            d,
            unit: 1e-12 * d.length(),
            extent: a.abs().max(b.abs()).max_element(),
            inv_len2: 1.0 / d.length_squared(),
        }
    }

    /// Where edge `x`-`y` can meet the polyline, as parameters along the segment (0 at its
    /// start, 1 at its end): those of the edge's points within the polyline's band around
    /// the line. `None` when both ends are on one side, each farther from the line than the
    /// polyline's points can be (rounding of a few ulps of the coordinates, bounded here by
    /// a millionth of a millionth of them, cross products' own rounding included; test
    /// `inserted_feet_are_never_apart_from_their_segment`). The polyline's points lie between
    /// the segment's ends, so the band is that bound at the segment's extent, taken twice
    /// with the edge's coordinates added; an edge nearly parallel to the line gets its whole
    /// length. The exact tests decide: this only bounds the polyline segments they run on.
    #[inline]
    fn window(&self, x: DVec2, y: DVec2) -> Option<(f64, f64)> {
        let m = x.abs().max(y.abs()).max_element();
        let tol = self.unit * (1.0 + self.extent + m);
        let (cx, cy) = (self.d.perp_dot(x - self.a), self.d.perp_dot(y - self.a));
        // Both ends beyond the band on one side, as one branch (the four tests in turn went
        // either way with the side of the edge).
        if ((cx > tol) & (cy > tol)) | ((cx < -tol) & (cy < -tol)) {
            return None;
        }
        let band = 2.0 * self.unit * (1.0 + 2.0 * self.extent + m);
        let den = cy - cx;
        // The edge's parameters (0 at x, 1 at y) within the band.
        let (s0, s1) = if den.abs() > 4.0 * band {
            let inv = 1.0 / den;
            let (u, v) = ((-band - cx) * inv, (band - cx) * inv);
            (u.min(v).max(0.0), u.max(v).min(1.0))
        } else {
            (0.0, 1.0)
        };
        let (tx, ty) = (
            (x - self.a).dot(self.d) * self.inv_len2,
            (y - self.a).dot(self.d) * self.inv_len2,
        );
        let (t0, t1) = (tx + (ty - tx) * s0, tx + (ty - tx) * s1);
        Some((t0.min(t1), t0.max(t1)))
    }
}

/// [`in_window`]'s slack on a window's parameters, against rounding.
const EPS: f64 = 1e-9;
/// [`in_window`] takes a prepared segment of at most this many polyline segments whole.
const WHOLE: u32 = 3;

/// The polyline segments of prepared segment `(j0, j1)` whose parameter span (from
/// [`along`]) meets `t0..=t1` widened by 1e-9 against rounding: one search for the first,
/// a scan for the few after it. A window from [`Strip::window`] mostly holds one or two.
#[inline]
fn in_window(tpar: &[f64], (j0, j1): (u32, u32), (t0, t1): (f64, f64)) -> std::ops::Range<u32> {
    if j1 - j0 <= WHOLE {
        return j0..j1;
    }
    let ts = &tpar[j0 as usize..j1 as usize];
    let first = ts.partition_point(|&t| t < t0 - EPS);
    let mut past = first;
    while past < ts.len() && ts[past] <= t1 + EPS {
        past += 1;
    }
    // Segment i spans ts[i]..ts[i + 1] (1 for the last): the one before the first start in
    // the window ends in it.
    j0 + first.saturating_sub(1) as u32..j0 + past as u32
}

/// Whether the exact tests of an edge against the polyline segments of prepared segment
/// `(j0, j1)` in window `w` ([`Strip::window`]) surely find nothing, when one end of the edge
/// sits on polyline point `j` (`NONE`: it does not) and `far` is the other end: `j` lies
/// strictly inside the range, the window holds no segment but the two at `j` (as
/// [`in_window`] would choose them), and `far` lies on neither's line. Both segments have
/// that end as an end point, where `orient` is exactly 0, so only a collinear far end would
/// make them meet the edge (the vertex loop reports the end itself). Cheaper than the window's
/// search and the tests, and most windows are of such an edge.
#[inline]
fn meets_only_at(
    tpar: &[f64],
    pts: &[DVec2],
    (j0, j1): (u32, u32),
    (t0, t1): (f64, f64),
    j: u32,
    far: DVec2,
) -> bool {
    // A range taken whole holds only the two pieces when it has two. One branch: whether an
    // end is on a point changes from edge to edge.
    if (j == NONE) | (j <= j0) | (j >= j1) | ((j1 - j0 <= WHOLE) & (j1 - j0 != 2)) {
        return false;
    }
    let j = j as usize;
    if (j - 1 > j0 as usize && tpar[j - 1] >= t0 - EPS)
        || (j + 1 < j1 as usize && tpar[j + 1] <= t1 + EPS)
    {
        return false;
    }
    orient(pts[j - 1], pts[j], far) != 0.0 && orient(pts[j], pts[j + 1], far) != 0.0
}

/// Each polyline point's parameter along its prepared segment (the points a segment snap
/// inserted lie on it, in order), made non-decreasing against rounding.
fn along(pts: &[DVec2], seg_range: &[(u32, u32)]) -> Vec<f64> {
    let mut t = vec![0.0; pts.len()];
    for &(j0, j1) in seg_range {
        let (p, d) = (pts[j0 as usize], pts[j1 as usize] - pts[j0 as usize]);
        let len2 = d.length_squared();
        let mut prev = 0.0f64;
        for j in j0 + 1..j1 {
            let x = if len2 > 0.0 {
                (pts[j as usize] - p).dot(d) / len2
            } else {
                0.0
            };
            prev = prev.max(x);
            t[j as usize] = prev;
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::{along, in_window, meets_only_at, Strip, NONE};
    use crate::cut::geom::orient;
    use glam::DVec2;

    /// An edge from an interior polyline point to a point off the line is skipped, and the
    /// tests it skips find nothing; not when the far end is on a piece's line, when the
    /// window reaches a third piece, when the point is an end of the range, or without a
    /// point.
    #[test]
    fn edges_from_a_polyline_point_are_skipped_only_when_nothing_is_met() {
        // One prepared segment (0, 0)-(10, 0) with feet at x = 2, 4, 6, 8.
        let pts: Vec<DVec2> = (0..=5).map(|i| DVec2::new(2.0 * i as f64, 0.0)).collect();
        let range = (0, 5);
        let tpar = along(&pts, &[range]);
        let strip = Strip::new(pts[0], pts[5]);
        let found = |a: DVec2, b: DVec2| {
            let w = strip.window(a, b).expect("the edge touches the line");
            in_window(&tpar, range, w).any(|k| {
                let (p, q) = (pts[k as usize], pts[k as usize + 1]);
                let (o1, o2) = (orient(p, q, a), orient(p, q, b));
                o1 * o2 < 0.0 || (o1 == 0.0 && o2 == 0.0)
            })
        };
        let skip = |j: u32, a: DVec2, b: DVec2| {
            meets_only_at(&tpar, &pts, range, strip.window(a, b).unwrap(), j, b)
        };
        let (a, off) = (pts[2], DVec2::new(4.3, 0.7));
        assert!(skip(2, a, off) && !found(a, off));
        // Along the line: the far end is on a piece.
        let along_line = DVec2::new(5.0, 0.0);
        assert!(!skip(2, a, along_line) && found(a, along_line));
        // A nearly parallel edge: its window reaches past the pieces at the point.
        let flat = DVec2::new(9.0, 1e-13);
        assert!(!skip(2, a, flat));
        // An end of the range, and no point.
        assert!(!skip(0, pts[0], DVec2::new(1.0, 1.0)));
        assert!(!skip(NONE, a, off));
    }

    /// A point a segment snap inserts (`a + t·(b − a)`, as `snap` computes it) is never
    /// "apart" from the segment's line, alone or with any other point: the filter only
    /// skips edges that cannot meet the polyline. Points a little off the line are.
    #[test]
    fn inserted_feet_are_never_apart_from_their_segment() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let scale = [1.0, 1e3, 1e6][(rnd() * 3.0) as usize];
            let a = DVec2::new(rnd() - 0.5, rnd() - 0.5) * scale;
            let b = a + DVec2::new(rnd() - 0.5, rnd() - 0.5) * scale * rnd();
            if a == b {
                continue;
            }
            let strip = Strip::new(a, b);
            let foot = a + (b - a) * rnd();
            let other = DVec2::new(rnd() - 0.5, rnd() - 0.5) * scale * 3.0;
            assert!(strip.window(foot, foot).is_some(), "{a} {b} {foot}");
            assert!(strip.window(foot, other).is_some() && strip.window(other, foot).is_some());
            // A millionth of the segment's length off the line, both on one side: apart.
            let n = (b - a).perp().normalize() * (b - a).length() * 1e-6;
            assert!(strip.window(foot + n, a + n).is_none() || (b - a).length() < 1e-3 * scale);
        }
    }
}
