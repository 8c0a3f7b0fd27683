//! Visible-only mode: is a point on a face seen from the eye? (seed 002 Fig. 2; spec §3,
//! gap-fill: decided per crossing by a ray through it.)
//!
//! Every face that can hide a point under the stroke projects onto that point, so it is in
//! the cut region ([`super::fast::grid`]): the ray is tested against the region's faces only,
//! bucketed by screen box in a uniform grid with cells about two faces wide, each bucket
//! nearest first so a ray stops at the first face wholly behind its point (for a ray through
//! a single pixel position, a 2D bucket grid does what a BVH would). Written here because it
//! is a hundred lines, and building a BVH (`parry3d`'s or `rstar`'s) over the region per cut
//! would cost more than the queries.
//!
//! Snapping moves vertices after the user saw the mesh: a point it did not move is seen only
//! if it was seen both before and after (katachi's gap-fill), so a snapped occluder that
//! slides aside does not expose what was hidden.
//!
//! Faces with a vertex behind the eye are not tested as occluders (they have no screen
//! triangle to bucket); a face that close to the camera rarely sits in front of a stroke.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::fast::grid::{cell_of, CellGrid};
use super::geom::{barycentric, in_triangle, map3};
use super::fast::radix::{f32_key, sort_by_key};
use super::region::{lift_with, Region};
use super::view::SeenList;

/// Faces whose screen boxes size the buckets' cells ([`FaceBuckets::new`]).
const SIZE_SAMPLE: usize = 512;

pub(crate) struct FaceBuckets {
    origin: DVec2,
    inv_cell: f64,
    nx: i32,
    ny: i32,
    start: Vec<u32>,
    list: Vec<Entry>,
    eps_world: f64,
    /// How far queries grow an entry's box: a billionth over the slack, which covers
    /// rounding `lo − pad` (and `hi + pad`) to nearest; the boxes' own outward rounding
    /// covers theirs.
    pad: f64,
}

/// A face in a bucket with its screen box rounded outwards to f32 (queries grow it by the
/// pad), and its nearest corner depth rounded down: most entries are rejected by the box, read in
/// line with the bucket instead of from three vertices, and a bucket (sorted by `near`)
/// stops at the first face wholly behind the point.
#[derive(Debug, Clone, Copy, Default)]
struct Entry {
    face: u32,
    near: f32,
    lo: [f32; 2],
    hi: [f32; 2],
}

/// `x` rounded down to f32: lowered first by 2e-7 of itself (more than rounding to nearest
/// can add back) and by 1e-30 (for 0). Branch-free; a box grows by a few ten-millionths.
#[inline]
fn down(x: f64) -> f32 {
    (x - x.abs() * 2e-7 - 1e-30) as f32
}

#[inline]
fn up(x: f64) -> f32 {
    -down(-x)
}

