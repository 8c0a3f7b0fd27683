//! Times repeated stroke cuts (`cut_edits`) on the benchmark's meshes, for tuning between
//! `cargo xtask bench` runs: the same view and 50-point stroke as `benches/cut.rs`.
//!
//! ```sh
//! cargo run --release --example cut_profile -- torus visible 100   # or: spot through-all
//! KATACHI_CUT_TRACE=1 cargo run --release --example cut_profile    # each step's time too
//! ```
//!
//! `torus` is the triangulated 1M-triangle torus, `spot` the shared `spot_quadrangulated.obj`
//! subdivided 4 times and triangulated (1.5M triangles). Prints the fastest, the first
//! quartile and the median call in milliseconds, and the cut's time over the floor's (the
//! bench's projection pass, run right before each cut; `NOFLOOR=1` leaves it out). Under
//! `valgrind --tool=callgrind --toggle-collect='katachi::cut::plan*'` with
//! `RAYON_NUM_THREADS=1` it counts the instructions of a cut, which, unlike times, do not
//! depend on what else the machine does.

use std::time::Instant;

use glam::DVec2;
use katachi::cut::{cut_edits, CutMode, CutOptions};
use katachi::mesh::shapes;

#[path = "../tests/cut_meshes/mod.rs"]
mod cut_meshes;
use cut_meshes::{bench_stroke, bench_view, project_all, spot_l4, triangulate_quads};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).cloned().unwrap_or(default.to_string());
    let mesh = match arg(0, "torus").as_str() {
        "torus" => triangulate_quads(&shapes::torus(707, 707, 2.0, 0.7).unwrap()),
        "spot" => spot_l4()?,
        other => return Err(format!("unknown mesh {other:?} (torus or spot)").into()),
    };
    let mode = match arg(1, "visible").as_str() {
        "visible" => CutMode::VisibleOnly,
        "through-all" => CutMode::ThroughAll,
        other => return Err(format!("unknown mode {other:?} (visible or through-all)").into()),
    };
    let calls: usize = arg(2, "60").parse()?;
    if calls == 0 {
        return Err("at least one call".into());
    }

    let (view, stroke) = (bench_view(&mesh), bench_stroke());
    let options = CutOptions::with_mode(mode);

    // Each cut right after one floor pass (the bench's: every vertex through the matrix and
    // viewport into a kept array), both timed, so the ratio is taken side by side.
    let (mut ms, mut floor, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
    let mut screen: Vec<DVec2> = Vec::new();
    for _ in 0..calls {
        let start = Instant::now();
        if std::env::var_os("NOFLOOR").is_none() {
            project_all(&mesh, &view, &mut screen);
        }
        std::hint::black_box(&screen);
        let f = start.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        drop(std::hint::black_box(cut_edits(
            &mesh, &stroke, &view, &options,
        )?));
        let c = start.elapsed().as_secs_f64() * 1e3;
        ms.push(c);
        floor.push(f);
        ratio.push(c / f);
    }
    for v in [&mut ms, &mut floor, &mut ratio] {
        v.sort_by(f64::total_cmp);
    }
    println!(
        "{} triangles, {mode:?}, {calls} calls: min {:.3} ms, p25 {:.3} ms, median {:.3} ms; \
         floor median {:.3} ms; cut / floor per call: p25 {:.2}, median {:.2}",
        mesh.face_count(),
        ms[0],
        ms[calls / 4],
        ms[calls / 2],
        floor[calls / 2],
        ratio[calls / 4],
        ratio[calls / 2],
    );
    Ok(())
}
