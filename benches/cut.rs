//! Stroke cut (seed 002, issue 5): the cut's time against the floor, one projection pass over
//! all vertices (view-projection, divide, viewport into a screen array kept between runs), and
//! against a clone of the mesh (the cost of any function returning a new mesh), in one run;
//! the floor also written with AVX-512 or AVX2 as the cut's vertex pass is ("floor4"); and `cut_edits`,
//! the same cut returned as edits (no new mesh built).
//! Goal: ≤ 3 × the floor on 1M triangles with a 50-point stroke. Meshes: triangulated tori of
//! 10k, 100k and 1M triangles, and the shared `spot_quadrangulated.obj` subdivided 4 times and
//! triangulated (1.5M triangles). Both modes; all cores (the machine has 2). A table of
//! medians over interleaved rounds, and ratios, is printed at the end: warm (each call right
//! after the same call) and cold (right after the caches were evicted). `cut_edits` over the
//! floor is given twice: as the ratio of the medians, and as the median of each round's ratio
//! (floor and cut measured moments apart, so a drift of the machine's speed between rounds,
//! ±25% here, cancels). Then `cut long stroke`: spirals of 25k to 200k points over the
//! chamfer cube, to show the cut grows linearly with the stroke's length (issue 34).

use std::time::{Duration, Instant};

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use glam::DVec2;
use katachi::cut::{cut_by_stroke, cut_edits, CutMode, CutOptions, Stroke, View};
use katachi::mesh::shapes;
use katachi::PolyMesh;
use rayon::prelude::*;

#[path = "../tests/cut_meshes/mod.rs"]
mod cut_meshes;
use cut_meshes::{bench_stroke, bench_view, project_all, spot_l4, triangulate_quads};

fn meshes() -> Vec<(String, PolyMesh)> {
    let mut v: Vec<(String, PolyMesh)> = [(71u32, "10k"), (224, "100k"), (707, "1M")]
        .iter()
        .map(|&(n, name)| {
            let m = triangulate_quads(&shapes::torus(n, n, 2.0, 0.7).unwrap());
            (format!("torus {name} ({} tris)", m.face_count()), m)
        })
        .collect();
    match spot_l4() {
        Ok(t) => v.push((format!("spot L4 ({} tris)", t.face_count()), t)),
        Err(e) => eprintln!("spot not benchmarked: {e}"),
    }
    v
}

/// The floor written the way the cut's vertex pass is: eight vertices at a time with AVX-512,
/// or four with AVX2 (on CPUs without them, the plain floor), so the cut is also measured
/// against a projection pass as hand-tuned as its own.
fn project_all_simd(mesh: &PolyMesh, view: &View, out: &mut Vec<DVec2>) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        let wide = std::arch::is_x86_feature_detected!("avx512f");
        let ps = mesh.positions();
        out.clear();
        out.reserve(ps.len());
        out.spare_capacity_mut()[..ps.len()]
            .par_chunks_mut(1 << 14)
            .zip(ps.par_chunks(1 << 14))
            // SAFETY: AVX2 (and AVX-512 F for the wide path) checked; the chunks have equal
            // lengths.
            .for_each(|(o, p)| unsafe {
                if wide {
                    let done = simd::project8(view, p, o);
                    simd::project(view, &p[done..], &mut o[done..]);
                } else {
                    simd::project(view, p, o);
                }
            });
        // SAFETY: every element was written.
        unsafe { out.set_len(ps.len()) };
        return;
    }
    project_all(mesh, view, out)
}

#[cfg(target_arch = "x86_64")]
mod simd {
    use std::arch::x86_64::*;
    use std::mem::MaybeUninit;

    use glam::{DVec2, DVec3, DVec4};
    use katachi::cut::View;

    /// Asks for `lines` cache lines 4.5 KiB past `p`, as the cut's vertex pass does.
    #[inline(always)]
    fn ahead(p: *const f64, lines: usize) {
        for k in 0..lines {
            // SAFETY: a prefetch has no effect on memory; the address is never dereferenced.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(576 + 8 * k) as *const i8) };
        }
    }

