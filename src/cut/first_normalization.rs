//! First normalization (seed 002 §3.3, Fig. 5): the stroke becomes the array A of the model
//! elements it meets — vertices V_j and edge crossings E_i — in stroke order, one array per
//! chain of faces it passes through (one sheet, one visible stretch; spec §6.14).
//!
//! Every element is found by exact predicates: a vertex is met when `orient2d` puts it on a
//! segment (snapped vertices sit exactly on stroke points), an edge when the segment and the
//! edge strictly separate each other's ends, or a stroke point lies inside the edge. Stroke
//! points strictly inside a face are not elements: they are what the first normalization
//! drops. Piece ends strictly inside a face become interior points P (seed 002 §3.4,
//! Fig. 12), or, within a third of the segment snap distance of an edge, points on that edge
//! (gap-fill: no sliver from the 1 → 3 split).
//!
//! Chains: for each face, consecutive elements (in stroke order) that the stroke joins
//! through the face's interior form a *visit*; visits sharing an element link into chains.
//! Where two visits begin or end at one element (a silhouette seen through all sheets) the
//! chain ends, so each chain is one sheet.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::fast::locate::Locator;
use super::fast::polyline::PolylineIndex;
use super::fast::radix::f64_key;
use super::fast::{Machinery, SegmentIndex};
use super::geom::{barycentric, in_triangle, on_segment, orient};
use super::ids::{Le, Lf, Lv};
use super::region::Region;
use super::snap::{Polyline, Snapped};
use super::stroke_checks::Pieces;
use super::visibility::{Before, Visibility};

/// No polyline point, no occurrence.
const NONE: u32 = u32::MAX;

/// A model element the stroke meets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Elem {
    /// A vertex.
    V(Lv),
    /// Edge `edge` crossed by segment `at`, or (`on_point`) containing stroke point `at`.
    E { edge: Le, at: u32, on_point: bool },
    /// Piece end point `point` (canonical polyline index) strictly inside face `face`.
    P { point: u32, face: Lf },
}

/// One meeting of the stroke with an element, at stroke position `key` = (index, t): a point
/// `index` when `t == 0`, else the point at parameter `t` of segment `index`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Occ {
    pub key: (u32, f64),
    pub elem: Elem,
    pub screen: DVec2,
    /// E: screen parameter along the edge from its first to its second end.
    pub edge_t: f64,
    pub visible: bool,
}

pub(crate) fn key_cmp(a: (u32, f64), b: (u32, f64)) -> std::cmp::Ordering {
    a.0.cmp(&b.0).then(a.1.total_cmp(&b.1))
}

/// Sorts by stroke position, then element, stably.
fn sort_occurrences(machinery: Machinery, occ: &mut Vec<Occ>) {
    machinery.sort_by_index_then_key(occ, |o| o.key.0, |o| (f64_key(o.key.1), o.elem));
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

/// The first normalization's result.
pub(crate) struct Elements<'a> {
    /// Every meeting of the stroke with an element, in stroke order.
    pub occ: Vec<Occ>,
    /// The element arrays A (indices into `occ`), each with its piece, in piece order.
    pub arrays: Vec<(u32, Vec<u32>)>,
    /// Whether each occurrence is in some chain.
    pub in_chain: Vec<bool>,
    /// Piece ends moved onto an edge (polyline points, ascending).
    pub ends_moved: Vec<u32>,
    /// Finds the faces under stroke points (the report sorts dropped points by it).
    pub locate: Locator<'a>,
}

