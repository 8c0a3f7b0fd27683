//! Finding the faces near the stroke in two streaming passes, the only work proportional to
//! the whole mesh.
//!
//! A grid over the stroke's bounding box (grown by the snap margin), with cells about one
//! edge long, marks the cells within the margin of some stroke segment. Pass 1 projects every
//! vertex and stores its cell (clamped to one ring of "outside" cells, or "behind the eye"),
//! with a bit saying whether the cell is next to a marked one; pass 2 keeps a face when the
//! cell box of its corners covers a marked cell — a conservative test, so every face within
//! the margin of the stroke is kept; most faces are rejected from the bits alone (the region
//! then measures the few kept ones on screen). Both passes run on
//! rayon in fixed chunks and concatenate in chunk order, so the result does not depend on
//! the thread count.
//!
//! The grid also lists each cell's nearby segments, for the region's tests; wider lists,
//! found beside the marks, serve a face or an edge up to three cells across in one read.

use std::mem::MaybeUninit;

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::cut::view::{Projector, ScreenRows, SCREEN_RANGE_PX};
use crate::mesh::VertexId;

/// Vertex code for "behind the eye".
pub(crate) const BEHIND: u32 = u32::MAX;
const CHUNK: usize = 1 << 14;
/// Faces rejected together in pass 2 (a divisor of `CHUNK`).
pub(crate) const BLOCK: usize = 16;
/// How far (in cells) the "near" marks reach around the band: faces spanning up to this many
/// cells are rejected from their corners' bits alone. Cells are about one mean edge long and
/// edges vary, so the ring is wider than one cell; 4 suits [`not_away`]'s lanes.
pub(crate) const NEAR_RING: u32 = 4;
/// Tighter rings for the slow test, which rejects a face spanning at most a ring's width with
/// a corner outside that ring without looking at the grid ([`far_for_span`]).
pub(crate) const MID_RING: u32 = 2;
pub(crate) const CLOSE_RING: u32 = 1;
/// Flags of the near table, as they sit in bits 24-31 of a vertex code: [`NEAR`], [`MID`] and
/// [`CLOSE`], within [`NEAR_RING`], [`MID_RING`] and [`CLOSE_RING`] cells of a marked cell (a
/// cell in a ring has the wider rings' flags too); [`MARKED`], the cell itself is marked.
pub(crate) const NEAR: u8 = 0x80;
pub(crate) const CLOSE: u8 = 0x40;
pub(crate) const MARKED: u8 = 0x20;
pub(crate) const MID: u8 = 0x10;

/// The grid over the stroke: geometry, marked cells and the segments near each cell.
#[derive(Debug, Clone)]
pub(crate) struct CellGrid {
    pub origin: DVec2,
    pub cell: f64,
    pub nx: i32,
    pub ny: i32,
    inv_cell: f64,
    /// Marked cells ([`MARKED`]) grown by [`NEAR_RING`] cells each way ([`NEAR`]) and by
    /// [`CLOSE_RING`] ([`CLOSE`] too), on the grid with its outside ring: a face none of whose corners is in
    /// a ring touches a marked cell only if it spans more cells than the ring is wide (its
    /// corners are then not all within the ring's width of the marked one). Three zero bytes
    /// follow the table, so a four-byte read at its last cell stays inside it (the AVX-512
    /// pass gathers the flags that way).
    near: Vec<u8>,
    /// The segments within the margin and half a diagonal of each cell's centre (so every
    /// segment within the margin of a point of the cell).
    lists: CellLists,
    /// For each cell, the segments within the margin, half a diagonal and a diagonal of its
    /// centre (with a relative slack of 1e-6, far above rounding, [`wide_reach`]): a superset
    /// of those its eight neighbours list (each of their centres is a diagonal away).
    wide: CellLists,
}

/// Where a grid lies on screen: its corner, one over its cells' width, its cells along x and y
/// (for the x86-64 passes in `codes_simd`).
#[cfg(target_arch = "x86_64")]
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridPlace {
    pub origin: DVec2,
    pub inv_cell: f64,
    pub nx: i32,
    pub ny: i32,
}

/// Segments listed per cell: `list[runs.get(cx, cy)]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct CellLists {
    runs: CellRuns,
    list: Vec<u32>,
}

impl CellLists {
    /// The lists of (cell, segment) `pairs`, sorted by cell, on an `nx` × `ny` grid.
    fn new(pairs: &[(u32, u32)], nx: i32, ny: i32) -> Self {
        CellLists {
            runs: CellRuns::new(pairs, nx, ny),
            list: pairs.iter().map(|&(_, s)| s).collect(),
        }
    }

    /// The segments of cell (cx, cy) on the grid.
    #[inline]
    fn at(&self, cx: i32, cy: i32) -> &[u32] {
        &self.list[self.runs.get(cx, cy)]
    }
}

/// Where each cell's run lies in a list sorted by cell, for a grid whose few listed cells lie
/// along the stroke: 8×8 blocks, a table over all blocks naming the listed ones, and for each
/// listed block its cells' (start, end), so a fine grid costs no dense table.
#[derive(Debug, Clone, Default)]
struct CellRuns {
    /// Blocks along a row.
    nbx: u32,
    /// Per block, its first entry in `runs` (64 a block), or `EMPTY_BLOCK`.
    block: Vec<u32>,
    runs: Vec<[u32; 2]>,
}

const EMPTY_BLOCK: u32 = u32::MAX;

impl CellRuns {
    /// The runs of `pairs` (cell, value), sorted by cell, on an `nx` × `ny` grid.
    fn new(pairs: &[(u32, u32)], nx: i32, ny: i32) -> Self {
        let (nbx, nby) = ((nx as u32).div_ceil(8), (ny as u32).div_ceil(8));
        let mut block = vec![EMPTY_BLOCK; (nbx * nby) as usize];
        let mut runs: Vec<[u32; 2]> = Vec::new();
        let mut i = 0;
        while i < pairs.len() {
            let c = pairs[i].0;
            let start = i as u32;
            while i < pairs.len() && pairs[i].0 == c {
                i += 1;
            }
            let (cx, cy) = (c % nx as u32, c / nx as u32);
            let b = &mut block[((cy >> 3) * nbx + (cx >> 3)) as usize];
            if *b == EMPTY_BLOCK {
                *b = runs.len() as u32;
                runs.resize(runs.len() + 64, [0, 0]);
            }
            runs[(*b + (cy & 7) * 8 + (cx & 7)) as usize] = [start, i as u32];
        }
        CellRuns { nbx, block, runs }
    }

