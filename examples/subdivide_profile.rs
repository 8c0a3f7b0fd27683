//! Times the parts of a subdivision as the Blender add-on asks for them, on the Blender
//! bench's mesh (a 384 × 256 torus with creased rings and a UV map with seams), for finding
//! where time goes (`cargo run --release --example subdivide_profile [-- LEVELS ROUNDS]`).
//! Speed goals are measured in the hosts (`cargo xtask blender-bench`), not here.

use std::time::{Duration, Instant};

use katachi::mesh::{shapes, VertexId};
use katachi::subdivide::{catmull_clark, FaceVarying, Refiner, SubdivideOptions};

fn main() {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let levels = args.first().copied().unwrap_or(2);
    let rounds = args.get(1).copied().unwrap_or(5);
    let (major, minor) = (384u32, 256u32);
    let mut mesh = shapes::torus(major, minor, 1.0, 0.3);
    // Creased rings around the tube, as the Blender bench sets them.
    let step = major / 8;
    let mut creases = Vec::new();
    for i in (0..major).filter(|i| i % (step / 2) == 0) {
        let s = if i % step == 0 { 10.0 } else { 2.5 };
        for j in 0..minor {
            let a = VertexId(i * minor + j);
            let b = VertexId(i * minor + (j + 1) % minor);
            creases.push((a, b, s));
        }
    }
    mesh.set_edge_sharpnesses(creases).unwrap();
    // UVs: (i, j) on a (major + 1) × (minor + 1) grid of values, seams where the torus wraps.
    let mut uv = Vec::new();
    for i in 0..=major {
        for j in 0..=minor {
            uv.push(glam::DVec2::new(
                i as f64 / major as f64,
                j as f64 / minor as f64,
            ));
        }
    }
    let id = |i: u32, j: u32| i * (minor + 1) + j;
    let mut indices = Vec::new();
    for i in 0..major {
        for j in 0..minor {
            indices.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let options = SubdivideOptions::with_levels(levels);
    println!(
        "torus {major}×{minor} ({} quads), {levels} levels, {} threads, {rounds} rounds",
        mesh.face_count(),
        rayon::current_num_threads()
    );
    let mut times: Vec<(&str, Vec<Duration>)> = Vec::new();
    let mut note = |name: &'static str, d: Duration| match times.iter_mut().find(|t| t.0 == name) {
        Some(t) => t.1.push(d),
        None => times.push((name, vec![d])),
    };
    for _ in 0..rounds {
        let t = Instant::now();
        let out = catmull_clark(&mesh, &options).unwrap();
        note("catmull_clark", t.elapsed());
        drop(out);
        let t = Instant::now();
        let refiner = Refiner::new(&mesh, &options).unwrap();
        note("Refiner::new (topology)", t.elapsed());
        let t = Instant::now();
        let p = refiner.refine_vertex_data(mesh.positions()).unwrap();
        note("refine_vertex_data (positions)", t.elapsed());
        let t = Instant::now();
        let m = refiner.mesh(p);
        note("Refiner::mesh", t.elapsed());
        drop(m);
        for (name, mode) in [
            (
                "face-varying linear boundaries",
                FaceVarying::LinearBoundaries,
            ),
            ("face-varying linear all", FaceVarying::LinearAll),
        ] {
            let t = Instant::now();
            let r = refiner
                .refine_face_varying(&mesh, &uv, &indices, mode)
                .unwrap();
            note(name, t.elapsed());
            drop(r);
        }
        let t = Instant::now();
        let s = refiner.stencils();
        note("stencils", t.elapsed());
        drop(s);
    }
    for (name, mut v) in times {
        v.sort();
        println!(
            "  {name:34} median {:8.1} ms  min {:8.1} ms",
            v[v.len() / 2].as_secs_f64() * 1e3,
            v[0].as_secs_f64() * 1e3
        );
    }
}
