//! Moving model vertices onto the stroke (seed 002 §3.2, Fig. 4; Biermann et al. 2001):
//! first to stroke vertices, then onto stroke segments, each within a ratio of L, parallel to
//! the screen. A snapped vertex sits exactly on a stroke point (a segment snap inserts one),
//! so later predicates see it on the stroke without tolerance.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::fast::SegmentIndex;
use super::geom::orient;
use super::ids::Lv;
use super::options::CutOptions;
use super::region::Region;
use super::stroke_checks::Prepared;
use super::view::Projector;
use super::visibility::Visibility;

/// No polyline point.
const NONE: u32 = u32::MAX;

/// The stroke after snapping, as a polyline of points.
#[derive(Debug, Clone)]
pub(crate) struct Polyline {
    pub pts: Vec<DVec2>,
    /// The prepared point each point is (`None` for a point inserted at a segment snap).
    pub src: Vec<Option<u32>>,
    /// Whether a model vertex was snapped onto the point.
    pub on_vertex: Vec<bool>,
}

pub(crate) struct Snapped {
    pub line: Polyline,
    /// The polyline segments `a..b` making up each prepared segment.
    pub seg_range: Vec<(u32, u32)>,
    /// The polyline index of each prepared point.
    pub start_of: Vec<u32>,
    /// (vertex, from, to, pixels), in snapping order.
    pub moves: Vec<(Lv, DVec3, DVec3, f64)>,
    /// The polyline point each move put its vertex on (`moves`' order).
    pub move_points: Vec<u32>,
    /// Vertices within reach whose move the fold-over guard refused.
    pub refused: Vec<Lv>,
}

