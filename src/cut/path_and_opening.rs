//! The cut path and its opening (spec §4 step 8).
//!
//! The normalized arrays' vertices, joined by the edges the split patterns made, are the cut
//! path: consecutive elements on one edge are joined along it (through the vertices other
//! paths split it at), a chord the patterns did not make an edge (several pieces in one face)
//! is recovered by flips inside the face, and one that crosses another piece's path follows
//! that face's edges instead.
//!
//! Opening (spec T5; as libigl's `cut_mesh` does): around each path vertex the faces fall
//! into wedges separated by path edges; the first wedge keeps the vertex, every other wedge
//! gets a copy. A slit's ends (one path edge, inside the mesh) have one wedge and stay whole;
//! a path end on the boundary splits; a closed loop duplicates every vertex on it and may
//! separate the mesh.

use super::ids::{Le, Lf, Lv};
use super::region::Region;
use super::split_patterns::Splitter;

/// A cut path: the stroke piece it cuts, its vertices, and the face of each step
/// ([`Lf::NONE`] along an edge).
pub(crate) struct Path {
    pub piece: u32,
    pub verts: Vec<Lv>,
    pub faces: Vec<Lf>,
}

/// Steps between two path vertices, as (piece, vertex, vertex).
pub(crate) type Steps = Vec<(u32, Lv, Lv)>;

/// Makes every step of `paths` a run of edges: along an edge, through the vertices split on
/// it; across a face, its chord made an edge by flips, or (when the chord crosses another
/// piece's path in that face) the shortest route along the face's edges. Returns the steps
/// rerouted, and those that could not be made edges (a broken path: should not happen).
pub(crate) fn join_steps(sp: &mut Splitter, paths: &mut [Path]) -> (Steps, Steps) {
    let mut unjoined = Vec::new();
    let mut rerouted = Vec::new();
    let mut protected: Vec<(Lv, Lv)> = Vec::new();
    for p in paths.iter_mut() {
        let mut verts = Vec::with_capacity(p.verts.len());
        let mut faces = Vec::with_capacity(p.faces.len());
        for k in 0..p.verts.len() {
            if k > 0 {
                let (u, w, f) = (p.verts[k - 1], p.verts[k], p.faces[k - 1]);
                if !f.is_some() {
                    if let Some(e) = edge_between(sp.r, u, w) {
                        let mut on: Vec<Lv> = sp.edge_vertices(e).iter().map(|x| x.1).collect();
                        if sp.r.ends(e)[0] != u {
                            on.reverse();
                        }
                        for m in on {
                            verts.push(m);
                            faces.push(Lf::NONE);
                        }
                    }
                    faces.push(f);
                } else if sp.ensure_chord(f, u, w, &protected) {
                    protected.push((u.min(w), u.max(w)));
                    faces.push(f);
                } else if let Some(inner) = sp.route(f, u, w) {
                    rerouted.push((p.piece, u, w));
                    let mut a = u;
                    for m in inner {
                        protected.push((a.min(m), a.max(m)));
                        verts.push(m);
                        faces.push(f);
                        a = m;
                    }
                    protected.push((a.min(w), a.max(w)));
                    faces.push(f);
                } else {
                    unjoined.push((p.piece, u, w));
                    faces.push(f);
                }
            }
            verts.push(p.verts[k]);
        }
        p.verts = verts;
        p.faces = faces;
    }
    (rerouted, unjoined)
}

/// The edge joining two region vertices, if any.
fn edge_between(region: &Region, u: Lv, w: Lv) -> Option<Le> {
    let n0 = region.vertex_count() as u32;
    if u.0 >= n0 || w.0 >= n0 {
        return None;
    }
    // The side of a face around `u` from one to the other.
    region.vertex_faces(u).iter().find_map(|&f| {
        let t = region.corners(f);
        (0..3)
            .find(|&i| {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                (a == u && b == w) || (a == w && b == u)
            })
            .map(|i| region.face_edges(f)[i])
    })
}

/// The paths' edges, each listed at its smaller end.
pub(crate) struct PathEdges {
    from: Vec<u32>,
    to: Vec<Lv>,
}

