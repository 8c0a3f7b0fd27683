//! Input validation (spec §1; seed 000 §2.1 conditions (a)–(b)): everything that can be
//! checked before meshing, each failure a [`CurvedError`] naming the curve, loop, region,
//! patch or metric sample at fault. Condition (c), curves meeting only at shared end points,
//! is decided while the guarding envelopes are separated ([`super::separate`]), and overlapping
//! regions once the guards are known.

use std::collections::HashMap;

use glam::DVec2;

use super::bezier::BezierCurve;
use super::cone::Cone;
use super::error::CurvedError;
use super::field::{Grid2, Grid3, MetricField, SizeField};
use super::input::TrimmedPatches;
use super::tensor::{Metric2, Metric3};

/// Bisections tried before a curve whose hodograph hull holds 0 is declared singular.
const REGULARITY_DEPTH: u32 = 24;

/// Checks everything about `input` that does not need the guards. On success, returns the
/// curves in use, in id order.
pub(crate) fn validate(input: &TrimmedPatches) -> Result<Vec<u32>, CurvedError> {
    if input.regions.is_empty() {
        return Err(CurvedError::Empty { what: "regions" });
    }
    for (i, p) in input.patches.iter().enumerate() {
        let (m, n) = p.degrees();
        if m == 0 || n == 0 {
            return Err(CurvedError::PatchDegree {
                patch: i as u32,
                degree_u: m,
                degree_v: n,
            });
        }
        let expected = (m + 1) * (n + 1);
        if p.points().len() != expected {
            return Err(CurvedError::PatchPointCount {
                patch: i as u32,
                degree_u: m,
                degree_v: n,
                expected,
                got: p.points().len(),
            });
        }
        for (k, q) in p.points().iter().enumerate() {
            if let Some(value) = q.to_array().into_iter().find(|x| !x.is_finite()) {
                return Err(CurvedError::NonFinite {
                    element: format!("patch {i}"),
                    index: k,
                    value,
                });
            }
        }
    }
    // Curves used by the regions, and how.
    let mut uses: HashMap<u32, Vec<(u32, u32, bool)>> = HashMap::new();
    for (r, region) in input.regions.iter().enumerate() {
        let r = r as u32;
        if region.patch.idx() >= input.patches.len() {
            return Err(CurvedError::UnknownPatch {
                region: r,
                patch: region.patch.0,
                patch_count: input.patches.len(),
            });
        }
        if region.loops.is_empty() {
            return Err(CurvedError::EmptyLoop {
                region: r,
                loop_index: None,
                what: "the list of loops",
            });
        }
        for (l, lp) in region.loops.iter().enumerate() {
            if lp.uses.is_empty() {
                return Err(CurvedError::EmptyLoop {
                    region: r,
                    loop_index: Some(l as u32),
                    what: "the loop",
                });
            }
            for (k, u) in lp.uses.iter().enumerate() {
                if u.curve.idx() >= input.curves.len() {
                    return Err(CurvedError::UnknownCurve {
                        region: r,
                        loop_index: l as u32,
                        position: k as u32,
                        curve: u.curve.0,
                        curve_count: input.curves.len(),
                    });
                }
                uses.entry(u.curve.0)
                    .or_default()
                    .push((r, l as u32, u.reversed));
            }
        }
    }
    let mut used: Vec<u32> = uses.keys().copied().collect();
    used.sort_unstable();
    for &c in &used {
        check_curve(c, &input.curves[c as usize])?;
    }
    for &c in &used {
        let list = &uses[&c];
        if list.len() > 2 {
            return Err(CurvedError::CurveUse {
                curve: c,
                reason: format!(
                    "it is used {} times; a curve bounds at most two regions, once each",
                    list.len()
                ),
            });
        }
        if let [(r0, l0, d0), (r1, l1, d1)] = list[..] {
            if d0 == d1 {
                return Err(CurvedError::CurveUse {
                    curve: c,
                    reason: format!(
                        "region {r0} loop {l0} and region {r1} loop {l1} both run it {}; two regions sharing a curve lie on its two sides and run it in opposite directions",
                        if d0 { "backwards" } else { "forwards" }
                    ),
                });
            }
            if r0 == r1 {
                return Err(CurvedError::CurveUse {
                    curve: c,
                    reason: format!("region {r0} uses it on both sides (a slit is not supported)"),
                });
            }
            let (p0, p1) = (
                input.regions[r0 as usize].patch,
                input.regions[r1 as usize].patch,
            );
            if p0 != p1 {
                return Err(CurvedError::CurveUse {
                    curve: c,
                    reason: format!(
                        "regions {r0} (patch {p0}) and {r1} (patch {p1}) share it, but a trim curve lies in one patch's parameter square"
                    ),
                });
            }
        }
    }
    check_duplicates(input, &used)?;
    for (r, region) in input.regions.iter().enumerate() {
        for (l, lp) in region.loops.iter().enumerate() {
            let n = lp.uses.len();
            for k in 0..n {
                let (u, next) = (lp.uses[k], lp.uses[(k + 1) % n]);
                let (end, start) = (input.use_end(u), input.use_start(next));
                if end != start {
                    return Err(CurvedError::LoopNotClosed {
                        region: r as u32,
                        loop_index: l as u32,
                        position: k as u32,
                        curve: u.curve.0,
                        next_curve: next.curve.0,
                        end: end.to_array(),
                        next_start: start.to_array(),
                    });
                }
            }
            let area: f64 = lp
                .uses
                .iter()
                .map(|u| {
                    let a = input.curves[u.curve.idx()].area_term();
                    if u.reversed {
                        -a
                    } else {
                        a
                    }
                })
                .sum();
            let outer = l == 0;
            if (outer && area <= 0.0) || (!outer && area >= 0.0) {
                return Err(CurvedError::LoopOrientation {
                    region: r as u32,
                    loop_index: l as u32,
                    role: if outer {
                        "an outer loop (loop 0)"
                    } else {
                        "a hole"
                    },
                    expected: if outer {
                        "counter-clockwise"
                    } else {
                        "clockwise"
                    },
                    found: if area > 0.0 {
                        "counter-clockwise"
                    } else if area < 0.0 {
                        "clockwise"
                    } else {
                        "around no area"
                    },
                    area,
                });
            }
        }
    }
    check_zero_angles(input, &used)?;
    check_metric(&input.metric)?;
    Ok(used)
}

