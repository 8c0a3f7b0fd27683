//! A round plate with a cylindrical boss (spec `rough_model.md` §6 S1), triangulated on a polar
//! grid so that the boss's foot, a concave crease, is a ring of mesh edges: the feature a band
//! around the foot must find. Also used by `tests/reference` (max-flow against Boost).

use katachi::{DVec3, FaceId, PolyMesh};

/// The mesh and where its rows are. Rows count quad rings outward-in: the plate's rows
/// `0..foot`, the wall's `foot..rim`, the top's `rim..rows` (the last one a fan to the centre).
pub struct BossPlate {
    pub mesh: PolyMesh,
    pub sectors: u32,
    pub rows: u32,
    /// The first row of the wall: the boss's foot is the ring between rows `foot - 1` and `foot`.
    pub foot: u32,
    /// The first row of the top.
    pub rim: u32,
}

/// The shape's sizes.
#[derive(Clone, Copy, Debug)]
pub struct BossSizes {
    pub sectors: u32,
    pub plate_rows: u32,
    pub wall_rows: u32,
    pub top_rows: u32,
    pub plate_radius: f64,
    pub boss_radius: f64,
    pub height: f64,
}

impl Default for BossSizes {
    fn default() -> Self {
        BossSizes {
            sectors: 48,
            plate_rows: 16,
            wall_rows: 10,
            top_rows: 8,
            plate_radius: 3.0,
            boss_radius: 1.0,
            height: 1.25,
        }
    }
}

/// A plate with a boss (`flat`: without, the "wall" lying in the plate's plane as rings
/// further in, for the flat-band case S2).
pub fn boss_plate(s: BossSizes, flat: bool) -> BossPlate {
    let k_count = s.plate_rows + s.wall_rows + s.top_rows; // profile points 0..=k_count
    let mut profile = Vec::new(); // (radius, z)
    let (r_plate, r_boss) = (s.plate_radius, s.boss_radius);
    for k in 0..s.plate_rows {
        let t = k as f64 / s.plate_rows as f64;
        profile.push((r_plate + (r_boss - r_plate) * t, 0.0));
    }
    let wall_inner = 0.5 * r_boss;
    for k in 0..s.wall_rows {
        let t = k as f64 / s.wall_rows as f64;
        profile.push(if flat {
            (r_boss + (wall_inner - r_boss) * t, 0.0)
        } else {
            (r_boss, s.height * t)
        });
    }
    let (r_top, z_top) = if flat {
        (wall_inner, 0.0)
    } else {
        (r_boss, s.height)
    };
    for k in 0..s.top_rows {
        let t = k as f64 / s.top_rows as f64;
        profile.push((r_top * (1.0 - t), z_top));
    }
    profile.push((0.0, z_top));
    debug_assert_eq!(profile.len() as u32, k_count + 1);

    let n = s.sectors;
    let mut p = Vec::new();
    for &(r, z) in &profile[..k_count as usize] {
        for j in 0..n {
            let a = std::f64::consts::TAU * j as f64 / n as f64;
            p.push(DVec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    let centre = p.len() as u32;
    p.push(DVec3::new(0.0, 0.0, z_top));
    let id = |k: u32, j: u32| k * n + j % n;
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for k in 0..k_count - 1 {
        for j in 0..n {
            let (a, b, c, d) = (id(k, j), id(k, j + 1), id(k + 1, j + 1), id(k + 1, j));
            if (k + j) % 2 == 0 {
                faces.push(vec![a, b, c]);
                faces.push(vec![a, c, d]);
            } else {
                faces.push(vec![a, b, d]);
                faces.push(vec![b, c, d]);
            }
        }
    }
    for j in 0..n {
        faces.push(vec![id(k_count - 1, j), id(k_count - 1, j + 1), centre]);
    }
    BossPlate {
        mesh: PolyMesh::from_polygons(p, faces).unwrap(),
        sectors: n,
        rows: k_count,
        foot: s.plate_rows,
        rim: s.plate_rows + s.wall_rows,
    }
}

impl BossPlate {
    /// The faces of row `k`, sector `j` (two, or one in the last row).
    pub fn faces_at(&self, k: u32, j: u32) -> Vec<FaceId> {
        let j = j % self.sectors;
        if k + 1 < self.rows {
            let f = 2 * (k * self.sectors + j);
            vec![FaceId(f), FaceId(f + 1)]
        } else {
            vec![FaceId(2 * (self.rows - 1) * self.sectors + j)]
        }
    }

    /// The row of face `f`.
    pub fn row_of(&self, f: FaceId) -> u32 {
        (f.0 / (2 * self.sectors)).min(self.rows - 1)
    }

    /// Per face: on the boss (wall or top), the feature a band around the foot must find.
    pub fn boss_faces(&self) -> Vec<bool> {
        (0..self.mesh.face_count())
            .map(|f| self.row_of(FaceId(f)) >= self.foot)
            .collect()
    }
}

/// xorshift64, for deterministic random bands and noise.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// A value in `0..k`.
    pub fn below(&mut self, k: u64) -> u64 {
        self.next_u64() % k
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Standard normal (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u = 1.0 - self.unit();
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// A random band around ring `ring` (between rows `ring - 1` and `ring`), `width` rows wide in
/// every sector, starting a random 1..width-1 rows below the ring in each sector (so that it
/// zigzags but stays closed).
pub fn random_band(plate: &BossPlate, ring: u32, width: u32, rng: &mut Rng) -> Vec<FaceId> {
    let mut band = Vec::new();
    for j in 0..plate.sectors {
        let below = 1 + rng.below(width as u64 - 1) as u32;
        for k in ring - below..ring - below + width {
            band.extend(plate.faces_at(k, j));
        }
    }
    band
}

/// The mesh with isotropic Gaussian noise of `sigma` on every vertex.
pub fn with_noise(mesh: &PolyMesh, sigma: f64, rng: &mut Rng) -> PolyMesh {
    let mut out = mesh.clone();
    let moved = mesh
        .positions()
        .iter()
        .map(|&p| p + sigma * DVec3::new(rng.normal(), rng.normal(), rng.normal()))
        .collect();
    out.set_positions(moved).unwrap();
    out
}
