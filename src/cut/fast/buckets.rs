//! The region's faces bucketed by screen box, for visible-only mode's "what lies in front of
//! this point" and for finding the faces under a point: a uniform grid over the stroke
//! grid's area with cells about two faces wide (the region's faces lie in a band along the
//! stroke), each bucket nearest first, so a query stops at the first face wholly behind its
//! point. For a ray through a single pixel position, a 2D bucket grid does what a BVH would.

use glam::DVec2;
use rayon::prelude::*;

use super::grid::{cell_of, CellGrid};
use super::radix::{f32_key, sort_by_key};
use crate::cut::geom::map3;
use crate::cut::ids::Lf;
use crate::cut::region::Region;

/// Faces whose screen boxes size the buckets' cells ([`FaceBuckets::new`]).
const SIZE_SAMPLE: usize = 512;

pub(crate) struct FaceBuckets {
    origin: DVec2,
    inv_cell: f64,
    nx: i32,
    ny: i32,
    start: Vec<u32>,
    list: Vec<Entry>,
    /// How far queries grow an entry's box: a billionth over the slack, which covers
    /// rounding `lo − pad` (and `hi + pad`) to nearest; the boxes' own outward rounding
    /// covers theirs.
    pad: f64,
}

/// A face in a bucket with its screen box rounded outwards to f32 (queries grow it by the
/// pad), and its nearest corner depth rounded down: most entries are rejected by the box,
/// read in line with the bucket, and a bucket (sorted by `near`) stops at the first face
/// wholly behind the point.
#[derive(Debug, Clone, Copy, Default)]
struct Entry {
    face: Lf,
    near: f32,
    lo: [f32; 2],
    hi: [f32; 2],
}

/// `x` rounded down to f32: lowered first by 2e-7 of itself (more than rounding to nearest
/// can add back) and by 1e-30 (for 0). A box grows by a few ten-millionths.
#[inline]
fn down(x: f64) -> f32 {
    (x - x.abs() * 2e-7 - 1e-30) as f32
}

#[inline]
fn up(x: f64) -> f32 {
    -down(-x)
}

