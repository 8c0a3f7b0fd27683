use glam::{DVec2, DVec3};
use katachi::curved::*;

fn arg<T: std::str::FromStr>(i: usize, d: T) -> T {
    std::env::args()
        .nth(i)
        .and_then(|s| s.parse().ok())
        .unwrap_or(d)
}

fn main() {
    let h: f64 = arg(1, 0.1);
    let steps: u64 = arg(2, 10_000_000);
    let case: String = arg(3, "square".to_string());
    let aniso: f64 = arg(4, 1.0);
    let patch = if case.starts_with("bump") {
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
    } else {
        BezierPatch::bilinear(
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
        )
    };
    let metric = if aniso == 1.0 {
        MetricField::isotropic(h)
    } else {
        MetricField::Constant(Metric3::from_direction(
            DVec3::new(1.0, 0.3, 0.0),
            h * aniso,
            h,
        ))
    };
    let mut input = TrimmedPatches {
        patches: vec![patch],
        curves: vec![],
        regions: vec![],
        metric,
    };
    input.add_polygon_region(
        0,
        &[
            DVec2::new(0.1, 0.1),
            DVec2::new(0.9, 0.1),
            DVec2::new(0.9, 0.9),
            DVec2::new(0.1, 0.9),
        ],
    );
    if case.ends_with("hole") {
        // A circular hole of 4 cubic arcs, clockwise.
        let k = 0.552_284_749_830_793_4;
        let c = DVec2::new(0.5, 0.5);
        let r = 0.2;
        let e = [DVec2::X, -DVec2::Y, -DVec2::X, DVec2::Y];
        let first = input.curves.len() as u32;
        for i in 0..4 {
            let (a, b) = (e[i], e[(i + 1) % 4]);
            input.curves.push(BezierCurve::new(vec![
                c + r * a,
                c + r * (a - k * a.perp()),
                c + r * (b + k * b.perp()),
                c + r * b,
            ]));
        }
        input.regions[0].loops.push(TrimLoop::new(
            (0..4).map(|i| CurveUse::forward(first + i)).collect(),
        ));
    }
    let mut o = CurvedOptions::with_order(2);
    o.max_steps = Some(steps);
    o.sampled_quality = false;
    let t = std::time::Instant::now();
    let out = mesh(&input, &o);
    match out {
        Ok(m) => {
            println!(
                "{} elements in {:?}; {:?}",
                m.element_count(),
                t.elapsed(),
                m.stats
            );
            let q = &m.quality;
            println!("straight min (vertex metrics) {:.3} median {:.2}; all-angle median {:.2} mean {:.2} max {:.2}; curved min {:.3}; exempt {}; jac {:.3}",
                q.straight_min_vertex.min, q.straight_min_vertex.median, q.straight_angles.median, q.straight_angles.mean, q.straight_angles.max,
                q.curved_angles.min, q.exempt.count, q.min_scaled_jacobian);
        }
        Err(e) => println!("error: {e}"),
    }
}
