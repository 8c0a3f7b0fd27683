//! Stroke preprocessing (spec §4, gap-fill): finite points, near points dropped, loops closed,
//! self-intersection rejected, sharp corners found (seed 002 §3.4, Fig. 11).

use glam::DVec2;

use super::geom::{on_segment, orient, point_segment_distance};
use super::options::CutOptions;
use super::snap::{Polyline, Snapped};
use super::view::{Stroke, SCREEN_RANGE_PX};
use crate::error::{Axis, Error, Result};

/// The stroke as the cut uses it.
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    /// Kept points. A closed stroke does not repeat its first point.
    pub points: Vec<DVec2>,
    /// The input index of each kept point.
    pub input_index: Vec<u32>,
    /// Input points dropped: closer than `min_stroke_px` to the previous kept point, or a
    /// closing point merged into the first.
    pub dropped: Vec<u32>,
    /// Whether the last kept point joins the first (a loop).
    pub closed: bool,
    /// Kept points where the stroke turns by more than `corner_angle_deg` (seed 002 §3.4).
    /// For an open stroke only interior points; for a closed one any point.
    pub corners: Vec<usize>,
}

impl Prepared {
    /// Number of segments (a closed stroke has one joining the last point to the first).
    pub fn segment_count(&self) -> usize {
        if self.closed {
            self.points.len()
        } else {
            self.points.len() - 1
        }
    }

    /// The segments, in order.
    pub fn segments(&self) -> Vec<(DVec2, DVec2)> {
        let n = self.points.len();
        (0..self.segment_count())
            .map(|k| (self.points[k], self.points[(k + 1) % n]))
            .collect()
    }
}

/// The stroke pieces (seed 002 §3.4): the snapped polyline split at the sharp corners.
pub(crate) struct Pieces {
    /// The polyline points that end pieces, ascending: the first and last point and the
    /// corners.
    pub bounds: Vec<u32>,
    /// Whether a closed stroke without two corners was split at its middle too (its halves
    /// are then reported as one closed path when they join up).
    pub artificial: bool,
}

impl Pieces {
    /// Each piece's first and last polyline point.
    pub fn spans(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.bounds.windows(2).map(|w| (w[0], w[1]))
    }

    pub fn count(&self) -> usize {
        self.bounds.len() - 1
    }
}

/// The pieces of the snapped stroke: split at its sharp corners (seed 002 §3.4); a closed
/// stroke without two corners is cut in two halves whose ends are shared, like corners
/// (gap-fill).
pub(crate) fn pieces(prep: &Prepared, snapped: &Snapped) -> Pieces {
    let line = &snapped.line;
    let last = line.pts.len() as u32 - 1;
    let mut bounds: Vec<u32> = vec![0, last];
    bounds.extend(prep.corners.iter().map(|&c| snapped.start_of[c]));
    bounds.sort_unstable();
    bounds.dedup();
    let artificial = prep.closed && bounds.len() < 3;
    if artificial {
        bounds.push(middle_point(line));
        bounds.sort_unstable();
        bounds.dedup();
    }
    Pieces { bounds, artificial }
}

/// The polyline point closest to half the length of a closed stroke, preferring points that
/// hold a model vertex (no interior vertex is then needed there).
fn middle_point(line: &Polyline) -> u32 {
    let n = line.pts.len();
    let mut acc = vec![0.0; n];
    for i in 1..n {
        acc[i] = acc[i - 1] + (line.pts[i] - line.pts[i - 1]).length();
    }
    let half = acc[n - 1] / 2.0;
    let pick = |pred: &dyn Fn(usize) -> bool| {
        (1..n - 1)
            .filter(|&i| pred(i))
            .min_by(|&a, &b| (acc[a] - half).abs().total_cmp(&(acc[b] - half).abs()))
    };
    // An on-vertex point within the middle half of the loop, else the nearest point.
    pick(&|i| line.on_vertex[i] && (acc[i] - half).abs() < half / 2.0)
        .or_else(|| pick(&|_| true))
        .unwrap_or(1) as u32
}