/// The arrays A of the snapped stroke's pieces (seed 002 §3.3, Fig. 5; spec §4 steps 4-5),
/// over the region's cuttable faces (in visible-only mode, the stretches seen:
/// `visibility`). `segments`: the prepared segments indexed; `end_reach`: how near an edge a
/// piece end inside a face goes onto it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn first_normalization<'a>(
    region: &Region,
    snapped: &Snapped,
    closed: bool,
    pieces: &Pieces,
    segments: &SegmentIndex,
    visibility: Option<&'a Visibility>,
    end_reach: EndReach,
    machinery: Machinery,
) -> Elements<'a> {
    let line = &snapped.line;
    let polyline = PolylineIndex::new(machinery, &line.pts, &snapped.seg_range);
    // The faces under piece ends, and under stroke points for the report.
    let locate = Locator::new(machinery, visibility.map(|v| &v.faces), region, || {
        (0..line.pts.len())
            .filter(|j| line.src[*j].is_some() || pieces.bounds.contains(&(*j as u32)))
            .map(|j| line.pts[j])
            .collect()
    });
    let mut ends_moved = Vec::new();
    let occ = find_occurrences(
        region,
        snapped,
        closed,
        segments,
        &polyline,
        &pieces.bounds,
        &locate,
        visibility,
        end_reach,
        &mut ends_moved,
        machinery,
    );
    ends_moved.sort_unstable();
    ends_moved.dedup();
    let mut in_chain = vec![false; occ.len()];
    let mut arrays = Vec::new();
    let mut last = LastVisits::new(region);
    for (piece, span) in pieces.spans().enumerate() {
        // Chains of one piece that follow each other along the stroke are normalized as one
        // array (gap-fill): a face the stroke leaves (through a silhouette or the boundary)
        // and re-enters is then still crossed once, as Fig. 9 intends; chains that overlap in
        // stroke order (other sheets) stay apart. Where the chains of several sheets end
        // before a chain begins, it follows the one it shares a face with: its own sheet's.
        let mut runs: Vec<(Vec<u32>, Vec<Lf>)> = Vec::new();
        for chain in chains(region, line, &occ, span, &mut last, machinery) {
            for &o in &chain.occ {
                in_chain[o as usize] = true;
            }
            let first = occ[chain.occ[0] as usize].key;
            let after = |r: &(Vec<u32>, Vec<Lf>)| {
                key_cmp(occ[*r.0.last().unwrap() as usize].key, first).is_lt()
            };
            let before: Vec<usize> = (0..runs.len()).filter(|&r| after(&runs[r])).collect();
            let pick = before
                .iter()
                .copied()
                .find(|&r| shares_a_face(&runs[r].1, &chain.faces))
                .or(before.first().copied());
            match pick {
                Some(r) => {
                    let (occ_r, faces_r) = &mut runs[r];
                    occ_r.extend_from_slice(&chain.occ);
                    faces_r.extend_from_slice(&chain.faces);
                    faces_r.sort_unstable();
                    faces_r.dedup();
                }
                None => runs.push((chain.occ, chain.faces)),
            }
        }
        arrays.extend(runs.into_iter().map(|r| (piece as u32, r.0)));
    }
    Elements {
        occ,
        arrays,
        in_chain,
        ends_moved,
        locate,
    }
}

