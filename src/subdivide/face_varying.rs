//! Face-varying interpolation (UV maps), with OpenSubdiv's linear-interpolation choices,
//! which are also Blender's "UV Smooth" menu.
//!
//! The smooth modes refine the UV topology itself: a mesh whose vertices are the distinct
//! UV values (so seams are boundaries) and whose faces are the input faces, carrying the
//! input's creases. Its faces refine in the same order as the input's, so output corners
//! correspond one to one.

use super::crease::INFINITE;
use super::level::{Creases, Level};
use super::options::BoundaryInterpolation;
use super::prepare::Prepared;
use super::primvar::Primvar;
use super::refiner::{Input, Refiner};
use crate::error::{Error, Result};

/// How face-varying data is interpolated (OpenSubdiv `FVarLinearInterpolation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FaceVarying {
    /// Smooth everywhere; UV boundaries smoothed along themselves (OpenSubdiv
    /// `FVAR_LINEAR_NONE`; Blender "All").
    Smooth,
    /// Smooth, UV corners pinned (OpenSubdiv `FVAR_LINEAR_CORNERS_ONLY`; Blender "Keep Corners").
    LinearCornersOnly,
    /// Smooth inside UV islands, linear along their boundaries (OpenSubdiv
    /// `FVAR_LINEAR_BOUNDARIES`; Blender "Keep Boundaries").
    LinearBoundaries,
    /// Bilinear everywhere (OpenSubdiv `FVAR_LINEAR_ALL`; Blender "None").
    LinearAll,
}

pub(crate) fn refine<T: Primvar>(
    refiner: &Refiner,
    values: &[T],
    indices: &[u32],
    mode: FaceVarying,
) -> Result<Vec<T>> {
    let expected = refiner.input_corner_count() as usize;
    if indices.len() != expected {
        return Err(Error::AttributeLength {
            attribute: "face-varying indices",
            per: "face corner",
            expected,
            got: indices.len(),
        });
    }
    if let Some((k, &i)) = indices
        .iter()
        .enumerate()
        .find(|(_, &i)| i as usize >= values.len())
    {
        return Err(Error::InvalidArgument(format!(
            "face-varying index {i} at corner {k} is out of range ({} values)",
            values.len()
        )));
    }
    // Level 0 may differ from the input (recovered or bridged faces): follow its corners.
    let mapped: Vec<u32>;
    let indices = match refiner.corner_origin() {
        None => indices,
        Some(o) => {
            mapped = o.iter().map(|&k| indices[k as usize]).collect();
            &mapped
        }
    };
    Ok(refine_level0(refiner, values, indices, mode)?.into_per_corner())
}

/// Refined face-varying data: one value per output corner, or values shared by corners
/// through an index (the smooth modes' refined UV topology), which callers read without
/// gathering them first.
pub(crate) enum Refined<T> {
    PerCorner(Vec<T>),
    Indexed { values: Vec<T>, corners: Vec<u32> },
}

impl<T: Clone> Refined<T> {
    /// The value of output corner `k`.
    #[inline]
    pub fn at(&self, k: usize) -> &T {
        match self {
            Refined::PerCorner(v) => &v[k],
            Refined::Indexed { values, corners } => &values[corners[k] as usize],
        }
    }

    fn into_per_corner(self) -> Vec<T> {
        match self {
            Refined::PerCorner(v) => v,
            Refined::Indexed { values, corners } => corners
                .iter()
                .map(|&i| values[i as usize].clone())
                .collect(),
        }
    }
}

/// [`refine`] with one index per level-0 corner (checked by the caller to be in range).
pub(crate) fn refine_level0<T: Primvar>(
    refiner: &Refiner,
    values: &[T],
    indices: &[u32],
    mode: FaceVarying,
) -> Result<Refined<T>> {
    match mode {
        FaceVarying::LinearAll => Ok(Refined::PerCorner(bilinear(refiner, values, indices))),
        _ => smooth(refiner, values, indices, mode),
    }
}

