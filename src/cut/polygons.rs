//! The cut in the input's own layout, for hosts that store polygons and an edge list
//! (Blender, C programs): [`CutOutput::polygons`].
//!
//! A host that rebuilt the cut's triangles into its own mesh had to find out, element by
//! element, which faces were untouched, which edge of the result lies on which of its
//! edges, and which corner keeps which UV. The kernel knows all of it, so it says it, as
//! arrays a host copies (gap-fill: the paper cuts a triangle mesh and says nothing of the
//! data around it):
//!
//! - Faces keep their index: output face `f < input faces` comes from input face `f`; a face
//!   the cut left alone is given back as the polygon it was (with `keep_polygons`), a face it
//!   touched as its triangles, the first in slot `f`, the others appended with their
//!   [`CutPolygons::face_origin`].
//! - Edges keep the host's index: output edge `e < input edges` is the host's edge `e` (a
//!   split edge keeps the piece at its first vertex); pieces, copies made by opening, and
//!   the edges the cut or the triangulation made inside faces follow, each with its input
//!   edge or [`NONE`] ([`CutPolygons::edge_origin`]). Loose edges stay as they were.
//! - Corners: each output corner's input corner where it sits at an input vertex (or an
//!   opening copy of one) of the face it lies in, else [`NONE`] and a blend of the source
//!   triangle's corners ([`CutPolygons::carry_corner_data`]).

use std::collections::HashMap;

use glam::DVec3;

use super::interpolate::barycentric;
use super::report::CutOutput;
use crate::error::{Error, Result};
use crate::mesh::PolyMesh;

/// No input element: a new edge, or a corner at a new vertex.
pub const NONE: u32 = u32::MAX;

/// The host's edges of the input mesh: `edges[e]` is edge `e`'s vertex pair, and
/// `corner_edges[k]` the edge from corner `k` to the next corner of its loop (corners in
/// `PolyMesh::corners` order). Edges no corner names are loose: they stay as they are.
#[derive(Debug, Clone, Copy)]
pub struct InputEdges<'a> {
    /// Vertex pairs, one per host edge.
    pub edges: &'a [[u32; 2]],
    /// One edge per input corner.
    pub corner_edges: &'a [u32],
}

/// A cut given as the arrays a polygon host stores (module docs).
#[derive(Debug, Clone, Default)]
pub struct CutPolygons {
    /// Output positions: the input's (snapped ones moved), then the new vertices.
    pub positions: Vec<DVec3>,
    /// Face `f`'s corners are `corners[face_offsets[f]..face_offsets[f + 1]]`.
    pub face_offsets: Vec<u32>,
    /// Output vertex of each corner.
    pub corners: Vec<u32>,
    /// Input face of each output face.
    pub face_origin: Vec<u32>,
    /// Input corner of each output corner, or [`NONE`] (blended, see
    /// [`CutPolygons::carry_corner_data`]).
    pub corner_origin: Vec<u32>,
    /// Vertex pairs of the output edges.
    pub edges: Vec<[u32; 2]>,
    /// Input edge each output edge lies on (pieces, copies), or [`NONE`].
    pub edge_origin: Vec<u32>,
    /// Output edge of each output corner (from it to the next corner of its face).
    pub corner_edges: Vec<u32>,
    /// Output edges on the cut paths (both sides of an opened cut), ascending.
    pub path_edges: Vec<u32>,
    /// Input faces given back whole.
    pub kept_faces: u32,
    /// Vertices of the input: output vertices below keep their ids.
    pub input_vertex_count: u32,
    /// Faces of the input: output faces below come from the face of the same id.
    pub input_face_count: u32,
    /// Edges of the input (the host's): output edges below are the host's of the same id.
    pub input_edge_count: u32,
    /// Corners of the input ([`CutPolygons::carry_corner_data`] reads this many values per
    /// component).
    pub input_corner_count: u32,
    /// For each new vertex (ids from `input_vertex_count` on), the input vertex it copies
    /// (an opened cut's copy of one), or [`NONE`].
    pub new_vertex_original: Vec<u32>,
    /// Corners without an input corner: (output corner, the source triangle's input
    /// corners, weights).
    blends: Vec<(u32, [u32; 3], [f64; 3])>,
}

fn key(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}

