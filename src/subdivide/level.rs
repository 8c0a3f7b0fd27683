//! One level of a subdivision hierarchy, in flat face–edge arrays (the layout of OpenSubdiv's
//! Vtr levels): faces → loops → corners, each corner knowing its vertex and the edge to the
//! next corner, each edge its two vertices and sharpness. Positions are computed by scatter
//! passes over these arrays (see `refine.rs`), so no vertex ring is ever walked.
//!
//! Numbering follows OpenSubdiv's uniform refinement (default options), so that outputs can
//! be compared index by index: edges are numbered by first use in corner order.

use super::crease::INFINITE;
use super::options::{BoundaryInterpolation, SubdivideOptions};
use crate::error::Result;
use crate::mem::Buf;
use crate::mesh::PolyMesh;
use rayon::prelude::*;

#[derive(Debug, Clone, Default)]
pub(crate) struct Level {
    pub vertex_count: u32,
    /// F + 1 offsets into `loop_offsets`.
    pub face_loops: Buf<u32>,
    /// L + 1 offsets into the corner arrays.
    pub loop_offsets: Buf<u32>,
    pub corner_verts: Buf<u32>,
    /// The edge from each corner to the next corner of its loop.
    pub corner_edges: Buf<u32>,
    pub edge_verts: Buf<[u32; 2]>,
    /// User sharpness, or [`INFINITE`] where `edge_forced` is set.
    pub edge_sharpness: Buf<f32>,
    /// Sharp because of topology (boundary, non-manifold), not because the user said so.
    pub edge_forced: Buf<bool>,
    pub vertex_sharpness: Buf<f32>,
    /// Pinned because of topology (boundary corner, non-manifold vertex).
    pub vertex_forced: Buf<bool>,
    /// Whether any vertex has sharpness > 0 (user's or forced), so that smooth levels skip
    /// every per-vertex sharpness pass.
    pub any_vertex_sharp: bool,
    /// Faces kept whole (faces with holes under method [b]): not split, loops refined.
    /// Empty when no face is kept.
    pub face_kept: Vec<bool>,
    /// Input face each face descends from.
    pub face_origin: Buf<u32>,
    /// In a last level (built without edges): the edges that are still creased.
    pub last_creases: Vec<([u32; 2], f32)>,
}

impl Level {
    pub fn face_count(&self) -> u32 {
        (self.face_loops.len() - 1) as u32
    }
    pub fn edge_count(&self) -> u32 {
        self.edge_verts.len() as u32
    }

    /// Whether face `f` is kept whole.
    #[inline]
    pub fn is_kept(&self, f: usize) -> bool {
        !self.face_kept.is_empty() && self.face_kept[f]
    }

    /// The corners of face `f` when it has a single loop.
    #[inline]
    pub fn face_corners(&self, f: usize) -> std::ops::Range<usize> {
        let l = self.face_loops[f] as usize;
        self.loop_offsets[l] as usize..self.loop_offsets[l + 1] as usize
    }

    /// Level 0 from a validated mesh, and the user's sharpness of each of its edges (empty
    /// when the mesh has none; level 0 itself keeps only what the topology does not force).
    /// Faces with holes are kept whole (their loop edges become infinitely sharp, seed 001
    /// §3.2 method [b]); method [a] has bridged the others before this.
    pub fn from_mesh(mesh: &PolyMesh, options: &SubdivideOptions) -> Result<(Level, Vec<f32>)> {
        let corners: Vec<u32> = mesh.corners().iter().map(|v| v.0).collect();
        let vertex_sharpness: Vec<f32> = mesh
            .vertex_sharpness()
            .iter()
            .map(|&s| (s as f32).min(INFINITE))
            .collect();
        Ok(Level::from_corners(
            mesh.vertex_count() as usize,
            mesh.face_loop_offsets().to_vec(),
            mesh.loop_offsets().to_vec(),
            corners,
            Creases::Pairs(&mut mesh.sharp_edges().map(|(a, b, s)| (a.0, b.0, s))),
            vertex_sharpness,
            options.boundary,
        ))
    }

