//! Max-flow side by side in one run: katachi's Boykov–Kolmogorov (`katachi::rough`, seed 003
//! §3) and Boost.Graph 1.74's `boykov_kolmogorov_max_flow`, on the same networks: a 1M-node
//! 4-connected grid with segmentation-like terminal links, and the dual graph of a band of
//! 100k faces around a boss with noise (the graph Select Feature solves; spec §6 S1's
//! shape). Each side is timed for the max-flow alone: Boost inside the shim around its call on a graph built once (it resets
//! the residual capacities itself), katachi around `FlowNetwork::solve` on a clone made
//! before the clock starts (its time includes laying the arcs out, which Boost's excludes).
//!
//! `cargo bench -p katachi-reference --bench max_flow`; the ratio katachi / Boost is the figure.

use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, Criterion};
use katachi::rough::{band_graph, Band, FlowNetwork, SegmentOptions};
use katachi_reference::boost_bk_max_flow;
use katachi_reference::flow_graphs::{grid, to_reference, Rng};

// Each user takes part of it.
#[allow(dead_code)]
#[path = "../../support/boss.rs"]
mod boss;

fn networks() -> Vec<(&'static str, FlowNetwork)> {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    // A boss on a plate, 2,500 sectors, with 1 % noise; a random band 20 rows wide around its
    // foot: 100,000 band faces.
    let sizes = boss::BossSizes {
        sectors: 2500,
        plate_rows: 24,
        wall_rows: 24,
        top_rows: 4,
        ..Default::default()
    };
    let plate = boss::boss_plate(sizes, false);
    let mut brng = boss::Rng(9);
    let mesh = boss::with_noise(&plate.mesh, 0.0025, &mut brng);
    let band = boss::random_band(&plate, plate.foot, 20, &mut brng);
    assert_eq!(band.len(), 100_000);
    let g = band_graph(&mesh, &Band::new(band), &SegmentOptions::default()).unwrap();
    vec![
        ("grid 1000x1000", grid(1000, 1000, &mut rng, 1 << 16)),
        ("boss band 100k faces", g.network),
    ]
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("max_flow");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    for (name, net) in networks() {
        let reference = to_reference(&net);
        group.bench_function(format!("katachi/{name}"), |b| {
            b.iter_custom(|iters| {
                let mut total = Duration::ZERO;
                for _ in 0..iters {
                    let g = net.clone();
                    let t = Instant::now();
                    std::hint::black_box(g.solve());
                    total += t.elapsed();
                }
                total
            })
        });
        group.bench_function(format!("boost/{name}"), |b| {
            b.iter_custom(|iters| {
                let r = boost_bk_max_flow(&reference, iters as u32).unwrap();
                r.times.iter().sum()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
