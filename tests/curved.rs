//! Curved anisotropic meshing (seed 000, spec `curved_mesh.md` §7): validation, guarding,
//! refinement with the angle bound, curved elements, shared curves, determinism.

use std::collections::HashMap;

use glam::{DVec2, DVec3};
use katachi::curved::*;
use katachi::Error;

mod support;
use support::property::counted_proptest;

fn v2(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

fn flat_patch() -> BezierPatch {
    BezierPatch::bilinear(
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
    )
}

/// A bicubic patch with a bump: P(u, v) = (u, v, z) with non-trivial z.
fn bumpy_patch() -> BezierPatch {
    let mut pts = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            let (u, v) = (i as f64 / 3.0, j as f64 / 3.0);
            let z = if (1..3).contains(&i) && (1..3).contains(&j) {
                0.4
            } else {
                0.0
            };
            pts.push(DVec3::new(u, v, z + 0.1 * u * v));
        }
    }
    BezierPatch::new(3, 3, pts)
}

fn input(patch: BezierPatch, metric: MetricField) -> TrimmedPatches {
    TrimmedPatches {
        patches: vec![patch],
        curves: vec![],
        regions: vec![],
        metric,
    }
}

/// Four cubic quarter arcs of a circle, clockwise (a hole) or counter-clockwise.
fn circle(c: DVec2, r: f64, clockwise: bool) -> Vec<BezierCurve> {
    let k = 0.552_284_749_830_793_4;
    let e = if clockwise {
        [DVec2::X, -DVec2::Y, -DVec2::X, DVec2::Y]
    } else {
        [DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y]
    };
    let s = if clockwise { -1.0 } else { 1.0 };
    (0..4)
        .map(|i| {
            let (a, b) = (e[i], e[(i + 1) % 4]);
            BezierCurve::new(vec![
                c + r * a,
                c + r * (a + s * k * a.perp()),
                c + r * (b - s * k * b.perp()),
                c + r * b,
            ])
        })
        .collect()
}

fn add_loop(inp: &mut TrimmedPatches, region: usize, curves: Vec<BezierCurve>) {
    let first = inp.curves.len() as u32;
    let n = curves.len() as u32;
    inp.curves.extend(curves);
    let l = TrimLoop::new((0..n).map(|i| CurveUse::forward(first + i)).collect());
    if region == inp.regions.len() {
        inp.regions.push(Region {
            patch: PatchId(0),
            loops: vec![l],
        });
    } else {
        inp.regions[region].loops.push(l);
    }
}

fn square_with_circle_hole(metric: MetricField) -> TrimmedPatches {
    let mut inp = input(bumpy_patch(), metric);
    inp.add_polygon_region(0, &[v2(0.1, 0.1), v2(0.9, 0.1), v2(0.9, 0.9), v2(0.1, 0.9)]);
    add_loop(&mut inp, 0, circle(v2(0.5, 0.5), 0.2, true));
    inp
}

fn curved_error(r: katachi::Result<CurvedMesh>) -> CurvedError {
    match r {
        Err(Error::Curved(e)) => e,
        Err(e) => panic!("expected a curved-meshing error, got {e}"),
        Ok(_) => panic!("expected an error"),
    }
}

