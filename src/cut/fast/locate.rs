//! Which faces may hold a screen point, for the few points a cut locates after snapping:
//! the piece ends (seed 002 §3.4, Fig. 12: an end strictly inside a face) and the stroke
//! points the report lists as dropped.
//!
//! Visible-only mode has its visibility buckets ([`FaceBuckets`]) and asks them. Through all,
//! nothing else needs buckets, and building them for a few dozen points would cost more
//! than the queries: [`PointFaces`] instead goes once over the region's faces and keeps, for
//! each of those points, the faces whose screen box holds it. The plain path looks at every
//! face.

use glam::DVec2;
use smallvec::SmallVec;

use super::buckets::FaceBuckets;
use super::{FaceIndex, Machinery};
use crate::cut::geom::map3;
use crate::cut::ids::Lf;
use crate::cut::region::Region;

/// Candidate faces of a point: a superset of the non-degenerate, projectable faces holding
/// it strictly inside (callers test each exactly).
pub(crate) enum Locator<'a> {
    Buckets(&'a FaceBuckets),
    Points(PointFaces),
    All,
}

impl<'a> Locator<'a> {
    /// A locator for `points` on the region as it is now: the visibility buckets when there
    /// are some (`faces`), else a table for just those points; every face on the plain path.
    pub fn new(
        machinery: Machinery,
        faces: Option<&'a FaceIndex>,
        region: &Region,
        points: impl FnOnce() -> Vec<DVec2>,
    ) -> Self {
        match (machinery, faces) {
            (Machinery::Plain, _) => Locator::All,
            (Machinery::Fast, Some(FaceIndex::Buckets(b))) => Locator::Buckets(b),
            (Machinery::Fast, _) => Locator::Points(PointFaces::new(region, points())),
        }
    }

    /// The candidate faces of `s`: nearest first from the buckets, ascending otherwise.
    pub fn faces_at(&self, region: &Region, s: DVec2) -> SmallVec<[Lf; 8]> {
        let by_box = || {
            region
                .faces()
                .filter(|&f| box_holds(region, f, s))
                .collect()
        };
        match self {
            Locator::Buckets(b) => b.faces_at(s).collect(),
            Locator::Points(p) => match p.faces_at(s) {
                Some(faces) => faces.iter().copied().collect(),
                // Not a point it was built for: every face's box (never happens in a cut;
                // correct anyway).
                None => by_box(),
            },
            Locator::All => by_box(),
        }
    }
}

/// For each of a few points, the region's faces (ascending) whose screen box holds it.
pub(crate) struct PointFaces {
    /// The points, sorted by x then y, without repeats.
    pts: Vec<DVec2>,
    /// CSR: point `k`'s faces are `list[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    list: Vec<Lf>,
}

impl PointFaces {
    /// The table for `points` on the region as it is now (after snapping).
    pub fn new(region: &Region, points: impl IntoIterator<Item = DVec2>) -> Self {
        let mut pts: Vec<DVec2> = points.into_iter().collect();
        pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        pts.dedup();
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(8 * pts.len());
        if let (Some(first), Some(last)) = (pts.first(), pts.last()) {
            // Columns over the points' x range, marked where a point is: most faces are
            // rejected by a bit or two.
            let (x0, width) = (first.x, (last.x - first.x).max(1e-300));
            const COLUMNS: usize = 4096;
            let scale = (COLUMNS - 1) as f64 / width;
            // Clamped, NaN to 0 (`f64::max` drops it); monotone in x.
            let column = |x: f64| ((x - x0) * scale).max(0.0).min((COLUMNS - 1) as f64) as usize;
            let mut marked = [0u64; COLUMNS / 64];
            for p in &pts {
                let c = column(p.x);
                marked[c / 64] |= 1 << (c % 64);
            }
            // A column range holds a mark when the count of marked columns up to its end
            // exceeds that up to its start, or its start is marked.
            let mut upto = [0u16; COLUMNS];
            let mut n = 0;
            for (c, u) in upto.iter_mut().enumerate() {
                n += (marked[c / 64] >> (c % 64) & 1) as u16;
                *u = n;
            }
            let any_marked = |c0: usize, c1: usize| {
                (upto[c1] != upto[c0]) | (marked[c0 / 64] >> (c0 % 64) & 1 == 1)
            };
            // Each vertex's screen x once (NaN behind the eye: its faces are skipped).
            let xs: Vec<f64> = region.seen_list().screen.iter().map(|s| s.x).collect();
            for (lf, t) in region.all_corners().iter().enumerate() {
                let x = map3(*t, |v| xs[v.idx()]);
                let (lo, hi) = (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]));
                // A corner behind the eye (NaN) drops out of min and max; `face_box` skips it.
                if !(hi >= x0 && lo <= last.x && any_marked(column(lo), column(hi))) {
                    continue;
                }
                let Some((lo, hi)) = face_box(region, Lf(lf as u32)) else {
                    continue;
                };
                let from = pts.partition_point(|p| p.x < lo.x);
                for (k, p) in pts.iter().enumerate().skip(from) {
                    if p.x > hi.x {
                        break;
                    }
                    if p.y >= lo.y && p.y <= hi.y {
                        pairs.push((k as u32, lf as u32));
                    }
                }
            }
        }
        // By point, faces ascending within each (pushed in face order).
        let (start, list) = super::radix::group_by_key(pts.len(), &pairs);
        let list = list.into_iter().map(Lf).collect();
        PointFaces { pts, start, list }
    }

    /// The faces of `s` if it is one of the table's points.
    fn faces_at(&self, s: DVec2) -> Option<&[Lf]> {
        let k = self
            .pts
            .binary_search_by(|p| p.x.total_cmp(&s.x).then(p.y.total_cmp(&s.y)))
            .ok()?;
        Some(&self.list[self.start[k] as usize..self.start[k + 1] as usize])
    }
}

/// The screen box of a face that can hold a point strictly inside (projectable, not
/// degenerate). Minima and maxima are exact: a point inside the face is inside its box.
fn face_box(region: &Region, f: Lf) -> Option<(DVec2, DVec2)> {
    if region.sign(f) == 0.0 || !region.projectable(f) {
        return None;
    }
    let [a, b, c] = region.face_screen(f);
    Some((a.min(b).min(c), a.max(b).max(c)))
}

fn box_holds(region: &Region, f: Lf, s: DVec2) -> bool {
    face_box(region, f).is_some_and(|(lo, hi)| s.cmpge(lo).all() && s.cmple(hi).all())
}