/// Steps 2 and 3 of spec §4 on the region, which holds every vertex within the snap
/// distance `reach` of the stroke (prepared as `prep`, its segments `segments` indexed by
/// `index`); L is `l` pixels. A vertex may move when every face around it is in the region,
/// in front of the eye and one of them cuttable (all of them, and the vertex seen, in
/// visible-only mode: `visibility`, which records the moves).
#[allow(clippy::too_many_arguments)]
pub(crate) fn snap(
    region: &mut Region,
    prep: &Prepared,
    segments: &[(DVec2, DVec2)],
    index: &SegmentIndex,
    l: f64,
    reach: f64,
    options: &CutOptions,
    proj: &Projector,
    visibility: Option<&mut Visibility>,
) -> Snapped {
    // A vertex the user could not see does not move (tested only within reach).
    let allowed: Vec<bool> = {
        let (region, vis) = (&*region, visibility.as_deref());
        region
            .vertices()
            .collect::<Vec<Lv>>()
            .into_par_iter()
            .with_min_len(256)
            .map(|v| {
                let (Some(seen), true) = (region.seen(v), region.movable(v)) else {
                    return false;
                };
                let Some(vis) = vis else {
                    return true;
                };
                index.distance_to(seen.screen, segments) >= reach
                    || !vis.hidden(
                        region,
                        seen.screen,
                        seen.z,
                        region.pos(v),
                        false,
                        region.vertex_faces(v),
                    )
            })
            .collect()
    };
    let n = prep.points.len();
    let rv = options.snap_vertex_ratio * l;
    let rs = options.snap_segment_ratio * l;
    let min_area2 = 2e-12 * l * l;
    let mut taken = vec![false; n];
    let nv = region.vertex_count();
    let mut snapped = vec![false; nv];
    let mut moves = Vec::with_capacity(nv / 4);
    let mut targets: Vec<Target> = Vec::with_capacity(nv / 4);
    let mut refused_any = vec![false; nv];

    // Each movable vertex's nearest stroke vertex within rv (step 2) and nearest foot on a
    // stroke segment within rs (step 3), in one pass over the segments near it (the
    // index's margin covers max(rv, rs)). A foot stays valid for step 3: step 2 moves only
    // the vertices it snaps, which step 3 skips.
    #[allow(clippy::type_complexity)]
    let found: Vec<(Lv, Option<(f64, u32)>, Option<(f64, u32, f64, DVec2)>)> = {
        let region = &*region;
        (0..nv as u32)
            .into_par_iter()
            .with_min_len(512)
            .filter_map(|v| {
                let v = Lv(v);
                if !allowed[v.idx()] {
                    return None;
                }
                let s = region.screen(v);
                let mut point: Option<(f64, u32)> = None;
                let mut foot: Option<(f64, u32, f64, DVec2)> = None;
                for &si in index.near_point(s) {
                    if rv > 0.0 {
                        for k in [si as usize, (si as usize + 1) % n] {
                            let d = (prep.points[k] - s).length();
                            if d < rv && point.is_none_or(|(bd, bk)| (d, k as u32) < (bd, bk)) {
                                point = Some((d, k as u32));
                            }
                        }
                    }
                    if rs > 0.0 {
                        let (a, b) = segments[si as usize];
                        let ab = b - a;
                        let t = ((s - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                        let q = if t == 0.0 {
                            a
                        } else if t == 1.0 {
                            b
                        } else {
                            a + ab * t
                        };
                        let d = (q - s).length();
                        if d < rs && foot.is_none_or(|(bd, bs, ..)| (d, si) < (bd, bs)) {
                            foot = Some((d, si, t, q));
                        }
                    }
                }
                (point.is_some() || foot.is_some()).then_some((v, point, foot))
            })
            .collect()
    };

    // Step 2: to stroke vertices; each stroke vertex takes its nearest model vertex, taken
    // nearest first.
    let mut pairs: Vec<(f64, Lv, u32)> = found
        .iter()
        .filter_map(|&(v, point, _)| point.map(|(d, k)| (d, v, k)))
        .collect();
    // By distance, then vertex (distances are lengths: neither negative nor NaN, so their
    // bits sort as they do).
    pairs.sort_unstable_by_key(|p| (p.0.to_bits(), p.1));
    for &(_, v, k) in &pairs {
        if taken[k as usize] || snapped[v.idx()] {
            continue;
        }
        let q = prep.points[k as usize];
        if guard(region, v, q, min_area2) {
            moves.push(apply(region, proj, v, q));
            targets.push(Target::Point(k));
            snapped[v.idx()] = true;
            taken[k as usize] = true;
        } else {
            refused_any[v.idx()] = true;
        }
    }

    // Step 3: onto stroke segments; each snap inserts a stroke point at the foot.
    // (dist, v, seg, t, q) of the vertices step 2 left where they were.
    let feet: Vec<(f64, Lv, u32, f64, DVec2)> = found
        .iter()
        .filter(|&&(v, ..)| !snapped[v.idx()])
        .filter_map(|&(v, _, foot)| foot.map(|(d, si, t, q)| (d, v, si, t, q)))
        .collect();
    // By distance, then vertex (one foot per vertex), as in step 2, as packed keys with
    // each foot's index.
    let mut keys: Vec<u128> = feet
        .iter()
        .enumerate()
        .map(|(i, f)| (f.0.to_bits() as u128) << 64 | (f.1 .0 as u128) << 32 | i as u128)
        .collect();
    keys.sort_unstable();
    // Every foot a vertex was moved to (those at a segment's end too: they say where the
    // vertex went), in snapping order.
    let mut placed: Vec<(u32, f64, DVec2)> = Vec::with_capacity(feet.len());
    for &(_, v, si, t, q) in keys.iter().map(|&k| &feet[k as u32 as usize]) {
        if guard(region, v, q, min_area2) {
            targets.push(Target::Foot(placed.len() as u32));
            placed.push((si, t, q));
            moves.push(apply(region, proj, v, q));
            snapped[v.idx()] = true;
            refused_any[v.idx()] = false;
        } else {
            refused_any[v.idx()] = true;
        }
    }
    // By segment, then parameter, ties in snapping order (a stable sort, as packed keys).
    let mut keys: Vec<u128> = placed
        .iter()
        .enumerate()
        .map(|(i, x)| {
            (x.0 as u128) << 96 | (super::fast::radix::f64_key(x.1) as u128) << 32 | i as u128
        })
        .collect();
    keys.sort_unstable();
    let order: Vec<u32> = keys.iter().map(|&k| k as u32).collect();

    // The snapped polyline: prepared points with the feet inserted in segment order. A closed
    // stroke starts at its first corner, else at a stroke vertex holding a model vertex, so
    // its closing point costs no interior vertex when it can (gap-fill).
    let k0 = if !prep.closed {
        0
    } else if let Some(&c) = prep.corners.first() {
        c
    } else {
        (0..n).find(|&k| taken[k]).unwrap_or(0)
    };
    let mut line = Polyline {
        pts: Vec::with_capacity(n + placed.len() + 1),
        src: Vec::new(),
        on_vertex: Vec::new(),
    };
    let mut start_of = vec![0u32; n];
    // The polyline point of each foot, by its index in `placed`.
    let mut foot_point = vec![NONE; placed.len()];
    let segs = prep.segment_count();
    for i in 0..n {
        let k = (k0 + i) % n;
        start_of[k] = line.pts.len() as u32;
        line.pts.push(prep.points[k]);
        line.src.push(Some(k as u32));
        line.on_vertex.push(taken[k]);
        if k >= segs {
            continue;
        }
        let in_k = |f: &u32| (placed[*f as usize].0 as usize).cmp(&k);
        let lo = order.partition_point(|f| in_k(f).is_lt());
        let hi = order.partition_point(|f| in_k(f).is_le());
        let mut at_end = Vec::new();
        let mut before: Option<DVec2> = None;
        for &f in &order[lo..hi] {
            let q = placed[f as usize].2;
            // A foot equal to an end point of the segment is that point; one equal to the
            // foot before it is that one's point.
            foot_point[f as usize] = if q == prep.points[k] {
                start_of[k]
            } else if q == prep.points[(k + 1) % n] {
                at_end.push(f);
                NONE
            } else if before == Some(q) {
                line.pts.len() as u32 - 1
            } else {
                line.pts.push(q);
                line.src.push(None);
                line.on_vertex.push(true);
                line.pts.len() as u32 - 1
            };
            before = Some(q);
        }
        // The segment's end is the next point pushed (the closing point of a closed stroke
        // after its last segment).
        for f in at_end {
            foot_point[f as usize] = line.pts.len() as u32;
        }
    }
    if prep.closed {
        line.pts.push(prep.points[k0]);
        line.src.push(Some(k0 as u32));
        line.on_vertex.push(taken[k0]);
    }
    let last = line.pts.len() as u32 - 1;
    let seg_range = (0..segs)
        .map(|k| {
            let next = (k + 1) % n;
            let end = if prep.closed && next == k0 {
                last
            } else {
                start_of[next]
            };
            (start_of[k], end)
        })
        .collect();
    let move_points = targets
        .iter()
        .map(|t| match *t {
            Target::Point(k) => start_of[k as usize],
            Target::Foot(f) => foot_point[f as usize],
        })
        .collect();
    let refused = region
        .vertices()
        .filter(|&v| refused_any[v.idx()] && !snapped[v.idx()])
        .collect();
    if let Some(vis) = visibility {
        vis.before.mark_moved(moves.iter().map(|m| m.0));
    }
    Snapped {
        line,
        seg_range,
        start_of,
        moves,
        move_points,
        refused,
    }
}

/// Where a move put its vertex: on prepared point `k`, or on foot `f` (its index among the
/// feet in snapping order).
#[derive(Clone, Copy)]
enum Target {
    Point(u32),
    Foot(u32),
}

/// Fold-over guard (spec §4 step 2, gap-fill): moving `v` to `q` keeps every non-degenerate
/// face around it turning the same way, with area at least 1e-12·L².
fn guard(region: &Region, v: Lv, q: DVec2, min_area2: f64) -> bool {
    let at = |x: Lv| if x == v { q } else { region.screen(x) };
    region.vertex_faces(v).iter().all(|&f| {
        let sign = region.sign(f);
        if sign == 0.0 {
            return true;
        }
        let [a, b, c] = region.corners(f);
        let o = orient(at(a), at(b), at(c));
        o * sign > 0.0 && o.abs() >= min_area2
    })
}

fn apply(region: &mut Region, proj: &Projector, v: Lv, q: DVec2) -> (Lv, DVec3, DVec3, f64) {
    let seen = region.seen(v).expect("a projectable vertex");
    let from = region.pos(v);
    let px = (q - seen.screen).length();
    let to = proj.unproject(q, seen.w, seen.z);
    region.move_vertex(v, q, to);
    (v, from, to, px)
}
