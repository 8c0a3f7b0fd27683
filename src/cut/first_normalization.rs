//! First normalization (seed 002 §3.3, Fig. 5): the stroke becomes the array A of the model
//! elements it meets — vertices V_j and edge crossings E_i — in stroke order, one array per
//! chain of faces it passes through (one sheet, one visible stretch; spec §6.14).
//!
//! Every element is found by exact predicates: a vertex is met when `orient2d` puts it on a
//! segment (snapped vertices sit exactly on stroke points), an edge when the segment and the
//! edge strictly separate each other's ends, or a stroke point lies inside the edge. Stroke
//! points strictly inside a face are not elements: they are what the first normalization
//! drops. Piece ends strictly inside a face become interior points P (seed 002 §3.4, Fig. 12).
//!
//! Chains: for each face, consecutive elements (in stroke order) that the stroke joins
//! through the face's interior form a *visit*; visits sharing an element link into chains.
//! Where two visits begin or end at one element (a silhouette seen through all sheets) the
//! chain ends, so each chain is one sheet.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::fast::grid::CellGrid;
use super::geom::{in_triangle, on_segment, orient};
use super::locate::Locator;
use super::region::{Region, NONE};
use super::snap::{Polyline, Snapped};
use super::visibility::{Before, FaceBuckets};

/// A model element the stroke meets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Elem {
    /// A local vertex.
    V(u32),
    /// Local edge `edge` crossed by segment `at`, or (`on_point`) containing stroke point `at`.
    E { edge: u32, at: u32, on_point: bool },
    /// Piece end point `point` (canonical polyline index) strictly inside local face `face`.
    P { point: u32, face: u32 },
}

/// One meeting of the stroke with an element, at stroke position `key` = (index, t): a point
/// `index` when `t == 0`, else the point at parameter `t` of segment `index`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Occ {
    pub key: (u32, f64),
    pub elem: Elem,
    pub screen: DVec2,
    /// E: screen parameter along `edges[edge]` from its first to its second vertex.
    pub edge_t: f64,
    pub visible: bool,
}

pub(crate) fn key_cmp(a: (u32, f64), b: (u32, f64)) -> std::cmp::Ordering {
    a.0.cmp(&b.0).then(a.1.total_cmp(&b.1))
}

/// Sorts by stroke position, then element, stably: `key_cmp(x.key, y.key).then(x.elem.cmp(
/// &y.elem))`, through integer keys (the order-preserving bits of `t`, the element's
/// variant and fields as `Elem`'s derived order compares them) and one permutation at the
/// end; sorting the occurrences themselves moved a few hundred kilobytes per merge pass.
fn sort_occurrences(occ: &mut Vec<Occ>) {
    // By stroke index first (a stable radix sort), then each index's few by the whole key:
    // one comparison sort of everything cost a tenth of finding the occurrences.
    let mut by_index: Vec<(u32, u32)> = occ
        .iter()
        .enumerate()
        .map(|(i, o)| (o.key.0, i as u32))
        .collect();
    super::fast::radix::sort_by_key(&mut by_index);
    // The runs' sorts and the copies in two halves on rayon, split between two indices (this
    // thread's alone, they were a tenth of finding the occurrences, the other thread idle).
    let mut mid = by_index.len() / 2;
    while mid > 0 && mid < by_index.len() && by_index[mid].0 == by_index[mid - 1].0 {
        mid += 1;
    }
    let mut sorted: Vec<Occ> = Vec::with_capacity(occ.len());
    let (lo, hi) = sorted.spare_capacity_mut()[..occ.len()].split_at_mut(mid);
    let from = &occ[..];
    if by_index.len() < 512 {
        sort_runs(from, &by_index, lo.iter_mut().chain(hi.iter_mut()));
    } else {
        rayon::join(
            || sort_runs(from, &by_index[..mid], lo.iter_mut()),
            || sort_runs(from, &by_index[mid..], hi.iter_mut()),
        );
    }
    // SAFETY: `sort_runs` wrote one occurrence per entry of `by_index`, `occ.len()` in all.
    unsafe { sorted.set_len(occ.len()) };
    *occ = sorted;
}