impl CutOutput {
    /// This cut of `input` in the input's own layout (module docs): untouched faces whole
    /// when `keep_polygons` (a face with holes never is: it comes back as triangles), edges
    /// numbered as the host's `edges` (or, when `None`, as the input's edges by first use in
    /// corner order).
    ///
    /// Errors: [`Error::InvalidArgument`] when `input` is not the mesh that was cut, or the
    /// host's edges do not match its faces (a corner's edge out of range or not joining the
    /// corner to the next one; the message names the corner).
    pub fn polygons(
        &self,
        input: &PolyMesh,
        edges: Option<InputEdges<'_>>,
        keep_polygons: bool,
    ) -> Result<CutPolygons> {
        let p = &self.provenance;
        if input.vertex_count() != p.input_vertices {
            return Err(Error::InvalidArgument(format!(
                "the mesh given has {} vertices, but the cut mesh had {}: pass the mesh that \
                 was cut",
                input.vertex_count(),
                p.input_vertices
            )));
        }
        let numbered;
        let host = match edges {
            Some(h) => {
                check_edges(input, &h)?;
                h
            }
            None => {
                numbered = number_edges(input);
                InputEdges {
                    edges: &numbered.0,
                    corner_edges: &numbered.1,
                }
            }
        };
        Ok(Builder::new(self, input, host, keep_polygons)?.build())
    }
}

/// Every corner's edge joins it to the next corner of its loop.
fn check_edges(input: &PolyMesh, h: &InputEdges) -> Result<()> {
    let nc = input.corner_count() as usize;
    if h.corner_edges.len() != nc {
        return Err(Error::InvalidArgument(format!(
            "{} corner edges were given, but the mesh has {nc} corners",
            h.corner_edges.len()
        )));
    }
    let corners = input.corners();
    let lo = input.loop_offsets();
    for w in lo.windows(2) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        for k in a..b {
            let next = if k + 1 < b { k + 1 } else { a };
            let (u, v) = (corners[k].0, corners[next].0);
            let e = h.corner_edges[k];
            let ok = h
                .edges
                .get(e as usize)
                .is_some_and(|&[x, y]| key(x, y) == key(u, v));
            if !ok {
                return Err(Error::InvalidArgument(format!(
                    "corner {k} goes from vertex {u} to vertex {v}, but its edge {e} is {}",
                    match h.edges.get(e as usize) {
                        Some([x, y]) => format!("{x}-{y}"),
                        None => format!("not one of the {} edges", h.edges.len()),
                    }
                )));
            }
        }
    }
    Ok(())
}

/// The input's edges numbered by first use in corner order, and each corner's.
fn number_edges(input: &PolyMesh) -> (Vec<[u32; 2]>, Vec<u32>) {
    let corners = input.corners();
    let mut ids: HashMap<u64, u32> = HashMap::with_capacity(corners.len() / 2 + 8);
    let mut edges = Vec::with_capacity(corners.len() / 2 + 8);
    let mut corner_edges = vec![0u32; corners.len()];
    for w in input.loop_offsets().windows(2) {
        let (a, b) = (w[0] as usize, w[1] as usize);
        for k in a..b {
            let (u, v) = (corners[k].0, corners[if k + 1 < b { k + 1 } else { a }].0);
            let next = edges.len() as u32;
            let e = *ids.entry(key(u, v)).or_insert(next);
            if e == next {
                edges.push([u, v]);
            }
            corner_edges[k] = e;
        }
    }
    (edges, corner_edges)
}

struct Builder<'a> {
    out: &'a CutOutput,
    input: &'a PolyMesh,
    host: InputEdges<'a>,
    /// Triangle slots of each input face: `tri_start[f]..tri_start[f + 1]`.
    tri_start: Vec<u32>,
    /// Whether each input face is given back whole.
    kept: Vec<bool>,
    /// Pieces of split input edges, by their (original) ends: output edge.
    pieces: HashMap<u64, u32>,
    /// Sides of the faces the cut touched: host edge.
    sides: HashMap<u64, u32>,
    /// Output edges found on triangles, by their ends.
    found: HashMap<u64, u32>,
    r: CutPolygons,
}

