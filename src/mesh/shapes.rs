//! Generated shapes with known counts, for tests, benchmarks and the demo.
//! Every face is wound counter-clockwise seen from outside.
//!
//! Every parameter is checked before it sizes or places anything: a count too small for the
//! shape or too large for katachi's 32-bit indices, or a length that is not finite and
//! positive, is an [`Error::InvalidArgument`] naming the shape and the parameter.

use std::f64::consts::TAU;

use glam::DVec3;

use super::polymesh::PolyMesh;
use crate::error::{Error, Result};

fn build(positions: Vec<DVec3>, faces: Vec<Vec<u32>>) -> Result<PolyMesh> {
    PolyMesh::from_polygons(positions, faces)
}

fn invalid(shape: &str, message: String) -> Error {
    Error::InvalidArgument(format!("{shape}: {message}"))
}

/// `value` is finite and greater than 0.
fn positive(shape: &str, name: &str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            shape,
            format!("{name} is {value}; it must be finite and greater than 0"),
        ))
    }
}

/// `count` is at least `min`.
fn at_least(shape: &str, name: &str, count: u32, min: u32) -> Result<()> {
    if count >= min {
        Ok(())
    } else {
        Err(invalid(
            shape,
            format!("{name} is {count}; it must be at least {min}"),
        ))
    }
}

/// The product of `factors` (name, value) as a vertex or face count that katachi's 32-bit
/// indices can address.
fn count(shape: &str, what: &str, factors: &[(&str, u64)]) -> Result<u32> {
    let product = factors
        .iter()
        .try_fold(1u64, |acc, &(_, f)| acc.checked_mul(f))
        .filter(|&n| n <= u32::MAX as u64);
    product.map(|n| n as u32).ok_or_else(|| {
        let names: Vec<String> = factors.iter().map(|(n, v)| format!("{n} = {v}")).collect();
        invalid(
            shape,
            format!(
                "{} gives more {what} than katachi's 32-bit indices can address",
                names.join(", ")
            ),
        )
    })
}

/// An axis-aligned cube of edge `size` centred at the origin: 8 vertices, 6 quads.
///
/// Errors: `size` not finite and positive.
pub fn cube(size: f64) -> Result<PolyMesh> {
    positive("cube", "size", size)?;
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
///
/// Errors: `n` < 3 or 2n past the index range; `radius` or `height` not finite and positive.
pub fn ngon_prism(n: u32, radius: f64, height: f64) -> Result<PolyMesh> {
    const SHAPE: &str = "ngon_prism";
    at_least(SHAPE, "n", n, 3)?;
    count(SHAPE, "vertices", &[("2", 2), ("n", n as u64)])?;
    positive(SHAPE, "radius", radius)?;
    positive(SHAPE, "height", height)?;
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
///
/// Errors: `m` or `n` < 3, or m·n past the index range; `minor` not finite and positive, or
/// `major` not finite and greater than `minor` (the tube would pass through the axis), or
/// `major + minor` past the largest `f64`.
pub fn torus(m: u32, n: u32, major: f64, minor: f64) -> Result<PolyMesh> {
    const SHAPE: &str = "torus";
    at_least(SHAPE, "m", m, 3)?;
    at_least(SHAPE, "n", n, 3)?;
    let quads = count(SHAPE, "vertices", &[("m", m as u64), ("n", n as u64)])?;
    positive(SHAPE, "minor", minor)?;
    if !(major.is_finite() && major > minor) {
        return Err(invalid(
            SHAPE,
            format!("major is {major}; it must be finite and greater than minor ({minor})"),
        ));
    }
    if !(major + minor).is_finite() {
        return Err(invalid(
            SHAPE,
            format!("major + minor ({major} + {minor}) is past the largest f64"),
        ));
    }
    let mut p = Vec::with_capacity(quads as usize);
    for i in 0..m {
        let u = TAU * i as f64 / m as f64;
        for j in 0..n {
            let v = TAU * j as f64 / n as f64;
            let r = major + minor * v.cos();
            p.push(DVec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % m) * n + (j % n);
    let mut faces = Vec::with_capacity(quads as usize);
    for i in 0..m {
        for j in 0..n {
            faces.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(p, faces)
}

/// An open `m × n` grid of unit quads in the z = 0 plane, normal +z: one boundary loop,
/// (m+1)(n+1) vertices.
///
/// Errors: `m` or `n` 0, or (m+1)(n+1) past the index range.
pub fn grid(m: u32, n: u32) -> Result<PolyMesh> {
    const SHAPE: &str = "grid";
    at_least(SHAPE, "m", m, 1)?;
    at_least(SHAPE, "n", n, 1)?;
    let vertices = count(
        SHAPE,
        "vertices",
        &[("m + 1", m as u64 + 1), ("n + 1", n as u64 + 1)],
    )?;
    let mut p = Vec::with_capacity(vertices as usize);
    for j in 0..=n {
        for i in 0..=m {
            p.push(DVec3::new(i as f64, j as f64, 0.0));
        }
    }
    let id = |i: u32, j: u32| j * (m + 1) + i;
    let mut faces = Vec::with_capacity(m as usize * n as usize);
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
///
/// Errors: a length not finite and positive, or `hole` not smaller than `size`.
pub fn plate_with_hole(size: f64, hole: f64, thickness: f64) -> Result<PolyMesh> {
    plate_parameters("plate_with_hole", size, hole, thickness)?;
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
    PolyMesh::from_faces_with_holes(p, faces)
}

fn plate_parameters(shape: &str, size: f64, hole: f64, thickness: f64) -> Result<()> {
    positive(shape, "size", size)?;
    positive(shape, "hole", hole)?;
    positive(shape, "thickness", thickness)?;
    if hole < size {
        Ok(())
    } else {
        Err(invalid(
            shape,
            format!("hole is {hole}; it must be smaller than size ({size})"),
        ))
    }
}

/// [`plate_with_hole`] with each face with holes cut into four trapezoids by the bridges
/// from its outer corners to the nearest hole corners (spec §5.4: the mesh on which method
/// \[a\] equals plain Catmull-Clark). 16 vertices, 16 quads, genus 1.
///
/// Errors: as [`plate_with_hole`].
pub fn bridged_plate(size: f64, hole: f64, thickness: f64) -> Result<PolyMesh> {
    plate_parameters("bridged_plate", size, hole, thickness)?;
    let plate = plate_with_hole(size, hole, thickness)?;
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
            c.iter()
                .copied()
                .min_by(|&x, &y| {
                    (pos(x) - pos(pv))
                        .length()
                        .total_cmp(&(pos(y) - pos(pv)).length())
                })
                .unwrap_or(pv)
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
///
/// Errors: as [`plate_with_hole`].
pub fn boolean_plate(size: f64, hole: f64, thickness: f64) -> Result<PolyMesh> {
    plate_parameters("boolean_plate", size, hole, thickness)?;
    let quads = bridged_plate(size, hole, thickness)?;
    let tris: Vec<Vec<u32>> = quads
        .faces()
        .flat_map(|f| {
            let q: Vec<u32> = quads.face_outer(f).iter().map(|v| v.0).collect();
            [vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]]
        })
        .collect();
    build(quads.positions().to_vec(), tris)
}