/// Checks the mesh invariants of spec §7.6–7.8: counter-clockwise corners, conforming
/// edges, boundary edges on the input curves, Euler characteristic and area per region,
/// valid Jacobians, curved-edge nodes on the input curves.
fn check_mesh(inp: &TrimmedPatches, m: &CurvedMesh) {
    let q = m.order;
    // Corners counter-clockwise, edges used once per direction.
    let mut uses: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for e in 0..m.element_count() {
        let n = m.element(e);
        let (a, b, c) = (
            m.nodes_uv[n[0] as usize],
            m.nodes_uv[n[1] as usize],
            m.nodes_uv[n[2] as usize],
        );
        if m.info[e].kind == ElementKind::Straight {
            assert!(
                (b - a).perp_dot(c - a) > 0.0,
                "element {e} is not counter-clockwise"
            );
        }
        for k in 0..3 {
            uses.entry((n[k], n[(k + 1) % 3])).or_default().push(e);
        }
        assert!(
            m.info[e].quality.scaled_jacobian > 0.0,
            "element {e} (order {q}) is inverted: {:?}",
            m.info[e]
        );
    }
    for (&(x, y), list) in &uses {
        assert_eq!(
            list.len(),
            1,
            "edge {x}→{y} is used {} times in one direction",
            list.len()
        );
        if !uses.contains_key(&(y, x)) {
            // A boundary edge: a curved element's edge 0, or on a straight input curve.
            let e = list[0];
            let n = m.element(e);
            let curved_edge = m.info[e].kind == ElementKind::Curved && n[0] == x && n[1] == y;
            let (a, b) = (m.nodes_uv[x as usize], m.nodes_uv[y as usize]);
            let on_line = inp.curves.iter().any(|c| {
                c.degree() == 1 && {
                    let (p, r) = (c.start(), c.end());
                    (r - p).perp_dot(a - p).abs() < 1e-12 && (r - p).perp_dot(b - p).abs() < 1e-12
                }
            });
            assert!(
                curved_edge || on_line,
                "boundary edge {x}→{y} ({a:?} → {b:?}) is on no input curve"
            );
        }
    }
    // Per region: Euler characteristic and area.
    for (r, region) in inp.regions.iter().enumerate() {
        let elems: Vec<usize> = (0..m.element_count())
            .filter(|&e| m.info[e].region.0 == r as u32)
            .collect();
        let mut verts = std::collections::HashSet::new();
        let mut edges = std::collections::HashSet::new();
        for &e in &elems {
            let n = m.element(e);
            for k in 0..3 {
                verts.insert(n[k]);
                let (a, b) = (n[k], n[(k + 1) % 3]);
                edges.insert((a.min(b), a.max(b)));
            }
        }
        let chi = verts.len() as i64 - edges.len() as i64 + elems.len() as i64;
        assert_eq!(
            chi,
            1 - (region.loops.len() as i64 - 1),
            "region {r}: V − E + F"
        );
        // Exact only when the elements reproduce the curves (order ≥ degree, spec §7.6).
        let max_degree = inp
            .curves
            .iter()
            .map(|c| c.degree() as u32)
            .max()
            .unwrap_or(1);
        if q >= max_degree {
            let area: f64 = elems.iter().map(|&e| m.element_area_uv(e)).sum();
            let exact = inp.region_area(RegionId(r as u32));
            assert!(
                ((area - exact) / exact).abs() < 1e-12,
                "region {r}: element areas {area} against {exact}"
            );
        }
    }
    // Curved edge nodes lie on the input curves (spec §7.8).
    for e in 0..m.element_count() {
        let Some(ce) = m.info[e].edge else { continue };
        let c = &inp.curves[ce.curve.idx()];
        let n = m.element(e);
        let edge: Vec<u32> = if q == 1 {
            vec![n[0], n[1]]
        } else {
            std::iter::once(n[0])
                .chain(n[3..3 + (q as usize - 1)].iter().copied())
                .chain([n[1]])
                .collect()
        };
        for (k, &node) in edge.iter().enumerate() {
            let s = k as f64 / q as f64;
            let s = if ce.reversed { 1.0 - s } else { s };
            let t = ce.t0 + s * (ce.t1 - ce.t0);
            let d = (m.nodes_uv[node as usize] - c.eval(t)).length();
            assert!(
                d < 1e-14,
                "element {e} node {k}: {d} from curve {} at t = {t}",
                ce.curve.0
            );
        }
    }
    // xyz is P(uv).
    for (i, uv) in m.nodes_uv.iter().enumerate() {
        let p = inp.patches[m.node_patch[i].idx()].eval(uv.x, uv.y);
        assert_eq!(p, m.nodes_xyz[i]);
    }
}

fn check_bound(m: &CurvedMesh) {
    let g = m.quality.guaranteed_angle_deg;
    for (e, info) in m.info.iter().enumerate() {
        if info.kind == ElementKind::Straight && !info.exempt {
            assert!(
                info.quality.min_angle_vertex >= g - 1e-9,
                "element {e}: {} < {g}",
                info.quality.min_angle_vertex
            );
        }
    }
    assert_eq!(m.stats.refine.unresolved, 0);
}

// ---- validation (spec §1) ----