impl PathEdges {
    /// The edges of `paths`, among `nv` vertices.
    pub fn new(paths: &[Path], nv: usize) -> Self {
        let edges = || {
            paths
                .iter()
                .flat_map(|p| p.verts.windows(2).map(|w| (w[0].min(w[1]), w[0].max(w[1]))))
        };
        let mut from = vec![0u32; nv + 1];
        for (a, _) in edges() {
            from[a.idx() + 1] += 1;
        }
        for v in 0..nv {
            from[v + 1] += from[v];
        }
        let mut to = vec![Lv::NONE; from[nv] as usize];
        let mut fill = from.clone();
        for (a, b) in edges() {
            to[fill[a.idx()] as usize] = b;
            fill[a.idx()] += 1;
        }
        PathEdges { from, to }
    }

    /// Whether there is no path edge.
    pub fn is_empty(&self) -> bool {
        self.to.is_empty()
    }

    /// Whether `a`-`b` is a path edge.
    pub fn contains(&self, a: Lv, b: Lv) -> bool {
        let (x, y) = (a.min(b).idx(), a.max(b));
        self.to[self.from[x] as usize..self.from[x + 1] as usize].contains(&y)
    }
}

/// Opens the cut: duplicates the vertices of `paths` (spec §4 step 8). Returns, for each copy
/// made (in creation order), the vertex it copies.
pub(crate) fn open(sp: &mut Splitter, paths: &[Path], edges: &PathEdges) -> Vec<Lv> {
    let mut path_vertices: Vec<Lv> = paths.iter().flat_map(|p| p.verts.iter().copied()).collect();
    path_vertices.sort_unstable();
    path_vertices.dedup();
    let is_cut = |a, b| edges.contains(a, b);
    let mut faces: Vec<Lf> = sp.touched.clone();
    for &v in &path_vertices {
        if !sp.is_new(v) {
            faces.extend_from_slice(sp.r.vertex_faces(v));
        }
    }
    faces.sort_unstable();
    faces.dedup();
    // (vertex, face, sub-triangle) for every corner at a path vertex.
    let mut inc: Vec<(Lv, Lf, u32)> = Vec::new();
    for &lf in &faces {
        for (i, t) in sp.face_subs(lf).iter().enumerate() {
            for &c in t {
                if path_vertices.binary_search(&c).is_ok() {
                    inc.push((c, lf, i as u32));
                }
            }
        }
    }
    inc.sort_unstable();
    let mut copies = Vec::new();
    // Wedges are found on the sub-triangles as they are, then corners are replaced at once,
    // so each vertex sees its neighbours (and the cut edges) by their original ids.
    let mut replace: Vec<(Lf, u32, Lv, Lv)> = Vec::new();
    let mut i = 0;
    while i < inc.len() {
        let v = inc[i].0;
        let mut j = i;
        while j < inc.len() && inc[j].0 == v {
            j += 1;
        }
        let items = &inc[i..j];
        // Union-find over the items: joined across a shared, uncut edge at v.
        let mut parent: Vec<usize> = (0..items.len()).collect();
        fn root(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let mut by_other: Vec<(Lv, usize)> = Vec::new();
        for (k, &(_, lf, si)) in items.iter().enumerate() {
            let t = sp.face_subs(lf)[si as usize];
            let r = t.iter().position(|&c| c == v).expect("the corner is v");
            for x in [t[(r + 1) % 3], t[(r + 2) % 3]] {
                if !is_cut(v, x) {
                    by_other.push((x, k));
                }
            }
        }
        by_other.sort_unstable();
        for w in by_other.windows(2) {
            if w[0].0 == w[1].0 {
                let (a, b) = (root(&mut parent, w[0].1), root(&mut parent, w[1].1));
                if a != b {
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        // Wedges in order of their first item; the first keeps v.
        let mut label: Vec<Option<Lv>> = vec![None; items.len()];
        let mut first_root = None;
        for (k, &(_, lf, si)) in items.iter().enumerate() {
            let rk = root(&mut parent, k);
            if first_root.is_none() {
                first_root = Some(rk);
            }
            if Some(rk) == first_root {
                continue;
            }
            let copy = match label[rk] {
                Some(c) => c,
                None => {
                    let c = sp.copy_vertex(v);
                    copies.push(v);
                    label[rk] = Some(c);
                    c
                }
            };
            replace.push((lf, si, v, copy));
        }
        i = j;
    }
    for (lf, si, v, copy) in replace {
        sp.replace_corner(lf, si as usize, v, copy);
    }
    copies
}