/// Per-corner data of `k` components (`values`: `k` per input corner, in the input's corner
/// order) as face-varying data: corners at the same vertex with the same value (bit for bit)
/// share one value, so the data's seams are where the values differ, as a host's UV map has
/// them. Returns the distinct values (`k` each) and one index per level-0 corner.
pub(crate) fn weld(refiner: &Refiner, values: &[f64], k: usize) -> (Vec<f64>, Vec<u32>) {
    let l0 = refiner.level(0);
    let n = l0.corner_verts.len();
    let nv = l0.vertex_count as usize;
    let input_corner = |j: usize| match refiner.corner_origin() {
        None => j,
        Some(o) => o[j] as usize,
    };
    // Level-0 corners by vertex (counting sort), so that each vertex's few corners are
    // compared with each other only.
    let mut start = vec![0u32; nv + 1];
    for &v in l0.corner_verts.iter() {
        start[v as usize + 1] += 1;
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut by_vertex = vec![0u32; n];
    let mut fill = start.clone();
    for (j, &v) in l0.corner_verts.iter().enumerate() {
        by_vertex[fill[v as usize] as usize] = j as u32;
        fill[v as usize] += 1;
    }
    let value = |j: usize| {
        let i = input_corner(j);
        &values[k * i..k * i + k]
    };
    let same = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
    let mut unique: Vec<f64> = Vec::with_capacity(values.len() / 2);
    let mut indices = vec![0u32; n];
    let mut seen: Vec<(u32, u32)> = Vec::new(); // (corner, index) of this vertex's values
    for v in 0..nv {
        seen.clear();
        for &j in &by_vertex[start[v] as usize..start[v + 1] as usize] {
            let val = value(j as usize);
            let found = seen
                .iter()
                .find(|&&(c, _)| same(value(c as usize), val))
                .map(|&(_, i)| i);
            let i = found.unwrap_or_else(|| {
                unique.extend_from_slice(val);
                let i = (unique.len() / k - 1) as u32;
                seen.push((j, i));
                i
            });
            indices[j as usize] = i;
        }
    }
    (unique, indices)
}

/// Bilinear: a child corner takes its parent corner's value, the average of the two corners
/// of its edge, or the face's average.
fn bilinear<T: Primvar>(refiner: &Refiner, values: &[T], indices: &[u32]) -> Vec<T> {
    let mut cur: Vec<T> = indices
        .iter()
        .map(|&i| values[i as usize].clone())
        .collect();
    for l in 0..refiner.levels() as usize {
        let parent: &Level = refiner.level(l);
        let mut next = Vec::with_capacity(cur.len() * 4);
        let mid = |a: &T, b: &T| {
            let mut m = a.scaled(0.5);
            m.add_scaled(b, 0.5);
            m
        };
        for f in 0..parent.face_count() as usize {
            let (l0, l1) = (
                parent.face_loops[f] as usize,
                parent.face_loops[f + 1] as usize,
            );
            if parent.is_kept(f) {
                for lp in l0..l1 {
                    let (a, b) = (
                        parent.loop_offsets[lp] as usize,
                        parent.loop_offsets[lp + 1] as usize,
                    );
                    for c in a..b {
                        let n = if c + 1 < b { c + 1 } else { a };
                        next.push(cur[c].clone());
                        next.push(mid(&cur[c], &cur[n]));
                    }
                }
                continue;
            }
            let cs = parent.face_corners(f);
            let mut centre = T::zero();
            let w = 1.0 / cs.len() as f64;
            for c in cs.clone() {
                centre.add_scaled(&cur[c], w);
            }
            let k = cs.len();
            for (j, c) in cs.clone().enumerate() {
                let n = if c + 1 < cs.end { c + 1 } else { cs.start };
                let p = if c == cs.start { cs.end - 1 } else { c - 1 };
                let mut quad = [
                    cur[c].clone(),
                    mid(&cur[c], &cur[n]),
                    centre.clone(),
                    mid(&cur[p], &cur[c]),
                ];
                if k == 4 {
                    quad.rotate_right(j); // as the child faces (see refine.rs)
                }
                next.extend(quad);
            }
        }
        cur = next;
    }
    cur
}

/// The smooth modes: refine the UV topology as a mesh of its own, level 0's faces with
/// the values' indices as vertices, carrying level 0's creases (the user's, not those the
/// vertex topology forces: the UV topology has its own boundaries) and, at each value, the
/// largest sharpness of the vertices it is used at.
fn smooth<T: Primvar>(
    refiner: &Refiner,
    values: &[T],
    indices: &[u32],
    mode: FaceVarying,
) -> Result<Refined<T>> {
    let l0 = refiner.level(0);
    check_distinct_in_loops(l0, indices)?;
    let input = refiner.input();
    let nv = values.len();
    let creases: Vec<f32> = if input.user_edge_sharpness.is_empty() {
        Vec::new()
    } else {
        l0.corner_edges
            .iter()
            .map(|&e| input.user_edge_sharpness[e as usize])
            .collect()
    };
    let mut vertex_sharpness = vec![0.0f32; nv];
    if let Some(user) = &input.user_vertex_sharpness {
        for (k, &i) in indices.iter().enumerate() {
            let s = user[l0.corner_verts[k] as usize].min(INFINITE);
            vertex_sharpness[i as usize] = vertex_sharpness[i as usize].max(s);
        }
    }
    let boundary = match mode {
        FaceVarying::LinearCornersOnly => BoundaryInterpolation::EdgeAndCorner,
        _ => BoundaryInterpolation::EdgeOnly,
    };
    let (mut uv0, _) = Level::from_corners(
        nv,
        l0.face_loops.to_vec(),
        l0.loop_offsets.to_vec(),
        indices.to_vec(),
        Creases::PerCorner(&creases),
        vertex_sharpness,
        boundary,
    );
    if mode == FaceVarying::LinearBoundaries {
        // Every value on a UV boundary (an edge one face uses) is pinned.
        let mut sides = vec![0u8; uv0.edge_count() as usize];
        for &e in uv0.corner_edges.iter() {
            sides[e as usize] = sides[e as usize].saturating_add(1);
        }
        for (e, &[a, b]) in uv0.edge_verts.iter().enumerate() {
            if sides[e] == 1 {
                uv0.vertex_sharpness[a as usize] = INFINITE;
                uv0.vertex_sharpness[b as usize] = INFINITE;
                uv0.any_vertex_sharp = true;
            }
        }
    }
    let mut options = refiner.options().clone();
    options.boundary = boundary;
    let uv_input = Input {
        vertices: nv as u32,
        faces: l0.face_count(),
        corners: indices.len() as u32,
        ..Default::default()
    };
    let (uv_refiner, refined) = Refiner::from_level0(
        uv0,
        Prepared::identity(),
        uv_input,
        &options,
        Default::default(),
        Some(values.to_vec().into()),
        &mut |_, _| {},
    );
    let values = refined.expect("values were given");
    let corners = uv_refiner.into_last_corners();
    debug_assert_eq!(corners.len(), refiner.corner_count() as usize);
    Ok(Refined::Indexed { values, corners })
}

/// Fails unless every loop's corners have distinct indices (a UV topology of valid faces).
fn check_distinct_in_loops(level: &Level, indices: &[u32]) -> Result<()> {
    for w in level.loop_offsets.windows(2) {
        let lp = &indices[w[0] as usize..w[1] as usize];
        let repeated = if lp.len() <= 16 {
            (1..lp.len()).any(|i| lp[..i].contains(&lp[i]))
        } else {
            let mut sorted = lp.to_vec();
            sorted.sort_unstable();
            sorted.windows(2).any(|p| p[0] == p[1])
        };
        if repeated {
            return Err(Error::InvalidArgument(format!(
                "face-varying indices do not form valid faces: a loop uses value indices {lp:?}, \
                 one of them twice"
            )));
        }
    }
    Ok(())
}