    /// Level 0 from flat arrays known to be valid (every loop at least three distinct
    /// vertices below `nv`): `face_loops` and `loop_offsets` as [`PolyMesh`]'s, the user's
    /// edge `creases` and `vertex_sharpness` (one per vertex, already clamped to
    /// [`INFINITE`]). Faces with more than one loop are kept whole, as in
    /// [`Level::from_mesh`]. Returns the level and, for `Creases::Pairs`, the user's
    /// sharpness per edge (empty when no pair is an edge).
    pub fn from_corners(
        nv: usize,
        face_loops: Vec<u32>,
        loop_offsets: Vec<u32>,
        corners: Vec<u32>,
        creases: Creases<'_>,
        mut vertex_sharpness: Vec<f32>,
        boundary: BoundaryInterpolation,
    ) -> (Level, Vec<f32>) {
        debug_assert_eq!(vertex_sharpness.len(), nv);
        let n = corners.len();
        // Next and previous vertex of each corner in its loop; beside them, corners counted
        // per vertex.
        let next_prev = || {
            let (mut head, mut tail) = (vec![0u32; n], vec![0u32; n]);
            for w in loop_offsets.windows(2) {
                let (a, b) = (w[0] as usize, w[1] as usize);
                head[a..b - 1].copy_from_slice(&corners[a + 1..b]);
                head[b - 1] = corners[a];
                tail[a + 1..b].copy_from_slice(&corners[a..b - 1]);
                tail[a] = corners[b - 1];
            }
            (head, tail)
        };
        let counts = || {
            let mut start = vec![0u32; nv + 1];
            for &v in &corners {
                start[v as usize + 1] += 1;
            }
            for i in 0..nv {
                start[i + 1] += start[i];
            }
            start
        };
        let ((head, tail), start) = rayon::join(next_prev, counts);
        // Corners bucketed by vertex (counting sort), each with its next and previous vertex
        // beside it: the scans below then read each bucket contiguously. Two halves of the
        // vertices fill their own buckets side by side, each reading every corner.
        let mut at = vec![[0u32; 3]; n];
        let mid = nv / 2;
        let (low, high) = at.split_at_mut(start[mid] as usize);
        let fill = |out: &mut [[u32; 3]], vertices: std::ops::Range<usize>| {
            let base = start[vertices.start];
            let mut next: Vec<u32> = start[vertices.clone()].iter().map(|&s| s - base).collect();
            for (k, &v) in corners.iter().enumerate() {
                if vertices.contains(&(v as usize)) {
                    let slot = &mut next[v as usize - vertices.start];
                    out[*slot as usize] = [k as u32, head[k], tail[k]];
                    *slot += 1;
                }
            }
        };
        if rayon::current_num_threads() > 1 {
            rayon::join(|| fill(low, 0..mid), || fill(high, mid..nv));
        } else {
            fill(&mut at, 0..nv);
        }
        let bucket = |v: u32| &at[start[v as usize] as usize..start[v as usize + 1] as usize];

        // Edges by first use in corner order, counting the face sides of each; beside it,
        // whether each vertex's corners form one fan (each vertex on its own, in parallel).
        let edges = || {
            let mut corner_edges = vec![u32::MAX; n];
            let mut edge_verts = Vec::with_capacity(n / 2 + 8);
            let mut edge_forced = Vec::with_capacity(n / 2 + 8);
            for k in 0..n {
                if corner_edges[k] != u32::MAX {
                    continue;
                }
                let (a, b) = (corners[k], head[k]);
                let e = edge_verts.len() as u32;
                let mut sides = 0u32;
                let mut same_direction = 0u32;
                for &[j, next, _] in bucket(a) {
                    if next == b {
                        corner_edges[j as usize] = e;
                        sides += 1;
                        same_direction += 1;
                    }
                }
                for &[j, next, _] in bucket(b) {
                    if next == a {
                        corner_edges[j as usize] = e;
                        sides += 1;
                    }
                }
                edge_verts.push([a, b]);
                // Boundary, non-manifold, or traversed twice the same way: infinitely sharp
                // (OpenSubdiv's treatment; spec §4.1, §4.2).
                edge_forced.push(sides != 2 || same_direction != 1);
            }
            (corner_edges, edge_verts, edge_forced)
        };
        let fans = || -> Vec<bool> {
            (0..nv)
                .into_par_iter()
                .with_min_len(4096)
                .map(|v| single_fan(&at[start[v] as usize..start[v + 1] as usize]))
                .collect()
        };
        let ((corner_edges, edge_verts, edge_forced), fans) = rayon::join(edges, fans);
        let ne = edge_verts.len();
        let mut edge_sharpness: Vec<f32> = edge_forced
            .iter()
            .map(|&f| if f { INFINITE } else { 0.0 })
            .collect();
        let mut user_edges = Vec::new();
        match creases {
            Creases::Pairs(pairs) => {
                let find_edge = |a: u32, b: u32| -> Option<u32> {
                    bucket(a)
                        .iter()
                        .find(|c| c[1] == b)
                        .or_else(|| bucket(b).iter().find(|c| c[1] == a))
                        .map(|c| corner_edges[c[0] as usize])
                };
                for (a, b, s) in pairs {
                    if let Some(e) = find_edge(a, b) {
                        let (e, s) = (e as usize, (s as f32).min(INFINITE));
                        if user_edges.is_empty() {
                            user_edges = vec![0.0; ne];
                        }
                        user_edges[e] = s;
                        if !edge_forced[e] {
                            edge_sharpness[e] = s;
                        }
                    }
                }
            }
            Creases::PerCorner(values) => {
                debug_assert!(values.is_empty() || values.len() == n);
                for (k, &s) in values.iter().enumerate() {
                    let e = corner_edges[k] as usize;
                    if s > 0.0 && !edge_forced[e] {
                        edge_sharpness[e] = s.min(INFINITE);
                    }
                }
            }
        }

        // Faces kept whole: their loop edges become infinitely sharp.
        let face_count = face_loops.len() - 1;
        let mut face_kept = vec![false; face_count];
        // Only faces with holes are kept: none when there are as many loops as faces.
        let any_holes = loop_offsets.len() - 1 > face_count;
        for f in (0..face_count).filter(|_| any_holes) {
            if face_loops[f + 1] - face_loops[f] > 1 {
                face_kept[f] = true;
                let (l0, l1) = (face_loops[f] as usize, face_loops[f + 1] as usize);
                for c in loop_offsets[l0] as usize..loop_offsets[l1] as usize {
                    edge_sharpness[corner_edges[c] as usize] = INFINITE;
                }
            }
        }

        // Vertices: user sharpness; pinned where the topology says corner.
        let mut vertex_forced = vec![false; nv];
        if boundary == BoundaryInterpolation::EdgeAndCorner {
            // A boundary vertex with a single face is a corner.
            for v in 0..nv as u32 {
                let b = bucket(v);
                if b.len() == 1 && edge_forced[corner_edges[b[0][0] as usize] as usize] {
                    vertex_forced[v as usize] = true;
                }
            }
        }
        drop((head, tail));
        for (v, single) in fans.into_iter().enumerate() {
            if !single {
                vertex_forced[v] = true;
            }
        }
        for v in 0..nv {
            if vertex_forced[v] {
                vertex_sharpness[v] = INFINITE;
            }
        }
        debug_assert_eq!(edge_sharpness.len(), ne);
        let any_vertex_sharp = vertex_sharpness.iter().any(|&s| s > 0.0);
        let level = Level {
            any_vertex_sharp,
            vertex_count: nv as u32,
            face_loops: face_loops.into(),
            loop_offsets: loop_offsets.into(),
            corner_verts: corners.into(),
            corner_edges: corner_edges.into(),
            edge_verts: edge_verts.into(),
            edge_sharpness: edge_sharpness.into(),
            edge_forced: edge_forced.into(),
            vertex_sharpness: vertex_sharpness.into(),
            vertex_forced: vertex_forced.into(),
            face_kept: if face_kept.contains(&true) {
                face_kept
            } else {
                Vec::new()
            },
            face_origin: (0..face_count as u32).collect::<Vec<_>>().into(),
            last_creases: Vec::new(),
        };
        (level, user_edges)
    }
}

