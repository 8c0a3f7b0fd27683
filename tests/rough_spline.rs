//! B-spline surfaces and their fitting (`katachi::rough::{BSplineSurface, fit_points,
//! fit_surface}`, seed 003 §4, spec `rough_model.md` §2 and §6 F1–F2): basis identities and
//! derivatives, exact recovery of a known bicubic, parameter correction, knot insertion, the
//! fit of a mesh region, typed errors.

mod support;

use katachi::error::RoughError;
use katachi::mesh::{shapes, FaceId};
use katachi::rough::{fit_points, fit_surface, BSplineSurface, FitOptions, Knots};
use katachi::{DVec3, Error};
use proptest::prelude::*;
use support::boss::{boss_plate, BossSizes, Rng};
use support::property::counted_proptest;

/// A bicubic surface over [0, 1]² with a 6 × 6 net: x, y on a grid, random heights.
fn known_surface(rng: &mut Rng) -> BSplineSurface {
    let (ku, kv) = (Knots::uniform(3, 6).unwrap(), Knots::uniform(3, 6).unwrap());
    let mut net = Vec::new();
    for k in 0..6 {
        for l in 0..6 {
            net.push(DVec3::new(k as f64, l as f64, 2.0 * rng.unit() - 1.0));
        }
    }
    BSplineSurface::new(ku, kv, net).unwrap()
}

fn samples(s: &BSplineSurface, count: usize, rng: &mut Rng) -> (Vec<DVec3>, Vec<[f64; 2]>) {
    let params: Vec<[f64; 2]> = (0..count).map(|_| [rng.unit(), rng.unit()]).collect();
    (params.iter().map(|p| s.point(p[0], p[1])).collect(), params)
}

#[test]
fn a_known_bicubic_is_recovered_exactly_without_smoothing() {
    // F1: 2,000 random samples, the true parameters, β = 0.
    let mut rng = Rng(0xf1);
    let truth = known_surface(&mut rng);
    let (points, params) = samples(&truth, 2000, &mut rng);
    let mut options = FitOptions::default();
    options.net = (6, 6);
    options.smoothing = 0.0;
    options.correction_rounds = 0;
    let fit = fit_points(&points, &params, &options).unwrap();
    assert!(fit.max < 1e-10, "max residual {}", fit.max);
    for (a, b) in fit
        .surface
        .control_points()
        .iter()
        .zip(truth.control_points())
    {
        assert!(a.distance(*b) < 1e-10, "control point {a} vs {b}");
    }
    // And with parameter correction on, the exact parameters stay put.
    options.correction_rounds = 3;
    let again = fit_points(&points, &params, &options).unwrap();
    assert!(again.max < 1e-10, "max residual {}", again.max);
}

#[test]
fn parameter_correction_lowers_the_error_of_a_perturbed_start_tenfold() {
    // F1: perturbed parameters; within 5 rounds of correction the RMS falls ≥ 10×.
    let mut rng = Rng(0xf2);
    let truth = known_surface(&mut rng);
    let (points, exact) = samples(&truth, 2000, &mut rng);
    let params: Vec<[f64; 2]> = exact
        .iter()
        .map(|p| {
            [
                (p[0] + 0.01 * rng.normal()).clamp(0.0, 1.0),
                (p[1] + 0.01 * rng.normal()).clamp(0.0, 1.0),
            ]
        })
        .collect();
    let mut options = FitOptions::default();
    options.net = (6, 6);
    options.smoothing = 0.0;
    options.correction_rounds = 5;
    let fit = fit_points(&points, &params, &options).unwrap();
    let h = &fit.rms_history;
    assert!(h.len() >= 2 && h.len() <= 6, "{h:?}");
    assert!(
        *h.last().unwrap() * 10.0 <= h[0],
        "RMS {} → {} ({h:?})",
        h[0],
        h.last().unwrap()
    );
}

#[test]
fn knots_are_inserted_until_a_half_cylinder_is_within_tolerance() {
    // F2: a half-cylinder of radius 10 (length 1), tolerance 0.02, starting from a 4 × 4 net.
    let mut rng = Rng(0xf3);
    let (r, len) = (10.0, 1.0);
    let mut points = Vec::new();
    let mut params = Vec::new();
    for _ in 0..3000 {
        let (a, b) = (rng.unit(), rng.unit());
        let t = std::f64::consts::PI * a;
        points.push(DVec3::new(r * t.cos(), len * b, r * t.sin()));
        params.push([a, b]);
    }
    let mut options = FitOptions::default();
    options.net = (4, 4);
    options.tolerance = Some(0.02);
    let fit = fit_points(&points, &params, &options).unwrap();
    let (nu, nv) = fit.surface.net_size();
    assert!(nu > 4, "no knot inserted in u");
    assert!(
        fit.rms <= 0.02 && fit.max <= 0.02,
        "rms {} max {} with {nu} × {nv}",
        fit.rms,
        fit.max
    );
    // Without insertion the 4 × 4 net is far off.
    options.tolerance = None;
    let coarse = fit_points(&points, &params, &options).unwrap();
    assert!(coarse.max > 0.02, "max {}", coarse.max);
}