    /// The run of cell (cx, cy) on the grid (empty for a cell without one).
    #[inline]
    fn get(&self, cx: i32, cy: i32) -> std::ops::Range<usize> {
        let (cx, cy) = (cx as u32, cy as u32);
        let b = self.block[((cy >> 3) * self.nbx + (cx >> 3)) as usize];
        if b == EMPTY_BLOCK {
            return 0..0;
        }
        let [s, e] = self.runs[(b + (cy & 7) * 8 + (cx & 7)) as usize];
        s as usize..e as usize
    }
}

impl CellGrid {
    /// `segments[i]` = (a, b); `margin` ≥ 0 pixels; cells about `cell_hint` pixels wide
    /// (the expected edge length: a band of cells then holds few faces beyond those the
    /// stroke meets), at most 2048 along a side and 2^20 in all, whatever the numbers: the
    /// segments lie within the screen range ([`SCREEN_RANGE_PX`]), and a margin or hint
    /// beyond it is taken as the range (the grid then covers everything a cut can see).
    pub fn new(segments: &[(DVec2, DVec2)], margin: f64, cell_hint: f64) -> Self {
        let limit = 4.0 * SCREEN_RANGE_PX;
        let margin = margin.clamp(0.0, limit);
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for &(a, b) in segments {
            lo = lo.min(a).min(b);
            hi = hi.max(a).max(b);
        }
        debug_assert!(crate::cut::view::in_range(lo) && crate::cut::view::in_range(hi));
        lo -= DVec2::splat(margin);
        hi += DVec2::splat(margin);
        let ext = hi - lo;
        let long = ext.x.max(ext.y);
        let mut cell = cell_hint.min(limit).max(long / 2048.0).max(1e-6);
        if (ext.x / cell + 1.0) * (ext.y / cell + 1.0) > (1u64 << 20) as f64 {
            cell = ((ext.x * ext.y) / (1u64 << 20) as f64).sqrt().max(cell);
        }
        // A border of NEAR_RING + 1 cells that no marked cell reaches: a corner clamped to
        // the outside ring is then never within NEAR_RING cells of a marked one.
        let pad = DVec2::splat((NEAR_RING + 1) as f64 * cell);
        lo -= pad;
        hi += pad;
        let ext = hi - lo;
        // Codes hold x + 1 in 16 bits and y + 1 in 12: a side has at most 2048 cells and the
        // border (clamped too, so no rounding can make more).
        let side =
            |e: f64| ((e / cell).ceil().max(1.0) as i32).min(2048 + 2 * NEAR_RING as i32 + 4);
        let (nx, ny) = (side(ext.x), side(ext.y));
        debug_assert!(nx + 2 <= 0xffff && ny + 2 <= 0xfff);
        let inv_cell = 1.0 / cell;
        let (wide_reach, geometry) = (wide_reach(margin, cell), (lo, cell, nx, ny));
        let wide = || {
            CellLists::new(
                &cell_pairs(segments, geometry, wide_reach, wide_reach),
                nx,
                ny,
            )
        };
        let ((near, lists), wide) = rayon::join(|| Self::marks(segments, geometry, margin), wide);
        CellGrid {
            origin: lo,
            cell,
            nx,
            ny,
            inv_cell,
            near,
            lists,
            wide,
        }
    }

    /// The near table ([`CellGrid::near`]) and the cells' lists of a grid `(origin, cell, nx,
    /// ny)` for `margin`.
    fn marks(
        segments: &[(DVec2, DVec2)],
        (lo, cell, nx, ny): (DVec2, f64, i32, i32),
        margin: f64,
    ) -> (Vec<u8>, CellLists) {
        let half_diag = cell * std::f64::consts::FRAC_1_SQRT_2;
        // Each cell whose centre is within the margin and half a diagonal of a segment (it may
        // hold a point within the margin of it).
        let pairs = cell_pairs(
            segments,
            (lo, cell, nx, ny),
            margin,
            margin + half_diag * 1.0001,
        );
        // Dilations by NEAR_RING, MID_RING, then CLOSE_RING cells (Chebyshev), from the runs
        // of marked cells along each row (pairs are in row-major cell order): one span per run
        // and row it reaches. The band is thin and mostly along rows, so this writes a few
        // spans where a span per cell wrote thousands. With the outside ring (never near), indexed
        // by code: (cy + 1)·(nx + 2) + cx + 1; and three bytes of padding.
        let mut near = vec![0u8; ((nx + 2) * (ny + 2)) as usize + 3];
        let runs = marked_runs(&pairs, nx as u32);
        for (r, flags) in [
            (NEAR_RING, NEAR),
            (MID_RING, NEAR | MID),
            (CLOSE_RING, NEAR | MID | CLOSE),
        ] {
            let r = r as i32;
            for &(cy, a, b) in &runs {
                let (x0, x1) = ((a - r).max(0), (b + r).min(nx - 1));
                for y in (cy - r).max(0)..(cy + r).min(ny - 1) + 1 {
                    let row = ((y + 1) * (nx + 2) + 1) as usize;
                    near[row + x0 as usize..=row + x1 as usize].fill(flags);
                }
            }
        }
        for &(c, _) in &pairs {
            let (cx, cy) = (c % nx as u32, c / nx as u32);
            near[((cy + 1) * (nx as u32 + 2) + cx + 1) as usize] |= MARKED;
        }
        (near, CellLists::new(&pairs, nx, ny))
    }

    /// The segments any cell of the inclusive range `(x0, y0, x1, y1)` (on the grid) lists,
    /// and a few more, each once, ascending, when the range is at most three cells wide and
    /// high: the wide list of its middle cell (one read, no walk over the range's rows).
    /// `None` for a larger range.
    #[inline]
    pub fn segments_around(&self, (x0, y0, x1, y1): (i32, i32, i32, i32)) -> Option<&[u32]> {
        if x1 - x0 > 2 || y1 - y0 > 2 {
            return None;
        }
        Some(self.wide.at((x0 + x1) / 2, (y0 + y1) / 2))
    }

    /// Where the grid lies on screen, for the passes that place points in it.
    #[cfg(target_arch = "x86_64")]
    pub fn place(&self) -> GridPlace {
        GridPlace {
            origin: self.origin,
            inv_cell: self.inv_cell,
            nx: self.nx,
            ny: self.ny,
        }
    }

