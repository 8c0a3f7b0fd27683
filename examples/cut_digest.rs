//! A fingerprint of the stroke cut over thousands of random cases, for changes that must
//! not change any result (speed work): each line is a case, the hash of its `cut_edits`
//! (or error) and the counts. Run it before and after a change and compare:
//!
//! ```sh
//! cargo run --release --example cut_digest -- 30000 > before.txt
//! # ... change the cut ...
//! cargo run --release --example cut_digest -- 30000 > after.txt && diff before.txt after.txt
//! ```
//!
//! `--plain` runs the plain path (`cut_edits_plain`: no grid, SIMD, buckets or radix sorts)
//! instead, which must print the same lines. `--detail` adds a second hash per case, of the edits with the report's mean edge lengths
//! left out (a change in how L is rounded then shows apart from a change in the edits), and
//! `--case K` prints case K's edits whole.
//!
//! Cases: triangulated grids (flat and perturbed), icospheres and tori, seen from random
//! directions in orthographic and perspective views, cut by random strokes (smooth or with
//! sharp turns, some closed) in both modes, opened or not, with random snap ratios.

use std::collections::BTreeMap;
use std::hash::{Hash, Hasher};

use glam::DVec2;
use katachi::cut::{cut_edits, cut_edits_plain, CutMode, CutOptions, Stroke};
use katachi::mesh::shapes;
use katachi::PolyMesh;

#[path = "../tests/cut_meshes/mod.rs"]
mod cut_meshes;
use cut_meshes::{icosphere, perturbed_grid, tri_grid, triangulate_quads, view_for};

fn tri_torus(n: u32) -> PolyMesh {
    triangulate_quads(&shapes::torus(n, n, 2.0, 0.7).unwrap())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.first().and_then(|s| s.parse().ok()).unwrap_or(3000);
    let detail = args.iter().any(|a| a == "--detail");
    let plain = args.iter().any(|a| a == "--plain");
    let only: Option<u64> = args
        .iter()
        .position(|a| a == "--case")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse().ok());
    let mut s = 0x1234_5678_9abc_def0u64;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut meshes: BTreeMap<String, PolyMesh> = BTreeMap::new();
    let mut lines = String::new();
    for case in 0..n {
        let kind = (rnd() * 6.0) as u32;
        let key = match kind {
            0 => format!("grid {}", 4 + (rnd() * 30.0) as u32),
            1 => format!(
                "pgrid {} {} {}",
                4 + (rnd() * 30.0) as u32,
                [1e-15, 0.1, 0.3][(rnd() * 3.0) as usize],
                (rnd() * 1000.0) as u64
            ),
            2 => format!("sphere {}", 1 + (rnd() * 4.0) as u32),
            3 => format!("torus {}", [8u32, 20, 40, 71][(rnd() * 4.0) as usize]),
            _ => format!("sphere {}", 2 + (rnd() * 3.0) as u32),
        };
        let mesh = meshes
            .entry(key.clone())
            .or_insert_with(|| {
                let w: Vec<&str> = key.split(' ').collect();
                match w[0] {
                    "grid" => tri_grid(w[1].parse().unwrap(), w[1].parse().unwrap()),
                    "pgrid" => perturbed_grid(
                        w[1].parse().unwrap(),
                        w[1].parse().unwrap(),
                        w[2].parse().unwrap(),
                        w[3].parse().unwrap(),
                    ),
                    "sphere" => icosphere(w[1].parse().unwrap()),
                    _ => tri_torus(w[1].parse().unwrap()),
                }
            })
            .clone();
        let view = view_for(
            &mesh,
            rnd() < 0.5,
            rnd() * std::f64::consts::TAU,
            rnd() * 1.2,
            1.5 + rnd() * 2.5,
        );
        let mut p = vec![DVec2::new(250.0 + rnd() * 300.0, 180.0 + rnd() * 240.0)];
        let mut a = rnd() * std::f64::consts::TAU;
        let steps = 1 + (rnd() * 40.0) as usize;
        let step = 3.0 + rnd() * 60.0;
        let sharp = rnd() < 0.3;
        for _ in 0..steps {
            a += if sharp && rnd() < 0.2 {
                (rnd() - 0.5) * 4.0
            } else {
                rnd() - 0.5
            };
            let q = *p.last().unwrap();
            p.push(q + DVec2::new(a.cos(), a.sin()) * step);
        }
        if rnd() < 0.15 {
            let f = p[0];
            p.push(f);
        }
        let mut o = CutOptions::with_mode(if rnd() < 0.5 {
            CutMode::VisibleOnly
        } else {
            CutMode::ThroughAll
        });
        o.open = rnd() < 0.3;
        if rnd() < 0.2 {
            o.snap_vertex_ratio = rnd() * 0.5;
            o.snap_segment_ratio = rnd() * 0.5;
        }
        if only.is_some_and(|k| k != case) {
            continue;
        }
        let r = if plain {
            cut_edits_plain(&mesh, &Stroke::new(p), &view, &o)
        } else {
            cut_edits(&mesh, &Stroke::new(p), &view, &o)
        };
        let text = match &r {
            Ok(e) => format!("{e:?}"),
            Err(e) => format!("error {e}"),
        };
        if only.is_some() {
            println!("{case} {key}\n{text}");
            return;
        }
        let hash = |t: &str| {
            let mut h = std::collections::hash_map::DefaultHasher::new();
            t.hash(&mut h);
            h.finish()
        };
        let summary = match &r {
            Ok(e) => format!(
                "nv {} rf {} af {}",
                e.new_vertices.len(),
                e.rewritten_faces.len(),
                e.appended_faces.len()
            ),
            Err(_) => "err".into(),
        };
        if detail {
            lines += &format!(
                "{case} {key} {:016x} {:016x} {summary}\n",
                hash(&text),
                hash(&without_lengths(&text))
            );
        } else {
            lines += &format!("{case} {key} {:016x} {summary}\n", hash(&text));
        }
    }
    print!("{lines}");
}

/// The edits' text without the report's mean edge lengths (their values up to the next
/// field).
fn without_lengths(text: &str) -> String {
    let mut out = text.to_string();
    for field in ["mean_edge_length_px: ", "mean_edge_length_world: "] {
        if let Some(at) = out.find(field) {
            let end = out[at..].find(',').map_or(out.len(), |e| at + e);
            out.replace_range(at..end, field);
        }
    }
    out
}
