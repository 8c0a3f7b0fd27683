//! katachi's Boykov–Kolmogorov max-flow (`katachi::rough::FlowNetwork`, seed 003 §3) against
//! Boost.Graph's `boykov_kolmogorov_max_flow` on the same graphs: the same flow value and the
//! same minimum-cut labels (the minimal source side, which every maximum flow shares).
//!
//! Graphs: random 4-connected grids with vision-like terminal links, random sparse graphs, and
//! the dual graphs of bands on the bundled models (`band_graphs_on_models` below).

use std::path::Path;

use katachi::rough::{band_graph, Band, FlowNetwork, SegmentOptions};
use katachi::{DVec3, FaceId, PolyMesh};
use katachi_reference::boost_bk_max_flow;
use katachi_reference::flow_graphs::{grid, to_reference, Rng};

// Each user takes part of it.
#[allow(dead_code)]
#[path = "../../support/boss.rs"]
mod boss;

/// Solves `net` with both and checks they agree; returns the flow.
fn agree(net: FlowNetwork, what: &str) -> i64 {
    let reference = boost_bk_max_flow(&to_reference(&net), 1).unwrap_or_else(|e| panic!("{e}"));
    let direct = net.direct_flow();
    let ours = net.solve();
    assert_eq!(ours.flow, reference.flow + direct, "{what}: flow");
    let differ: Vec<usize> = (0..ours.source_side.len())
        .filter(|&i| ours.source_side[i] != reference.source_side[i])
        .collect();
    assert!(
        differ.is_empty(),
        "{what}: {} nodes labelled differently, first {:?}",
        differ.len(),
        &differ[..differ.len().min(10)]
    );
    ours.flow
}

#[test]
fn random_grids_agree_with_boost() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for case in 0..60 {
        let (w, h) = (2 + rng.below(60) as u32, 2 + rng.below(60) as u32);
        let max_cap = [2, 10, 1000, 1 << 20][case % 4];
        let net = grid(w, h, &mut rng, max_cap);
        agree(
            net,
            &format!("grid case {case} ({w} x {h}, capacities < {max_cap})"),
        );
    }
}

#[test]
fn random_sparse_graphs_agree_with_boost() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for case in 0..200 {
        let n = 2 + rng.below(300) as u32;
        let mut g = FlowNetwork::new(n);
        for i in 0..n {
            let (s, t) = (rng.below(3) * rng.below(50), rng.below(3) * rng.below(50));
            g.add_terminal(i, s as i64, t as i64).unwrap();
        }
        for _ in 0..rng.below(4 * n as u64) {
            let (a, b) = (rng.below(n as u64) as u32, rng.below(n as u64) as u32);
            if a != b {
                g.add_edge(a, b, rng.below(30) as i64, rng.below(30) as i64)
                    .unwrap();
            }
        }
        agree(g, &format!("sparse case {case} ({n} nodes)"));
    }
}

#[test]
fn a_large_grid_agrees_with_boost() {
    let mut rng = Rng(7);
    let flow = agree(grid(400, 400, &mut rng, 1 << 20), "400 x 400 grid");
    assert!(flow > 0);
}

/// The faces whose centroid lies in a slab across the middle of the mesh along `axis`, a
/// tenth of its extent wide: a band around most closed shapes.
fn slab_band(mesh: &PolyMesh, axis: usize) -> Vec<FaceId> {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let (mid, half) = (0.5 * (lo[axis] + hi[axis]), 0.05 * (hi[axis] - lo[axis]));
    mesh.faces()
        .filter(|&f| {
            let outer = mesh.face_outer(f);
            let c: DVec3 =
                outer.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / outer.len() as f64;
            (c[axis] - mid).abs() <= half
        })
        .collect()
}

#[test]
fn band_graphs_on_models_agree_with_boost() {
    // The networks segmentation solves: slab bands across the bundled models, and random
    // bands around the boss of spec S1 (with noise, so capacities vary).
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/models");
    let mut solved = 0;
    for name in [
        "fandisk.off",
        "greek_helmet.obj",
        "spot_quadrangulated.obj",
        "trim-star.off",
    ] {
        let mesh = katachi::io::read(&dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        for axis in 0..3 {
            let band = Band::new(slab_band(&mesh, axis));
            match band_graph(&mesh, &band, &SegmentOptions::default()) {
                Ok(g) => {
                    agree(g.network, &format!("{name}, slab band on axis {axis}"));
                    solved += 1;
                }
                // A slab that does not separate the shape (its two sides meet elsewhere).
                Err(katachi::Error::Rough(e)) => eprintln!("{name}, axis {axis}: {e}"),
                Err(e) => panic!("{name}: {e}"),
            }
        }
    }
    let plate = boss::boss_plate(boss::BossSizes::default(), false);
    let mut rng = boss::Rng(5);
    for case in 0..20 {
        let mesh = boss::with_noise(&plate.mesh, 0.01, &mut rng);
        let band = boss::random_band(&plate, plate.foot, 3 + case % 8, &mut rng);
        let g = band_graph(&mesh, &Band::new(band), &SegmentOptions::default()).unwrap();
        agree(g.network, &format!("boss band {case}"));
        solved += 1;
    }
    assert!(solved >= 30, "only {solved} band graphs solved");
}