    /// The vertex code of world point `p` seen through `view` ([`Projector::screen_rows`]:
    /// [`Projector::screen_of`]'s arithmetic, operation by operation): its cell, clamped to
    /// one outside ring, packed (x in bits 0-15, y in 16-27, both offset by one so the ring
    /// below is 0), with the cell's [`NEAR`], [`CLOSE`], [`MARKED`] and [`MID`] flags in bits
    /// 31, 30, 29 and 28; [`BEHIND`] when the projector does not see it (behind the eye, or
    /// beyond the screen range). (No `floor`: without SSE4.1 it is a libm call.)
    #[inline]
    pub fn code(&self, view: &ScreenRows, p: DVec3) -> u32 {
        let h = p.extend(1.0);
        let w = view.w.dot(h);
        if !(w > 0.0 && w < f64::INFINITY) {
            return BEHIND;
        }
        let inv = 1.0 / w;
        let sx = view.x0 + (view.x.dot(h) * inv + 1.0) * view.half_w;
        let sy = view.y0 + (1.0 - view.y.dot(h) * inv) * view.half_h;
        if !(sx.abs() <= SCREEN_RANGE_PX && sy.abs() <= SCREEN_RANGE_PX) {
            return BEHIND;
        }
        // The cell plus one, clamped to [0, n + 1] (NaN → 0: `f64::max` drops it), so the
        // casts cannot overflow and the index is inside the (nx + 2) × (ny + 2) table.
        // Unchecked because this is the whole-mesh pass.
        let clamp = |x: f64, n: i32| x.max(0.0).min(n as f64 + 1.0);
        // SAFETY: as above, finite values in [0, n + 1].
        let (cx, cy) = unsafe {
            (
                clamp((sx - self.origin.x) * self.inv_cell + 1.0, self.nx).to_int_unchecked::<i32>()
                    as u32,
                clamp((sy - self.origin.y) * self.inv_cell + 1.0, self.ny).to_int_unchecked::<i32>()
                    as u32,
            )
        };
        let at = (cy * (self.nx as u32 + 2) + cx) as usize;
        debug_assert!(at < self.near.len());
        // SAFETY: as above, in the table.
        let flags = unsafe { *self.near.get_unchecked(at) };
        cx | (cy << 16) | (flags as u32) << 24
    }

    /// [`code`](Self::code) of every point of `ps` into `out`, eight at a time with AVX-512
    /// or four with AVX2 when the CPU has it (same bits).
    fn codes_into(&self, view: &ScreenRows, ps: &[DVec3], out: &mut [MaybeUninit<u32>]) {
        #[allow(unused_mut)]
        let mut done = 0;
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            let wide = std::arch::is_x86_feature_detected!("avx512f")
                && std::arch::is_x86_feature_detected!("avx512vl");
            let place = self.place();
            // SAFETY: AVX2 (and for `codes8` AVX-512 F and VL) is there; `out` is as long as
            // `ps`; `near` is (nx + 2) × (ny + 2) and its padding.
            done = unsafe {
                if wide {
                    super::codes_simd::codes8(view, &place, &self.near, ps, out)
                } else {
                    super::codes_simd::codes(view, &place, &self.near, ps, out)
                }
            };
        }
        for (o, p) in out[done..].iter_mut().zip(&ps[done..]) {
            o.write(self.code(view, *p));
        }
    }

    /// Inclusive cell range of a box, clamped to the grid; `None` when it misses the grid.
    pub fn range(&self, lo: DVec2, hi: DVec2) -> Option<(i32, i32, i32, i32)> {
        self.clamp(self.cell(lo), self.cell(hi))
    }

    /// The cell of a point, unclamped. Monotone in each coordinate, so the cells of a box's
    /// corners are the least and greatest of its points' cells.
    #[inline]
    pub fn cell(&self, s: DVec2) -> (i32, i32) {
        cell_of(self.origin, self.inv_cell, s)
    }

    /// The inclusive range from cell `lo` to cell `hi` clamped to the grid; `None` when it
    /// misses the grid.
    #[inline]
    pub fn clamp(
        &self,
        (x0, y0): (i32, i32),
        (x1, y1): (i32, i32),
    ) -> Option<(i32, i32, i32, i32)> {
        if x1 < 0 || y1 < 0 || x0 >= self.nx || y0 >= self.ny {
            return None;
        }
        Some((
            x0.max(0),
            y0.max(0),
            x1.min(self.nx - 1),
            y1.min(self.ny - 1),
        ))
    }

    /// Whether any cell of the inclusive range of packed codes is marked.
    #[inline]
    fn any_marked(&self, codes: [u32; 3]) -> bool {
        // A corner in a marked cell: its cell is in the box.
        if (codes[0] | codes[1] | codes[2]) >> 24 & MARKED as u32 != 0 {
            return true;
        }
        let b = cell_box(codes);
        let all = ((codes[0] & codes[1] & codes[2]) >> 24) as u8;
        !far_for_span(all, (b.2 - b.0).max(b.3 - b.1) as u32) && self.box_marked(b)
    }

    /// Whether any cell of the inclusive range `(x0, y0, x1, y1)` is marked, cell by cell
    /// (the rest of the range off the grid).
    pub(crate) fn box_marked(&self, (x0, y0, x1, y1): (i32, i32, i32, i32)) -> bool {
        if x1 < 0 || y1 < 0 || x0 >= self.nx || y0 >= self.ny {
            return false;
        }
        let stride = self.nx + 2;
        for cy in y0.max(0)..y1.min(self.ny - 1) + 1 {
            let row = ((cy + 1) * stride + 1) as usize;
            for cx in x0.max(0)..x1.min(self.nx - 1) + 1 {
                if self.near[row + cx as usize] & MARKED != 0 {
                    return true;
                }
            }
        }
        false
    }

    /// Segments listed in the cell of point `s` (none off the grid): every segment within
    /// the margin of `s` is among them.
    #[inline]
    pub fn segments_near(&self, s: DVec2) -> &[u32] {
        match self.range(s, s) {
            Some((cx, cy, _, _)) => self.segments_at(cx, cy),
            None => &[],
        }
    }

    /// Segments near cell (cx, cy).
    #[inline]
    pub fn segments_at(&self, cx: i32, cy: i32) -> &[u32] {
        self.lists.at(cx, cy)
    }

    /// The lists of cells `x0..=x1` of row `cy`, one after the other (cells are stored in
    /// row-major order): what [`segments_at`](Self::segments_at) gives cell by cell, as one
    /// slice.
    #[inline]
    pub fn segments_along(&self, cy: i32, x0: i32, x1: i32) -> &[u32] {
        // From the first listed cell's start to the last one's end.
        let runs = &self.lists.runs;
        let Some(first) = (x0..=x1).map(|cx| runs.get(cx, cy)).find(|r| !r.is_empty()) else {
            return &[];
        };
        let last = (x0..=x1)
            .rev()
            .map(|cx| runs.get(cx, cy))
            .find(|r| !r.is_empty());
        &self.lists.list[first.start..last.expect("a listed cell").end]
    }

    /// The segments listed in the cells of the box `lo..=hi` (every segment within the
    /// margin of a point of the box), each once: the wide list of its middle cell when the
    /// box is at most three cells across, else gathered into `scratch` in cell order.
    #[inline]
    pub fn segments_in_box<'a>(
        &'a self,
        lo: DVec2,
        hi: DVec2,
        scratch: &'a mut Vec<u32>,
    ) -> &'a [u32] {
        let Some(range) = self.range(lo, hi) else {
            return &[];
        };
        if let Some(list) = self.segments_around(range) {
            return list;
        }
        let (x0, y0, x1, y1) = range;
        scratch.clear();
        for cy in y0..y1 + 1 {
            for &k in self.segments_along(cy, x0, x1) {
                if !scratch.contains(&k) {
                    scratch.push(k);
                }
            }
        }
        scratch
    }
}

