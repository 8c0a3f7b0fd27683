//! File I/O benchmarks: reading a 1M-face binary PLY, side by side with `std::fs::read`
//! of the same file, so the ratio is measured in one run on one machine.
//! Goal (issue 2): PLY reading ≤ 3× the time of reading the file's bytes into memory.
//!
//! The file (a 1000 × 1000 quad torus, double coordinates, ~41 MB) is written once into a
//! temporary directory at start and removed at the end.

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use katachi::io::{self, ply, Format, PlyEncoding, WriteOptions};
use katachi::mesh::shapes;

fn read_ply(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("katachi-bench-io-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path: PathBuf = dir.join("torus-1m.ply");
    let mesh = shapes::torus(1000, 1000, 2.0, 0.5).unwrap();
    io::write_with(
        &path,
        &mesh,
        &WriteOptions::with_ply_encoding(PlyEncoding::BinaryLittleEndian),
    )
    .unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(io::read(&path).unwrap().face_count(), 1_000_000);

    let mut g = c.benchmark_group("read 1M-face binary PLY");
    g.sample_size(20);
    g.measurement_time(std::time::Duration::from_secs(8));
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("std::fs::read (bytes only)", |b| {
        b.iter(|| std::fs::read(&path).unwrap())
    });
    g.bench_function("katachi::io::read (file to PolyMesh)", |b| {
        b.iter(|| io::read(&path).unwrap())
    });
    g.bench_function("ply::read_bytes (in memory to PolyMesh)", |b| {
        b.iter(|| ply::read_bytes(&bytes, &path).unwrap())
    });
    g.finish();

    let mut g = c.benchmark_group("write 1M-face mesh");
    g.sample_size(10);
    g.measurement_time(std::time::Duration::from_secs(8));
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("binary PLY to memory", |b| {
        b.iter(|| {
            let mut out = Vec::with_capacity(bytes.len());
            io::write_to(&mut out, Format::Ply, &mesh, &WriteOptions::default()).unwrap();
            out
        })
    });
    g.finish();

    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, read_ply);
criterion_main!(benches);