/// All meetings of the stroke with elements of cuttable faces, sorted by key: of the snapped
/// polyline and the vertices snapped onto it (`snapped`, its segments indexed by
/// `polyline`, the prepared segments by `segments`); `piece_ends`, the polyline points that
/// end pieces, found in faces by `locate`; in visible-only mode (`visibility`) each marked
/// seen or hidden. Piece ends moved onto an edge (within `end_reach` of it) are pushed to
/// `ends_moved`.
#[allow(clippy::too_many_arguments)]
fn find_occurrences(
    region: &Region,
    snapped: &Snapped,
    closed: bool,
    segments: &SegmentIndex,
    polyline: &PolylineIndex,
    piece_ends: &[u32],
    locate: &Locator,
    visibility: Option<&Visibility>,
    end_reach: EndReach,
    ends_moved: &mut Vec<u32>,
    machinery: Machinery,
) -> Vec<Occ> {
    let (moves, move_points) = (&snapped.moves, &snapped.move_points);
    let line = &snapped.line;
    let pts = &line.pts;
    let last = (pts.len() - 1) as u32;
    let mk = |key: (u32, f64), elem: Elem, screen: DVec2| Occ {
        key,
        elem,
        screen,
        edge_t: 0.0,
        visible: true,
    };
    // Vertices on the stroke, once per vertex of a cuttable face (the edge loop would find
    // each from all its edges). Only vertices on the stroke's band can be on it.
    let nv = region.vertex_count() as u32;
    let mut snapped_on = vec![NONE; nv as usize];
    for (&(v, ..), &j) in moves.iter().zip(move_points) {
        snapped_on[v.idx()] = j;
    }
    let on_stroke: Vec<Vec<Occ>> = (0..nv)
        .into_par_iter()
        .chunks(256)
        .map(|chunk| {
            let mut occ: Vec<Occ> = Vec::new();
            for v in chunk.into_iter().map(Lv) {
                if !region.on_band(v) || !region.vertex_faces(v).iter().any(|&f| region.cuttable(f))
                {
                    continue;
                }
                let x = region.screen(v);
                let near = segments.near_point(x);
                polyline.for_vertex(x, snapped_on[v.idx()], near, |k| {
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
                });
            }
            occ
        })
        .collect();
    // The polyline point each vertex sits on exactly (snapped vertices), else NONE.
    let mut point_of = vec![NONE; nv as usize];
    for o in on_stroke.iter().flatten() {
        if let Elem::V(v) = o.elem {
            if o.key.1 == 0.0 && pts[o.key.0 as usize] == o.screen {
                point_of[v.idx()] = o.key.0;
            }
        }
    }
    // Edge crossings, in fixed chunks of edges concatenated in edge order.
    let edges: Vec<Le> = (0..region.edge_count() as u32).map(Le).collect();
    let crossings: Vec<Vec<Occ>> = edges
        .par_chunks(256)
        .map(|chunk| {
            let mut occ: Vec<Occ> = Vec::new();
            let mut scratch: Vec<u32> = Vec::new();
            for &e in chunk {
                if !region
                    .edge_faces(e)
                    .iter()
                    .any(|&f| f.is_some() && region.cuttable(f))
                {
                    continue;
                }
                let [ia, ib] = region.ends(e);
                let (a, b) = (region.screen(ia), region.screen(ib));
                let near = segments.near_box(a.min(b), a.max(b), &mut scratch);
                let ends_on = (point_of[ia.idx()], point_of[ib.idx()]);
                polyline.for_edge((a, b), ends_on, near, |k| {
                    let (p, q) = (pts[k as usize], pts[k as usize + 1]);
                    // Boxes apart: nothing to meet (exact: comparisons only).
                    if (p.x.max(q.x) < a.x.min(b.x))
                        | (p.x.min(q.x) > a.x.max(b.x))
                        | (p.y.max(q.y) < a.y.min(b.y))
                        | (p.y.min(q.y) > a.y.max(b.y))
                    {
                        return;
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
                            return;
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
                                edge: e,
                                at,
                                on_point,
                            },
                            screen,
                        );
                        o.edge_t = edge_t;
                        occ.push(o);
                    } else if o1 == 0.0 && o2 == 0.0 {
                        // The segment runs along the edge's line: stroke points strictly
                        // inside the edge are on it.
                        let ab = b - a;
                        for (j, x) in [(k, p), (k + 1, q)] {
                            if (j == k || j == last) && x != a && x != b && on_segment(a, b, x) {
                                let mut o = mk(
                                    (j, 0.0),
                                    Elem::E {
                                        edge: e,
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
                });
            }
            occ
        })
        .collect();
    let mut occ: Vec<Occ> = crossings.into_iter().chain(on_stroke).flatten().collect();
    // Piece ends strictly inside faces (seed 002 §3.4, Figs. 12-13).
    for &j in piece_ends {
        let s = pts[j as usize];
        for f in locate.faces_at(region, s) {
            if !region.cuttable(f) {
                continue;
            }
            let [a, b, c] = region.face_screen(f);
            if in_triangle(a, b, c, region.sign(f), s) == Some(true) {
                // An end this close to an edge (a third of the segment snap distance) would
                // make a sliver of the 1 → 3 split: it goes onto the edge instead, splitting
                // it (gap-fill: spec §4 step 4's "ties → edge" widened).
                if let Some((edge, t, foot)) = near_edge(region, f, s, end_reach) {
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
                        face: f,
                    },
                    s,
                ));
            }
        }
    }
    sort_occurrences(machinery, &mut occ);
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
        sort_occurrences(machinery, &mut occ);
    }
    if let Some(vis) = visibility {
        occ.par_iter_mut().with_min_len(64).for_each(|o| {
            let (z, x) = elem_depth(region, o);
            // A point snapping did not move must also have been seen before it.
            let unmoved = !elem_moved(region, &vis.before, o.elem);
            let (pair, one);
            let own: &[Lf] = match o.elem {
                Elem::V(v) => region.vertex_faces(v),
                Elem::E { edge, .. } => {
                    pair = region.edge_faces(edge);
                    &pair
                }
                Elem::P { face, .. } => {
                    one = [face];
                    &one
                }
            };
            o.visible = !vis.hidden(region, o.screen, z, x, unmoved, own);
        });
        // In visible-only mode a piece end inside faces belongs to the nearest visible one.
        occ.retain(|o| !matches!(o.elem, Elem::P { .. }) || o.visible);
    }
    occ
}