/// The occurrences of `by_index` (stroke index, occurrence; whole runs of indices, sorted
/// by index) sorted within each index by the whole key ([`sort_occurrences`]), written to
/// `out` in order (one slot per entry).
fn sort_runs<'a>(
    occ: &[Occ],
    by_index: &[(u32, u32)],
    mut out: impl Iterator<Item = &'a mut std::mem::MaybeUninit<Occ>>,
) {
    type Key = (u32, u64, u8, u32, u32, bool, u32);
    let key = |i: usize, o: &Occ| -> Key {
        let t = super::fast::radix::f64_key(o.key.1);
        let (tag, a, c, d) = match o.elem {
            Elem::V(v) => (0, v, 0, false),
            Elem::E { edge, at, on_point } => (1, edge, at, on_point),
            Elem::P { point, face } => (2, point, face, false),
        };
        (o.key.0, t, tag, a, c, d, i as u32)
    };
    let mut keys: Vec<Key> = Vec::new();
    for run in by_index.chunk_by(|a, b| a.0 == b.0) {
        keys.clear();
        keys.extend(run.iter().map(|&(_, i)| key(i as usize, &occ[i as usize])));
        super::fast::radix::small_sort(&mut keys);
        for k in &keys {
            out.next()
                .expect("a slot per entry")
                .write(occ[k.6 as usize]);
        }
    }
}

/// The prepared segments listed in the cells of an inclusive range, each once, in cell
/// order (a range holds a few: a linear check beats sorting).
fn segments_in(grid: &CellGrid, (x0, y0, x1, y1): (i32, i32, i32, i32), out: &mut Vec<u32>) {
    out.clear();
    for cy in y0..y1 + 1 {
        for &k in grid.segments_along(cy, x0, x1) {
            if !out.contains(&k) {
                out.push(k);
            }
        }
    }
}

/// The last polyline index of a closed stroke stands for index 0.
#[inline]
pub(crate) fn canon(line: &Polyline, closed: bool, j: u32) -> u32 {
    if closed && j as usize == line.pts.len() - 1 {
        0
    } else {
        j
    }
}