/// (cell, segment) for each cell of grid `(origin, cell, nx, ny)` whose centre is within
/// `reach` of a segment ([`within`]), looked for in the segment's box grown by `pad`, per
/// row only among the cells whose x the slab of the row's centres can reach; by cell, each
/// cell's segments ascending (pushed in segment order, and the radix sort is stable).
fn cell_pairs(
    segments: &[(DVec2, DVec2)],
    (lo, cell, nx, ny): (DVec2, f64, i32, i32),
    pad: f64,
    reach: f64,
) -> Vec<(u32, u32)> {
    let inv_cell = 1.0 / cell;
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (si, &(a, b)) in segments.iter().enumerate() {
        let (smin, smax) = (a.min(b) - DVec2::splat(pad), a.max(b) + DVec2::splat(pad));
        let (x0, y0) = cell_of(lo, inv_cell, smin);
        let (x1, y1) = cell_of(lo, inv_cell, smax);
        let (x0, x1) = (x0.max(0), x1.min(nx - 1));
        for cy in y0.max(0)..y1.min(ny - 1) + 1 {
            let yc = lo.y + (cy as f64 + 0.5) * cell;
            let Some((xa, xb)) = x_span_in_slab(a, b, yc - reach, yc + reach) else {
                continue;
            };
            // A cell either side against rounding: `within` decides.
            let (ca, _) = cell_of(lo, inv_cell, DVec2::new(xa - reach, yc));
            let (cb, _) = cell_of(lo, inv_cell, DVec2::new(xb + reach, yc));
            for cx in (ca - 1).max(x0)..(cb + 1).min(x1) + 1 {
                let centre = lo + DVec2::new(cx as f64 + 0.5, cy as f64 + 0.5) * cell;
                if within(centre, a, b, reach) {
                    pairs.push(((cy * nx + cx) as u32, si as u32));
                }
            }
        }
    }
    super::radix::sort_by_key(&mut pairs);
    pairs
}

/// The inclusive cell range `(x0, y0, x1, y1)` of three packed codes (not behind the eye).
#[inline]
pub(crate) fn cell_box(codes: [u32; 3]) -> (i32, i32, i32, i32) {
    let xs = codes.map(|c| (c & 0xffff) as i32 - 1);
    let ys = codes.map(|c| ((c >> 16) & 0xfff) as i32 - 1);
    (
        xs[0].min(xs[1]).min(xs[2]),
        ys[0].min(ys[1]).min(ys[2]),
        xs[0].max(xs[1]).max(xs[2]),
        ys[0].max(ys[1]).max(ys[2]),
    )
}

/// The x range of the part of segment `ab` with y in `[y0, y1]`, `None` when there is none
/// (widened by a millionth of the segment's extent: callers only bound a search with it).
#[inline]
fn x_span_in_slab(a: DVec2, b: DVec2, y0: f64, y1: f64) -> Option<(f64, f64)> {
    let slack = 1e-6 * (1.0 + a.abs().max(b.abs()).max_element());
    let (y0, y1) = (y0 - slack, y1 + slack);
    if a.y.max(b.y) < y0 || a.y.min(b.y) > y1 {
        return None;
    }
    let dy = b.y - a.y;
    if dy.abs() <= slack {
        return Some((a.x.min(b.x) - slack, a.x.max(b.x) + slack));
    }
    // Parameters where the segment's line crosses the slab's edges, clipped to [0, 1].
    let (u, v) = ((y0 - a.y) / dy, (y1 - a.y) / dy);
    let (t0, t1) = (u.min(v).max(0.0), u.max(v).min(1.0));
    let (xa, xb) = (a.x + (b.x - a.x) * t0, a.x + (b.x - a.x) * t1);
    Some((xa.min(xb) - slack, xa.max(xb) + slack))
}

/// Runs of consecutive marked cells along rows, `(row, first, last)`, from `(cell, segment)`
/// pairs sorted by cell (row-major, `nx` cells a row).
fn marked_runs(pairs: &[(u32, u32)], nx: u32) -> Vec<(i32, i32, i32)> {
    let mut runs: Vec<(i32, i32, i32)> = Vec::new();
    for &(c, _) in pairs {
        let (cx, cy) = ((c % nx) as i32, (c / nx) as i32);
        match runs.last_mut() {
            Some((y, _, b)) if *y == cy && cx - *b <= 1 => *b = cx,
            _ => runs.push((cy, cx, cx)),
        }
    }
    runs
}

/// The reach of the wide lists ([`CellGrid::wide`]) for `margin` and cells `cell` wide.
fn wide_reach(margin: f64, cell: f64) -> f64 {
    let half_diag = cell * std::f64::consts::FRAC_1_SQRT_2;
    (margin + half_diag * 1.0001 + cell * std::f64::consts::SQRT_2) * (1.0 + 1e-6)
}

/// The cell of `s` in a grid at `origin` with cells `1 / inv_cell` wide (unclamped).
#[inline]
pub(crate) fn cell_of(origin: DVec2, inv_cell: f64, s: DVec2) -> (i32, i32) {
    let q = (s - origin) * inv_cell;
    (floor_i32(q.x), floor_i32(q.y))
}