impl<'a> Builder<'a> {
    fn new(
        out: &'a CutOutput,
        input: &'a PolyMesh,
        host: InputEdges<'a>,
        keep_polygons: bool,
    ) -> Result<Self> {
        let p = &out.provenance;
        let nf = input.face_count() as usize;
        let tri_count = p.tri_count as usize;
        // Triangles follow their faces (triangulate.rs), so each face's are one range.
        let tri_start: Vec<u32> = if tri_count == nf {
            (0..=nf as u32).collect()
        } else {
            let mut s = vec![0u32; nf + 1];
            for f in &out.face_origin[..tri_count] {
                s[f.idx() + 1] += 1;
            }
            for f in 0..nf {
                s[f + 1] += s[f];
            }
            s
        };
        let mut touched = vec![false; nf];
        for &t in &p.rewritten {
            touched[out.face_origin[t as usize].idx()] = true;
        }
        let flo = input.face_loop_offsets();
        let lo = input.loop_offsets();
        let corners = input.corners();
        // A path along a diagonal of an untouched polygon needs that diagonal as an edge.
        let nv_in = p.input_vertices as usize;
        let mut on_path = vec![false; nv_in];
        let mut path_keys: Vec<u64> = Vec::new();
        for path in &out.report.paths {
            let v = &path.vertices;
            let n = v.len();
            let steps = if path.closed && n > 2 {
                n
            } else {
                n.saturating_sub(1)
            };
            for i in 0..steps {
                let (a, b) = (v[i].0, v[(i + 1) % n].0);
                path_keys.push(key(a, b));
                for x in [a, b] {
                    if (x as usize) < nv_in {
                        on_path[x as usize] = true;
                    }
                }
            }
        }
        path_keys.sort_unstable();
        path_keys.dedup();
        let kept: Vec<bool> = (0..nf)
            .map(|f| {
                let single = flo[f + 1] == flo[f] + 1;
                if !keep_polygons || touched[f] || !single {
                    return false;
                }
                let own = &corners[lo[flo[f] as usize] as usize..lo[flo[f + 1] as usize] as usize];
                let n = own.len();
                if n == 3 {
                    return true;
                }
                let ends: Vec<usize> = (0..n).filter(|&i| on_path[own[i].idx()]).collect();
                !ends.iter().enumerate().any(|(x, &i)| {
                    ends[x + 1..].iter().any(|&j| {
                        j - i != 1
                            && !(i == 0 && j == n - 1)
                            && path_keys.binary_search(&key(own[i].0, own[j].0)).is_ok()
                    })
                })
            })
            .collect();
        let mut sides = HashMap::new();
        for f in (0..nf).filter(|&f| touched[f]) {
            for k in lo[flo[f] as usize] as usize..lo[flo[f + 1] as usize] as usize {
                let e = host.corner_edges[k];
                let [u, v] = host.edges[e as usize];
                sides.insert(key(u, v), e);
            }
        }
        let mut r = CutPolygons {
            positions: out.mesh.positions().to_vec(),
            edges: host.edges.to_vec(),
            edge_origin: (0..host.edges.len() as u32).collect(),
            input_corner_count: input.corner_count(),
            input_vertex_count: p.input_vertices,
            input_face_count: input.face_count(),
            input_edge_count: host.edges.len() as u32,
            new_vertex_original: (p.input_vertices..out.mesh.vertex_count())
                .map(|v| match p.original(v) {
                    o if o < p.input_vertices => o,
                    _ => NONE,
                })
                .collect(),
            ..Default::default()
        };
        // Split input edges: the piece at the host's first vertex keeps the edge's index.
        let mut pieces = HashMap::new();
        let sp = &p.split;
        for i in 0..sp.ends.len() {
            let (u, w) = sp.ends[i];
            let on = &sp.on[sp.start[i] as usize..sp.start[i + 1] as usize];
            // A split diagonal of a polygon is no host edge: its pieces are new edges.
            let Some(&e) = sides.get(&key(u, w)) else {
                continue;
            };
            let mut chain: Vec<u32> = Vec::with_capacity(on.len() + 2);
            chain.push(u);
            chain.extend_from_slice(on);
            chain.push(w);
            if r.edges[e as usize][0] != u {
                chain.reverse();
            }
            for (j, s) in chain.windows(2).enumerate() {
                let id = if j == 0 {
                    r.edges[e as usize] = [s[0], s[1]];
                    e
                } else {
                    r.edges.push([s[0], s[1]]);
                    r.edge_origin.push(e);
                    r.edges.len() as u32 - 1
                };
                pieces.insert(key(s[0], s[1]), id);
            }
        }
        Ok(Builder {
            out,
            input,
            host,
            tri_start,
            kept,
            pieces,
            sides,
            found: HashMap::new(),
            r,
        })
    }