/// The user's edge sharpness given to [`Level::from_corners`].
pub(crate) enum Creases<'a> {
    /// `(a, b, sharpness)` for edges between vertices `a` and `b`; pairs that are no edge
    /// are ignored.
    Pairs(&'a mut dyn Iterator<Item = (u32, u32, f64)>),
    /// One value per corner: the sharpness of the edge from it to the next corner of its loop
    /// (empty: none).
    PerCorner(&'a [f32]),
}

/// Whether the corners at one vertex (`at_v`: corner, next vertex, previous vertex) form one
/// fan. Fast path: the chain "next vertex of one corner = previous vertex of the next corner"
/// visits every corner. Otherwise (two fans touching, or non-manifold edges) faces are
/// grouped across any shared edge at the vertex, and one group is one fan, as `Topology`
/// defines a non-manifold vertex.
fn single_fan(at_v: &[[u32; 3]]) -> bool {
    let d = at_v.len();
    if d <= 1 {
        return true;
    }
    let succ = |i: usize| at_v.iter().position(|c| c[2] == at_v[i][1]);
    let start = (0..d)
        .find(|&i| !at_v.iter().any(|c| c[1] == at_v[i][2]))
        .unwrap_or(0);
    let (mut cur, mut visited) = (start, 1);
    while let Some(j) = succ(cur) {
        if j == start || visited > d {
            break;
        }
        cur = j;
        visited += 1;
    }
    if visited == d {
        return true;
    }
    let mut group: Vec<usize> = (0..d).collect();
    fn root(g: &mut [usize], mut x: usize) -> usize {
        while g[x] != x {
            g[x] = g[g[x]];
            x = g[x];
        }
        x
    }
    for i in 0..d {
        for j in i + 1..d {
            let ends_i = [at_v[i][1], at_v[i][2]];
            if ends_i.contains(&at_v[j][1]) || ends_i.contains(&at_v[j][2]) {
                let (a, b) = (root(&mut group, i), root(&mut group, j));
                group[a.max(b)] = a.min(b);
            }
        }
    }
    (0..d).filter(|&i| root(&mut group, i) == i).count() == 1
}