/// `x.floor() as i32`: saturating, NaN → 0, so far-away points stay far away. Without
/// SSE4.1 `floor` is a libm call, and this is on every box query.
#[inline]
fn floor_i32(x: f64) -> i32 {
    let t = x as i32;
    if t as f64 > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// Whether `p` is within `r` of segment `ab`: [`point_segment_distance`] `<= r` up to
/// rounding, without its square root and division (the grid asks this thousands of times
/// per cut).
#[inline]
pub(crate) fn within(p: DVec2, a: DVec2, b: DVec2, r: f64) -> bool {
    let (ab, ap) = (b - a, p - a);
    let t = ap.dot(ab);
    let r2 = r * r;
    if t <= 0.0 {
        return ap.length_squared() <= r2;
    }
    let len2 = ab.length_squared();
    if t >= len2 {
        return (p - b).length_squared() <= r2;
    }
    let c = ab.perp_dot(ap);
    c * c <= r2 * len2
}

/// Pass 1: every vertex's code.
pub(crate) fn vertex_codes(positions: &[DVec3], proj: &Projector, grid: &CellGrid) -> Vec<u32> {
    let view = proj.screen_rows();
    let mut codes: Vec<u32> = crate::mem::with_capacity(positions.len());
    // Chunks written in place.
    codes.spare_capacity_mut()[..positions.len()]
        .par_chunks_mut(CHUNK)
        .zip(positions.par_chunks(CHUNK))
        .for_each(|(out, ps)| grid.codes_into(&view, ps, out));
    // SAFETY: every one of the first `positions.len()` elements was written above.
    unsafe { codes.set_len(positions.len()) };
    codes
}

/// Zero when a face is surely away from every marked cell, from its corners' codes alone: no
/// corner is near a marked cell, and corners 1 and 2 lie within `NEAR_RING` cells of corner
/// 0 on both axes (differences in [-4, 3]), so the face's cell box lies within `NEAR_RING` of
/// corner 0 and holds no marked cell. (A [`BEHIND`] corner has the near bit.) The scan's hot
/// test, both axes in one subtraction: with the near bits clear, `c − (c0 − 4·(1, 1))` has
/// each 16-bit lane in [0, 7] exactly when the differences are in range; a lane out of
/// range sets a bit above 2 in it (a negative low lane also borrows from the high one, which
/// only adds bits).
#[inline(always)]
fn not_away(c: [u32; 3]) -> u32 {
    const OFFSET: u32 = NEAR_RING | NEAR_RING << 16;
    let base = c[0].wrapping_sub(OFFSET);
    let spread = c[1].wrapping_sub(base) | c[2].wrapping_sub(base);
    (spread & 0xfff8_fff8) | ((c[0] | c[1] | c[2]) >> 31)
}

/// Whether some corner of a face is farther from every marked cell than the face's cell box
/// is wide, `span` cells (Chebyshev, from the ring flags `all` the corners have): every cell of
/// the box is within its width of each corner, so the box then holds no marked cell. Each
/// ring rejects the faces it is wider than with one corner outside it.
#[inline(always)]
fn far_for_span(all: u8, span: u32) -> bool {
    ((all & NEAR == 0) & (span <= NEAR_RING))
        | ((all & MID == 0) & (span <= MID_RING))
        | ((all & CLOSE == 0) & (span <= CLOSE_RING))
}

/// Pass 2: the faces whose corners' cell box covers a marked cell, ascending, with their
/// corners (read here while in cache); and, ascending, the kept faces straddling the eye
/// plane. A conservative superset of the faces within the margin of the stroke (the region
/// measures them exactly on screen, once per vertex: measuring here projected each vertex
/// once per face around it).
pub(crate) fn candidate_faces(
    corners: &[VertexId],
    codes: &[u32],
    grid: &CellGrid,
) -> (Kept, Vec<u32>) {
    // Whole blocks sixteen faces at a time with AVX-512 (`faces_simd`).
    #[cfg(target_arch = "x86_64")]
    let wide = std::arch::is_x86_feature_detected!("avx512f") && codes.len() <= i32::MAX as usize;
    let chunks: Vec<(Kept, Vec<u32>)> = corners
        .par_chunks(3 * CHUNK)
        .enumerate()
        .map(|(ci, chunk)| {
            let base = (ci * CHUNK) as u32;
            let mut keep = Kept::default();
            let mut clipped = Vec::new();
            #[allow(unused_mut)]
            let mut done = 0;
            // SAFETY: AVX-512 F is there; a PolyMesh's corners name its vertices, and there
            // are at most i32::MAX of them (`wide`).
            #[cfg(target_arch = "x86_64")]
            if wide {
                done = unsafe {
                    super::faces_simd::scan_blocks(
                        as_ids(chunk),
                        codes,
                        grid,
                        base,
                        &mut keep,
                        &mut clipped,
                    )
                };
            }
            let code = |v: VertexId| {
                debug_assert!(v.idx() < codes.len());
                // SAFETY: a PolyMesh's corners name its vertices (every constructor checks
                // it), and there is a code per vertex.
                unsafe { *codes.get_unchecked(v.idx()) }
            };
            // Blocks of faces rejected together, one branch per block; a block with a face
            // near the stroke is gone through again face by face (few are: faces near each
            // other in the mesh are mostly near each other in the face order too).
            for (bi, block) in chunk.chunks(3 * BLOCK).enumerate().skip(done / BLOCK) {
                prefetch_blocks_ahead(block.as_ptr().cast());
                // Fixed length (unrolled) but for a mesh's last block.
                let near = match <&[VertexId; 3 * BLOCK]>::try_from(block) {
                    Ok(b) => b.chunks_exact(3).fold(0, |acc, t| {
                        acc | not_away([code(t[0]), code(t[1]), code(t[2])])
                    }),
                    Err(_) => 1,
                };
                if near == 0 {
                    continue;
                }
                keep.reserve_first();
                for (i, t) in block.chunks_exact(3).enumerate() {
                    let c = [code(t[0]), code(t[1]), code(t[2])];
                    if not_away(c) == 0 {
                        continue;
                    }
                    let f = base + (bi * BLOCK + i) as u32;
                    let behind = c.iter().filter(|&&x| x == BEHIND).count();
                    let straddles = behind > 0 && behind < 3;
                    if (behind == 0 && grid.any_marked(c)) || straddles {
                        keep.faces.push(f);
                        keep.corners.push([t[0].0, t[1].0, t[2].0]);
                    }
                    if straddles {
                        // Never cut, but kept so an edge it shares with a cut face gets its
                        // split vertex too (no T-junction).
                        clipped.push(f);
                    }
                }
            }
            (keep, clipped)
        })
        .collect();
    let kept = chunks.iter().map(|(k, _)| k.faces.len()).sum();
    let mut keep = Kept {
        faces: Vec::with_capacity(kept),
        corners: Vec::with_capacity(kept),
    };
    let mut clipped = Vec::new();
    for (k, c) in chunks {
        keep.faces.extend(k.faces);
        keep.corners.extend(k.corners);
        clipped.extend(c);
    }
    (keep, clipped)
}

/// Asks for the corners 16 blocks (3 KiB) ahead of a block at `p`, which the hardware's
/// stream prefetch does not reach in time.
#[inline(always)]
pub(crate) fn prefetch_blocks_ahead(p: *const u32) {
    for line in 0..3 {
        crate::mem::prefetch(p.wrapping_add(3 * BLOCK * 16 + 16 * line));
    }
}

/// Corners as plain ids.
#[cfg(target_arch = "x86_64")]
fn as_ids(c: &[VertexId]) -> &[u32] {
    // SAFETY: VertexId is a transparent u32.
    unsafe { std::slice::from_raw_parts(c.as_ptr().cast(), c.len()) }
}

/// Kept faces (ascending) and their corners (global vertex ids).
#[derive(Debug, Default)]
pub(crate) struct Kept {
    pub faces: Vec<u32>,
    pub corners: Vec<[u32; 3]>,
}

impl Kept {
    /// Room for a chunk's kept faces, at its first near block (most chunks have none;
    /// growing from nothing reallocated a dozen times, under the allocator's lock).
    #[inline]
    pub fn reserve_first(&mut self) {
        if self.faces.capacity() == 0 {
            self.faces.reserve(CHUNK / 16);
            self.corners.reserve(CHUNK / 16);
        }
    }
}

/// A cheap guess of the mean screen edge length, to size the snap margin before the real L
/// is known (a wrong guess costs a second pass, never a wrong result): 512 faces, in 32
/// evenly spaced runs of 16 consecutive ones. Runs, because faces read far apart miss every
/// cache and page-table level.
pub(crate) fn sample_edge_length(
    positions: &[DVec3],
    corners: &[VertexId],
    proj: &Projector,
) -> f64 {
    const RUNS: usize = 32;
    const RUN: usize = 16;
    let nf = corners.len() / 3;
    let step = (nf / RUNS).max(RUN);
    // Every corner's position asked for first, so the misses overlap (on a mesh whose vertex
    // order is not spatial, nearly every read misses).
    for start in (0..nf).step_by(step) {
        for &v in &corners[3 * start..3 * (start + RUN).min(nf)] {
            crate::mem::prefetch(positions.as_ptr().wrapping_add(v.idx()));
        }
    }
    let (mut sum, mut n) = (0.0, 0u32);
    for start in (0..nf).step_by(step) {
        for t in corners[3 * start..3 * (start + RUN).min(nf)].chunks_exact(3) {
            if let [Some(a), Some(b), Some(c)] =
                [t[0], t[1], t[2]].map(|v| proj.screen_of(positions[v.idx()]))
            {
                sum += (a - b).length() + (b - c).length() + (c - a).length();
                n += 3;
            }
        }
    }
    if n == 0 {
        0.0
    } else {
        sum / n as f64
    }
}

#[cfg(test)]
mod tests {
    use super::{floor_i32, CellGrid, BEHIND};
    use crate::cut::view::SCREEN_RANGE_PX;
    use crate::cut::view::{Projector, View};
    use glam::{DMat4, DVec2, DVec3};

    /// The AVX2 and AVX-512 passes give the portable codes bit for bit: points everywhere on and off the
    /// grid, on cell borders, behind the eye, on the eye plane, huge and NaN.
    #[test]
    #[cfg(target_arch = "x86_64")]
    fn simd_codes_match_the_portable_ones() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("no AVX2 on this CPU: only the portable path runs");
            return;
        }
        let vp = DMat4::perspective_rh_gl(0.9, 1.5, 0.1, 50.0)
            * DMat4::look_at_rh(DVec3::new(0.3, -2.0, 3.0), DVec3::ZERO, DVec3::Z);
        let proj = Projector::new(&View::new(vp, [10.0, 20.0, 900.0, 600.0])).unwrap();
        let segs = [
            (DVec2::new(100.0, 100.0), DVec2::new(700.0, 400.0)),
            (DVec2::new(700.0, 400.0), DVec2::new(300.0, 550.0)),
        ];
        let grid = CellGrid::new(&segs, 6.0, 4.0);
        let view = proj.screen_rows();
        // A deterministic spread: a lattice with irrational steps, plus special values.
        let mut ps: Vec<DVec3> = (0..20_000)
            .map(|i| {
                let t = i as f64;
                DVec3::new(
                    (t * 0.618_034).fract() * 8.0 - 4.0,
                    (t * 0.414_214).fract() * 8.0 - 4.0,
                    (t * 0.732_051).fract() * 8.0 - 4.0,
                )
            })
            .collect();
        let eye = DVec3::new(0.3, -2.0, 3.0);
        ps.extend([
            eye,
            eye + DVec3::new(1e-300, 0.0, 0.0),
            DVec3::splat(f64::NAN),
            DVec3::new(f64::INFINITY, 0.0, 0.0),
            DVec3::new(1e300, -1e300, 1e300),
            DVec3::ZERO,
        ]);
        // Points exactly on cell borders of the grid's plane z = 0 seen head-on are rare;
        // add screen-space borders unprojected on the near and far side of the origin.
        for k in 0..64 {
            let s = grid.origin + DVec2::splat(k as f64 * grid.cell);
            ps.push(proj.unproject(s, 3.0, 0.5));
            ps.push(proj.unproject(s + DVec2::new(0.0, 0.5 * grid.cell), 5.0, -0.2));
        }
        // Points seen far off screen, at the edge of the screen range and beyond it.
        for k in -8..8 {
            let edge = SCREEN_RANGE_PX * (1.0 + k as f64 * 1e-16);
            for s in [
                DVec2::new(edge, 300.0),
                DVec2::new(-edge, 300.0),
                DVec2::new(400.0, edge),
            ] {
                ps.push(proj.unproject(s, 2.0, 0.3));
            }
            ps.push(eye + DVec3::new(1.0, 0.0, 0.0) * 10f64.powi(k) + DVec3::new(0.0, 1e-12, 0.0));
        }
        let portable: Vec<u32> = ps.iter().map(|&p| grid.code(&view, p)).collect();
        // Behind exactly where the projector does not see a point.
        for (p, &c) in ps.iter().zip(&portable) {
            assert_eq!(c == BEHIND, proj.screen_of(*p).is_none(), "{p}");
        }
        let check = |name: &str, done: usize, simd: &[std::mem::MaybeUninit<u32>], lanes: usize| {
            assert_eq!(done, ps.len() / lanes * lanes, "{name}");
            for (i, (a, b)) in portable.iter().zip(&simd[..done]).enumerate() {
                // SAFETY: initialized above.
                assert_eq!(
                    *a,
                    unsafe { b.assume_init() },
                    "{name}, point {i}: {:?}",
                    ps[i]
                );
            }
        };
        let mut simd = vec![std::mem::MaybeUninit::new(0u32); ps.len()];
        // SAFETY: AVX2 checked; sizes as required.
        let done = unsafe {
            super::super::codes_simd::codes(&view, &grid.place(), &grid.near, &ps, &mut simd)
        };
        check("AVX2", done, &simd, 4);
        if std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512vl")
        {
            let mut simd = vec![std::mem::MaybeUninit::new(0u32); ps.len()];
            // SAFETY: AVX-512 F, VL and AVX2 checked; sizes as required.
            let done = unsafe {
                super::super::codes_simd::codes8(&view, &grid.place(), &grid.near, &ps, &mut simd)
            };
            check("AVX-512", done, &simd, 8);
        } else {
            eprintln!("no AVX-512 on this CPU: its path is not checked here");
        }
        assert!(portable.contains(&BEHIND));
        assert!(portable.iter().any(|&c| c >> 31 == 1 && c != BEHIND));
    }

    /// A grid over a wavy band of twelve segments (margin 1.5, cells 1 wide).
    fn wavy_grid() -> CellGrid {
        let segs: Vec<(DVec2, DVec2)> = (0..12)
            .map(|i| {
                let p = |k: f64| DVec2::new(20.0 + 9.0 * k, 40.0 + 14.0 * (0.7 * k).sin());
                (p(i as f64), p(i as f64 + 1.0))
            })
            .collect();
        CellGrid::new(&segs, 1.5, 1.0)
    }

    /// The vertex code of a point in cell (cx, cy) of `grid` (−1 and n: the outside ring).
    fn cell_code(grid: &CellGrid, cx: i32, cy: i32) -> u32 {
        let at = ((cy + 1) * (grid.nx + 2) + cx + 1) as usize;
        (cx + 1) as u32 | ((cy + 1) as u32) << 16 | (grid.near[at] as u32) << 24
    }

    /// Deterministic draws in `0..m` (xorshift from `seed`).
    fn draws(seed: u64) -> impl FnMut(i32) -> i32 {
        let mut r = seed;
        move |m| {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            (r % m as u64) as i32
        }
    }

    /// The face test keeps every face whose corners' cell box holds a marked cell, and only
    /// those: corner cells on and around a wavy band (the outside ring included), boxes up
    /// to nine cells wide, against a scan of the box. The fast block test never rejects one.
    #[test]
    fn the_face_test_is_the_marked_box_test() {
        let grid = wavy_grid();
        let (nx, ny) = (grid.nx, grid.ny);
        let code = |cx: i32, cy: i32| cell_code(&grid, cx, cy);
        let marked_in_box = |c: [(i32, i32); 3]| {
            let (x0, x1) = (
                c.iter().map(|p| p.0).min().unwrap(),
                c.iter().map(|p| p.0).max().unwrap(),
            );
            let (y0, y1) = (
                c.iter().map(|p| p.1).min().unwrap(),
                c.iter().map(|p| p.1).max().unwrap(),
            );
            (y0.max(0)..=y1.min(ny - 1)).any(|y| {
                (x0.max(0)..=x1.min(nx - 1))
                    .any(|x| grid.near[((y + 1) * (nx + 2) + x + 1) as usize] & super::MARKED != 0)
            })
        };
        // A deterministic spread of corners: every cell as corner 0, the others within
        // nine cells of it.
        let (mut kept, mut seen) = (0, 0);
        let mut next = draws(0x2545_f491_4f6c_dd1d);
        for cy in -1..=ny {
            for cx in -1..=nx {
                for _ in 0..6 {
                    let mut c = [(cx, cy); 3];
                    for corner in &mut c[1..] {
                        *corner = (
                            (cx + next(19) - 9).clamp(-1, nx),
                            (cy + next(19) - 9).clamp(-1, ny),
                        );
                    }
                    let codes = c.map(|(x, y)| code(x, y));
                    let truth = marked_in_box(c);
                    assert_eq!(grid.any_marked(codes), truth, "corners {c:?}");
                    if truth {
                        assert_ne!(super::not_away(codes), 0, "corners {c:?}");
                    }
                    kept += truth as u32;
                    seen += 1;
                }
            }
        }
        assert!(kept > 100 && kept < seen / 2, "{kept} of {seen}");
    }

    /// The AVX-512 near-block classifier decides every face as the face-by-face loop does:
    /// random corners on and around a band (some behind the eye), in blocks of 16.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn simd_near_blocks_match_the_face_loop() {
        if !std::arch::is_x86_feature_detected!("avx512f") {
            eprintln!("no AVX-512 on this CPU: its path is not checked here");
            return;
        }
        let grid = wavy_grid();
        let (nx, ny) = (grid.nx, grid.ny);
        let mut next = draws(0x9e37_79b9_7f4a_7c15);
        // Vertex codes: each cell of the grid and its outside ring, and "behind".
        let mut codes: Vec<u32> = (-1..=ny)
            .flat_map(|cy| (-1..=nx).map(move |cx| (cx, cy)))
            .map(|(cx, cy)| cell_code(&grid, cx, cy))
            .collect();
        codes.push(BEHIND);
        let id =
            |cx: i32, cy: i32| ((cy.clamp(-1, ny) + 1) * (nx + 2) + cx.clamp(-1, nx) + 1) as u32;
        let behind = codes.len() as u32 - 1;
        let (mut kept, mut scanned, mut not_away_blocks) = (0, 0, 0);
        // Every block, and what the face loop keeps and clips of them, for the whole-run scan.
        let (mut all, mut loop_kept, mut loop_clipped) =
            (Vec::new(), super::Kept::default(), Vec::new());
        for round in 0..20_000 {
            let mut block = [0u32; 48];
            // Every other block: small faces away from the band but for one face in some
            // (the block test then passes and fails).
            let quiet = round % 2 == 0;
            for (k, f) in block.chunks_exact_mut(3).enumerate() {
                let (mut cx, mut cy) = (next(nx + 2) - 1, next(ny + 2) - 1);
                while quiet && codes[id(cx, cy) as usize] >> 31 != 0 {
                    (cx, cy) = (next(nx + 2) - 1, next(ny + 2) - 1);
                }
                let reach = if quiet && (round % 4 == 0 || k > 0) {
                    1
                } else {
                    [2, 5, 19][next(3) as usize]
                };
                f[0] = id(cx, cy);
                for v in &mut f[1..] {
                    *v = id(cx + next(reach) - reach / 2, cy + next(reach) - reach / 2);
                }
                for v in f.iter_mut() {
                    if !quiet && next(40) == 0 {
                        *v = behind;
                    }
                }
            }
            // SAFETY: AVX-512 F checked; every id names a code.
            let corners = unsafe { super::super::faces_simd::gather(&block, &codes) };
            // SAFETY: as above.
            let lanes = unsafe { super::super::faces_simd::near_block(&corners) };
            // SAFETY: as above.
            let whole = unsafe { super::super::faces_simd::block_not_away(&corners) };
            let any_face = block.chunks_exact(3).any(|f| {
                super::not_away([
                    codes[f[0] as usize],
                    codes[f[1] as usize],
                    codes[f[2] as usize],
                ]) != 0
            });
            assert_eq!(whole, any_face, "block {block:?}");
            not_away_blocks += whole as u32;
            for (i, f) in block.chunks_exact(3).enumerate() {
                let c = [
                    codes[f[0] as usize],
                    codes[f[1] as usize],
                    codes[f[2] as usize],
                ];
                let bit = |m: u16| m >> i & 1 != 0;
                let n = c.iter().filter(|&&x| x == BEHIND).count();
                let straddles = n > 0 && n < 3;
                let loop_keeps =
                    super::not_away(c) != 0 && ((n == 0 && grid.any_marked(c)) || straddles);
                let simd_keeps = bit(lanes.keep) || (bit(lanes.scan) && grid.any_marked(c));
                assert_eq!(simd_keeps, loop_keeps, "codes {c:x?}");
                assert_eq!(bit(lanes.straddles), straddles && super::not_away(c) != 0);
                assert!(!(bit(lanes.keep) && bit(lanes.scan)));
                kept += loop_keeps as u32;
                scanned += bit(lanes.scan) as u32;
                let face = (all.len() / 3) as u32;
                if loop_keeps {
                    loop_kept.faces.push(face);
                    loop_kept.corners.push([f[0], f[1], f[2]]);
                }
                if straddles && super::not_away(c) != 0 {
                    loop_clipped.push(face);
                }
                all.extend_from_slice(f);
            }
        }
        // The whole run, from a face number not a multiple of 16 (as a chunk's first face is
        // not, in general, of the run's): the same faces, corners and clipped faces.
        let (mut scan_kept, mut scan_clipped) = (super::Kept::default(), Vec::new());
        let base = 7;
        // SAFETY: AVX-512 F checked; every id names a code.
        let done = unsafe {
            super::super::faces_simd::scan_blocks(
                &all,
                &codes,
                &grid,
                base,
                &mut scan_kept,
                &mut scan_clipped,
            )
        };
        assert_eq!(done, all.len() / 3);
        let shifted = |v: &[u32]| v.iter().map(|f| f + base).collect::<Vec<u32>>();
        assert_eq!(scan_kept.faces, shifted(&loop_kept.faces));
        assert_eq!(scan_kept.corners, loop_kept.corners);
        assert_eq!(scan_clipped, shifted(&loop_clipped));
        assert!(
            kept > 1000 && scanned > 100 && (2_000..18_000).contains(&not_away_blocks),
            "{kept} kept, {scanned} scanned, {not_away_blocks} blocks not away"
        );
    }

    /// Each cell lists exactly the segments within the margin and a half diagonal of its
    /// centre among those whose margin box it overlaps (a scan of each box, cell by cell),
    /// in segment order: strokes of random directions and lengths, steep and flat, with
    /// margins from a tenth of a cell to several cells. A row's stretch lists its cells'
    /// segments in turn, and a wide list holds those of every cell of a range up to three
    /// cells across around it.
    #[test]
    fn cell_lists_are_those_of_a_scan_of_each_box() {
        let mut next = draws(0x5851_f42d_4c95_7f2d);
        let mut listed = 0;
        for case in 0..60 {
            let mut p = DVec2::new(100.0, 100.0);
            let segs: Vec<(DVec2, DVec2)> = (0..8)
                .map(|_| {
                    let a = p;
                    let len = [0.3, 3.0, 25.0][next(3) as usize];
                    let angle = next(3600) as f64 * std::f64::consts::PI / 1800.0;
                    p += DVec2::new(angle.cos(), angle.sin()) * len;
                    (a, p)
                })
                .collect();
            let margin = [0.1, 0.7, 3.0][case % 3];
            let grid = CellGrid::new(&segs, margin, 1.0);
            let reach = margin + grid.cell * std::f64::consts::FRAC_1_SQRT_2 * 1.0001;
            let mut scan: Vec<Vec<u32>> = vec![Vec::new(); (grid.nx * grid.ny) as usize];
            for (si, &(a, b)) in segs.iter().enumerate() {
                let m = DVec2::splat(margin);
                let (x0, y0) = grid.cell(a.min(b) - m);
                let (x1, y1) = grid.cell(a.max(b) + m);
                for cy in y0.max(0)..=y1.min(grid.ny - 1) {
                    for cx in x0.max(0)..=x1.min(grid.nx - 1) {
                        let centre =
                            grid.origin + DVec2::new(cx as f64 + 0.5, cy as f64 + 0.5) * grid.cell;
                        if super::within(centre, a, b, reach) {
                            scan[(cy * grid.nx + cx) as usize].push(si as u32);
                        }
                    }
                }
            }
            for cy in 0..grid.ny {
                for cx in 0..grid.nx {
                    let want = &scan[(cy * grid.nx + cx) as usize];
                    assert_eq!(
                        grid.segments_at(cx, cy),
                        &want[..],
                        "case {case}, cell ({cx}, {cy})"
                    );
                    listed += want.len();
                }
            }
            // A row's stretch: its cells' lists one after the other.
            for _ in 0..200 {
                let cy = next(grid.ny);
                let x0 = next(grid.nx);
                let x1 = (x0 + next(6)).min(grid.nx - 1);
                let want: Vec<u32> = (x0..=x1)
                    .flat_map(|cx| scan[(cy * grid.nx + cx) as usize].iter().copied())
                    .collect();
                assert_eq!(grid.segments_along(cy, x0, x1), &want[..], "case {case}");
            }
            // The wide lists: for every range up to three cells across, a superset of its
            // cells' lists, ascending, each once.
            for cy in 0..grid.ny {
                for cx in 0..grid.nx {
                    let (w, h) = (next(3), next(3));
                    let range = (cx, cy, (cx + w).min(grid.nx - 1), (cy + h).min(grid.ny - 1));
                    let wide = grid.segments_around(range).expect("at most three across");
                    assert!(
                        wide.windows(2).all(|p| p[0] < p[1]),
                        "case {case}: {wide:?}"
                    );
                    for y in range.1..=range.3 {
                        for x in range.0..=range.2 {
                            for k in &scan[(y * grid.nx + x) as usize] {
                                assert!(wide.contains(k), "case {case}, {range:?}: {k}");
                            }
                        }
                    }
                }
            }
            assert!(grid.segments_around((0, 0, 3, 0)).is_none(), "four across");
        }
        assert!(listed > 10_000, "{listed} listings");
    }

    #[test]
    fn floor_i32_is_a_saturating_floor() {
        let cases = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            2.999,
            -2.001,
            1e300,
            -1e300,
            3e9,
            -3e9,
            2147483647.5,
            -2147483648.5,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
        ];
        for x in cases {
            assert_eq!(floor_i32(x), x.floor() as i32, "{x}");
        }
    }
}