    /// [`project`] eight at a time with AVX-512 F on the first `8·(len / 8)` points; returns
    /// how many it did.
    #[target_feature(enable = "avx512f,avx2")]
    pub unsafe fn project8(view: &View, ps: &[DVec3], out: &mut [MaybeUninit<DVec2>]) -> usize {
        let (vp, v) = (view.view_proj, view.viewport);
        let b = |x: f64| _mm512_set1_pd(x);
        let row = |r: DVec4| (b(r.x), b(r.y), b(r.z), b(r.w));
        let (rx, ry, rw) = (row(vp.row(0)), row(vp.row(1)), row(vp.row(3)));
        let (one, half) = (b(1.0), b(0.5));
        let (x0, y0, sw, sh) = (b(v[0]), b(v[1]), b(v[2]), b(v[3]));
        let pick = |a: [i64; 8]| _mm512_setr_epi64(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]);
        let (ax, ay, az) = (
            pick([0, 3, 6, 9, 12, 15, 0, 0]),
            pick([1, 4, 7, 10, 13, 0, 0, 0]),
            pick([2, 5, 8, 11, 14, 0, 0, 0]),
        );
        let (bx, by, bz) = (
            pick([0, 1, 2, 3, 4, 5, 10, 13]),
            pick([0, 1, 2, 3, 4, 8, 11, 14]),
            pick([0, 1, 2, 3, 4, 9, 12, 15]),
        );
        // Screen x and y interleaved: lanes 0..8 from sx, 8..16 from sy.
        let (lo, hi) = (
            pick([0, 8, 1, 9, 2, 10, 3, 11]),
            pick([4, 12, 5, 13, 6, 14, 7, 15]),
        );
        let n8 = ps.len() / 8;
        let src = ps.as_ptr() as *const f64;
        let dst = out.as_mut_ptr() as *mut f64;
        for i in 0..n8 {
            let p = src.add(24 * i);
            ahead(p, 3);
            let (v0, v1, v2) = (
                _mm512_loadu_pd(p),
                _mm512_loadu_pd(p.add(8)),
                _mm512_loadu_pd(p.add(16)),
            );
            let x = _mm512_permutex2var_pd(_mm512_permutex2var_pd(v0, ax, v1), bx, v2);
            let y = _mm512_permutex2var_pd(_mm512_permutex2var_pd(v0, ay, v1), by, v2);
            let z = _mm512_permutex2var_pd(_mm512_permutex2var_pd(v0, az, v1), bz, v2);
            let dot = |r: (__m512d, __m512d, __m512d, __m512d)| {
                _mm512_add_pd(
                    _mm512_add_pd(
                        _mm512_add_pd(_mm512_mul_pd(r.0, x), _mm512_mul_pd(r.1, y)),
                        _mm512_mul_pd(r.2, z),
                    ),
                    r.3,
                )
            };
            let inv = _mm512_div_pd(one, dot(rw));
            let sx = _mm512_add_pd(
                x0,
                _mm512_mul_pd(
                    _mm512_mul_pd(_mm512_add_pd(_mm512_mul_pd(dot(rx), inv), one), half),
                    sw,
                ),
            );
            let sy = _mm512_add_pd(
                y0,
                _mm512_mul_pd(
                    _mm512_mul_pd(_mm512_sub_pd(one, _mm512_mul_pd(dot(ry), inv)), half),
                    sh,
                ),
            );
            let q = dst.add(16 * i);
            _mm512_storeu_pd(q, _mm512_permutex2var_pd(sx, lo, sy));
            _mm512_storeu_pd(q.add(8), _mm512_permutex2var_pd(sx, hi, sy));
        }
        8 * n8
    }

    /// `out[i]` = screen position of `ps[i]`, as `project_all` computes it.
    #[target_feature(enable = "avx2")]
    pub unsafe fn project(view: &View, ps: &[DVec3], out: &mut [MaybeUninit<DVec2>]) {
        let (vp, v) = (view.view_proj, view.viewport);
        let b = |x: f64| _mm256_set1_pd(x);
        let row = |r: DVec4| (b(r.x), b(r.y), b(r.z), b(r.w));
        let (rx, ry, rw) = (row(vp.row(0)), row(vp.row(1)), row(vp.row(3)));
        let (one, half) = (b(1.0), b(0.5));
        let (x0, y0, sw, sh) = (b(v[0]), b(v[1]), b(v[2]), b(v[3]));
        let n4 = ps.len() / 4;
        let src = ps.as_ptr() as *const f64;
        let dst = out.as_mut_ptr() as *mut f64;
        for i in 0..n4 {
            let p = src.add(12 * i);
            ahead(p, 2);
            let (v0, v1, v2) = (
                _mm256_loadu_pd(p),
                _mm256_loadu_pd(p.add(4)),
                _mm256_loadu_pd(p.add(8)),
            );
            let xy = _mm256_permute2f128_pd::<0x30>(v0, v1);
            let zx = _mm256_permute2f128_pd::<0x21>(v0, v2);
            let yz = _mm256_permute2f128_pd::<0x30>(v1, v2);
            let x = _mm256_blend_pd::<0b1010>(xy, zx);
            let y = _mm256_shuffle_pd::<0b0101>(xy, yz);
            let z = _mm256_blend_pd::<0b1010>(zx, yz);
            let dot = |r: (__m256d, __m256d, __m256d, __m256d)| {
                _mm256_add_pd(
                    _mm256_add_pd(
                        _mm256_add_pd(_mm256_mul_pd(r.0, x), _mm256_mul_pd(r.1, y)),
                        _mm256_mul_pd(r.2, z),
                    ),
                    r.3,
                )
            };
            let inv = _mm256_div_pd(one, dot(rw));
            let sx = _mm256_add_pd(
                x0,
                _mm256_mul_pd(
                    _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(dot(rx), inv), one), half),
                    sw,
                ),
            );
            let sy = _mm256_add_pd(
                y0,
                _mm256_mul_pd(
                    _mm256_mul_pd(_mm256_sub_pd(one, _mm256_mul_pd(dot(ry), inv)), half),
                    sh,
                ),
            );
            let lo = _mm256_unpacklo_pd(sx, sy);
            let hi = _mm256_unpackhi_pd(sx, sy);
            let q = dst.add(8 * i);
            _mm256_storeu_pd(q, _mm256_permute2f128_pd::<0x20>(lo, hi));
            _mm256_storeu_pd(q.add(4), _mm256_permute2f128_pd::<0x31>(lo, hi));
        }
        for i in 4 * n4..ps.len() {
            let c = vp * ps[i].extend(1.0);
            let inv = 1.0 / c.w;
            out[i].write(DVec2::new(
                v[0] + (c.x * inv + 1.0) * 0.5 * v[2],
                v[1] + (1.0 - c.y * inv) * 0.5 * v[3],
            ));
        }
    }
}

