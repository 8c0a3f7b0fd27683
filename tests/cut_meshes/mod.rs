//! Meshes for the stroke cut's tests, benchmark and tuning examples (`tests/cut.rs`,
//! `benches/cut.rs`, `examples/cut_*.rs` include this file): triangulated grids, flat and
//! perturbed, icospheres, quads split into triangles, cameras around a mesh, and the
//! benchmark's spot, view, stroke and floor.
#![allow(dead_code)] // each includer uses some

use std::collections::BTreeMap;

use glam::{DMat4, DVec2, DVec3};
use katachi::cut::{Stroke, View};
use katachi::subdivide::{catmull_clark, SubdivideOptions};
use katachi::PolyMesh;
use rayon::prelude::*;

/// An m × n grid of unit squares in z = 0, each split into two triangles (normal +z).
pub fn tri_grid(m: u32, n: u32) -> PolyMesh {
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
pub fn perturbed_grid(m: u32, n: u32, amount: f64, seed: u64) -> PolyMesh {
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
pub fn icosphere(levels: u32) -> PolyMesh {
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

/// Each quad of `quads` split along its diagonal from corner 0 (the benchmark's meshes).
pub fn triangulate_quads(quads: &PolyMesh) -> PolyMesh {
    let tris: Vec<[u32; 3]> = quads
        .faces()
        .flat_map(|f| {
            let q = quads.face_outer(f);
            [[q[0].0, q[1].0, q[2].0], [q[0].0, q[2].0, q[3].0]]
        })
        .collect();
    PolyMesh::from_polygons(quads.positions().to_vec(), tris.iter()).unwrap()
}

/// A camera looking at the mesh's centre from a random direction: orthographic or perspective.
pub fn view_for(mesh: &PolyMesh, ortho: bool, theta: f64, phi: f64, dist: f64) -> View {
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

/// The benchmark's spot: the bundled `spot_quadrangulated.obj` subdivided 4 times and
/// triangulated (1.5M triangles).
pub fn spot_l4() -> Result<PolyMesh, String> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/models/spot_quadrangulated.obj"
    );
    let m = katachi::io::read(std::path::Path::new(path)).map_err(|e| e.to_string())?;
    let sub = catmull_clark(&m, &SubdivideOptions::with_levels(4)).map_err(|e| e.to_string())?;
    Ok(triangulate_quads(&sub.mesh))
}

/// The benchmark's view: the whole mesh in perspective from above and aside, 1280 × 720.
pub fn bench_view(mesh: &PolyMesh) -> View {
    let (lo, hi) = mesh.bounding_box().unwrap();
    let c = (lo + hi) / 2.0;
    let r = (hi - lo).length() / 2.0;
    let eye = c + DVec3::new(0.3, -0.9, 1.2).normalize() * r * 2.2;
    let vp = DMat4::perspective_rh_gl(45f64.to_radians(), 1280.0 / 720.0, 0.01 * r, 10.0 * r)
        * DMat4::look_at_rh(eye, c, DVec3::Z);
    View::new(vp, [0.0, 0.0, 1280.0, 720.0])
}

/// The benchmark's stroke: 50 points across the view, a gentle wave.
pub fn bench_stroke() -> Stroke {
    Stroke::new(
        (0..50)
            .map(|i| {
                let t = i as f64 / 49.0;
                DVec2::new(200.0 + 880.0 * t, 360.0 + 60.0 * (t * 6.0).sin())
            })
            .collect(),
    )
}

/// The benchmark's floor: every vertex through the view-projection matrix and viewport, into
/// `out` (kept between runs, so the floor is the pass alone: a fresh array's page faults cost
/// from nothing to more than the pass, depending on the allocator's state).
pub fn project_all(mesh: &PolyMesh, view: &View, out: &mut Vec<DVec2>) {
    let (vp, v) = (view.view_proj, view.viewport);
    mesh.positions()
        .par_iter()
        .with_min_len(1 << 14)
        .map(|&p| {
            let c = vp * p.extend(1.0);
            let inv = 1.0 / c.w;
            DVec2::new(
                v[0] + (c.x * inv + 1.0) * 0.5 * v[2],
                v[1] + (1.0 - c.y * inv) * 0.5 * v[3],
            )
        })
        .collect_into_vec(out);
}

/// A random cut: a mesh (named by `key`), a view, a stroke and options ([`RandomCuts`]).
pub struct RandomCut {
    pub key: String,
    pub mesh: PolyMesh,
    pub view: View,
    /// `view_for`'s arguments after the mesh: (ortho, theta, phi, dist).
    pub view_args: (bool, f64, f64, f64),
    pub stroke: Stroke,
    pub options: katachi::cut::CutOptions,
}

/// A fixed sequence of random cuts (`examples/cut_digest.rs` fingerprints them, the tests
/// compare the plain and fast paths on them): triangulated grids (flat and perturbed),
/// icospheres and tori, seen from random directions in orthographic and perspective views,
/// cut by random strokes (smooth or with sharp turns, some closed) in both modes, opened or
/// not, with random snap ratios.
pub struct RandomCuts {
    state: u64,
    meshes: BTreeMap<String, PolyMesh>,
}

impl Default for RandomCuts {
    fn default() -> Self {
        Self::new()
    }
}

impl RandomCuts {
    pub fn new() -> Self {
        RandomCuts {
            state: 0x1234_5678_9abc_def0,
            meshes: BTreeMap::new(),
        }
    }

    fn rnd(&mut self) -> f64 {
        let s = &mut self.state;
        *s ^= *s << 13;
        *s ^= *s >> 7;
        *s ^= *s << 17;
        (*s >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next cut of the sequence.
    pub fn next_cut(&mut self) -> RandomCut {
        use katachi::cut::{CutMode, CutOptions};
        use katachi::mesh::shapes;
        let tri_torus = |n: u32| triangulate_quads(&shapes::torus(n, n, 2.0, 0.7).unwrap());
        let kind = (self.rnd() * 6.0) as u32;
        let key = match kind {
            0 => format!("grid {}", 4 + (self.rnd() * 30.0) as u32),
            1 => format!(
                "pgrid {} {} {}",
                4 + (self.rnd() * 30.0) as u32,
                [1e-15, 0.1, 0.3][(self.rnd() * 3.0) as usize],
                (self.rnd() * 1000.0) as u64
            ),
            2 => format!("sphere {}", 1 + (self.rnd() * 4.0) as u32),
            3 => format!("torus {}", [8u32, 20, 40, 71][(self.rnd() * 4.0) as usize]),
            _ => format!("sphere {}", 2 + (self.rnd() * 3.0) as u32),
        };
        let mesh = self
            .meshes
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
        let view_args = (
            self.rnd() < 0.5,
            self.rnd() * std::f64::consts::TAU,
            self.rnd() * 1.2,
            1.5 + self.rnd() * 2.5,
        );
        let view = view_for(&mesh, view_args.0, view_args.1, view_args.2, view_args.3);
        let mut p = vec![DVec2::new(
            250.0 + self.rnd() * 300.0,
            180.0 + self.rnd() * 240.0,
        )];
        let mut a = self.rnd() * std::f64::consts::TAU;
        let steps = 1 + (self.rnd() * 40.0) as usize;
        let step = 3.0 + self.rnd() * 60.0;
        let sharp = self.rnd() < 0.3;
        for _ in 0..steps {
            a += if sharp && self.rnd() < 0.2 {
                (self.rnd() - 0.5) * 4.0
            } else {
                self.rnd() - 0.5
            };
            let q = *p.last().unwrap();
            p.push(q + DVec2::new(a.cos(), a.sin()) * step);
        }
        if self.rnd() < 0.15 {
            let f = p[0];
            p.push(f);
        }
        let mut o = CutOptions::with_mode(if self.rnd() < 0.5 {
            CutMode::VisibleOnly
        } else {
            CutMode::ThroughAll
        });
        o.open = self.rnd() < 0.3;
        if self.rnd() < 0.2 {
            o.snap_vertex_ratio = self.rnd() * 0.5;
            o.snap_segment_ratio = self.rnd() * 0.5;
        }
        RandomCut {
            key,
            mesh,
            view,
            view_args,
            stroke: Stroke::new(p),
            options: o,
        }
    }
}