#[test]
fn loop_not_closed_names_the_curves() {
    let mut inp = input(flat_patch(), MetricField::isotropic(0.2));
    inp.curves = vec![
        BezierCurve::line(v2(0.1, 0.1), v2(0.9, 0.1)),
        BezierCurve::line(v2(0.9, 0.1), v2(0.5, 0.9)),
        BezierCurve::line(v2(0.5, 0.9), v2(0.1, 0.100000001)),
    ];
    inp.regions.push(Region {
        patch: PatchId(0),
        loops: vec![TrimLoop::new((0..3).map(CurveUse::forward).collect())],
    });
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(
        matches!(
            e,
            CurvedError::LoopNotClosed {
                region: 0,
                loop_index: 0,
                position: 2,
                curve: 2,
                next_curve: 0,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("region 0, loop 0"));
}

#[test]
fn clockwise_outer_loop_is_rejected() {
    let mut inp = input(flat_patch(), MetricField::isotropic(0.2));
    inp.add_polygon_region(0, &[v2(0.1, 0.1), v2(0.1, 0.9), v2(0.9, 0.9)]);
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(
        matches!(
            e,
            CurvedError::LoopOrientation {
                region: 0,
                loop_index: 0,
                ..
            }
        ),
        "{e}"
    );
}

#[test]
fn singular_curve_is_rejected() {
    let mut inp = input(flat_patch(), MetricField::isotropic(0.2));
    inp.curves = vec![
        // A repeated first control point: c'(0) = 0.
        BezierCurve::new(vec![v2(0.1, 0.1), v2(0.1, 0.1), v2(0.9, 0.1)]),
        BezierCurve::line(v2(0.9, 0.1), v2(0.5, 0.9)),
        BezierCurve::line(v2(0.5, 0.9), v2(0.1, 0.1)),
    ];
    inp.regions.push(Region {
        patch: PatchId(0),
        loops: vec![TrimLoop::new((0..3).map(CurveUse::forward).collect())],
    });
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(
        matches!(e, CurvedError::SingularCurve { curve: 0, .. }),
        "{e}"
    );
}

#[test]
fn zero_angle_is_rejected() {
    let mut inp = input(flat_patch(), MetricField::isotropic(0.2));
    // Two quadratics leave (0.1, 0.5) both heading along +x.
    inp.curves = vec![
        BezierCurve::new(vec![v2(0.1, 0.5), v2(0.5, 0.5), v2(0.9, 0.2)]),
        BezierCurve::line(v2(0.9, 0.2), v2(0.9, 0.8)),
        BezierCurve::new(vec![v2(0.9, 0.8), v2(0.5, 0.5), v2(0.1, 0.5)]),
    ];
    inp.regions.push(Region {
        patch: PatchId(0),
        loops: vec![TrimLoop::new((0..3).map(CurveUse::forward).collect())],
    });
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(
        matches!(e, CurvedError::ZeroAngle { a: 0, b: 2, .. }),
        "{e}"
    );
}

#[test]
fn crossing_curves_are_rejected() {
    let mut inp = input(flat_patch(), MetricField::isotropic(0.2));
    // A bow tie: the two diagonals cross.
    inp.add_polygon_region(0, &[v2(0.1, 0.1), v2(0.9, 0.9), v2(0.9, 0.1), v2(0.1, 0.9)]);
    let r = mesh(&inp, &CurvedOptions::default());
    let e = curved_error(r);
    assert!(
        matches!(
            e,
            CurvedError::CurvesIntersect { .. } | CurvedError::LoopOrientation { .. }
        ),
        "{e}"
    );
    // A loop that crosses itself with the right orientation.
    let mut inp = input(flat_patch(), MetricField::isotropic(0.2));
    inp.add_polygon_region(
        0,
        &[
            v2(0.1, 0.1),
            v2(0.9, 0.1),
            v2(0.9, 0.9),
            v2(0.5, 0.05),
            v2(0.1, 0.9),
        ],
    );
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(matches!(e, CurvedError::CurvesIntersect { .. }), "{e}");
}

#[test]
fn private_copies_of_a_shared_curve_are_rejected() {
    let mut inp = input(flat_patch(), MetricField::isotropic(0.2));
    inp.add_polygon_region(0, &[v2(0.1, 0.1), v2(0.5, 0.1), v2(0.5, 0.9), v2(0.1, 0.9)]);
    inp.add_polygon_region(0, &[v2(0.5, 0.1), v2(0.9, 0.1), v2(0.9, 0.9), v2(0.5, 0.9)]);
    // Curves 1 (0.5,0.1)→(0.5,0.9) and 7 (0.5,0.9)→(0.5,0.1) are the same segment.
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(
        matches!(e, CurvedError::DuplicateCurve { a: 1, b: 7 }),
        "{e}"
    );
}

#[test]
fn bad_metrics_are_rejected() {
    let mut inp = input(
        flat_patch(),
        MetricField::Constant(Metric3::new(1.0, 2.0, 0.0, 1.0, 0.0, 1.0)),
    );
    inp.add_polygon_region(0, &[v2(0.1, 0.1), v2(0.9, 0.1), v2(0.5, 0.9)]);
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(matches!(e, CurvedError::InvalidMetric { .. }), "{e}");
    inp.metric = MetricField::isotropic(-1.0);
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(matches!(e, CurvedError::InvalidMetric { .. }), "{e}");
}

#[test]
fn degenerate_patch_is_rejected() {
    // The edge v = 1 collapses to a point; the region touches it.
    let patch = BezierPatch::bilinear(
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.5, 1.0, 0.0),
        DVec3::new(0.5, 1.0, 0.0),
    );
    let mut inp = input(patch, MetricField::isotropic(0.1));
    inp.add_polygon_region(0, &[v2(0.0, 0.0), v2(1.0, 0.0), v2(1.0, 1.0), v2(0.0, 1.0)]);
    let e = curved_error(mesh(&inp, &CurvedOptions::default()));
    assert!(
        matches!(e, CurvedError::DegenerateSurface { patch: 0, .. }),
        "{e}"
    );
    // Away from the collapsed edge it meshes.
    let mut inp = inp.clone();
    inp.curves.clear();
    inp.regions.clear();
    inp.add_polygon_region(0, &[v2(0.1, 0.1), v2(0.9, 0.1), v2(0.9, 0.6), v2(0.1, 0.6)]);
    let m = mesh(&inp, &CurvedOptions::default()).unwrap();
    check_mesh(&inp, &m);
}

#[test]
fn invalid_options_are_rejected() {
    let inp = square_with_circle_hole(MetricField::isotropic(0.1));
    let mut o = CurvedOptions::default();
    o.order = 0;
    assert!(matches!(
        mesh(&inp, &o),
        Err(Error::InvalidOption {
            option: "order",
            ..
        })
    ));
    let mut o = CurvedOptions::default();
    o.radius_edge_bound = 1.0;
    assert!(matches!(
        mesh(&inp, &o),
        Err(Error::InvalidOption {
            option: "radius_edge_bound",
            ..
        })
    ));
}

// ---- meshing ----

#[test]
fn square_with_a_circular_hole() {
    for order in 1..=3 {
        let inp = square_with_circle_hole(MetricField::isotropic(0.08));
        let m = mesh(&inp, &CurvedOptions::with_order(order)).unwrap();
        check_mesh(&inp, &m);
        check_bound(&m);
        assert!(
            m.quality.all_angles.median > 50.0,
            "{:?}",
            m.quality.all_angles
        );
        assert!(m.info.iter().any(|i| i.kind == ElementKind::Curved));
    }
}

#[test]
fn constant_anisotropic_metric() {
    let metric = MetricField::Constant(Metric3::from_direction(
        DVec3::new(1.0, 0.3, 0.0),
        0.2,
        0.02,
    ));
    let inp = square_with_circle_hole(metric);
    let m = mesh(&inp, &CurvedOptions::with_order(2)).unwrap();
    check_mesh(&inp, &m);
    check_bound(&m);
}

#[test]
fn two_regions_share_a_curve() {
    // A wavy cubic splits the square; the left region runs it upwards, the right downwards.
    let mut inp = input(bumpy_patch(), MetricField::isotropic(0.07));
    let wave = BezierCurve::new(vec![v2(0.5, 0.1), v2(0.3, 0.4), v2(0.7, 0.6), v2(0.5, 0.9)]);
    inp.curves = vec![
        BezierCurve::line(v2(0.1, 0.1), v2(0.5, 0.1)),
        wave,
        BezierCurve::line(v2(0.5, 0.9), v2(0.1, 0.9)),
        BezierCurve::line(v2(0.1, 0.9), v2(0.1, 0.1)),
        BezierCurve::line(v2(0.5, 0.1), v2(0.9, 0.1)),
        BezierCurve::line(v2(0.9, 0.1), v2(0.9, 0.9)),
        BezierCurve::line(v2(0.9, 0.9), v2(0.5, 0.9)),
    ];
    // The wave bulges left at the bottom and right at the top: left region is on its left.
    inp.regions.push(Region {
        patch: PatchId(0),
        loops: vec![TrimLoop::new(vec![
            CurveUse::forward(0),
            CurveUse::forward(1),
            CurveUse::forward(2),
            CurveUse::forward(3),
        ])],
    });
    inp.regions.push(Region {
        patch: PatchId(0),
        loops: vec![TrimLoop::new(vec![
            CurveUse::forward(4),
            CurveUse::forward(5),
            CurveUse::forward(6),
            CurveUse::backward(1),
        ])],
    });
    let m = mesh(&inp, &CurvedOptions::with_order(3)).unwrap();
    check_mesh(&inp, &m);
    check_bound(&m);
    // Along the wave, both sides use the same nodes: every curved edge on curve 1 has a twin
    // on the other side with the same nodes reversed.
    let mut left: HashMap<(u64, u64), Vec<u32>> = HashMap::new();
    let mut right: HashMap<(u64, u64), Vec<u32>> = HashMap::new();
    for e in 0..m.element_count() {
        let Some(ce) = m.info[e].edge else { continue };
        if ce.curve.0 != 1 {
            continue;
        }
        let n = m.element(e);
        let mut edge = vec![n[0]];
        edge.extend_from_slice(&n[3..5]);
        edge.push(n[1]);
        let key = (ce.t0.to_bits(), ce.t1.to_bits());
        if ce.reversed {
            edge.reverse();
            right.insert(key, edge);
        } else {
            left.insert(key, edge);
        }
    }
    assert!(!left.is_empty());
    assert_eq!(left, right, "the two sides of the shared curve differ");
    // The pieces of each curve tile [0, 1] exactly.
    for c in 0..inp.curves.len() as u32 {
        let mut spans: Vec<(f64, f64)> = m
            .info
            .iter()
            .filter_map(|i| i.edge)
            .filter(|ce| ce.curve.0 == c)
            .map(|ce| (ce.t0, ce.t1))
            .collect();
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        spans.dedup();
        if spans.is_empty() {
            continue;
        }
        assert_eq!(spans[0].0, 0.0);
        assert_eq!(spans.last().unwrap().1, 1.0);
        for w in spans.windows(2) {
            assert_eq!(w[0].1, w[1].0, "curve {c}: gap or overlap");
        }
    }
}

#[test]
fn same_bits_every_run_and_thread_count() {
    let inp = square_with_circle_hole(MetricField::isotropic(0.05));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| mesh(&inp, &CurvedOptions::with_order(3)).unwrap())
    };
    let a = run(1);
    let b = run(4);
    assert_eq!(a.elements, b.elements);
    assert_eq!(
        a.nodes_uv
            .iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits()])
            .collect::<Vec<_>>(),
        b.nodes_uv
            .iter()
            .map(|p| [p.x.to_bits(), p.y.to_bits()])
            .collect::<Vec<_>>()
    );
    assert_eq!(
        a.nodes_xyz
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect::<Vec<_>>(),
        b.nodes_xyz
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect::<Vec<_>>()
    );
}