/// Rounds of the side-by-side measurement: each is one timed call of every kind, so their
/// medians need many (with 9, one run's two ratios of the same calls differed by a tenth).
const ROUNDS: usize = 25;

fn time(f: impl FnOnce()) -> Duration {
    let s = Instant::now();
    f();
    s.elapsed()
}

fn median(mut t: Vec<Duration>) -> Duration {
    t.sort();
    t[t.len() / 2]
}

fn cut(c: &mut Criterion) {
    let s = bench_stroke();
    let mut table = Vec::new();
    let mut evict = Evictor::new();
    for (name, mesh) in meshes() {
        let view = bench_view(&mesh);
        let mut g = c.benchmark_group(format!("cut {name}"));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(300));
        g.measurement_time(Duration::from_secs(2));
        g.bench_function("floor: project all vertices", |b| {
            let mut out = Vec::new();
            b.iter(|| project_all(&mesh, &view, &mut out))
        });
        g.bench_function("floor, SIMD: project all vertices", |b| {
            let mut out = Vec::new();
            b.iter(|| project_all_simd(&mesh, &view, &mut out))
        });
        g.bench_function("clone the mesh", |b| {
            b.iter_with_large_drop(|| mesh.clone())
        });
        for mode in [CutMode::VisibleOnly, CutMode::ThroughAll] {
            let o = CutOptions::with_mode(mode);
            g.bench_with_input(BenchmarkId::new("cut", format!("{mode:?}")), &o, |b, o| {
                b.iter_with_large_drop(|| cut_by_stroke(&mesh, &s, &view, o).unwrap())
            });
            g.bench_with_input(
                BenchmarkId::new("cut_edits", format!("{mode:?}")),
                &o,
                |b, o| b.iter_with_large_drop(|| cut_edits(&mesh, &s, &view, o).unwrap()),
            );
        }
        g.finish();
        // Side by side for the ratios: every measurement once per round, medians over the
        // rounds (this machine's speed drifts; interleaving keeps the ratios fair).
        let (mut plain, mut fast) = (Vec::new(), Vec::new());
        project_all(&mesh, &view, &mut plain);
        project_all_simd(&mesh, &view, &mut fast);
        let worst = plain
            .iter()
            .zip(&fast)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-6,
            "the SIMD floor projects elsewhere ({worst} px)"
        );
        let modes = [CutMode::VisibleOnly, CutMode::ThroughAll];
        let opts = modes.map(CutOptions::with_mode);
        // Warm: each call timed right after the same call untimed (steady state, as criterion
        // measures it), so no call pays for the caches its predecessor in the round filled
        // with something else (a new mesh evicts the input). Cold: right after the caches
        // were evicted, as a one-off call on a mesh the host has not touched lately.
        let mut warm: Vec<Vec<Duration>> = vec![Vec::new(); 3 + 2 * modes.len()];
        let mut cold: Vec<Vec<Duration>> = vec![Vec::new(); 1 + modes.len()];
        for _ in 0..ROUNDS {
            let twice = |f: &mut dyn FnMut()| {
                f();
                time(f)
            };
            warm[0].push(twice(&mut || {
                project_all(&mesh, &view, &mut plain);
                std::hint::black_box(&plain);
            }));
            warm[1].push(twice(&mut || {
                project_all_simd(&mesh, &view, &mut fast);
                std::hint::black_box(&fast);
            }));
            warm[2].push(twice(&mut || drop(std::hint::black_box(mesh.clone()))));
            for (k, o) in opts.iter().enumerate() {
                warm[3 + 2 * k].push(twice(&mut || {
                    drop(std::hint::black_box(
                        cut_by_stroke(&mesh, &s, &view, o).unwrap(),
                    ))
                }));
                warm[4 + 2 * k].push(twice(&mut || {
                    drop(std::hint::black_box(
                        cut_edits(&mesh, &s, &view, o).unwrap(),
                    ))
                }));
            }
            evict.run();
            cold[0].push(time(|| {
                project_all(&mesh, &view, &mut plain);
                std::hint::black_box(&plain);
            }));
            for (k, o) in opts.iter().enumerate() {
                evict.run();
                cold[1 + k].push(time(|| {
                    drop(std::hint::black_box(
                        cut_edits(&mesh, &s, &view, o).unwrap(),
                    ))
                }));
            }
        }
        // Each round's edits over the same round's floor, measured moments apart: steadier
        // than the ratio of medians while the machine's speed drifts between rounds.
        let per_round = |k: usize| {
            let mut r: Vec<f64> = warm[4 + 2 * k]
                .iter()
                .zip(&warm[0])
                .map(|(e, f)| e.as_secs_f64() / f.as_secs_f64())
                .collect();
            r.sort_by(f64::total_cmp);
            r[r.len() / 2]
        };
        let round_ratio: Vec<f64> = (0..modes.len()).map(per_round).collect();
        let m: Vec<Duration> = warm.into_iter().map(median).collect();
        let c: Vec<Duration> = cold.into_iter().map(median).collect();
        for (k, (mode, o)) in modes.iter().zip(&opts).enumerate() {
            let out = cut_by_stroke(&mesh, &s, &view, o).unwrap();
            table.push(Row {
                name: name.clone(),
                mode: format!("{mode:?}"),
                floor: m[0],
                floor4: m[1],
                clone: m[2],
                cut: m[3 + 2 * k],
                edits: m[4 + 2 * k],
                cold_floor: c[0],
                cold_edits: c[1 + k],
                edits_per_floor_by_round: round_ratio[k],
                new_faces: out.report.new_faces,
                paths: out.report.paths.len(),
            });
        }
    }
    eprintln!("\nstroke cut, 50-point stroke, medians of {ROUNDS} interleaved rounds (all cores):");
    eprintln!(
        "(floor: one projection pass; floor4: the same with AVX-512 or AVX2, as the cut's vertex pass is \
         written; clone: PolyMesh::clone, what any new output costs; warm: each call right after \
         the same call; cold: right after evicting the caches; by round: the median of each \
         round's edits over the same round's floor)"
    );
    eprintln!(
        "{:<28} {:<12} {:>9} {:>9} {:>9} {:>9} {:>7} {:>8} {:>9} {:>7} {:>9} {:>8} {:>10} {:>10} {:>6} {:>9} {:>6}",
        "mesh",
        "mode",
        "floor",
        "floor4",
        "clone",
        "cut",
        "/floor",
        "/clone",
        "edits",
        "/floor",
        "by round",
        "/floor4",
        "cold floor",
        "cold edits",
        "/floor",
        "new faces",
        "paths"
    );
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    for r in table {
        eprintln!(
            "{:<28} {:<12} {:>7.2}ms {:>7.2}ms {:>7.2}ms {:>7.2}ms {:>6.1}x {:>7.1}x {:>7.2}ms {:>6.2}x {:>8.2}x {:>7.1}x {:>8.2}ms {:>8.2}ms {:>5.2}x {:>9} {:>6}",
            r.name,
            r.mode,
            ms(r.floor),
            ms(r.floor4),
            ms(r.clone),
            ms(r.cut),
            ms(r.cut) / ms(r.floor),
            ms(r.cut) / ms(r.clone),
            ms(r.edits),
            ms(r.edits) / ms(r.floor),
            r.edits_per_floor_by_round,
            ms(r.edits) / ms(r.floor4),
            ms(r.cold_floor),
            ms(r.cold_edits),
            ms(r.cold_edits) / ms(r.cold_floor),
            r.new_faces,
            r.paths
        );
    }
}