    fn original(&self, v: u32) -> u32 {
        self.out.provenance.original(v)
    }

    /// Input face `f`'s corner range.
    fn corner_range(&self, f: usize) -> std::ops::Range<usize> {
        let (flo, lo) = (self.input.face_loop_offsets(), self.input.loop_offsets());
        lo[flo[f] as usize] as usize..lo[flo[f + 1] as usize] as usize
    }

    /// Input face `f`'s corner at input vertex `v`.
    fn corner_at(&self, f: usize, v: u32) -> Option<u32> {
        let c = self.input.corners();
        self.corner_range(f)
            .find(|&k| c[k].0 == v)
            .map(|k| k as u32)
    }

    /// The output edge from `a` to `b` on a triangle of input face `f`.
    fn edge(&mut self, f: usize, a: u32, b: u32) -> u32 {
        let k = key(a, b);
        if let Some(&e) = self.found.get(&k) {
            return e;
        }
        let (oa, ob) = (self.original(a), self.original(b));
        let base = key(oa, ob);
        let nv_in = self.out.provenance.input_vertices;
        let own = if self.pieces.contains_key(&base) || self.sides.contains_key(&base) {
            self.pieces
                .get(&base)
                .map(|&p| (p, self.r.edge_origin[p as usize]))
                .or_else(|| self.sides.get(&base).map(|&e| (e, e)))
        } else if oa < nv_in && ob < nv_in {
            // An untouched face's side: the host's edge of that corner.
            let c = self.input.corners();
            let range = self.corner_range(f);
            let (s, n) = (range.start, range.len());
            (0..n)
                .find(|&i| key(c[s + i].0, c[s + (i + 1) % n].0) == base)
                .map(|i| {
                    let e = self.host.corner_edges[s + i];
                    (e, e)
                })
        } else {
            None
        };
        let e = match own {
            Some((e, _)) if base == k => e,
            other => {
                self.r.edges.push([a, b]);
                self.r.edge_origin.push(other.map_or(NONE, |(_, o)| o));
                self.r.edges.len() as u32 - 1
            }
        };
        self.found.insert(k, e);
        e
    }