#[test]
fn site_budget_is_a_typed_error() {
    let inp = square_with_circle_hole(MetricField::isotropic(0.001));
    let mut o = CurvedOptions::default();
    o.max_sites = Some(2000);
    let e = curved_error(mesh(&inp, &o));
    assert!(
        matches!(
            e,
            CurvedError::Budget {
                option: "max_sites",
                ..
            }
        ),
        "{e}"
    );
}

// ---- the angle bound over random metrics and domains (spec §7.10) ----

use proptest::prelude::*;

fn cases() -> u32 {
    std::env::var("KATACHI_CURVED_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(24)
}

/// A random star-shaped trim loop around (0.5, 0.5): `n` corners at radii in [0.25, 0.45],
/// each edge a line, quadratic or cubic bulging by up to a fifth of its length.
fn star_loop(
    n: usize,
    radii: &[f64],
    jitter: &[f64],
    kinds: &[u8],
    bulges: &[f64],
) -> Vec<BezierCurve> {
    let c = v2(0.5, 0.5);
    let pts: Vec<DVec2> = (0..n)
        .map(|i| {
            let a = (i as f64 + 0.4 * jitter[i]) / n as f64 * std::f64::consts::TAU;
            c + radii[i] * DVec2::new(a.cos(), a.sin())
        })
        .collect();
    (0..n)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            let normal = (b - a).perp() * bulges[i] * 0.2;
            match kinds[i] % 3 {
                0 => BezierCurve::line(a, b),
                1 => BezierCurve::new(vec![a, 0.5 * (a + b) + 2.0 * normal, b]),
                _ => BezierCurve::new(vec![
                    a,
                    a + (b - a) / 3.0 + 1.5 * normal,
                    a + 2.0 * (b - a) / 3.0 - 0.5 * normal,
                    b,
                ]),
            }
        })
        .collect()
}

