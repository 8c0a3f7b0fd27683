//! Catmull-Clark side by side in one run: katachi (one thread and all cores), OpenSubdiv 3.5 (Far refiner +
//! PrimvarRefinerReal<double>, one thread) and OpenMesh 9, levels 1-3, on a 200 × 160 quad
//! torus (32k quads) and beast.obj. The reference libraries are timed inside the shim (their
//! own work only, not the freeing of their refiners); katachi is timed for the whole call,
//! input to output mesh, not the freeing of that mesh. Both free their results between
//! iterations.
//!
//! "katachi C ABI" is what a C caller does to get the result: `katachi_subdivide`, then the
//! positions and faces copied into its own buffers (`katachi_subdivision_copy_positions`,
//! `_copy_faces`), timed against the kernel call alone (`catmull_clark`, whose output mesh is
//! the same arrays): the goal is at most 1.3× the kernel.
//! Peak memory is measured per library in fresh processes (`peak_rss`) and printed.

use std::time::{Duration, Instant};

// The test models and the record (tests/support), shared with the root crate's tests.
#[allow(dead_code)]
#[path = "../../support/models.rs"]
mod models;
#[allow(dead_code)]
#[path = "../../support/record.rs"]
mod record;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use katachi::mesh::shapes;
use katachi::subdivide::{catmull_clark, SubdivideOptions};
use katachi::PolyMesh;
use katachi_reference as r;

fn to_ref(mesh: &PolyMesh) -> r::RefMesh {
    r::RefMesh {
        positions: mesh.positions().iter().map(|p| p.to_array()).collect(),
        face_sizes: mesh
            .faces()
            .map(|f| mesh.face_outer(f).len() as u32)
            .collect(),
        face_vertices: mesh.corners().iter().map(|v| v.0).collect(),
    }
}

/// Times one `catmull_clark` per iteration; its result is freed after the clock stops and
/// before the next iteration, as the shim frees OpenSubdiv's refiner and buffers.
fn timed(b: &mut criterion::Bencher, mesh: &PolyMesh, o: &SubdivideOptions) {
    b.iter_batched(
        || (),
        |()| catmull_clark(mesh, o).unwrap(),
        criterion::BatchSize::PerIteration,
    )
}

/// The C caller's path: subdivide through the C ABI, copy positions and faces out, free the
/// result (outside the clock, as the kernel's mesh is freed outside it).
fn c_abi(b: &mut criterion::Bencher, mesh: Handle, levels: u32) {
    use katachi::ffi::*;
    let mesh = mesh.0.cast_const();
    b.iter_custom(|iters| {
        let mut total = Duration::ZERO;
        for _ in 0..iters {
            // SAFETY: `mesh` is a live handle; every buffer holds the counts given.
            unsafe {
                let t = Instant::now();
                let mut o = katachi_subdivide_options_default();
                o.levels = levels;
                let mut s = std::ptr::null_mut();
                assert_eq!(katachi_subdivide(mesh, &o, &mut s), KatachiStatus::Ok);
                let mut info = katachi_subdivision_info_default();
                assert_eq!(katachi_subdivision_info(s, &mut info), KatachiStatus::Ok);
                let mut positions = vec![0.0f64; 3 * info.vertex_count as usize];
                let mut loop_sizes = vec![0u32; info.loop_count as usize];
                let mut face_loops = vec![0u32; info.face_count as usize];
                let mut corners = vec![0u32; info.corner_count as usize];
                assert_eq!(
                    katachi_subdivision_copy_positions(s, positions.as_mut_ptr(), positions.len()),
                    KatachiStatus::Ok
                );
                assert_eq!(
                    katachi_subdivision_copy_faces(
                        s,
                        loop_sizes.as_mut_ptr(),
                        loop_sizes.len(),
                        face_loops.as_mut_ptr(),
                        face_loops.len(),
                        corners.as_mut_ptr(),
                        corners.len(),
                    ),
                    KatachiStatus::Ok
                );
                total += t.elapsed();
                katachi_subdivision_free(s);
                drop((positions, loop_sizes, face_loops, corners));
            }
        }
        total
    })
}

/// A C mesh handle the benchmark only reads (katachi's meshes may be read from several
/// threads at once: the header's promise).
#[derive(Clone, Copy)]
struct Handle(*mut katachi::ffi::KatachiMesh);
// SAFETY: only read, never changed or freed while in use (see above).
unsafe impl Send for Handle {}
unsafe impl Sync for Handle {}