/// All meetings of the stroke with elements of cuttable faces, sorted by key: of the
/// snapped polyline and the vertices snapped onto it (`snapped`); `make_locate` makes
/// what finds the faces of piece ends (beside the edge and vertex loops; it is returned with
/// the occurrences); `seen`, in visible-only mode, the visibility buckets and the region
/// before snapping.
#[allow(clippy::too_many_arguments)]
pub(crate) fn find_occurrences<'b>(
    region: &Region,
    snapped: &Snapped,
    closed: bool,
    grid: &CellGrid,
    piece_ends: &[u32],
    make_locate: impl FnOnce() -> Locator<'b> + Send,
    seen: Option<(&FaceBuckets, &Before)>,
    end_snap: f64,
    ends_moved: &mut Vec<u32>,
) -> (Vec<Occ>, Locator<'b>) {
    let (moves, move_points) = (&snapped.moves, &snapped.move_points);
    let (line, seg_range) = (&snapped.line, &snapped.seg_range[..]);
    let pts = &line.pts;
    let last = (pts.len() - 1) as u32;
    let mk = |key: (u32, f64), elem: Elem, screen: DVec2| Occ {
        key,
        elem,
        screen,
        edge_t: 0.0,
        visible: true,
    };
    let tpar = along(pts, seg_range);
    let strips: Vec<Strip> = seg_range
        .iter()
        .map(|&(j0, j1)| Strip::new(pts[j0 as usize], pts[j1 as usize]))
        .collect();
    // Each vertex's screen point and grid cell side by side, once (an edge's cell range is
    // its ends' least and greatest); NaN for a vertex behind the eye, which no cuttable face
    // has.
    let at: Vec<(DVec2, (i32, i32))> = (0..region.verts.len() as u32)
        .into_par_iter()
        .with_min_len(1024)
        .map(|v| match region.seen.get(v) {
            Some(s) => (s.screen, grid.cell(s.screen)),
            None => (DVec2::NAN, (0, 0)),
        })
        .collect();
    let (locate, (chunks, on_stroke)) = super::fast::schedule::join(make_locate, || {
        // Vertices on the stroke, once per vertex of a cuttable face (the edge loop would find
        // each from all its edges). First: the edge loop skips most pairs at the polyline
        // points they give. Only vertices on the stroke's band can be on it: the others are
        // skipped untested (the loop −28% on spot, through all). A snapped vertex is on the
        // point the snap put it on and on no other segment: the stroke's check keeps its
        // non-adjacent segments 1e-9 of its size apart (`stroke::check_self_intersection`),
        // and the polyline's points are a few ulps off them. Untested too (most of the band's
        // vertices are snapped).
        let nv = region.verts.len() as u32;
        let mut snapped_on = vec![NONE; nv as usize];
        for (&(v, ..), &j) in moves.iter().zip(move_points) {
            snapped_on[v as usize] = j;
        }
        let snapped_on = &snapped_on;
        let on_stroke: Vec<Vec<Occ>> = (0..nv)
            .into_par_iter()
            .chunks(256)
            .map(|chunk| {
                let mut occ: Vec<Occ> = Vec::with_capacity(64);
                for v in chunk {
                    if !region.on_band[v as usize] {
                        continue;
                    }
                    let faces = region.vertex_faces(v);
                    if !faces.iter().any(|&f| region.cuttable[f as usize]) {
                        continue;
                    }
                    let (x, (cx, cy)) = at[v as usize];
                    let j = snapped_on[v as usize];
                    if j != NONE {
                        debug_assert_eq!(pts[j as usize], x, "a snapped vertex on its point");
                        occ.push(mk((j, 0.0), Elem::V(v), x));
                        continue;
                    }
                    let near = match grid.clamp((cx, cy), (cx, cy)) {
                        Some(_) => grid.segments_at(cx, cy),
                        None => &[],
                    };
                    for &si in near {
                        let Some(w) = strips[si as usize].window(x, x) else {
                            continue;
                        };
                        for k in in_window(&tpar, seg_range[si as usize], w) {
                            let (p, q) = (pts[k as usize], pts[k as usize + 1]);
                            if on_segment(p, q, x) && orient(p, q, x) == 0.0 {
                                let key = if x == p {
                                    (k, 0.0)
                                } else if x == q {
                                    (k + 1, 0.0)
                                } else {
                                    let pq = q - p;
                                    (k, ((x - p).dot(pq) / pq.length_squared()).clamp(0.0, 1.0))
                                };
                                occ.push(mk(key, Elem::V(v), x));
                            }
                        }
                    }
                }
                occ
            })
            .collect();
        // The polyline point each vertex sits on exactly (snapped vertices), else NONE.
        let mut point_of = vec![NONE; nv as usize];
        for o in on_stroke.iter().flatten() {
            if let Elem::V(v) = o.elem {
                if o.key.1 == 0.0 && pts[o.key.0 as usize] == o.screen {
                    point_of[v as usize] = o.key.0;
                }
            }
        }
        let point_of = &point_of;
        // Edges in fixed chunks on rayon, concatenated in edge order (thread-count independent).
        let chunks: Vec<Vec<Occ>> = region
            .edges
            .par_chunks(256)
            .enumerate()
            .map(|(ci, chunk)| {
                let mut occ: Vec<Occ> = Vec::with_capacity(64);
                let mut near: Vec<u32> = Vec::with_capacity(16);
                for (i, &[ia, ib]) in chunk.iter().enumerate() {
                    let e = ci * 256 + i;
                    let ef = region.edge_faces[e];
                    if !ef.iter().any(|&f| f != NONE && region.cuttable[f as usize]) {
                        continue;
                    }
                    let ((a, ca), (b, cb)) = (at[ia as usize], at[ib as usize]);
                    let near = match grid.clamp(
                        (ca.0.min(cb.0), ca.1.min(cb.1)),
                        (ca.0.max(cb.0), ca.1.max(cb.1)),
                    ) {
                        None => continue,
                        // At most three cells across (nearly all): the middle cell's wide
                        // list, whose extra segments are too far to meet the edge.
                        Some(range) => match grid.segments_around(range) {
                            Some(list) => list,
                            None => {
                                segments_in(grid, range, &mut near);
                                &near[..]
                            }
                        },
                    };
                    let (ja, jb) = (point_of[ia as usize], point_of[ib as usize]);
                    // Ends on consecutive polyline points: the edge is that polyline
                    // segment, which no other one meets (as for the snapped vertices
                    // above), so it meets the polyline only at its ends (the vertex loop's).
                    if ja != NONE && jb != NONE && ja.abs_diff(jb) == 1 {
                        continue;
                    }
                    for &si in near {
                        let Some(w) = strips[si as usize].window(a, b) else {
                            continue;
                        };
                        // Most edges that pass the window have an end snapped onto the
                        // polyline: skipped when they meet it only there.
                        let range = seg_range[si as usize];
                        if meets_only_at(&tpar, pts, range, w, ja, b)
                            || meets_only_at(&tpar, pts, range, w, jb, a)
                        {
                            debug_assert!(in_window(&tpar, range, w).all(|k| {
                                let (p, q) = (pts[k as usize], pts[k as usize + 1]);
                                let (o1, o2) = (orient(p, q, a), orient(p, q, b));
                                o1 * o2 >= 0.0 && (o1 != 0.0 || o2 != 0.0)
                            }));
                            continue;
                        }
                        for k in in_window(&tpar, range, w) {
                            let (p, q) = (pts[k as usize], pts[k as usize + 1]);
                            // Boxes apart: nothing to meet (exact: comparisons only; one
                            // branch, not one per comparison).
                            if (p.x.max(q.x) < a.x.min(b.x))
                                | (p.x.min(q.x) > a.x.max(b.x))
                                | (p.y.max(q.y) < a.y.min(b.y))
                                | (p.y.min(q.y) > a.y.max(b.y))
                            {
                                continue;
                            }
                            let (o1, o2) = (orient(p, q, a), orient(p, q, b));
                            if o1 * o2 < 0.0 {
                                let (o3, o4) = (orient(a, b, p), orient(a, b, q));
                                let edge_t = o1 / (o1 - o2);
                                let (key, on_point) = if o3 * o4 < 0.0 {
                                    ((k, o3 / (o3 - o4)), false)
                                } else if o3 == 0.0 {
                                    ((k, 0.0), true)
                                } else if o4 == 0.0 && k + 1 == last {
                                    ((k + 1, 0.0), true)
                                } else {
                                    continue;
                                };
                                let screen = if on_point {
                                    pts[key.0 as usize]
                                } else {
                                    p + (q - p) * key.1
                                };
                                let at = if on_point {
                                    canon(line, closed, key.0)
                                } else {
                                    k
                                };
                                let mut o = mk(
                                    key,
                                    Elem::E {
                                        edge: e as u32,
                                        at,
                                        on_point,
                                    },
                                    screen,
                                );
                                o.edge_t = edge_t;
                                occ.push(o);
                            } else if o1 == 0.0 && o2 == 0.0 {
                                // The segment runs along the edge's line: stroke points strictly inside
                                // the edge are on it.
                                let ab = b - a;
                                for (j, x) in [(k, p), (k + 1, q)] {
                                    if (j == k || j == last)
                                        && x != a
                                        && x != b
                                        && on_segment(a, b, x)
                                    {
                                        let mut o = mk(
                                            (j, 0.0),
                                            Elem::E {
                                                edge: e as u32,
                                                at: canon(line, closed, j),
                                                on_point: true,
                                            },
                                            x,
                                        );
                                        o.edge_t = (x - a).dot(ab) / ab.length_squared();
                                        occ.push(o);
                                    }
                                }
                            }
                        }
                    }
                }
                occ
            })
            .collect();
        (chunks, on_stroke)
    });
    // Copied slice by slice (an iterator over the chunks copied element by element).
    let total = chunks.iter().chain(&on_stroke).map(Vec::len).sum::<usize>();
    let mut occ: Vec<Occ> = Vec::with_capacity(total + piece_ends.len());
    for c in chunks.iter().chain(&on_stroke) {
        occ.extend_from_slice(c);
    }
    // Piece ends strictly inside faces (seed 002 §3.4, Figs. 12-13).
    for &j in piece_ends {
        let s = pts[j as usize];
        for lf in locate.faces_at(region, s) {
            if !region.cuttable[lf as usize] {
                continue;
            }
            let [a, b, c] = region.face_screen(lf);
            if in_triangle(a, b, c, region.sign[lf as usize], s) == Some(true) {
                // An end this close to an edge (a third of the segment snap distance) would
                // make a sliver of the 1 → 3 split: it goes onto the edge instead, splitting
                // it (gap-fill: spec §4 step 4's "ties → edge" widened).
                if let Some((edge, t, foot)) = near_edge(region, lf, s, end_snap) {
                    let mut o = mk(
                        (j, 0.0),
                        Elem::E {
                            edge,
                            at: canon(line, closed, j),
                            on_point: true,
                        },
                        foot,
                    );
                    o.edge_t = t;
                    occ.push(o);
                    ends_moved.push(j);
                    continue;
                }
                occ.push(mk(
                    (j, 0.0),
                    Elem::P {
                        point: canon(line, closed, j),
                        face: lf,
                    },
                    s,
                ));
            }
        }
    }
    sort_occurrences(&mut occ);
    occ.dedup_by(|x, y| x.elem == y.elem && key_cmp(x.key, y.key).is_eq());
    if closed {
        // The closing point is both the first and the last point.
        let extra: Vec<Occ> = occ
            .iter()
            .filter(|o| o.key == (0, 0.0))
            .map(|o| Occ {
                key: (last, 0.0),
                ..*o
            })
            .collect();
        occ.retain(|o| o.key.0 != last);
        occ.extend(extra);
        sort_occurrences(&mut occ);
    }
    if let Some((buckets, before)) = seen {
        occ.par_iter_mut().with_min_len(64).for_each(|o| {
            let (z, x) = elem_depth(region, o);
            // A point snapping did not move must also have been seen before it.
            let still = Some(before).filter(|b| !elem_moved(region, b, o.elem));
            let (pair, one);
            let own: &[u32] = match o.elem {
                Elem::V(v) => region.vertex_faces(v),
                Elem::E { edge, .. } => {
                    pair = region.edge_faces[edge as usize];
                    &pair
                }
                Elem::P { face, .. } => {
                    one = [face];
                    &one
                }
            };
            o.visible = !buckets.hidden(region, o.screen, z, x, still, own);
        });
        // In visible-only mode a piece end inside faces belongs to the nearest visible one.
        occ.retain(|o| !matches!(o.elem, Elem::P { .. }) || o.visible);
    }
    (occ, locate)
}