#[test]
fn smoothing_flattens_noise() {
    // Noisy samples of a plane: the smoothed fit is closer to the plane than the data.
    let mut rng = Rng(0xf4);
    let mut points = Vec::new();
    let mut params = Vec::new();
    for _ in 0..1000 {
        let (u, v) = (rng.unit(), rng.unit());
        points.push(DVec3::new(u, v, 0.01 * rng.normal()));
        params.push([u, v]);
    }
    let z_of = |fit: &katachi::rough::SurfaceFit| {
        (0..=20)
            .flat_map(|i| (0..=20).map(move |j| (i as f64 / 20.0, j as f64 / 20.0)))
            .map(|(u, v)| fit.surface.point(u, v).z.abs())
            .fold(0.0, f64::max)
    };
    let mut options = FitOptions::default();
    options.correction_rounds = 0;
    options.smoothing = 0.0;
    let rough = fit_points(&points, &params, &options).unwrap();
    options.smoothing = 1.0;
    let smooth = fit_points(&points, &params, &options).unwrap();
    assert!(
        z_of(&smooth) < 0.5 * z_of(&rough),
        "{} vs {}",
        z_of(&smooth),
        z_of(&rough)
    );
}

#[test]
fn a_plate_region_fits_its_plane() {
    // The plate of spec S1 around its boss: the base surface is the plane z = 0.
    let plate = boss_plate(BossSizes::default(), false);
    let region: Vec<FaceId> = (0..plate.mesh.face_count())
        .map(FaceId)
        .filter(|&f| plate.row_of(f) < plate.foot)
        .collect();
    let fit = fit_surface(&plate.mesh, &region, &FitOptions::default()).unwrap();
    assert!(fit.max < 1e-9, "max {}", fit.max);
    for p in fit.surface.control_points() {
        assert!(p.z.abs() < 1e-9, "control point {p}");
    }
    for i in 0..=10 {
        let e = fit.surface.evaluate(i as f64 / 10.0, 0.3);
        assert!(e.point.z.abs() < 1e-9);
        assert!(fit.surface.normal(i as f64 / 10.0, 0.3).z.abs() > 1.0 - 1e-9);
    }
}

#[test]
fn bad_regions_and_options_are_typed_errors() {
    let cube = shapes::cube(1.0).unwrap();
    let all: Vec<FaceId> = cube.faces().collect();
    let mut options = FitOptions::default();
    options.net = (4, 4);
    // Folds over any plane (and too few points anyway: checked after the fold).
    assert!(matches!(
        fit_surface(&cube, &all, &options),
        Err(Error::Rough(RoughError::RegionFolds { .. }))
    ));
    let grid = shapes::grid(4, 4).unwrap();
    let all: Vec<FaceId> = grid.faces().collect();
    assert!(matches!(
        fit_surface(&grid, &all, &FitOptions::default()),
        Err(Error::Rough(RoughError::RegionTooSmall { points: 25, .. }))
    ));
    assert!(matches!(
        fit_surface(&grid, &[FaceId(16)], &options),
        Err(Error::Rough(RoughError::FaceOutOfRange { face: 16, .. }))
    ));
    options.smoothing = -1.0;
    assert!(matches!(
        fit_surface(&grid, &all, &options),
        Err(Error::InvalidOption {
            option: "smoothing",
            ..
        })
    ));
    // Without smoothing, a net with a control point no sample reaches is singular.
    let points: Vec<DVec3> = (0..200)
        .map(|i| DVec3::new(i as f64 * 0.001, 0.0, 0.0))
        .collect();
    let params: Vec<[f64; 2]> = (0..200).map(|i| [i as f64 * 0.001, 0.0]).collect();
    let mut options = FitOptions::default();
    options.net = (4, 4);
    options.smoothing = 0.0;
    assert!(matches!(
        fit_points(&points, &params, &options),
        Err(Error::Rough(RoughError::FitSingular { .. }))
    ));
}

counted_proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn basis_sums_to_one_and_derivatives_match_differences(
        extra in prop::collection::vec(0.01..0.99f64, 0..6),
        degree in 1usize..=5,
        u in 0.0..1.0f64,
        heights in prop::collection::vec(-1.0..1.0f64, 100),
    ) {
        let mut interior = extra.clone();
        interior.sort_by(f64::total_cmp);
        interior.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
        let ku = Knots::clamped(degree, interior).unwrap();
        let kv = Knots::uniform(3, 5).unwrap();
        let n = ku.count() * kv.count();
        prop_assume!(n <= heights.len());
        let net: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new((i / kv.count()) as f64, (i % kv.count()) as f64, heights[i]))
            .collect();
        let s = BSplineSurface::new(ku.clone(), kv, net).unwrap();
        // Partition of unity: a surface whose net is all one point is that point.
        let one = BSplineSurface::new(ku, s.knots_v().clone(), vec![DVec3::ONE; n]).unwrap();
        prop_assert!(one.point(u, 0.4).distance(DVec3::ONE) < 1e-12);
        // First and second derivatives against central differences, away from the knots.
        let t = s.knots_u().as_slice();
        let h = 1e-5;
        prop_assume!(t.iter().all(|k| (k - u).abs() > 3.0 * h));
        let e = s.evaluate(u, 0.4);
        let (a, b) = (s.evaluate(u + h, 0.4), s.evaluate(u - h, 0.4));
        prop_assert!((e.du - (a.point - b.point) / (2.0 * h)).length() < 1e-5 * (1.0 + e.du.length()));
        prop_assert!((e.duu - (a.du - b.du) / (2.0 * h)).length() < 1e-4 * (1.0 + e.duu.length()));
        let (c, d) = (s.evaluate(u, 0.4 + h), s.evaluate(u, 0.4 - h));
        prop_assert!((e.duv - (c.du - d.du) / (2.0 * h)).length() < 1e-4 * (1.0 + e.duv.length()));
        prop_assert!((e.dvv - (c.dv - d.dv) / (2.0 * h)).length() < 1e-4 * (1.0 + e.dvv.length()));
    }
}