/// How near an edge a piece end inside a face goes onto it (screen pixels).
#[derive(Debug, Clone, Copy)]
pub(crate) struct EndReach {
    /// An edge between two faces of one sheet, or on the boundary: a third of the segment snap
    /// distance (an end nearer would make a sliver of the 1 → 3 split).
    pub edge: f64,
    /// A silhouette edge (its faces turn opposite ways on screen): a rounding error. A
    /// fold's faces hold the points beside it on both sheets, and the vertices there often
    /// cannot snap (the fold-over guard), so only an end that lies on the edge up to
    /// rounding goes onto it, one vertex for both sheets.
    pub silhouette: f64,
}

/// The edge of face `f` nearest to `s` if closer than `reach` with its foot strictly inside
/// the edge: (edge, screen parameter from its first end, foot).
fn near_edge(region: &Region, f: Lf, s: DVec2, reach: EndReach) -> Option<(Le, f64, DVec2)> {
    let mut best: Option<(f64, Le, f64, DVec2)> = None;
    let sign = region.sign(f);
    for e in region.face_edges(f) {
        let other = region
            .edge_faces(e)
            .into_iter()
            .find(|&g| g != f && g.is_some());
        let reach = if other.is_some_and(|g| region.sign(g) != sign) {
            reach.silhouette
        } else {
            reach.edge
        };
        let [u, w] = region.ends(e);
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
        Elem::E { edge, .. } => region.ends(edge).iter().any(|&v| b.moved(v)),
        Elem::P { face, .. } => region.corners(face).iter().any(|&v| b.moved(v)),
    }
}

/// NDC depth and world position of an occurrence (perspective-correct, spec §4 step 5).
pub(crate) fn elem_depth(region: &Region, o: &Occ) -> (f64, DVec3) {
    match o.elem {
        Elem::V(v) => (region.seen(v).expect("projectable").z, region.pos(v)),
        Elem::E { edge, .. } => {
            let [a, b] = region.ends(edge);
            let (sa, sb) = (region.seen(a).unwrap(), region.seen(b).unwrap());
            let s = o.edge_t;
            let t = s * sa.w / ((1.0 - s) * sb.w + s * sa.w);
            (
                sa.z + (sb.z - sa.z) * s,
                region.pos(a).lerp(region.pos(b), t),
            )
        }
        Elem::P { face, .. } => {
            let [a, b, c] = region.face_screen(face);
            region.lift(face, barycentric(a, b, c, o.screen))
        }
    }
}