/// One line of the table (medians).
struct Row {
    name: String,
    mode: String,
    floor: Duration,
    floor4: Duration,
    clone: Duration,
    cut: Duration,
    edits: Duration,
    cold_floor: Duration,
    cold_edits: Duration,
    /// The median over rounds of edits / floor within each round.
    edits_per_floor_by_round: f64,
    new_faces: u32,
    paths: usize,
}

/// Evicts the caches by writing a buffer larger than the last-level cache of the machines
/// this runs on (32 MiB here).
struct Evictor {
    buf: Vec<u64>,
    round: u64,
}

impl Evictor {
    fn new() -> Self {
        Evictor {
            buf: vec![0; 16 << 20],
            round: 0,
        }
    }

    fn run(&mut self) {
        self.round += 1;
        let r = self.round;
        self.buf
            .par_chunks_mut(1 << 16)
            .for_each(|c| c.iter_mut().for_each(|x| *x = x.wrapping_add(r)));
        std::hint::black_box(&self.buf);
    }
}

/// An Archimedean spiral of `n` points about `c`, `step` pixels apart along it and `gap`
/// pixels between turns: a stroke that never crosses itself, as long as one likes.
fn spiral(n: usize, c: DVec2, step: f64, gap: f64) -> Stroke {
    let k = gap / std::f64::consts::TAU;
    let mut t: f64 = std::f64::consts::TAU;
    Stroke::new(
        (0..n)
            .map(|_| {
                let r = k * t;
                let p = c + DVec2::new(t.cos(), t.sin()) * r;
                t += step / (r * r + k * k).sqrt();
                p
            })
            .collect(),
    )
}

