//! Times the parts of a subdivision as the Blender add-on asks for them, on the Blender
//! bench's mesh (a 384 × 256 torus with creased rings and a UV map with seams), for finding
//! where time goes (`cargo run --release --example subdivide_profile [-- LEVELS ROUNDS]`).
//! Speed goals are measured in the hosts (`cargo xtask blender-bench`), not here.
//!
//! Each part is timed by the wall clock and by the process's CPU time (all threads), which
//! a busy machine disturbs less: run with `RAYON_NUM_THREADS=1` to compare work.

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
    let mut mesh = shapes::torus(major, minor, 1.0, 0.3).unwrap();
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
    let corner_uv: Vec<f32> = indices
        .iter()
        .flat_map(|&i| [uv[i as usize].x as f32, uv[i as usize].y as f32])
        .collect();
    println!(
        "torus {major}×{minor} ({} quads), {levels} levels, {} threads, {rounds} rounds",
        mesh.face_count(),
        rayon::current_num_threads()
    );
    let mut times: Vec<(&str, Vec<(Duration, Duration)>)> = Vec::new();
    let mut cpu_at = cpu();
    let mut note = |name: &'static str, d: Duration| {
        let now = cpu();
        let c = now.saturating_sub(cpu_at);
        cpu_at = now;
        match times.iter_mut().find(|t| t.0 == name) {
            Some(t) => t.1.push((d, c)),
            None => times.push((name, vec![(d, c)])),
        }
    };
    for _ in 0..rounds {
        note("(start)", Duration::ZERO);
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
        let m = refiner.mesh(p).unwrap();
        note("Refiner::mesh", t.elapsed());
        drop(m);
        for (name, mode) in [
            (
                "face-varying linear boundaries",
                FaceVarying::LinearBoundaries,
            ),
            ("face-varying linear all", FaceVarying::LinearAll),
            ("face-varying smooth", FaceVarying::Smooth),
        ] {
            let t = Instant::now();
            let r = refiner.refine_face_varying(&uv, &indices, mode).unwrap();
            note(name, t.elapsed());
            drop(r);
        }
        if std::env::var_os("STENCILS").is_some() {
            let t = Instant::now();
            let s = refiner.stencils();
            note("stencils", t.elapsed());
            drop(s);
        }
        host_path(&mesh, &corner_uv, levels, &mut note);
    }
    for (name, v) in times.into_iter().filter(|t| t.0 != "(start)") {
        let ms = |mut d: Vec<Duration>| {
            d.sort();
            (d[d.len() / 2].as_secs_f64() * 1e3, d[0].as_secs_f64() * 1e3)
        };
        let (wall, wall_min) = ms(v.iter().map(|x| x.0).collect());
        let (cpu, cpu_min) = ms(v.iter().map(|x| x.1).collect());
        println!(
            "  {name:34} wall median {wall:8.1} ms (min {wall_min:8.1})   cpu median {cpu:8.1} ms (min {cpu_min:8.1})"
        );
    }
}

/// CPU time of the whole process so far.
fn cpu() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: a valid clock id and a pointer to a timespec it fills in.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// The Blender add-on's calls through the C ABI, each timed: the mesh from a host's arrays
/// with its creases, the subdivision, and every copy out.
fn host_path(
    mesh: &katachi::PolyMesh,
    corner_uv: &[f32],
    levels: u32,
    note: &mut dyn FnMut(&'static str, Duration),
) {
    use katachi::ffi::*;
    use std::ptr::null_mut;
    let positions: Vec<f32> = mesh
        .positions()
        .iter()
        .flat_map(|p| p.as_vec3().to_array())
        .collect();
    let nf = mesh.face_count();
    let starts: Vec<u32> = mesh.loop_offsets()[..nf as usize].to_vec();
    let corners: Vec<u32> = mesh.corners().iter().map(|v| v.0).collect();
    let mut edges = Vec::new();
    let mut creases = Vec::new();
    for (a, b, s) in mesh.sharp_edges() {
        edges.extend([a.0, b.0]);
        creases.push(((s / 10.0).sqrt()) as f32);
    }
    let ok = |s: KatachiStatus| assert_eq!(s, KatachiStatus::Ok);
    // SAFETY: every array holds the counts given; handles are freed once.
    unsafe {
        let t = Instant::now();
        let mut m = null_mut();
        ok(katachi_mesh_create_polygons_f32(
            positions.as_ptr(),
            mesh.vertex_count(),
            starts.as_ptr(),
            std::ptr::null(),
            nf,
            corners.as_ptr(),
            corners.len() as u32,
            &mut m,
        ));
        note("C: create_polygons_f32", t.elapsed());
        let t = Instant::now();
        ok(katachi_mesh_set_edge_sharpness_f32(
            m,
            edges.as_ptr(),
            creases.as_ptr(),
            creases.len() as u32,
            std::ptr::null(),
            0,
            1,
            null_mut(),
        ));
        note("C: set_edge_sharpness_f32", t.elapsed());
        let mut o = katachi_subdivide_options_default();
        o.levels = levels;
        o.split_faces_with_holes = 1;
        let t = Instant::now();
        let mut s = null_mut();
        ok(katachi_subdivide(m, &o, &mut s));
        note("C: subdivide", t.elapsed());
        let mut info = katachi_subdivision_info_default();
        ok(katachi_subdivision_info(s, &mut info));
        let (nv, nf, nc, ne) = (
            info.vertex_count as usize,
            info.face_count as usize,
            info.corner_count as usize,
            info.edge_count as usize,
        );
        let t = Instant::now();
        let mut p = vec![0f32; 3 * nv];
        ok(katachi_subdivision_copy_positions_f32(
            s,
            p.as_mut_ptr(),
            p.len(),
        ));
        note("C: copy positions f32", t.elapsed());
        let t = Instant::now();
        let (mut fs, mut c) = (vec![0u32; nf], vec![0u32; nc]);
        ok(katachi_subdivision_copy_polygons(
            s,
            fs.as_mut_ptr(),
            nf,
            null_mut(),
            0,
            c.as_mut_ptr(),
            nc,
        ));
        note("C: copy polygons", t.elapsed());
        let t = Instant::now();
        let (mut ev, mut ce) = (vec![0u32; 2 * ne], vec![0u32; nc]);
        ok(katachi_subdivision_copy_edges(
            s,
            ev.as_mut_ptr(),
            2 * ne,
            ce.as_mut_ptr(),
            nc,
        ));
        note("C: copy edges (computed)", t.elapsed());
        let t = Instant::now();
        let mut sh = vec![0f32; ne];
        ok(katachi_subdivision_copy_edge_sharpness_f32(
            s,
            sh.as_mut_ptr(),
            ne,
            1,
        ));
        note("C: copy edge creases", t.elapsed());
        let t = Instant::now();
        let mut uv = vec![0f32; 2 * nc];
        ok(katachi_subdivision_refine_corner_data_f32(
            s,
            corner_uv.as_ptr(),
            corner_uv.len(),
            2,
            2,
            uv.as_mut_ptr(),
            uv.len(),
        ));
        note("C: refine corner UVs", t.elapsed());
        let t = Instant::now();
        katachi_subdivision_free(s);
        katachi_mesh_free(m);
        note("C: free", t.elapsed());
    }
}
