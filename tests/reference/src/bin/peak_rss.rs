//! `peak_rss LIB MODEL LEVEL`: runs one Catmull-Clark refinement in a fresh process and
//! prints the process's peak resident memory (KiB) and the time, for the side-by-side
//! benchmark. LIB is katachi, opensubdiv or openmesh; MODEL is `torus` (200 × 160 quads) or a
//! mesh file.

use std::time::Instant;

use katachi::mesh::shapes;
use katachi::subdivide::{catmull_clark, SubdivideOptions};
use katachi_reference as r;

fn peak_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or(0)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() != 4 {
        eprintln!("usage: peak_rss katachi|opensubdiv|openmesh torus|FILE LEVEL");
        std::process::exit(2);
    }
    let mesh = if args[2] == "torus" {
        shapes::torus(200, 160, 2.0, 0.5).unwrap()
    } else {
        katachi::io::read(std::path::Path::new(&args[2])).expect("a readable mesh")
    };
    let level: u32 = args[3].parse().expect("a level");
    let rm = r::RefMesh {
        positions: mesh.positions().iter().map(|p| p.to_array()).collect(),
        face_sizes: mesh
            .faces()
            .map(|f| mesh.face_outer(f).len() as u32)
            .collect(),
        face_vertices: mesh.corners().iter().map(|v| v.0).collect(),
    };
    let before = peak_kib();
    let t = Instant::now();
    let faces = match args[1].as_str() {
        "katachi" => {
            drop(rm);
            catmull_clark(&mesh, &SubdivideOptions::with_levels(level))
                .expect("subdivides")
                .mesh
                .face_count() as usize
        }
        "opensubdiv" => r::osd_catmark(
            &rm,
            &r::Creases::default(),
            &r::OsdOptions::default(),
            level,
        )
        .expect("subdivides")
        .face_sizes
        .len(),
        "openmesh" => r::openmesh_catmull_clark(&rm, level)
            .expect("subdivides")
            .face_sizes
            .len(),
        other => panic!("unknown library {other}"),
    };
    let ms = t.elapsed().as_secs_f64() * 1e3;
    println!("{} {} {} {} {}", args[1], faces, before, peak_kib(), ms);
}
