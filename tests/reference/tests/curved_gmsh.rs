//! Curved meshing (seed 000) against Gmsh 4.8 (spec §7.8, §7.12): Gmsh reads every MSH file
//! katachi writes, at every order and in both spaces, finds every element valid by its own
//! Jacobian check (`AnalyseMeshQuality`), and the curved edges' nodes it reads are points of
//! the input curves.

use std::collections::HashMap;

use glam::{DVec2, DVec3};
use katachi::curved::{
    mesh, BezierCurve, BezierPatch, CurveUse, CurvedMesh, CurvedOptions, ElementKind, Metric3,
    MetricField, PatchId, Region, Space, TrimLoop, TrimmedPatches,
};
use katachi_reference::gmsh::read_and_check_msh;

fn v2(x: f64, y: f64) -> DVec2 {
    DVec2::new(x, y)
}

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

/// The spec's cases (§7.10): a square with a circular hole (isotropic), the same with a
/// 10:1 metric, two regions glued along a wavy cubic, and a region bounded by quadratics
/// and a cubic S-curve.
fn cases() -> Vec<(&'static str, TrimmedPatches)> {
    let base = |metric: MetricField| TrimmedPatches {
        patches: vec![bumpy_patch()],
        curves: vec![],
        regions: vec![],
        metric,
    };
    let mut out = Vec::new();
    for (name, metric) in [
        ("hole, isotropic", MetricField::isotropic(0.07)),
        (
            "hole, 10:1",
            MetricField::Constant(Metric3::from_direction(
                DVec3::new(1.0, 0.3, 0.0),
                0.25,
                0.025,
            )),
        ),
    ] {
        let mut inp = base(metric);
        inp.add_polygon_region(0, &[v2(0.1, 0.1), v2(0.9, 0.1), v2(0.9, 0.9), v2(0.1, 0.9)]);
        let first = inp.curves.len() as u32;
        inp.curves.extend(circle(v2(0.5, 0.5), 0.2, true));
        inp.regions[0].loops.push(TrimLoop::new(
            (0..4).map(|i| CurveUse::forward(first + i)).collect(),
        ));
        out.push((name, inp));
    }
    let mut inp = base(MetricField::isotropic(0.06));
    inp.curves = vec![
        BezierCurve::line(v2(0.1, 0.1), v2(0.5, 0.1)),
        BezierCurve::new(vec![v2(0.5, 0.1), v2(0.3, 0.4), v2(0.7, 0.6), v2(0.5, 0.9)]),
        BezierCurve::line(v2(0.5, 0.9), v2(0.1, 0.9)),
        BezierCurve::line(v2(0.1, 0.9), v2(0.1, 0.1)),
        BezierCurve::line(v2(0.5, 0.1), v2(0.9, 0.1)),
        BezierCurve::line(v2(0.9, 0.1), v2(0.9, 0.9)),
        BezierCurve::line(v2(0.9, 0.9), v2(0.5, 0.9)),
    ];
    inp.regions = vec![
        Region {
            patch: PatchId(0),
            loops: vec![TrimLoop::new((0..4).map(CurveUse::forward).collect())],
        },
        Region {
            patch: PatchId(0),
            loops: vec![TrimLoop::new(vec![
                CurveUse::forward(4),
                CurveUse::forward(5),
                CurveUse::forward(6),
                CurveUse::backward(1),
            ])],
        },
    ];
    out.push(("two regions", inp));
    let mut inp = base(MetricField::isotropic(0.05));
    inp.curves = vec![
        BezierCurve::new(vec![v2(0.15, 0.2), v2(0.5, 0.05), v2(0.85, 0.2)]),
        BezierCurve::new(vec![v2(0.85, 0.2), v2(0.95, 0.5), v2(0.85, 0.8)]),
        // A cubic S.
        BezierCurve::new(vec![
            v2(0.85, 0.8),
            v2(0.6, 1.0),
            v2(0.4, 0.6),
            v2(0.15, 0.8),
        ]),
        BezierCurve::new(vec![v2(0.15, 0.8), v2(0.05, 0.5), v2(0.15, 0.2)]),
    ];
    inp.regions = vec![Region {
        patch: PatchId(0),
        loops: vec![TrimLoop::new((0..4).map(CurveUse::forward).collect())],
    }];
    out.push(("quadratics and an S", inp));
    out
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("katachi-gmsh-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Gmsh reads the file back: same elements and nodes (bit for bit), every element valid.
fn check_with_gmsh(name: &str, m: &CurvedMesh, space: Space) {
    let path = tmp(&format!(
        "{}-{}-{:?}.msh",
        name.replace([' ', ',', ':'], "_"),
        m.order,
        space
    ));
    m.write(&path, space).unwrap();
    let g = read_and_check_msh(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    let ty = katachi::curved::gmsh_triangle_type(m.order).unwrap() as i32;
    let total: usize = g.elements.iter().map(|(_, t, _)| t.len()).sum();
    assert_eq!(total, m.element_count(), "{name}: element count");
    assert!(
        g.elements.iter().all(|(t, _, _)| *t == ty),
        "{name}: element types"
    );
    for (tags, coords) in g.node_tags.iter().zip(&g.node_coords) {
        let mine = match space {
            Space::Surface => m.nodes_xyz[tags - 1],
            Space::Parameter => m.nodes_uv[tags - 1].extend(0.0),
        };
        assert_eq!(mine.to_array(), *coords, "{name}: node {tags}");
    }
    // Element nodes as Gmsh read them.
    let n = m.nodes_per_element();
    for (_, tags, nodes) in &g.elements {
        for (k, &e) in tags.iter().enumerate() {
            let theirs: Vec<u32> = nodes[k * n..(k + 1) * n]
                .iter()
                .map(|&t| t as u32 - 1)
                .collect();
            assert_eq!(theirs, m.element(e - 1), "{name}: element {e}");
        }
    }
    assert_eq!(
        g.min_over_max_jacobian.len(),
        m.element_count(),
        "{name}: Jacobians"
    );
    let invalid: Vec<(usize, f64)> = g
        .min_over_max_jacobian
        .iter()
        .copied()
        .filter(|&(_, j)| j.is_nan() || j <= 0.0)
        .collect();
    assert!(
        invalid.is_empty(),
        "{name}, order {}, {space:?}: Gmsh finds {} elements invalid, the first (tag, minJ/maxJ) {:?}",
        m.order,
        invalid.len(),
        invalid.first()
    );
    // katachi's own measure of Gmsh's surface check agrees.
    assert!(
        m.quality.min_scaled_jacobian_surface > 0.0,
        "{name}, order {}: katachi reports an element invalid on the surface ({})",
        m.order,
        m.quality.min_scaled_jacobian_surface
    );
}

#[test]
fn gmsh_reads_every_order_and_finds_every_element_valid() {
    for (name, inp) in cases() {
        for order in 1..=3 {
            let m = mesh(&inp, &CurvedOptions::with_order(order))
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            for space in [Space::Parameter, Space::Surface] {
                check_with_gmsh(name, &m, space);
            }
        }
    }
}

/// Spec §7.8: the curved edges' nodes, as Gmsh reads them in parameter space, are points of
/// the input curves, `c(t0 + s (t1 − t0))` to 1e-14; the pieces of each curve tile [0, 1].
#[test]
fn edge_nodes_read_by_gmsh_lie_on_the_input_curves() {
    for (name, inp) in cases() {
        let m = mesh(&inp, &CurvedOptions::with_order(3)).unwrap();
        let path = tmp(&format!("edges-{}.msh", name.replace([' ', ',', ':'], "_")));
        m.write(&path, Space::Parameter).unwrap();
        let g = read_and_check_msh(&path).unwrap();
        let coord: HashMap<usize, [f64; 3]> = g
            .node_tags
            .iter()
            .copied()
            .zip(g.node_coords.iter().copied())
            .collect();
        let mut checked = 0;
        for (_, tags, nodes) in &g.elements {
            for (k, &e) in tags.iter().enumerate() {
                let info = &m.info[e - 1];
                let Some(ce) = info.edge else { continue };
                assert_eq!(info.kind, ElementKind::Curved);
                let c = &inp.curves[ce.curve.idx()];
                let el = &nodes[k * 10..(k + 1) * 10];
                // Edge 0: corner 0, nodes 3 and 4, corner 1.
                for (j, &node) in [el[0], el[3], el[4], el[1]].iter().enumerate() {
                    let s = j as f64 / 3.0;
                    let s = if ce.reversed { 1.0 - s } else { s };
                    let t = ce.t0 + s * (ce.t1 - ce.t0);
                    let p = coord[&node];
                    let d = (DVec2::new(p[0], p[1]) - c.eval(t)).length();
                    assert!(
                        d < 1e-14,
                        "{name}: element {e}, edge node {j}: {d} off curve {}",
                        ce.curve
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 0, "{name}: no curved elements");
    }
}