impl FaceBuckets {
    /// Buckets of the region's faces that have an orientation (projectable, not degenerate)
    /// over `grid`'s area; each face's screen box is grown by `slack` pixels so the buckets
    /// stay valid while vertices move that far (snapping). Each bucket is nearest first.
    pub fn new(region: &Region, grid: &CellGrid, slack: f64) -> Self {
        let (tri, seen) = (region.all_corners(), region.seen_list());
        let (origin, ext) = (
            grid.origin,
            DVec2::new(grid.nx as f64, grid.ny as f64) * grid.cell,
        );
        // The screen box of a projectable face.
        let screen_box = |f: usize| {
            let t = tri[f];
            if !seen.front3(t) {
                return None;
            }
            let [a, b, c] = map3(t, |v| seen.screen[v.idx()]);
            Some((a.min(b).min(c), a.max(b).max(c)))
        };
        // The mean box size from evenly spaced faces (it only sizes the cells).
        let step = tri.len().div_ceil(SIZE_SAMPLE).max(1);
        let (mut size, mut n) = (0.0, 0u32);
        for (lo, hi) in (0..tri.len()).step_by(step).filter_map(screen_box) {
            let e = hi - lo;
            size += e.x.max(e.y);
            n += 1;
        }
        let mean = if n > 0 { size / n as f64 } else { 0.0 };
        let cell = (2.0 * mean)
            .max(((ext.x * ext.y) / (1u64 << 22) as f64).sqrt())
            .max(ext.x.max(ext.y) / 8192.0)
            .max(1e-9);
        let nx = ((ext.x / cell).ceil() as i32).max(1);
        let ny = ((ext.y / cell).ceil() as i32).max(1);
        let ncell = (nx * ny) as usize;
        let inv_cell = 1.0 / cell;
        let range = |a: DVec2, b: DVec2| cell_range(origin, inv_cell, nx, ny, a, b);
        // The cells a millionth wider than the box test, so rounding never leaves a point the
        // test accepts in a cell that misses the face.
        let pad = DVec2::splat(slack * (1.0 + 1e-6));
        let boxes: Vec<Option<(CellRange, Entry)>> = (0..tri.len())
            .into_par_iter()
            .with_min_len(1024)
            .map(|f| {
                if region.sign(Lf(f as u32)) == 0.0 {
                    return None;
                }
                let (lo, hi) = screen_box(f)?;
                let cells = range(lo - pad, hi + pad)?;
                let z = map3(tri[f], |v| seen.depth[v.idx()].x);
                let near = down(z[0].min(z[1]).min(z[2]));
                let entry = Entry {
                    face: Lf(f as u32),
                    near,
                    lo: [down(lo.x), down(lo.y)],
                    hi: [up(hi.x), up(hi.y)],
                };
                Some((cells, entry))
            })
            .collect();
        let mut order: Vec<(u32, u32)> = boxes
            .iter()
            .enumerate()
            .filter_map(|(i, b)| b.map(|(_, e)| (f32_key(e.near), i as u32)))
            .collect();
        // Nearest first (ties by face), so every bucket is sorted by `near`.
        sort_by_key(&mut order);
        // Counting sort by cell (stable, so nearest first within a cell).
        let mut start = vec![0u32; ncell + 1];
        for &((x0, y0, x1, y1), _) in boxes.iter().flatten() {
            for cy in y0..y1 + 1 {
                for cx in x0..x1 + 1 {
                    start[(cy * nx + cx) as usize + 1] += 1;
                }
            }
        }
        for i in 0..ncell {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut list = vec![Entry::default(); start[ncell] as usize];
        for &(_, i) in &order {
            let Some(((x0, y0, x1, y1), entry)) = boxes[i as usize] else {
                unreachable!("ordered entries are bucketed")
            };
            for cy in y0..y1 + 1 {
                for cx in x0..x1 + 1 {
                    let c = (cy * nx + cx) as usize;
                    list[fill[c] as usize] = entry;
                    fill[c] += 1;
                }
            }
        }
        FaceBuckets {
            origin,
            inv_cell,
            nx,
            ny,
            start,
            list,
            pad: slack * (1.0 + 1e-9),
        }
    }

    /// Faces whose screen box covers the cell of `s` (a superset of those holding `s`),
    /// nearest corner depth first.
    pub fn faces_at(&self, s: DVec2) -> impl Iterator<Item = Lf> + '_ {
        self.entries_at(s).iter().map(|e| e.face)
    }

    fn entries_at(&self, s: DVec2) -> &[Entry] {
        let range = match cell_range(self.origin, self.inv_cell, self.nx, self.ny, s, s) {
            Some((cx, cy, _, _)) => {
                let c = (cy * self.nx + cx) as usize;
                self.start[c] as usize..self.start[c + 1] as usize
            }
            None => 0..0,
        };
        &self.list[range]
    }

    /// Whether `f` holds for a face that may hold `s` at a depth nearer than `z` (a
    /// superset): the faces of `s`'s bucket whose (grown) box holds `s`, up to the first
    /// whose every corner is behind `z` (NDC depth is affine on a screen triangle, and
    /// snapping keeps depth, so none from there on is nearer at `s`, before or after).
    pub fn any_in_front(&self, s: DVec2, z: f64, mut f: impl FnMut(Lf) -> bool) -> bool {
        for e in self.entries_at(s) {
            if e.near as f64 > z {
                break;
            }
            if s.x < e.lo[0] as f64 - self.pad
                || s.y < e.lo[1] as f64 - self.pad
                || s.x > e.hi[0] as f64 + self.pad
                || s.y > e.hi[1] as f64 + self.pad
            {
                continue;
            }
            if f(e.face) {
                return true;
            }
        }
        false
    }
}

/// Inclusive cell range (x0, y0, x1, y1).
type CellRange = (i32, i32, i32, i32);

fn cell_range(
    origin: DVec2,
    inv_cell: f64,
    nx: i32,
    ny: i32,
    lo: DVec2,
    hi: DVec2,
) -> Option<CellRange> {
    let (x0, y0) = cell_of(origin, inv_cell, lo);
    let (x1, y1) = cell_of(origin, inv_cell, hi);
    if x1 < 0 || y1 < 0 || x0 >= nx || y0 >= ny {
        return None;
    }
    Some((x0.max(0), y0.max(0), x1.min(nx - 1), y1.min(ny - 1)))
}