#[derive(Debug, Clone)]
enum MetricKind {
    Isotropic(f64),
    Directional {
        h: f64,
        ratio: f64,
        dir: [f64; 3],
    },
    Rotating {
        h: f64,
        ratio: f64,
        start: f64,
        turn: f64,
    },
}

fn metric_of(k: &MetricKind) -> MetricField {
    match *k {
        MetricKind::Isotropic(h) => MetricField::isotropic(h),
        MetricKind::Directional { h, ratio, dir } => MetricField::Constant(
            Metric3::from_direction(DVec3::from_array(dir), h * ratio, h),
        ),
        MetricKind::Rotating {
            h,
            ratio,
            start,
            turn,
        } => {
            // Parameter space: the long axis turns by `turn` (at most π/2) across the square.
            MetricField::ParameterFunction(std::sync::Arc::new(move |p: DVec2| {
                let a = start + turn * 0.5 * (p.x + p.y);
                Metric2::from_axes(DVec2::new(a.cos(), a.sin()), h * ratio, h)
            }))
        }
    }
}

fn metric_strategy() -> impl Strategy<Value = MetricKind> {
    prop_oneof![
        (0.04f64..0.1).prop_map(MetricKind::Isotropic),
        (
            0.015f64..0.05,
            1.0f64..10.0,
            prop::array::uniform3(-1.0f64..1.0)
        )
            .prop_filter("a direction", |(_, _, d)| DVec3::from_array(*d).length()
                > 0.1)
            .prop_map(|(h, ratio, dir)| MetricKind::Directional { h, ratio, dir }),
        (
            0.015f64..0.05,
            1.0f64..5.0,
            0.0f64..3.2,
            0.0f64..std::f64::consts::FRAC_PI_2
        )
            .prop_map(|(h, ratio, start, turn)| MetricKind::Rotating {
                h,
                ratio,
                start,
                turn
            }),
    ]
}