/// Issue 34: a 200,000-point stroke over the 26-face chamfer cube took 27 s (every pair of
/// segments was tested for crossing). The cut of spirals of 25k to 200k points (2.5 px
/// apart, turns 4 px apart, centred on the cube in a 400 × 400 view), through all sheets:
/// linear means each size's time over the 25k one's is about the ratio of their lengths.
fn long_strokes(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/models/chamfer-cube.off"
    );
    let cube = katachi::io::read(std::path::Path::new(path)).unwrap();
    let cube = triangulate_any(&cube);
    let vp = glam::DMat4::orthographic_rh_gl(-1.6, 1.6, -1.6, 1.6, 0.1, 20.0)
        * glam::DMat4::look_at_rh(
            glam::DVec3::splat(5.0 / 3f64.sqrt()),
            glam::DVec3::ZERO,
            glam::DVec3::Y,
        );
    let view = View::new(vp, [0.0, 0.0, 400.0, 400.0]);
    let o = CutOptions::with_mode(CutMode::ThroughAll);
    let sizes = [25_000usize, 50_000, 100_000, 200_000];
    let strokes: Vec<Stroke> = sizes
        .iter()
        .map(|&n| spiral(n, DVec2::new(200.0, 200.0), 2.5, 4.0))
        .collect();
    let mut g = c.benchmark_group("cut long stroke");
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(300));
    g.measurement_time(Duration::from_secs(2));
    for (n, s) in sizes.iter().zip(&strokes) {
        g.bench_with_input(BenchmarkId::new("cut_edits", n), s, |b, s| {
            b.iter_with_large_drop(|| cut_edits(&cube, s, &view, &o).unwrap())
        });
    }
    g.finish();
    // Side by side: every size once per round, medians over the rounds.
    let mut t: Vec<Vec<Duration>> = vec![Vec::new(); sizes.len()];
    for _ in 0..LONG_ROUNDS {
        for (k, s) in strokes.iter().enumerate() {
            t[k].push(time(|| {
                drop(std::hint::black_box(
                    cut_edits(&cube, s, &view, &o).unwrap(),
                ))
            }));
        }
    }
    let m: Vec<Duration> = t.into_iter().map(median).collect();
    eprintln!(
        "\nstroke cut of the chamfer cube ({} triangles) along spirals, through all, medians of {LONG_ROUNDS} interleaved rounds:",
        cube.face_count()
    );
    eprintln!(
        "{:>9} {:>10} {:>12} {:>16}",
        "points", "cut_edits", "per point", "over 25k (len ×)"
    );
    for (k, n) in sizes.iter().enumerate() {
        eprintln!(
            "{:>9} {:>8.2}ms {:>10.1}ns {:>9.2}x ({}x)",
            n,
            m[k].as_secs_f64() * 1e3,
            m[k].as_secs_f64() * 1e9 / *n as f64,
            m[k].as_secs_f64() / m[0].as_secs_f64(),
            n / sizes[0]
        );
    }
}

const LONG_ROUNDS: usize = 9;

/// Triangles of any mesh: each polygon fanned from its first corner (the chamfer cube's
/// faces are convex).
fn triangulate_any(m: &PolyMesh) -> PolyMesh {
    let faces: Vec<Vec<u32>> = m
        .faces()
        .flat_map(|f| {
            let l: Vec<u32> = m.face_outer(f).iter().map(|v| v.0).collect();
            (1..l.len() - 1)
                .map(move |i| vec![l[0], l[i], l[i + 1]])
                .collect::<Vec<_>>()
        })
        .collect();
    PolyMesh::from_polygons(m.positions().to_vec(), faces).unwrap()
}

criterion_group!(benches, cut, long_strokes);
criterion_main!(benches);