/// Control points, parameter square, regularity (spec §1.4 (a)).
fn check_curve(id: u32, c: &BezierCurve) -> Result<(), CurvedError> {
    if c.points().len() < 2 {
        return Err(CurvedError::CurveTooShort {
            curve: id,
            points: c.points().len(),
        });
    }
    for (k, p) in c.points().iter().enumerate() {
        if let Some(value) = p.to_array().into_iter().find(|x| !x.is_finite()) {
            return Err(CurvedError::NonFinite {
                element: format!("curve {id}"),
                index: k,
                value,
            });
        }
    }
    check_inside_square(id, c, 0.0, 1.0, 0)?;
    check_regular(id, c, 0.0, 1.0, 0)
}

/// The curve stays within `[0, 1]²` (up to 1e-12): the control box decides, or the halves do.
fn check_inside_square(
    id: u32,
    c: &BezierCurve,
    t0: f64,
    t1: f64,
    depth: u32,
) -> Result<(), CurvedError> {
    const TOL: f64 = 1e-12;
    let (lo, hi) = c.control_box();
    if lo.x >= -TOL && lo.y >= -TOL && hi.x <= 1.0 + TOL && hi.y <= 1.0 + TOL {
        return Ok(());
    }
    // A point of the curve outside proves it.
    for p in [c.start(), c.end(), c.eval(0.5)] {
        if p.x < -TOL || p.y < -TOL || p.x > 1.0 + TOL || p.y > 1.0 + TOL {
            return Err(CurvedError::OutsideParameterSquare {
                curve: id,
                u: p.x,
                v: p.y,
            });
        }
    }
    if depth >= 16 {
        return Ok(());
    }
    let (a, b) = c.split_half();
    let tm = 0.5 * (t0 + t1);
    check_inside_square(id, &a, t0, tm, depth + 1)?;
    check_inside_square(id, &b, tm, t1, depth + 1)
}

/// `c'(t) ≠ 0`: 0 outside the hull of the hodograph's control points, on the whole curve or
/// on each piece of a bisection (spec §1.4 (a)).
fn check_regular(
    id: u32,
    c: &BezierCurve,
    t0: f64,
    t1: f64,
    depth: u32,
) -> Result<(), CurvedError> {
    let h = c.hodograph();
    if Cone::of(&h).is_some() {
        return Ok(());
    }
    if depth >= REGULARITY_DEPTH || h.len() == 1 {
        return Err(CurvedError::SingularCurve {
            curve: id,
            t: 0.5 * (t0 + t1),
        });
    }
    let (a, b) = c.split_half();
    let tm = 0.5 * (t0 + t1);
    check_regular(id, &a, t0, tm, depth + 1)?;
    check_regular(id, &b, tm, t1, depth + 1)
}

/// Two distinct curves with the same control points, forwards or backwards (spec §7.9's
/// negative test: private copies of a shared curve).
fn check_duplicates(input: &TrimmedPatches, used: &[u32]) -> Result<(), CurvedError> {
    let key = |pts: &mut dyn Iterator<Item = &DVec2>| -> Vec<u64> {
        pts.flat_map(|p| [p.x.to_bits(), p.y.to_bits()]).collect()
    };
    let mut seen: HashMap<Vec<u64>, u32> = HashMap::new();
    for &c in used {
        let pts = input.curves[c as usize].points();
        let fwd = key(&mut pts.iter());
        let bwd = key(&mut pts.iter().rev());
        for k in [&fwd, &bwd] {
            if let Some(&other) = seen.get(k) {
                return Err(CurvedError::DuplicateCurve { a: other, b: c });
            }
        }
        seen.insert(fwd, c);
    }
    Ok(())
}