counted_proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    /// Every straight, non-exempt triangle has all its angles ≥ arcsin(1/4) in the metric
    /// of each of its vertices, and the mesh is valid, on random trimmed patches and
    /// metrics; inputs the validator rejects must be rejected with a typed error.
    #[test]
    fn angle_bound_on_random_inputs(
        n in 3usize..8,
        radii in prop::collection::vec(0.25f64..0.45, 8),
        jitter in prop::collection::vec(-1.0f64..1.0, 8),
        kinds in prop::collection::vec(0u8..3, 8),
        bulges in prop::collection::vec(-1.0f64..1.0, 8),
        hole in prop::option::of(0.04f64..0.1),
        bump in 0.0f64..0.6,
        metric in metric_strategy(),
        order in 1u32..=3,
    ) {
        let mut pts = Vec::new();
        for i in 0..4 {
            for j in 0..4 {
                let (u, v) = (i as f64 / 3.0, j as f64 / 3.0);
                let z = if (1..3).contains(&i) && (1..3).contains(&j) { bump } else { 0.0 };
                pts.push(DVec3::new(u, v, z));
            }
        }
        let mut inp = input(BezierPatch::new(3, 3, pts), metric_of(&metric));
        let outer = star_loop(n, &radii, &jitter, &kinds, &bulges);
        // A hole only where it clears every edge and its bulge (a valid input).
        let clear = |r: f64| outer.iter().all(|c| {
            let (a, b) = (c.start(), c.end());
            let d = (b - a).perp_dot(v2(0.5, 0.5) - a) / (b - a).length();
            d > r + 0.3 * (b - a).length()
        });
        add_loop(&mut inp, 0, outer.clone());
        if let Some(r) = hole.filter(|&r| clear(r)) {
            add_loop(&mut inp, 0, circle(v2(0.5, 0.5), r, true));
        }
        match mesh(&inp, &CurvedOptions::with_order(order)) {
            Ok(m) => {
                check_mesh(&inp, &m);
                check_bound(&m);
                prop_assert!(m.quality.all_angles.median > 45.0, "{:?}", m.quality.all_angles);
            }
            Err(Error::Curved(CurvedError::CurvesIntersect { .. })) => {}
            Err(e) => prop_assert!(false, "{e}"),
        }
    }
}