/// Cuttable faces incident to an element, ascending.
pub(crate) fn elem_faces(region: &Region, e: Elem, out: &mut Vec<Lf>) {
    out.clear();
    match e {
        Elem::V(v) => out.extend(
            region
                .vertex_faces(v)
                .iter()
                .copied()
                .filter(|&f| region.cuttable(f)),
        ),
        Elem::E { edge, .. } => {
            out.extend(
                region
                    .edge_faces(edge)
                    .iter()
                    .copied()
                    .filter(|&f| f.is_some() && region.cuttable(f)),
            );
            if out.len() == 2 && out[0] > out[1] {
                out.swap(0, 1);
            }
        }
        Elem::P { face, .. } => out.push(face),
    }
}

/// A chain: occurrences in stroke order (one sheet), and the faces its visits pass through
/// (ascending).
#[derive(Debug, Clone)]
pub(crate) struct Chain {
    pub occ: Vec<u32>,
    pub faces: Vec<Lf>,
}

/// Whether two ascending face lists have a face in common.
fn shares_a_face(a: &[Lf], b: &[Lf]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

/// Whether consecutive visits `x` then `y` of face `f` (occurrence indices) make a visit:
/// stroke joins them through the face's interior.
#[inline]
fn joins(region: &Region, line: &Polyline, occ: &[Occ], x: u32, y: u32, f: Lf) -> bool {
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
    in_triangle(a, b, c, region.sign(f), line.pts[j as usize]) == Some(true)
}

/// Each face's latest occurrence while the occurrences of a piece are walked (NONE before its
/// first), kept across pieces and reset where it was set, so each piece costs its own size.
pub(crate) struct LastVisits {
    last: Vec<u32>,
    set: Vec<Lf>,
}

impl LastVisits {
    pub fn new(region: &Region) -> Self {
        LastVisits {
            last: vec![NONE; region.face_count()],
            set: Vec::new(),
        }
    }
}

/// Visits of one piece (polyline indices `j0..=j1`) linked into chains.
pub(crate) fn chains(
    region: &Region,
    line: &Polyline,
    occ: &[Occ],
    (j0, j1): (u32, u32),
    last: &mut LastVisits,
    machinery: Machinery,
) -> Vec<Chain> {
    let lo = occ.partition_point(|o| key_cmp(o.key, (j0, 0.0)).is_lt());
    let hi = occ.partition_point(|o| key_cmp(o.key, (j1, 0.0)).is_le());
    // The links of consecutive visits of each face, in order of their second element, and
    // each link's face.
    let mut links: Vec<(u32, u32)> = Vec::with_capacity(hi - lo);
    let mut link_faces: Vec<(u32, u32, Lf)> = Vec::with_capacity(hi - lo);
    let mut faces = Vec::new();
    for y in lo as u32..hi as u32 {
        elem_faces(region, occ[y as usize].elem, &mut faces);
        for &f in &faces {
            let x = std::mem::replace(&mut last.last[f.idx()], y);
            if x == NONE {
                last.set.push(f);
            } else if joins(region, line, occ, x, y, f) {
                links.push((x, y));
                link_faces.push((x, y, f));
            }
        }
    }
    link_faces.sort_unstable();
    for f in last.set.drain(..) {
        last.last[f.idx()] = NONE;
    }
    // By first element, stably: each one's links are in order of their second.
    machinery.sort_pairs(&mut links);
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
        let mut faces: Vec<Lf> = chain
            .windows(2)
            .flat_map(|w| {
                let at = link_faces.partition_point(|l| (l.0, l.1) < (w[0], w[1]));
                link_faces[at..]
                    .iter()
                    .take_while(move |l| (l.0, l.1) == (w[0], w[1]))
                    .map(|l| l.2)
            })
            .collect();
        faces.sort_unstable();
        faces.dedup();
        result.push(Chain { occ: chain, faces });
    }
    result
}