/// The line through a prepared segment. Every polyline point of the segment lies on it up
/// to rounding (a snap inserts its foot `a + t·(b − a)`, a few ulps off), so points clearly
/// on one side of it cannot meet any of those polyline segments: most edges of the region
/// are dismissed by two cross products, before the exact tests.
struct Strip {
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
/// a scan for the few after it. A window from [`Strip::window`] holds one or two (the
/// edge's box, which set the span before, held four on average on spot, through all).
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
/// search and the tests: on spot, through all, two windows in three are skipped.
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

/// The edge of face `lf` nearest to `s` if closer than `reach` with its foot strictly inside
/// the edge: (local edge, screen parameter from its first vertex, foot).
fn near_edge(region: &Region, lf: u32, s: DVec2, reach: f64) -> Option<(u32, f64, DVec2)> {
    let mut best: Option<(f64, u32, f64, DVec2)> = None;
    let sign = region.sign[lf as usize];
    for &e in &region.face_edges[lf as usize] {
        // Not onto an edge into another sheet (a silhouette): that would split its face.
        let other = region.edge_faces[e as usize]
            .into_iter()
            .find(|&f| f != lf && f != NONE);
        if other.is_some_and(|f| region.sign[f as usize] != sign) {
            continue;
        }
        let [u, w] = region.edges[e as usize];
        let (a, b) = (region.screen(u), region.screen(w));
        let ab = b - a;
        let t = (s - a).dot(ab) / ab.length_squared();
        if !(t > 0.0 && t < 1.0) {
            continue;
        }
        let foot = a + ab * t;
        let d = (foot - s).length();
        if d < reach && best.is_none_or(|b| (d, e) < (b.0, b.1)) {
            best = Some((d, e, t, foot));
        }
    }
    best.map(|(_, e, t, foot)| (e, t, foot))
}

/// Whether snapping moved the point of an element (a vertex, an edge end, a face corner).
fn elem_moved(region: &Region, b: &Before, e: Elem) -> bool {
    match e {
        Elem::V(v) => b.moved(v),
        Elem::E { edge, .. } => region.edges[edge as usize].iter().any(|&v| b.moved(v)),
        Elem::P { face, .. } => region.tri[face as usize].iter().any(|&v| b.moved(v)),
    }
}

/// NDC depth and world position of an occurrence (perspective-correct, spec §4 step 5).
pub(crate) fn elem_depth(region: &Region, o: &Occ) -> (f64, DVec3) {
    match o.elem {
        Elem::V(v) => (
            region.seen.get(v).expect("projectable").z,
            region.pos[v as usize],
        ),
        Elem::E { edge, .. } => {
            let [a, b] = region.edges[edge as usize];
            let (sa, sb) = (region.seen.get(a).unwrap(), region.seen.get(b).unwrap());
            let s = o.edge_t;
            let t = s * sa.w / ((1.0 - s) * sb.w + s * sa.w);
            (
                sa.z + (sb.z - sa.z) * s,
                region.pos[a as usize].lerp(region.pos[b as usize], t),
            )
        }
        // Screen barycentrics recomputed (few P; carrying them made every crossing larger).
        Elem::P { face, .. } => {
            let [a, b, c] = region.face_screen(face);
            region.lift(face, super::geom::barycentric(a, b, c, o.screen))
        }
    }
}

/// Cuttable faces incident to an element, ascending.
pub(crate) fn elem_faces(region: &Region, e: Elem, out: &mut Vec<u32>) {
    out.clear();
    match e {
        Elem::V(v) => out.extend(
            region
                .vertex_faces(v)
                .iter()
                .copied()
                .filter(|&f| region.cuttable[f as usize]),
        ),
        Elem::E { edge, .. } => {
            out.extend(
                region.edge_faces[edge as usize]
                    .iter()
                    .copied()
                    .filter(|&f| f != NONE && region.cuttable[f as usize]),
            );
            if out.len() == 2 && out[0] > out[1] {
                out.swap(0, 1);
            }
        }
        Elem::P { face, .. } => out.push(face),
    }
}

/// A chain: occurrences in stroke order (one sheet).
#[derive(Debug, Clone)]
pub(crate) struct Chain {
    pub occ: Vec<u32>,
}

/// Whether consecutive visits `x` then `y` of face `f` (occurrence indices) make a visit:
/// stroke joins them through the face's interior.
#[inline]
fn joins(region: &Region, line: &Polyline, occ: &[Occ], x: u32, y: u32, f: u32) -> bool {
    let (ox, oy) = (&occ[x as usize], &occ[y as usize]);
    // A visit needs stroke between its ends: two elements at one stroke position (a moved
    // end and another sheet's) are not joined.
    if !(ox.visible && oy.visible) || ox.elem == oy.elem || key_cmp(ox.key, oy.key).is_eq() {
        return false;
    }
    let j = ox.key.0 + 1;
    let between = j < oy.key.0 || (j == oy.key.0 && oy.key.1 > 0.0);
    if !between {
        // Same segment: the chord lies in the (convex) face, or along one of its edges.
        return true;
    }
    let [a, b, c] = region.face_screen(f);
    in_triangle(a, b, c, region.sign[f as usize], line.pts[j as usize]) == Some(true)
}

/// The visits among occurrences `range` as (x, y) links, in order of y then of y's faces,
/// from `last`, each face's latest occurrence so far (updated). A face met for the first
/// time here goes to `first` as (face, y) when given.
fn visits_in(
    region: &Region,
    line: &Polyline,
    occ: &[Occ],
    range: std::ops::Range<usize>,
    last: &mut [u32],
    mut first: Option<&mut Vec<(u32, u32)>>,
) -> Vec<(u32, u32)> {
    let mut links = Vec::with_capacity(range.len());
    let mut faces = Vec::new();
    for y in range {
        let y = y as u32;
        elem_faces(region, occ[y as usize].elem, &mut faces);
        for &f in &faces {
            let x = std::mem::replace(&mut last[f as usize], y);
            if x == NONE {
                if let Some(first) = first.as_deref_mut() {
                    first.push((f, y));
                }
            } else if joins(region, line, occ, x, y, f) {
                links.push((x, y));
            }
        }
    }
    links
}

/// The links of consecutive visits of each face among occurrences `range` (positions
/// ascending), in order of second element: what a sort of (face, position) would put side
/// by side. A long range's two halves on rayon (this was a third of the serial time of
/// normalization on spot, through all); a face's first occurrence in the second half then
/// links to its last in the first, as one pass would have, and those links come between the
/// halves', so the stable sort by first element orders them as before.
fn visit_links(
    region: &Region,
    line: &Polyline,
    occ: &[Occ],
    range: std::ops::Range<usize>,
) -> Vec<(u32, u32)> {
    let nf = region.tri.len();
    if range.len() < 512 {
        return visits_in(region, line, occ, range, &mut vec![NONE; nf], None);
    }
    let mid = range.start + range.len() / 2;
    let ((last, mut links), (later, first)) = rayon::join(
        || {
            let mut last = vec![NONE; nf];
            let links = visits_in(region, line, occ, range.start..mid, &mut last, None);
            (last, links)
        },
        || {
            let (mut last, mut first) = (vec![NONE; nf], Vec::with_capacity(range.len() / 2));
            let links = visits_in(
                region,
                line,
                occ,
                mid..range.end,
                &mut last,
                Some(&mut first),
            );
            (links, first)
        },
    );
    for (f, y) in first {
        let x = last[f as usize];
        if x != NONE && joins(region, line, occ, x, y, f) {
            links.push((x, y));
        }
    }
    links.extend_from_slice(&later);
    links
}

/// Visits of one piece (polyline indices `j0..=j1`) linked into chains.
pub(crate) fn chains(
    region: &Region,
    line: &Polyline,
    occ: &[Occ],
    j0: u32,
    j1: u32,
) -> Vec<Chain> {
    let lo = occ.partition_point(|o| key_cmp(o.key, (j0, 0.0)).is_lt());
    let hi = occ.partition_point(|o| key_cmp(o.key, (j1, 0.0)).is_le());
    let mut links = visit_links(region, line, occ, lo..hi);
    // By first element; each one's links were made with ascending second elements, and the
    // radix sort is stable, so this is the order of the pairs.
    super::fast::radix::sort_by_key(&mut links);
    links.dedup();
    let n = hi - lo;
    let mut out_deg = vec![0u32; n];
    let mut in_deg = vec![0u32; n];
    for &(x, y) in &links {
        out_deg[x as usize - lo] += 1;
        in_deg[y as usize - lo] += 1;
    }
    let through = |x: u32| in_deg[x as usize - lo] == 1 && out_deg[x as usize - lo] == 1;
    // The first link of each element (links are sorted by it).
    let mut first = vec![0u32; n + 1];
    for &(x, _) in &links {
        first[x as usize - lo + 1] += 1;
    }
    for k in 0..n {
        first[k + 1] += first[k];
    }
    let mut used = vec![false; links.len()];
    let mut result = Vec::new();
    for start in 0..links.len() {
        if used[start] || through(links[start].0) {
            continue;
        }
        let mut chain = Vec::with_capacity(64);
        chain.push(links[start].0);
        let mut l = start;
        loop {
            used[l] = true;
            let y = links[l].1;
            chain.push(y);
            if !through(y) {
                break;
            }
            l = first[y as usize - lo] as usize;
            if used[l] {
                break;
            }
        }
        result.push(Chain { occ: chain });
    }
    result
}

#[cfg(test)]
mod tests {
    use super::{
        along, in_window, key_cmp, meets_only_at, sort_occurrences, Elem, Occ, Strip, NONE,
    };
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