/// `mesh` as a C handle.
fn handle(mesh: &PolyMesh) -> Handle {
    use katachi::ffi::*;
    let positions: Vec<f64> = mesh.positions().iter().flat_map(|p| p.to_array()).collect();
    let loop_sizes: Vec<u32> = mesh
        .loop_offsets()
        .windows(2)
        .map(|w| w[1] - w[0])
        .collect();
    let face_loops: Vec<u32> = mesh
        .face_loop_offsets()
        .windows(2)
        .map(|w| w[1] - w[0])
        .collect();
    let corners: Vec<u32> = mesh.corners().iter().map(|v| v.0).collect();
    let mut out = std::ptr::null_mut();
    // SAFETY: the arrays hold the counts given.
    let status = unsafe {
        katachi_mesh_create(
            positions.as_ptr(),
            mesh.vertex_count(),
            loop_sizes.as_ptr(),
            loop_sizes.len() as u32,
            face_loops.as_ptr(),
            face_loops.len() as u32,
            corners.as_ptr(),
            corners.len() as u32,
            &mut out,
        )
    };
    assert_eq!(status, KatachiStatus::Ok);
    Handle(out)
}

fn models() -> Vec<(&'static str, String, PolyMesh)> {
    let mut v = vec![(
        "torus 200x160",
        "torus".to_string(),
        shapes::torus(200, 160, 2.0, 0.5).unwrap(),
    )];
    // beast.obj is in the corpus only (its license does not allow bundling it).
    match models::corpus_models("subdivide bench", &["beast.obj"]) {
        Some(paths) => {
            let m = katachi::io::read(&paths[0]).unwrap_or_else(|e| panic!("{e}"));
            v.push(("beast.obj", paths[0].to_string_lossy().into_owned(), m));
        }
        None => eprintln!("beast.obj not benchmarked: no corpus (set KATACHI_CORPUS)"),
    }
    v
}

fn subdivide(c: &mut Criterion) {
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for (name, _, mesh) in models() {
        let rm = to_ref(&mesh);
        let c_mesh = handle(&mesh);
        let mut g = c.benchmark_group(format!("catmull-clark {name}"));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(500));
        g.measurement_time(Duration::from_secs(3));
        for level in 1..=3u32 {
            let o = SubdivideOptions::with_levels(level);
            g.bench_with_input(
                BenchmarkId::new("katachi 1 thread", level),
                &level,
                |b, _| one_thread.install(|| timed(b, &mesh, &o)),
            );
            g.bench_with_input(
                BenchmarkId::new("katachi C ABI 1 thread", level),
                &level,
                |b, &l| one_thread.install(|| c_abi(b, c_mesh, l)),
            );
            g.bench_with_input(
                BenchmarkId::new("katachi all cores", level),
                &level,
                |b, _| timed(b, &mesh, &o),
            );
            g.bench_with_input(
                BenchmarkId::new("katachi C ABI all cores", level),
                &level,
                |b, &l| c_abi(b, c_mesh, l),
            );
            g.bench_with_input(BenchmarkId::new("opensubdiv", level), &level, |b, &l| {
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        let (_, t) = r::osd_catmark_timed(
                            &rm,
                            &r::Creases::default(),
                            &r::OsdOptions::default(),
                            l,
                        )
                        .unwrap();
                        total += t.total();
                    }
                    total
                })
            });
            if level <= 2 || mesh.face_count() < 40_000 {
                g.bench_with_input(BenchmarkId::new("openmesh", level), &level, |b, &l| {
                    b.iter_custom(|iters| {
                        let mut total = Duration::ZERO;
                        for _ in 0..iters {
                            let (_, t) = r::openmesh_catmull_clark_timed(&rm, l).unwrap();
                            total += t.total();
                        }
                        total
                    })
                });
            }
        }
        g.finish();
        // SAFETY: made by `handle`, freed once.
        unsafe { katachi::ffi::katachi_mesh_free(c_mesh.0) };
    }
}

/// Peak resident memory of each library at level 3, each in a fresh process.
fn peak_memory(_c: &mut Criterion) {
    let exe = env!("CARGO_BIN_EXE_peak_rss");
    println!("\npeak memory (fresh process each; KiB before the call / peak after; time)");
    for (name, arg, _) in models() {
        for lib in ["katachi", "opensubdiv", "openmesh"] {
            let t = Instant::now();
            let out = std::process::Command::new(exe)
                .args([lib, &arg, "3"])
                .output();
            match out {
                Ok(o) if o.status.success() => {
                    let s = String::from_utf8_lossy(&o.stdout);
                    let f: Vec<&str> = s.split_whitespace().collect();
                    if f.len() == 5 {
                        println!(
                            "  {name:14} L3 {lib:10} faces {:>8}  peak {:>7} MiB (before {:>5} MiB)  {:>7.1} ms",
                            f[1],
                            f[3].parse::<u64>().unwrap_or(0) / 1024,
                            f[2].parse::<u64>().unwrap_or(0) / 1024,
                            f[4].parse::<f64>().unwrap_or(0.0)
                        );
                    }
                }
                Ok(o) => println!(
                    "  {name} {lib}: failed: {}",
                    String::from_utf8_lossy(&o.stderr)
                ),
                Err(e) => println!("  {name} {lib}: cannot run: {e} ({:?})", t.elapsed()),
            }
        }
    }
}

criterion_group!(benches, subdivide, peak_memory);
criterion_main!(benches);