/// Curves leaving a common end point must leave in different directions (seed 000 §2.1 (b)).
fn check_zero_angles(input: &TrimmedPatches, used: &[u32]) -> Result<(), CurvedError> {
    // Departures from each end point: (position bits, curve, direction away from the point).
    let mut departures: Vec<([u64; 2], u32, DVec2)> = Vec::with_capacity(2 * used.len());
    for &c in used {
        let p = input.curves[c as usize].points();
        let d = p.len() - 1;
        departures.push(([p[0].x.to_bits(), p[0].y.to_bits()], c, p[1] - p[0]));
        departures.push(([p[d].x.to_bits(), p[d].y.to_bits()], c, p[d - 1] - p[d]));
    }
    departures.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut i = 0;
    while i < departures.len() {
        let mut j = i + 1;
        while j < departures.len() && departures[j].0 == departures[i].0 {
            j += 1;
        }
        for a in i..j {
            for b in a + 1..j {
                let (da, db) = (departures[a].2, departures[b].2);
                if super::predicates::cross_sign(da, db) == 0.0 && da.dot(db) > 0.0 {
                    let at = DVec2::new(
                        f64::from_bits(departures[a].0[0]),
                        f64::from_bits(departures[a].0[1]),
                    );
                    return Err(CurvedError::ZeroAngle {
                        a: departures[a].1,
                        b: departures[b].1,
                        at: at.to_array(),
                    });
                }
            }
        }
        i = j;
    }
    Ok(())
}

fn bad_metric(at: String, reason: String) -> CurvedError {
    CurvedError::InvalidMetric { at, reason }
}

fn check_grid_frame(
    counts: &[u32],
    min: &[f64],
    max: &[f64],
    values: usize,
) -> Result<(), CurvedError> {
    if counts.contains(&0) {
        return Err(bad_metric(
            "grid".into(),
            format!("sample counts {counts:?} must all be at least 1"),
        ));
    }
    let n: u64 = counts.iter().map(|&c| c as u64).product();
    if n != values as u64 {
        return Err(bad_metric(
            "grid".into(),
            format!("counts {counts:?} need {n} samples, there are {values}"),
        ));
    }
    for (k, (lo, hi)) in min.iter().zip(max).enumerate() {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(bad_metric(
                "grid".into(),
                format!("axis {k}: the box [{lo}, {hi}] is not a finite interval"),
            ));
        }
    }
    Ok(())
}

/// Constant tensors and grid samples are symmetric positive definite, sizes positive.
fn check_metric(m: &MetricField) -> Result<(), CurvedError> {
    let spd3 = |at: String, t: &Metric3| {
        if t.is_positive_definite() {
            Ok(())
        } else {
            Err(bad_metric(
                at,
                format!(
                    "the tensor {:?} (xx, xy, xz, yy, yz, zz) is not positive definite",
                    t.to_array()
                ),
            ))
        }
    };
    let spd2 = |at: String, t: &Metric2| {
        if t.is_positive_definite() {
            Ok(())
        } else {
            Err(bad_metric(
                at,
                format!(
                    "the tensor [{}, {}, {}] (uu, uv, vv) is not positive definite",
                    t.xx, t.xy, t.yy
                ),
            ))
        }
    };
    let size = |at: String, h: f64| {
        if h.is_finite() && h > 0.0 {
            Ok(())
        } else {
            Err(bad_metric(
                at,
                format!("the size {h} is not a positive number"),
            ))
        }
    };
    match m {
        MetricField::Constant(t) => spd3("the constant tensor".into(), t),
        MetricField::Isotropic(SizeField::Constant(h)) => size("the constant size".into(), *h),
        MetricField::Isotropic(SizeField::Grid(g)) => {
            check_grid3(g)?;
            g.values
                .iter()
                .enumerate()
                .try_for_each(|(k, h)| size(format!("size sample {k}"), *h))
        }
        MetricField::Grid(g) => {
            check_grid3(g)?;
            g.values
                .iter()
                .enumerate()
                .try_for_each(|(k, t)| spd3(format!("tensor sample {k}"), t))
        }
        MetricField::ParameterGrid(g) => {
            check_grid2(g)?;
            g.values
                .iter()
                .enumerate()
                .try_for_each(|(k, t)| spd2(format!("tensor sample {k}"), t))
        }
        // Functions are checked wherever they are evaluated.
        MetricField::Isotropic(SizeField::Function(_))
        | MetricField::Function(_)
        | MetricField::ParameterFunction(_) => Ok(()),
    }
}

fn check_grid3<T>(g: &Grid3<T>) -> Result<(), CurvedError> {
    check_grid_frame(
        &g.counts,
        &g.min.to_array(),
        &g.max.to_array(),
        g.values.len(),
    )
}

fn check_grid2<T>(g: &Grid2<T>) -> Result<(), CurvedError> {
    check_grid_frame(
        &g.counts,
        &g.min.to_array(),
        &g.max.to_array(),
        g.values.len(),
    )
}
