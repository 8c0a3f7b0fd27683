//! Entry checks for [`super::PolyMesh`]: each returns the first fault, naming the element.

use glam::DVec3;

use super::ids::VertexId;
use crate::error::{Axis, Error, Result};

/// Every coordinate finite.
pub(crate) fn positions(positions: &[DVec3]) -> Result<()> {
    for (i, p) in positions.iter().enumerate() {
        if !p.is_finite() {
            let (axis, value) = [(Axis::X, p.x), (Axis::Y, p.y), (Axis::Z, p.z)]
                .into_iter()
                .find(|(_, c)| !c.is_finite())
                .expect("a non-finite vector has a non-finite coordinate");
            return Err(Error::NonFiniteCoordinate {
                vertex: i as u32,
                axis,
                value,
            });
        }
    }
    Ok(())
}

/// An operation's result positions are finite; otherwise [`Error::CoordinateOverflow`]
/// naming the input vertex with the largest coordinate (the input is finite, so only its size
/// can have made the arithmetic overflow).
pub(crate) fn result_positions(
    operation: &'static str,
    input: &[DVec3],
    result: &[DVec3],
) -> Result<()> {
    if result.iter().all(|p| p.is_finite()) {
        return Ok(());
    }
    let mut worst = (0u32, Axis::X, 0.0f64);
    for (i, p) in input.iter().enumerate() {
        for (axis, c) in [(Axis::X, p.x), (Axis::Y, p.y), (Axis::Z, p.z)] {
            if c.abs() > worst.2.abs() {
                worst = (i as u32, axis, c);
            }
        }
    }
    Err(Error::CoordinateOverflow {
        operation,
        vertex: worst.0,
        axis: worst.1,
        value: worst.2,
    })
}

/// Offsets monotone and in bounds; every face has a loop; every loop has ≥ 3 distinct
/// in-range vertices and none repeated.
pub(crate) fn faces(
    vertex_count: usize,
    face_loop_offsets: &[u32],
    loop_offsets: &[u32],
    corners: &[VertexId],
) -> Result<()> {
    let bad = |m: &str| {
        Err(Error::InconsistentArrays {
            message: m.to_string(),
        })
    };
    if face_loop_offsets.first() != Some(&0) || loop_offsets.first() != Some(&0) {
        return bad("offset arrays must start at 0");
    }
    if *face_loop_offsets.last().unwrap() as usize != loop_offsets.len() - 1 {
        return bad("face loop offsets do not end at the number of loops");
    }
    if *loop_offsets.last().unwrap() as usize != corners.len() {
        return bad("loop offsets do not end at the number of corners");
    }
    let mut scratch: Vec<u32> = Vec::new();
    for (f, w) in face_loop_offsets.windows(2).enumerate() {
        let face = f as u32;
        if w[1] < w[0] {
            return bad(&format!("face {face}: loop offsets decrease"));
        }
        if w[1] == w[0] {
            return Err(Error::FaceWithoutLoops { face });
        }
        for (k, l) in (w[0]..w[1]).enumerate() {
            let (a, b) = (loop_offsets[l as usize], loop_offsets[l as usize + 1]);
            if b < a {
                return bad(&format!("face {face}, loop {k}: corner offsets decrease"));
            }
            check_loop(
                face,
                k as u32,
                &corners[a as usize..b as usize],
                vertex_count,
                &mut scratch,
            )?;
        }
    }
    Ok(())
}

fn check_loop(
    face: u32,
    loop_index: u32,
    lp: &[VertexId],
    vertex_count: usize,
    scratch: &mut Vec<u32>,
) -> Result<()> {
    for v in lp {
        if v.idx() >= vertex_count {
            return Err(Error::VertexOutOfRange {
                face,
                loop_index,
                index: v.0 as u64,
                vertex_count: vertex_count as u32,
            });
        }
    }
    let (distinct, repeated) = if lp.len() <= 8 {
        // Small loops (nearly all of them): pairwise, no sorting.
        let mut distinct = lp.len() as u32;
        let mut repeated = None;
        for i in 1..lp.len() {
            if lp[..i].contains(&lp[i]) {
                distinct -= 1;
                repeated.get_or_insert(lp[i].0);
            }
        }
        (distinct, repeated)
    } else {
        scratch.clear();
        scratch.extend(lp.iter().map(|v| v.0));
        scratch.sort_unstable();
        let mut distinct = scratch.len() as u32;
        let mut repeated = None;
        for w in scratch.windows(2) {
            if w[0] == w[1] {
                distinct -= 1;
                repeated.get_or_insert(w[0]);
            }
        }
        (distinct, repeated)
    };
    if distinct < 3 {
        return Err(Error::DegenerateLoop {
            face,
            loop_index,
            distinct,
        });
    }
    if let Some(vertex) = repeated {
        return Err(Error::RepeatedVertex {
            face,
            loop_index,
            vertex,
        });
    }
    Ok(())
}