pub(crate) fn prepare(stroke: &Stroke, options: &CutOptions) -> Result<Prepared> {
    for (i, p) in stroke.points.iter().enumerate() {
        for (axis, value) in [(Axis::X, p.x), (Axis::Y, p.y)] {
            if !value.is_finite() {
                return Err(Error::NonFiniteStrokePoint {
                    index: i as u32,
                    axis,
                    value,
                });
            }
            if value.abs() > SCREEN_RANGE_PX {
                return Err(Error::StrokePointOutOfRange {
                    index: i as u32,
                    axis,
                    value,
                    limit: SCREEN_RANGE_PX,
                });
            }
        }
    }
    let min = options.min_stroke_px;
    let mut points: Vec<DVec2> = Vec::with_capacity(stroke.points.len());
    let mut input_index = Vec::with_capacity(stroke.points.len());
    let mut dropped = Vec::new();
    for (i, &p) in stroke.points.iter().enumerate() {
        // Zero-length segments are dropped whatever `min_stroke_px` is.
        match points.last() {
            Some(&q) if (p - q).length() < min || p == q => dropped.push(i as u32),
            _ => {
                points.push(p);
                input_index.push(i as u32);
            }
        }
    }
    let mut closed = false;
    if points.len() >= 4 {
        let (first, last) = (points[0], points[points.len() - 1]);
        if (last - first).length() < min.max(f64::MIN_POSITIVE) || last == first {
            closed = true;
            points.pop();
            dropped.push(input_index.pop().expect("a kept point"));
            dropped.sort_unstable();
        }
    }
    if points.len() < 2 {
        return Err(Error::StrokeTooShort {
            points: points.len() as u32,
            min_px: min,
        });
    }
    let mut prepared = Prepared {
        points,
        input_index,
        dropped,
        closed,
        corners: Vec::new(),
    };
    check_self_intersection(&prepared)?;
    prepared.corners = corners(&prepared, options.corner_angle_deg);
    Ok(prepared)
}

/// Every pair of segments: non-adjacent segments may not touch, adjacent ones may not fold
/// back onto each other — exactly (`orient2d`), and also not within 1e-9 of the stroke's size
/// (a stroke that numerically doubles back would make the cut run both ways through the same
/// faces). The error names the first failing pair in (first, second) order. Only pairs whose
/// boxes come within that tolerance can fail, and [`close_pairs`] finds those in time linear
/// in the stroke's length for strokes people draw (a 200,000-point stroke is checked in
/// milliseconds; every pair was O(n²)).
fn check_self_intersection(s: &Prepared) -> Result<()> {
    let n = s.points.len();
    let m = s.segment_count();
    let (lo, hi) = s
        .points
        .iter()
        .fold((s.points[0], s.points[0]), |(l, h), &p| {
            (l.min(p), h.max(p))
        });
    let tol = 1e-9 * (hi - lo).length();
    let seg = |i: usize| (s.points[i], s.points[(i + 1) % n]);
    let boxes: Vec<(DVec2, DVec2)> = (0..m)
        .map(|i| {
            let (a, b) = seg(i);
            (a.min(b), a.max(b))
        })
        .collect();
    let mut pairs = close_pairs(&boxes, tol, lo, hi);
    // Adjacent pairs are always looked at (a fold is within any box).
    pairs.extend((0..m.saturating_sub(1)).map(|i| (i as u32, i as u32 + 1)));
    if s.closed && m > 2 {
        pairs.push((0, m as u32 - 1));
    }
    pairs.sort_unstable();
    pairs.dedup();
    for (i, j) in pairs.into_iter().map(|(i, j)| (i as usize, j as usize)) {
        let adjacent_fwd = j == i + 1;
        let adjacent_wrap = s.closed && i == 0 && j == m - 1;
        let (a, b) = seg(i);
        let (c, d) = seg(j);
        let fails = if adjacent_fwd || adjacent_wrap {
            // Shared point: b == c (forward) or d == a (wrap). Folding back = collinear and
            // pointing the other way.
            let (p, q, r) = if adjacent_fwd { (a, b, d) } else { (c, a, b) };
            let (d1, d2) = (q - p, r - q);
            d1.dot(d2) < 0.0
                && (orient(p, q, r) == 0.0
                    || d1.perp_dot(d2).abs() <= 1e-9 * d1.length() * d2.length())
        } else {
            let (bi, bj) = (boxes[i], boxes[j]);
            let apart = bi.1.x + tol < bj.0.x
                || bj.1.x + tol < bi.0.x
                || bi.1.y + tol < bj.0.y
                || bj.1.y + tol < bi.0.y;
            !apart
                && ([(a, c, d), (b, c, d), (c, a, b), (d, a, b)]
                    .iter()
                    .any(|&(p, x, y)| point_segment_distance(p, x, y) <= tol)
                    || segments_meet(a, b, c, d))
        };
        if fails {
            return Err(Error::StrokeSelfIntersects {
                first: s.input_index[i],
                second: s.input_index[j],
            });
        }
    }
    Ok(())
}

