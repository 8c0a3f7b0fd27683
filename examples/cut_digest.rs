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
//! Cases: triangulated grids (flat and perturbed), icospheres and tori, seen from random
//! directions in orthographic and perspective views, cut by random strokes (smooth or with
//! sharp turns, some closed) in both modes, opened or not, with random snap ratios.

use std::collections::BTreeMap;
use std::hash::{Hash, Hasher};

use glam::{DMat4, DVec2, DVec3};
use katachi::cut::{cut_edits, CutMode, CutOptions, Stroke, View};
use katachi::mesh::shapes;
use katachi::PolyMesh;

fn tri_grid(m: u32, n: u32) -> PolyMesh {
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=m {
            p.push(DVec3::new(i as f64, j as f64, 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (m + 1) + i;
    let mut f = Vec::new();
    for j in 0..n {
        for i in 0..m {
            f.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            f.push(vec![id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    PolyMesh::from_polygons(p, f).unwrap()
}

/// `tri_grid` with each interior vertex moved by up to `amount` in x and y and up to
/// min(amount, 0.2) in z (deterministic).
fn perturbed_grid(m: u32, n: u32, amount: f64, seed: u64) -> PolyMesh {
    let g = tri_grid(m, n);
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut rnd = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let p: Vec<DVec3> = g
        .positions()
        .iter()
        .map(|&q| {
            let interior = q.x > 0.0 && q.y > 0.0 && q.x < m as f64 && q.y < n as f64;
            let (dx, dy, dz) = (rnd(), rnd(), rnd());
            if interior {
                q + DVec3::new(dx * amount, dy * amount, dz * amount.min(0.2))
            } else {
                q
            }
        })
        .collect();
    let faces: Vec<Vec<u32>> = g
        .faces()
        .map(|f| g.face_outer(f).iter().map(|v| v.0).collect())
        .collect();
    PolyMesh::from_polygons(p, faces).unwrap()
}

/// An icosphere of radius 1 (outward winding), `levels` midpoint subdivisions.
fn icosphere(levels: u32) -> PolyMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mid: BTreeMap<(u32, u32), u32> = BTreeMap::new();
        let mut nf = Vec::new();
        for t in &f {
            let mut m = [0u32; 3];
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                m[i] = *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    p.push(((p[a as usize] + p[b as usize]) / 2.0).normalize());
                    p.len() as u32 - 1
                });
            }
            nf.push([t[0], m[0], m[2]]);
            nf.push([t[1], m[1], m[0]]);
            nf.push([t[2], m[2], m[1]]);
            nf.push([m[0], m[1], m[2]]);
        }
        f = nf;
    }
    PolyMesh::from_polygons(p, f.iter()).unwrap()
}

/// A camera looking at the mesh's centre from a random direction: orthographic or perspective.
fn view_for(mesh: &PolyMesh, ortho: bool, theta: f64, phi: f64, dist: f64) -> View {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let c = (lo + hi) / 2.0;
    let r = (hi - lo).length() / 2.0;
    let dir = DVec3::new(phi.sin() * theta.cos(), phi.sin() * theta.sin(), phi.cos());
    let eye = c + dir * r * dist;
    let up = if dir.cross(DVec3::Y).length() < 1e-3 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let look = DMat4::look_at_rh(eye, c, up);
    let proj = if ortho {
        DMat4::orthographic_rh_gl(-r * 1.2, r * 1.2, -r * 0.9, r * 0.9, 0.01, 100.0 * r)
    } else {
        DMat4::perspective_rh_gl(50f64.to_radians(), 800.0 / 600.0, 0.01, 100.0 * r)
    };
    View::new(proj * look, [0.0, 0.0, 800.0, 600.0])
}

fn tri_torus(n: u32) -> PolyMesh {
    let q = shapes::torus(n, n, 2.0, 0.7);
    let tris: Vec<[u32; 3]> = q
        .faces()
        .flat_map(|f| {
            let l = q.face_outer(f);
            [[l[0].0, l[1].0, l[2].0], [l[0].0, l[2].0, l[3].0]]
        })
        .collect();
    PolyMesh::from_polygons(q.positions().to_vec(), tris.iter()).unwrap()
}

fn main() {
    let n: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(3000);
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
        let r = cut_edits(&mesh, &Stroke::new(p), &view, &o);
        let text = match &r {
            Ok(e) => format!("{e:?}"),
            Err(e) => format!("error {e}"),
        };
        let mut h = std::collections::hash_map::DefaultHasher::new();
        text.hash(&mut h);
        let summary = match &r {
            Ok(e) => format!(
                "nv {} rf {} af {}",
                e.new_vertices.len(),
                e.rewritten_faces.len(),
                e.appended_faces.len()
            ),
            Err(_) => "err".into(),
        };
        lines += &format!("{case} {key} {:016x} {summary}\n", h.finish());
    }
    print!("{lines}");
}
