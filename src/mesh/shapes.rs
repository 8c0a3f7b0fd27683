//! Generated shapes with known counts, for tests, benchmarks and the demo.
//! Every face is wound counter-clockwise seen from outside.

use std::f64::consts::TAU;

use glam::DVec3;

use super::polymesh::PolyMesh;

fn build(positions: Vec<DVec3>, faces: Vec<Vec<u32>>) -> PolyMesh {
    PolyMesh::from_polygons(positions, faces).expect("generated shapes are valid")
}

/// An axis-aligned cube of edge `size` centred at the origin: 8 vertices, 6 quads.
pub fn cube(size: f64) -> PolyMesh {
    let h = size / 2.0;
    let p = (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 != 0 { h } else { -h },
                if i & 2 != 0 { h } else { -h },
                if i & 4 != 0 { h } else { -h },
            )
        })
        .collect();
    let faces = vec![
        vec![0, 2, 3, 1], // z = -h
        vec![4, 5, 7, 6], // z = +h
        vec![0, 1, 5, 4], // y = -h
        vec![2, 6, 7, 3], // y = +h
        vec![0, 4, 6, 2], // x = -h
        vec![1, 3, 7, 5], // x = +h
    ];
    build(p, faces)
}

/// A prism over a regular `n`-gon (n ≥ 3): 2n vertices, two n-gon caps and n quads.
pub fn ngon_prism(n: u32, radius: f64, height: f64) -> PolyMesh {
    assert!(n >= 3, "a prism needs n >= 3");
    let mut p = Vec::with_capacity(2 * n as usize);
    for z in [0.0, height] {
        for i in 0..n {
            let t = TAU * i as f64 / n as f64;
            p.push(DVec3::new(radius * t.cos(), radius * t.sin(), z));
        }
    }
    let mut faces = vec![(0..n).rev().collect::<Vec<_>>(), (n..2 * n).collect()];
    for i in 0..n {
        let j = (i + 1) % n;
        faces.push(vec![i, j, n + j, n + i]);
    }
    build(p, faces)
}

/// A torus of `m × n` quads (m around the main circle, n around the tube): genus 1,
/// m·n vertices, m·n faces, 2·m·n edges.
pub fn torus(m: u32, n: u32, major: f64, minor: f64) -> PolyMesh {
    assert!(m >= 3 && n >= 3, "a torus grid needs at least 3 × 3 quads");
    let mut p = Vec::with_capacity((m * n) as usize);
    for i in 0..m {
        let u = TAU * i as f64 / m as f64;
        for j in 0..n {
            let v = TAU * j as f64 / n as f64;
            let r = major + minor * v.cos();
            p.push(DVec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % m) * n + (j % n);
    let mut faces = Vec::with_capacity((m * n) as usize);
    for i in 0..m {
        for j in 0..n {
            faces.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(p, faces)
}

/// An open `m × n` grid of unit quads in the z = 0 plane, normal +z: one boundary loop,
/// (m+1)(n+1) vertices.
pub fn grid(m: u32, n: u32) -> PolyMesh {
    let mut p = Vec::with_capacity(((m + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=m {
            p.push(DVec3::new(i as f64, j as f64, 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (m + 1) + i;
    let mut faces = Vec::with_capacity((m * n) as usize);
    for j in 0..n {
        for i in 0..m {
            faces.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(p, faces)
}

/// A square plate `size × size × thickness` with a square through hole of side `hole`,
/// whose top and bottom faces are faces with holes (P loop + C loop, seed 001 §2):
/// 16 vertices, 10 faces (2 with a hole), 24 edges, genus 1.
pub fn plate_with_hole(size: f64, hole: f64, thickness: f64) -> PolyMesh {
    assert!(hole < size, "the hole must be smaller than the plate");
    let (a, b) = (size / 2.0, hole / 2.0);
    let square =
        |r: f64, z: f64| [(-r, -r), (r, -r), (r, r), (-r, r)].map(|(x, y)| DVec3::new(x, y, z));
    // 0..4 outer bottom, 4..8 outer top, 8..12 inner bottom, 12..16 inner top (all CCW from +z).
    let mut p = Vec::with_capacity(16);
    p.extend(square(a, 0.0));
    p.extend(square(a, thickness));
    p.extend(square(b, 0.0));
    p.extend(square(b, thickness));
    let top = vec![vec![4, 5, 6, 7], vec![15, 14, 13, 12]];
    let bottom = vec![vec![3, 2, 1, 0], vec![8, 9, 10, 11]];
    let mut faces = vec![top, bottom];
    for i in 0..4u32 {
        let j = (i + 1) % 4;
        faces.push(vec![vec![i, j, 4 + j, 4 + i]]); // outer wall, facing out
        faces.push(vec![vec![8 + j, 8 + i, 12 + i, 12 + j]]); // hole wall, facing the hole axis
    }
    PolyMesh::from_faces_with_holes(p, faces).expect("generated shapes are valid")
}

/// [`plate_with_hole`] with each face with holes cut into four trapezoids by the bridges
/// from its outer corners to the nearest hole corners (spec §5.4: the mesh on which method
/// \[a\] equals plain Catmull-Clark). 16 vertices, 16 quads, genus 1.
pub fn bridged_plate(size: f64, hole: f64, thickness: f64) -> PolyMesh {
    let plate = plate_with_hole(size, hole, thickness);
    let pos = |v: u32| plate.positions()[v as usize];
    let mut faces: Vec<Vec<u32>> = Vec::with_capacity(16);
    for f in plate.faces() {
        let loops: Vec<Vec<u32>> = plate
            .face_loops(f)
            .map(|l| plate.loop_vertices(l).iter().map(|v| v.0).collect())
            .collect();
        if loops.len() == 1 {
            faces.push(loops[0].clone());
            continue;
        }
        // Outer corner i sits diagonally outside its nearest hole corner (same quadrant).
        let (p, c) = (&loops[0], &loops[1]);
        let near = |pv: u32| -> u32 {
            *c.iter()
                .min_by(|&&x, &&y| {
                    (pos(x) - pos(pv))
                        .length()
                        .total_cmp(&(pos(y) - pos(pv)).length())
                })
                .expect("a hole has vertices")
        };
        for a in 0..4 {
            let (p0, p1) = (p[a], p[(a + 1) % 4]);
            faces.push(vec![p0, p1, near(p1), near(p0)]);
        }
    }
    build(plate.positions().to_vec(), faces)
}

/// [`plate_with_hole`] as a CAD boolean (box minus box) outputs it: every face triangulated
/// (the [`bridged_plate`] quads split along a diagonal). 16 vertices, 32 triangles, genus 1;
/// `merge_coplanar_regions` turns it back into the plate.
pub fn boolean_plate(size: f64, hole: f64, thickness: f64) -> PolyMesh {
    let quads = bridged_plate(size, hole, thickness);
    let tris: Vec<Vec<u32>> = quads
        .faces()
        .flat_map(|f| {
            let q: Vec<u32> = quads.face_outer(f).iter().map(|v| v.0).collect();
            [vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]]
        })
        .collect();
    build(quads.positions().to_vec(), tris)
}