/// The pairs (i < j) of `boxes` that come within `tol` of each other, and some farther
/// apart: each box, grown by `tol`, is listed in the cells of a uniform grid over the
/// stroke's extent (`lo`, `hi`) it covers, and boxes sharing a cell pair up. Cells are about
/// twice the mean segment's size, widened until the boxes cover at most 16 cells each on
/// average, so a stroke's few long segments cannot make the grid's work quadratic.
fn close_pairs(boxes: &[(DVec2, DVec2)], tol: f64, lo: DVec2, hi: DVec2) -> Vec<(u32, u32)> {
    let m = boxes.len();
    let mean = boxes.iter().map(|b| (b.1 - b.0).max_element()).sum::<f64>() / m as f64;
    let extent = (hi - lo).max_element();
    // At most 2^20 cells along a side, so indices fit easily.
    let mut cell = (2.0 * mean)
        .max(extent / (1u64 << 20) as f64)
        .max(f64::MIN_POSITIVE);
    let range = |b: &(DVec2, DVec2), cell: f64| {
        let at = |x: f64| ((x / cell).floor().max(0.0) as u64).min(1 << 21);
        let (a, z) = (b.0 - lo - DVec2::splat(tol), b.1 - lo + DVec2::splat(tol));
        (at(a.x), at(a.y), at(z.x), at(z.y))
    };
    loop {
        let covered: f64 = boxes
            .iter()
            .map(|b| {
                let (x0, y0, x1, y1) = range(b, cell);
                ((x1 - x0 + 1) * (y1 - y0 + 1)) as f64
            })
            .sum();
        if covered <= 16.0 * m as f64 || cell >= extent {
            break;
        }
        cell *= 2.0;
    }
    let stride = (1u64 << 21) + 1;
    let mut listed: Vec<(u64, u32)> = Vec::with_capacity(4 * m);
    for (i, b) in boxes.iter().enumerate() {
        let (x0, y0, x1, y1) = range(b, cell);
        for y in y0..=y1 {
            for x in x0..=x1 {
                listed.push((y * stride + x, i as u32));
            }
        }
    }
    listed.sort_unstable();
    let mut pairs = Vec::new();
    for run in listed.chunk_by(|a, b| a.0 == b.0) {
        for (k, &(_, i)) in run.iter().enumerate() {
            pairs.extend(run[k + 1..].iter().map(|&(_, j)| (i, j)));
        }
    }
    pairs
}

/// Whether closed segments ab and cd share a point (exact).
pub(crate) fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (o1, o2) = (orient(a, b, c), orient(a, b, d));
    let (o3, o4) = (orient(c, d, a), orient(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && on_segment(a, b, c))
        || (o2 == 0.0 && on_segment(a, b, d))
        || (o3 == 0.0 && on_segment(c, d, a))
        || (o4 == 0.0 && on_segment(c, d, b))
}

fn corners(s: &Prepared, angle_deg: f64) -> Vec<usize> {
    let n = s.points.len();
    let range: Vec<usize> = if s.closed {
        (0..n).collect()
    } else {
        (1..n.saturating_sub(1)).collect()
    };
    range
        .into_iter()
        .filter(|&k| {
            let prev = s.points[(k + n - 1) % n];
            let next = s.points[(k + 1) % n];
            let (d1, d2) = (s.points[k] - prev, next - s.points[k]);
            let turn = d1.perp_dot(d2).atan2(d1.dot(d2)).abs().to_degrees();
            turn > angle_deg
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::close_pairs;
    use glam::DVec2;

    /// Every pair of boxes within the tolerance of each other is among [`close_pairs`]' (the
    /// check's only filter), on random walks with long and short steps and on boxes that
    /// just touch.
    #[test]
    fn close_pairs_holds_every_pair_of_boxes_within_the_tolerance() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..200 {
            let n = 2 + (rnd() * 120.0) as usize;
            let mut p = vec![DVec2::new(rnd() * 100.0, rnd() * 100.0)];
            for _ in 1..n {
                let step = if rnd() < 0.1 { 300.0 } else { 3.0 };
                let q = *p.last().unwrap() + DVec2::new(rnd() - 0.5, rnd() - 0.5) * step;
                p.push(if case % 3 == 0 { q.round() } else { q });
            }
            let boxes: Vec<(DVec2, DVec2)> = p
                .windows(2)
                .map(|w| (w[0].min(w[1]), w[0].max(w[1])))
                .collect();
            let (lo, hi) = p
                .iter()
                .fold((p[0], p[0]), |(l, h), &q| (l.min(q), h.max(q)));
            let tol = if case % 2 == 0 {
                0.0
            } else {
                1e-9 * (hi - lo).length()
            };
            let mut got = close_pairs(&boxes, tol, lo, hi);
            got.sort_unstable();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    let (a, b) = (boxes[i], boxes[j]);
                    let apart = a.1.x + tol < b.0.x
                        || b.1.x + tol < a.0.x
                        || a.1.y + tol < b.0.y
                        || b.1.y + tol < a.0.y;
                    if !apart {
                        assert!(
                            got.binary_search(&(i as u32, j as u32)).is_ok(),
                            "case {case}: boxes {i} and {j}"
                        );
                    }
                }
            }
        }
    }
}