    /// The occurrences' sort gives the order of a stable comparison sort by key then element,
    /// below and above the size at which its two halves run apart, with ties in both.
    #[test]
    fn occurrences_sort_as_a_comparison_sort_would() {
        let mut rnd = crate::cut::fast::radix::tests::xorshift(0x1234_5678_9abc_def1);
        for n in [0usize, 1, 5, 300, 511, 512, 2000] {
            let occ: Vec<Occ> = (0..n)
                .map(|i| {
                    let r = rnd();
                    let elem = match r % 3 {
                        0 => Elem::V((r >> 8) as u32 % 7),
                        1 => Elem::E {
                            edge: (r >> 8) as u32 % 7,
                            at: (r >> 16) as u32 % 3,
                            on_point: r >> 24 & 1 == 1,
                        },
                        _ => Elem::P {
                            point: (r >> 8) as u32 % 3,
                            face: (r >> 16) as u32 % 5,
                        },
                    };
                    let t = [0.0, 0.25, 0.5, 1e-300][(r >> 32) as usize % 4];
                    Occ {
                        key: ((r >> 40) as u32 % (n as u32 / 4 + 1), t),
                        elem,
                        screen: DVec2::new(i as f64, 0.0),
                        edge_t: 0.0,
                        visible: true,
                    }
                })
                .collect();
            let mut want = occ.clone();
            want.sort_by(|x, y| key_cmp(x.key, y.key).then(x.elem.cmp(&y.elem)));
            let mut got = occ;
            sort_occurrences(&mut got);
            let ids = |v: &[Occ]| v.iter().map(|o| o.screen.x).collect::<Vec<_>>();
            assert_eq!(ids(&got), ids(&want), "n = {n}");
        }
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