    /// Appends output triangle `t` (a slot of the cut's triangle mesh) as a face of input
    /// face `f`.
    fn push_triangle(&mut self, f: usize, t: usize) {
        let out = self.out;
        let tri: [u32; 3] = std::array::from_fn(|i| out.mesh.corners()[3 * t + i].0);
        let nv_in = out.provenance.input_vertices;
        let start = self.r.corners.len() as u32;
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            let o = self.original(a);
            let origin = if o < nv_in {
                self.corner_at(f, o).unwrap_or(NONE)
            } else {
                NONE
            };
            if origin == NONE {
                let blend = self.blend(f, t, a);
                self.r.blends.push((start + i as u32, blend.0, blend.1));
            }
            self.r.corners.push(a);
            self.r.corner_origin.push(origin);
            let e = self.edge(f, a, b);
            self.r.corner_edges.push(e);
        }
        self.r.face_offsets.push(self.r.corners.len() as u32);
        self.r.face_origin.push(f as u32);
    }

    /// Input corners and weights that blend into a corner at new vertex `v` of output
    /// triangle `t` of input face `f`: its source triangle's corners at `v`'s position.
    fn blend(&self, f: usize, t: usize, v: u32) -> ([u32; 3], [f64; 3]) {
        let p = &self.out.provenance;
        let slot = if t < p.tri_count as usize {
            t as u32
        } else {
            p.appended_from[t - p.tri_count as usize]
        };
        let src = match p.rewritten.binary_search(&slot) {
            Ok(i) => p.rewritten_sources[i],
            Err(_) => std::array::from_fn(|i| self.out.mesh.corners()[3 * slot as usize + i].0),
        };
        let pos = self.out.mesh.positions();
        let w = barycentric(
            pos[v as usize],
            pos[src[0] as usize],
            pos[src[1] as usize],
            pos[src[2] as usize],
        );
        let c = src.map(|u| self.corner_at(f, u).unwrap_or(0));
        (c, w)
    }

    fn build(mut self) -> CutPolygons {
        let nf = self.input.face_count() as usize;
        let p = &self.out.provenance;
        let tri_count = p.tri_count as usize;
        self.r.face_offsets.push(0);
        // Faces in their own slots.
        for f in 0..nf {
            if self.kept[f] {
                let range = self.corner_range(f);
                let c = self.input.corners();
                self.r.corners.extend(c[range.clone()].iter().map(|v| v.0));
                self.r
                    .corner_origin
                    .extend(range.start as u32..range.end as u32);
                self.r
                    .corner_edges
                    .extend_from_slice(&self.host.corner_edges[range]);
                self.r.face_offsets.push(self.r.corners.len() as u32);
                self.r.face_origin.push(f as u32);
                self.r.kept_faces += 1;
            } else {
                self.push_triangle(f, self.tri_start[f] as usize);
            }
        }
        // The other triangles of the faces given as triangles, then the pieces the cut
        // appended, both in slot order.
        for f in 0..nf {
            if !self.kept[f] {
                for t in self.tri_start[f] as usize + 1..self.tri_start[f + 1] as usize {
                    self.push_triangle(f, t);
                }
            }
        }
        let appended = p.appended_from.len();
        for i in 0..appended {
            let t = tri_count + i;
            let f = self.out.face_origin[t].idx();
            self.push_triangle(f, t);
        }
        self.path_edges();
        self.r
    }

    /// Output edges on the paths: found on the triangles, or (a path along input edges
    /// between untouched faces) the host's edge.
    fn path_edges(&mut self) {
        let mut keys: Vec<u64> = Vec::new();
        for path in &self.out.report.paths {
            let v = &path.vertices;
            let n = v.len();
            let steps = if path.closed && n > 2 {
                n
            } else {
                n.saturating_sub(1)
            };
            keys.extend((0..steps).map(|i| key(v[i].0, v[(i + 1) % n].0)));
        }
        if keys.is_empty() {
            return;
        }
        keys.sort_unstable();
        keys.dedup();
        let mut out: Vec<u32> = Vec::new();
        let mut missing = keys.clone();
        for (&k, &e) in &self.found {
            let [a, b] = self.r.edges[e as usize];
            let base = key(self.original(a), self.original(b));
            if keys.binary_search(&base).is_ok() {
                out.push(e);
                if base == k {
                    if let Ok(i) = missing.binary_search(&k) {
                        missing.remove(i);
                    }
                }
            }
        }
        if !missing.is_empty() {
            for (e, &[a, b]) in self.host.edges.iter().enumerate() {
                if missing.binary_search(&key(a, b)).is_ok() && !self.found.contains_key(&key(a, b))
                {
                    out.push(e as u32);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        self.r.path_edges = out;
    }
}

impl CutPolygons {
    /// Per-corner data of the input (`dim` values per input corner, in `PolyMesh::corners`
    /// order) carried to the output's corners: a corner with an input corner takes its
    /// values, the others the blend of their source triangle's corners at their position
    /// (as [`CutOutput::interpolate_corner_data`]).
    ///
    /// Errors: [`Error::InvalidArgument`] when `dim` is 0 or `values` does not hold `dim` ×
    /// the input's corner count.
    pub fn carry_corner_data(&self, values: &[f32], dim: usize) -> Result<Vec<f32>> {
        let want = self.input_corner_count as usize * dim;
        if dim == 0 || values.len() != want {
            return Err(Error::InvalidArgument(format!(
                "corner data holds {} values, but {} corners × dim {dim} = {want} were \
                 expected (dim ≥ 1)",
                values.len(),
                self.input_corner_count
            )));
        }
        let mut out = vec![0.0f32; self.corner_origin.len() * dim];
        for (o, &c) in out.chunks_exact_mut(dim).zip(&self.corner_origin) {
            if c != NONE {
                o.copy_from_slice(&values[c as usize * dim..(c as usize + 1) * dim]);
            }
        }
        for &(k, c, w) in &self.blends {
            for d in 0..dim {
                let v: f64 = (0..3)
                    .map(|i| w[i] * f64::from(values[c[i] as usize * dim + d]))
                    .sum();
                out[k as usize * dim + d] = v as f32;
            }
        }
        Ok(out)
    }
}