impl FaceBuckets {
    /// Buckets of the region's faces; each face's screen box is grown by `slack` pixels (the
    /// snap distance) so the buckets stay valid while vertices move that far (snapping).
    /// The faces are `tri` (local vertex ids) with screen orientations `sign` (0: not
    /// bucketed), their vertices seen as `seen` at `pos`. Each bucket is nearest first.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        tri: &[[u32; 3]],
        sign: &[f64],
        seen: &SeenList,
        pos: &[DVec3],
        grid: &CellGrid,
        depth_eps_rel: f64,
        slack: f64,
    ) -> Self {
        // Buckets over the stroke grid's area, about two faces wide: the region's faces lie
        // in a band along the stroke, so sizing cells by area per face would put dozens of
        // faces in each (the stroke grid's cells are too coarse for point queries too).
        let (origin, ext) = (
            grid.origin,
            DVec2::new(grid.nx as f64, grid.ny as f64) * grid.cell,
        );
        // The screen box of a projectable face.
        let screen_box = |t: [u32; 3]| {
            if !seen.front3(t) {
                return None;
            }
            let [a, b, c] = map3(t, |v| seen.screen[v as usize]);
            Some((a.min(b).min(c), a.max(b).max(c)))
        };
        // The mean box size from evenly spaced faces (it only sizes the cells): a pass over
        // every box before the one that buckets them made the region 9% slower on the 1M
        // torus, visible-only (this table is the longer side of the region's last join).
        let step = tri.len().div_ceil(SIZE_SAMPLE).max(1);
        let (mut size, mut n) = (0.0, 0u32);
        for (lo, hi) in tri.iter().step_by(step).filter_map(|&t| screen_box(t)) {
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
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &p in pos {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        // Counting sort by cell (stable, so nearest first within a cell): count, prefix-sum,
        // fill.
        let inv_cell = 1.0 / cell;
        let range = |a: DVec2, b: DVec2| cell_range(origin, inv_cell, nx, ny, a, b);
        // The cells a millionth wider than the box test, so rounding never leaves a point the
        // test accepts in a cell that misses the face.
        let pad = DVec2::splat(slack * (1.0 + 1e-6));
        // Each bucketed face's cell range, from its box grown by the slack (snapping moves
        // vertices after this), and entry.
        let boxes: Vec<Option<(CellRange, Entry)>> = tri
            .par_iter()
            .zip(sign)
            .enumerate()
            .with_min_len(1024)
            .map(|(lf, (&t, &sign))| {
                if sign == 0.0 {
                    return None;
                }
                let (lo, hi) = screen_box(t)?;
                let cells = range(lo - pad, hi + pad)?;
                let z = map3(t, |v| seen.depth[v as usize].x);
                let near = down(z[0].min(z[1]).min(z[2]));
                let entry = Entry {
                    face: lf as u32,
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
        // Nearest first (ties by face), so every bucket is sorted by `near` for `hidden`.
        sort_by_key(&mut order);
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
        let n = start[ncell] as usize;
        let mut list: Vec<Entry> = Vec::with_capacity(n);
        let slots = &mut list.spare_capacity_mut()[..n];
        for &(_, i) in &order {
            let Some(((x0, y0, x1, y1), entry)) = boxes[i as usize] else {
                unreachable!("ordered entries are bucketed")
            };
            for cy in y0..y1 + 1 {
                for cx in x0..x1 + 1 {
                    let c = (cy * nx + cx) as usize;
                    slots[fill[c] as usize].write(entry);
                    fill[c] += 1;
                }
            }
        }
        // SAFETY: the counts made room for exactly the entries written, each slot once.
        unsafe { list.set_len(n) };
        let diag = if pos.is_empty() {
            0.0
        } else {
            (hi - lo).length()
        };
        FaceBuckets {
            origin,
            inv_cell,
            nx,
            ny,
            start,
            list,
            eps_world: depth_eps_rel * diag,
            pad: slack * (1.0 + 1e-9),
        }
    }

    /// Candidate faces whose screen box covers the cell of `s` (a superset of those holding
    /// `s`), nearest corner depth first.
    pub fn faces_at(&self, s: DVec2) -> impl Iterator<Item = u32> + '_ {
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

    /// Whether some candidate face lies in front of world point `x` (screen `s`, NDC depth
    /// `z`) by more than the depth tolerance; with `before`, for a point that snapping did
    /// not move, also whether the faces hid it as they were before snapping (so a snap that
    /// pulls an occluder aside does not expose what the user could not see). `own`: the faces
    /// the point lies on (its edge's, its vertex's), which hold it at its own depth and never
    /// hide it: skipped (their inside tests are the costly near-zero ones).
    pub fn hidden(
        &self,
        r: &Region,
        s: DVec2,
        z: f64,
        x: DVec3,
        before: Option<&Before>,
        own: &[u32],
    ) -> bool {
        for e in self.entries_at(s) {
            // Every face from here on has all its corners behind the point: NDC depth is
            // affine on a screen triangle, and snapping keeps depth, so none of them is
            // nearer at `s`, before or after.
            if e.near as f64 > z {
                break;
            }
            // Outside the face's (outward-rounded, grown by the pad) box is outside
            // the face, before and after snapping; most bucket entries end here.
            if s.x < e.lo[0] as f64 - self.pad
                || s.y < e.lo[1] as f64 - self.pad
                || s.x > e.hi[0] as f64 + self.pad
                || s.y > e.hi[1] as f64 + self.pad
                || own.contains(&e.face)
            {
                continue;
            }
            let (t, sign) = (r.tri[e.face as usize], r.sign[e.face as usize]);
            if self.hides(t, sign, &r.seen, &r.pos, s, z, x) {
                return true;
            }
            if let Some(b) = before {
                if t.iter().any(|&v| b.moved(v)) && self.hides(t, sign, &b.seen, &b.pos, s, z, x) {
                    return true;
                }
            }
        }
        false
    }

    /// Whether triangle `t` (orientation `sign`), its vertices seen as `seen` at `pos`, holds
    /// screen point `s` at a depth nearer than `z`, and away from world point `x`.
    #[allow(clippy::too_many_arguments)]
    fn hides(
        &self,
        t: [u32; 3],
        sign: f64,
        seen: &SeenList,
        pos: &[DVec3],
        s: DVec2,
        z: f64,
        x: DVec3,
    ) -> bool {
        debug_assert!(seen.front3(t), "a bucketed face is projectable");
        let [a, b, c] = map3(t, |v| seen.screen[v as usize]);
        if in_triangle(a, b, c, sign, s).is_none() {
            return false;
        }
        let (zf, y) = lift_with(seen, pos, t, barycentric(a, b, c, s));
        zf < z && (y - x).length() > self.eps_world
    }
}

/// The region's vertices as they were before snapping, and which ones moved.
pub(crate) struct Before {
    seen: SeenList,
    pos: Vec<DVec3>,
    moved: Vec<bool>,
}

impl Before {
    /// The region as it is now (call before snapping).
    pub fn new(r: &Region) -> Self {
        Before {
            seen: r.seen.clone(),
            pos: r.pos.clone(),
            moved: vec![false; r.pos.len()],
        }
    }

    /// Records the vertices snapping moved.
    pub fn mark_moved(&mut self, moved: impl IntoIterator<Item = u32>) {
        for v in moved {
            self.moved[v as usize] = true;
        }
    }

    /// Whether local vertex `v` moved.
    #[inline]
    pub fn moved(&self, v: u32) -> bool {
        self.moved[v as usize]
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
