//! Mesh benchmarks: building half-edge connectivity for a 1M-face quad mesh.
//! Goal (issue 2): ≥ 20M half-edges/s on one core. Criterion reports the throughput.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use katachi::mesh::{inspect, shapes};

fn connectivity(c: &mut Criterion) {
    let mesh = shapes::torus(1000, 1000, 2.0, 0.5).unwrap();
    let halfedges = mesh.connectivity().unwrap().halfedge_count();
    let mut g = c.benchmark_group("connectivity");
    g.sample_size(20);
    g.throughput(Throughput::Elements(halfedges as u64));
    g.bench_function("torus 1000x1000 quads (4M half-edges)", |b| {
        b.iter(|| mesh.connectivity().unwrap())
    });
    g.finish();
    let mut g = c.benchmark_group("inspect");
    g.sample_size(10);
    g.bench_function("torus 1000x1000 quads", |b| {
        b.iter(|| inspect(&mesh).unwrap())
    });
    g.finish();
}

criterion_group!(benches, connectivity);
criterion_main!(benches);
