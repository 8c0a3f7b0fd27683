//! Half-edge connectivity in flat arrays, built once in O(n) from a [`PolyMesh`].
//!
//! Half-edges come in pairs: edge `e` owns half-edges `2e` and `2e + 1`, so the twin of `h`
//! is `h ^ 1` (geometry-central's layout). Every loop of every face (outer loops and holes
//! alike) contributes one half-edge per corner; an edge used by one face side gets a boundary
//! half-edge (no face) as its twin, and boundary half-edges are linked into boundary loops.
//!
//! Building: corners are bucketed by their start vertex with a counting sort (O(n)), and each
//! corner `a → b` finds its twin `b → a` among the few corners leaving `b`. No hashing, no
//! per-element allocation.

use super::ids::{EdgeId, FaceId, HalfedgeId, LoopId, VertexId};
use super::polymesh::PolyMesh;
use crate::error::{Error, Result};

/// What [`Topology::build`] accepts instead of rejecting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct TopologyOptions {
    /// Build even where more than two face sides share an edge: the sides are paired
    /// opposite-direction first, the rest become separate edges with boundary twins, and
    /// the edge is listed in [`Defects::non_manifold_edges`]. Default value: `false`.
    pub tolerate_non_manifold: bool,
    /// Build even where two faces traverse an edge in the same direction: both sides get
    /// boundary twins, and the edge is listed in [`Defects::inconsistent_edges`].
    /// Default value: `false`.
    pub tolerate_inconsistent_orientation: bool,
}

impl TopologyOptions {
    /// Tolerate every defect, for inspection tools.
    pub fn tolerant() -> Self {
        TopologyOptions {
            tolerate_non_manifold: true,
            tolerate_inconsistent_orientation: true,
        }
    }
}

/// Defects found while building; empty unless tolerated (vertices are always checked).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Defects {
    /// Vertex pairs `(a, b)` whose edge has more than two face sides, with the number of sides.
    pub non_manifold_edges: Vec<(VertexId, VertexId, u32)>,
    /// Vertex pairs whose edge two faces traverse in the same direction.
    pub inconsistent_edges: Vec<(VertexId, VertexId)>,
    /// Vertices whose faces form more than one fan (e.g. two cones touching at a tip).
    pub non_manifold_vertices: Vec<VertexId>,
}

impl Defects {
    /// Whether nothing was found.
    pub fn is_empty(&self) -> bool {
        self.non_manifold_edges.is_empty()
            && self.inconsistent_edges.is_empty()
            && self.non_manifold_vertices.is_empty()
    }
}

/// Half-edge connectivity of a [`PolyMesh`]. Arrays are indexed by [`HalfedgeId`] (2 × #E),
/// [`VertexId`] (#V), corner (#corners) and [`LoopId`] (#L).
#[derive(Debug, Clone)]
pub struct Topology {
    to: Vec<VertexId>,
    next: Vec<HalfedgeId>,
    prev: Vec<HalfedgeId>,
    face: Vec<FaceId>,
    lp: Vec<LoopId>,
    vertex_out: Vec<HalfedgeId>,
    corner_halfedge: Vec<HalfedgeId>,
    loop_face: Vec<FaceId>,
    face_count: u32,
    defects: Defects,
}

impl PolyMesh {
    /// Builds the half-edge connectivity, rejecting non-manifold edges and inconsistent
    /// orientation. See [`Topology::build`] to tolerate them.
    pub fn connectivity(&self) -> Result<Topology> {
        Topology::build(self, &TopologyOptions::default())
    }
}

impl Topology {
    /// Builds the connectivity of `mesh` in O(#corners).
    pub fn build(mesh: &PolyMesh, options: &TopologyOptions) -> Result<Topology> {
        let nv = mesh.vertex_count() as usize;
        let corners = mesh.corners();
        let n = corners.len();
        // The vertex each corner's half-edge points to, and loop → face.
        let mut head = vec![VertexId::INVALID; n];
        let mut loop_face = Vec::with_capacity(mesh.loop_count() as usize);
        let loop_offsets = mesh.loop_offsets();
        for f in mesh.faces() {
            for l in mesh.face_loops(f) {
                loop_face.push(f);
                let (a, b) = (
                    loop_offsets[l.idx()] as usize,
                    loop_offsets[l.idx() + 1] as usize,
                );
                head[a..b - 1].copy_from_slice(&corners[a + 1..b]);
                head[b - 1] = corners[a];
            }
        }

        // Counting sort of corners by start vertex.
        let mut out_start = vec![0u32; nv + 1];
        for v in corners {
            out_start[v.idx() + 1] += 1;
        }
        for i in 0..nv {
            out_start[i + 1] += out_start[i];
        }
        let mut fill = out_start.clone();
        let mut out_list = vec![0u32; n];
        for (k, v) in corners.iter().enumerate() {
            out_list[fill[v.idx()] as usize] = k as u32;
            fill[v.idx()] += 1;
        }
        drop(fill);
        let leaving =
            |v: VertexId| &out_list[out_start[v.idx()] as usize..out_start[v.idx() + 1] as usize];

        // Pair corners into edges, in corner order (deterministic).
        let mut corner_halfedge = vec![HalfedgeId::INVALID; n];
        let mut to: Vec<VertexId> = Vec::with_capacity(n + n / 8);
        let mut defects = Defects::default();
        for k in 0..n as u32 {
            if corner_halfedge[k as usize].is_valid() {
                continue;
            }
            let (a, b) = (corners[k as usize], head[k as usize]);
            let (mut n_opp, mut twin, mut min_opp) = (0u32, None, u32::MAX);
            for &j in leaving(b) {
                if head[j as usize] == a {
                    n_opp += 1;
                    min_opp = min_opp.min(j);
                    if twin.is_none() && !corner_halfedge[j as usize].is_valid() {
                        twin = Some(j);
                    }
                }
            }
            let (mut n_same, mut min_same) = (0u32, u32::MAX);
            for &j in leaving(a) {
                if head[j as usize] == b {
                    n_same += 1;
                    min_same = min_same.min(j);
                }
            }
            if n_same > 1 || n_opp > 1 {
                let first = min_same.min(min_opp) == k;
                if n_same + n_opp > 2 {
                    if !options.tolerate_non_manifold {
                        return Err(Error::NonManifoldEdge {
                            a: a.0,
                            b: b.0,
                            uses: n_same + n_opp,
                        });
                    }
                    if first {
                        defects.non_manifold_edges.push((a, b, n_same + n_opp));
                    }
                } else {
                    if !options.tolerate_inconsistent_orientation {
                        return Err(Error::InconsistentOrientation { a: a.0, b: b.0 });
                    }
                    if first {
                        defects.inconsistent_edges.push((a, b));
                    }
                }
            }
            let h = HalfedgeId(to.len() as u32);
            corner_halfedge[k as usize] = h;
            to.push(b);
            if let Some(j) = twin {
                corner_halfedge[j as usize] = HalfedgeId(h.0 + 1);
            }
            to.push(a);
        }
        let nh = to.len();

        // Faces, loops, next and prev of face half-edges.
        let mut next = vec![HalfedgeId::INVALID; nh];
        let mut prev = vec![HalfedgeId::INVALID; nh];
        let mut face = vec![FaceId::INVALID; nh];
        let mut lp = vec![LoopId::INVALID; nh];
        for (l, &f) in loop_face.iter().enumerate() {
            let (a, b) = (loop_offsets[l], loop_offsets[l + 1]);
            for k in a..b {
                let h = corner_halfedge[k as usize];
                let hn = corner_halfedge[if k + 1 < b { k + 1 } else { a } as usize];
                face[h.idx()] = f;
                lp[h.idx()] = LoopId(l as u32);
                next[h.idx()] = hn;
                prev[hn.idx()] = h;
            }
        }
        // Boundary half-edges: next is the boundary half-edge leaving the head in the same
        // fan, found by rotating through the faces. The rotation cannot cycle: its start
        // (the twin of a boundary half-edge) has no predecessor under it.
        for h in 0..nh {
            if face[h].is_valid() {
                continue;
            }
            let mut g = h ^ 1;
            loop {
                let t = prev[g].0 as usize ^ 1;
                if !face[t].is_valid() {
                    next[h] = HalfedgeId(t as u32);
                    prev[t] = HalfedgeId(h as u32);
                    break;
                }
                g = t;
            }
        }

        // One outgoing half-edge per vertex, a boundary one where there is one.
        let mut vertex_out = vec![HalfedgeId::INVALID; nv];
        let mut out_degree = vec![0u32; nv];
        for h in 0..nh {
            let from = to[h ^ 1].idx();
            out_degree[from] += 1;
            let cur = vertex_out[from];
            if !cur.is_valid() || (!face[h].is_valid() && face[cur.idx()].is_valid()) {
                vertex_out[from] = HalfedgeId(h as u32);
            }
        }
        let mut topo = Topology {
            to,
            next,
            prev,
            face,
            lp,
            vertex_out,
            corner_halfedge,
            loop_face,
            face_count: mesh.face_count(),
            defects,
        };
        for v in 0..nv as u32 {
            let v = VertexId(v);
            // Fast test: one fan visits every half-edge leaving v. Only where it fails, the
            // precise test joins v's faces across any shared edge (non-manifold ones included).
            if out_degree[v.idx()] > 0
                && topo.outgoing(v).count() as u32 != out_degree[v.idx()]
                && fans_at(v, leaving(v), corners, &head, loop_offsets) > 1
            {
                topo.defects.non_manifold_vertices.push(v);
            }
        }
        Ok(topo)
    }

    /// Number of half-edges (2 × #E).
    pub fn halfedge_count(&self) -> u32 {
        self.to.len() as u32
    }
    /// Number of undirected edges.
    pub fn edge_count(&self) -> u32 {
        (self.to.len() / 2) as u32
    }
    /// Number of vertices (as in the mesh, referenced or not).
    pub fn vertex_count(&self) -> u32 {
        self.vertex_out.len() as u32
    }
    /// Number of faces.
    pub fn face_count(&self) -> u32 {
        self.face_count
    }
    /// What was found wrong (tolerated edges, non-manifold vertices).
    pub fn defects(&self) -> &Defects {
        &self.defects
    }

    /// A cursor on half-edge `h`: `topo.he(h).next().twin().to()`.
    pub fn he(&self, h: HalfedgeId) -> HalfedgeRef<'_> {
        HalfedgeRef { topo: self, h }
    }
    /// The vertex half-edge `h` points to.
    #[inline]
    pub fn to(&self, h: HalfedgeId) -> VertexId {
        self.to[h.idx()]
    }
    /// The vertex half-edge `h` starts from.
    #[inline]
    pub fn from(&self, h: HalfedgeId) -> VertexId {
        self.to[h.idx() ^ 1]
    }
    /// The next half-edge around `h`'s face loop (or boundary loop).
    #[inline]
    pub fn next(&self, h: HalfedgeId) -> HalfedgeId {
        self.next[h.idx()]
    }
    /// The previous half-edge around `h`'s face loop (or boundary loop).
    #[inline]
    pub fn prev(&self, h: HalfedgeId) -> HalfedgeId {
        self.prev[h.idx()]
    }
    /// The opposite half-edge, `h ^ 1`.
    #[inline]
    pub fn twin(&self, h: HalfedgeId) -> HalfedgeId {
        HalfedgeId(h.0 ^ 1)
    }
    /// The face of `h`, [`FaceId::INVALID`] for a boundary half-edge.
    #[inline]
    pub fn face(&self, h: HalfedgeId) -> FaceId {
        self.face[h.idx()]
    }
    /// The face loop of `h`, [`LoopId::INVALID`] for a boundary half-edge.
    #[inline]
    pub fn loop_of(&self, h: HalfedgeId) -> LoopId {
        self.lp[h.idx()]
    }
    /// The undirected edge of `h`.
    #[inline]
    pub fn edge(&self, h: HalfedgeId) -> EdgeId {
        EdgeId(h.0 >> 1)
    }
    /// Whether `h` has no face.
    #[inline]
    pub fn is_boundary(&self, h: HalfedgeId) -> bool {
        !self.face[h.idx()].is_valid()
    }
    /// The two half-edges of edge `e`.
    pub fn edge_halfedges(&self, e: EdgeId) -> [HalfedgeId; 2] {
        [HalfedgeId(2 * e.0), HalfedgeId(2 * e.0 + 1)]
    }
    /// The two end vertices of edge `e`.
    pub fn edge_vertices(&self, e: EdgeId) -> [VertexId; 2] {
        [self.to[2 * e.idx() + 1], self.to[2 * e.idx()]]
    }
    /// Whether edge `e` has a boundary side.
    pub fn is_boundary_edge(&self, e: EdgeId) -> bool {
        self.is_boundary(HalfedgeId(2 * e.0)) || self.is_boundary(HalfedgeId(2 * e.0 + 1))
    }

    /// The half-edge leaving the corner with flat index `corner` (see [`PolyMesh::corners`]).
    pub fn corner_halfedge(&self, corner: u32) -> HalfedgeId {
        self.corner_halfedge[corner as usize]
    }
    /// The face a loop belongs to.
    pub fn loop_face(&self, l: LoopId) -> FaceId {
        self.loop_face[l.idx()]
    }
    /// One outgoing half-edge of `v` (a boundary one if `v` is on the boundary),
    /// [`HalfedgeId::INVALID`] for an isolated vertex.
    pub fn vertex_halfedge(&self, v: VertexId) -> HalfedgeId {
        self.vertex_out[v.idx()]
    }
    /// Whether `v` has a boundary half-edge leaving it (isolated vertices are not boundary).
    pub fn is_boundary_vertex(&self, v: VertexId) -> bool {
        let h = self.vertex_out[v.idx()];
        h.is_valid() && self.is_boundary(h)
    }

    /// The half-edges leaving `v`, rotating through its fan, starting at
    /// [`Self::vertex_halfedge`]. At a non-manifold vertex only that fan is visited.
    pub fn outgoing(&self, v: VertexId) -> Outgoing<'_> {
        let start = self.vertex_out[v.idx()];
        Outgoing {
            topo: self,
            start,
            cur: start,
        }
    }
    /// The one-ring: the vertices joined to `v` by an edge, in fan order.
    pub fn one_ring(&self, v: VertexId) -> impl Iterator<Item = VertexId> + '_ {
        self.outgoing(v).map(move |h| self.to(h))
    }
    /// Number of edges at `v` (in its fan).
    pub fn valence(&self, v: VertexId) -> u32 {
        self.outgoing(v).count() as u32
    }

    /// The half-edges of one loop, in order, starting at its first corner.
    pub fn loop_halfedges(&self, mesh: &PolyMesh, l: LoopId) -> LoopWalk<'_> {
        let start = self.corner_halfedge[mesh.loop_first_corner(l) as usize];
        LoopWalk {
            topo: self,
            start,
            cur: start,
        }
    }

    /// The boundary loops, each as its half-edges in order (a hole of the surface, not of a face).
    pub fn boundary_loops(&self) -> Vec<Vec<HalfedgeId>> {
        let mut seen = vec![false; self.to.len()];
        let mut loops = Vec::new();
        for h in 0..self.to.len() {
            if seen[h] || self.face[h].is_valid() {
                continue;
            }
            let start = HalfedgeId(h as u32);
            let lp: Vec<HalfedgeId> = LoopWalk {
                topo: self,
                start,
                cur: start,
            }
            .collect();
            for g in &lp {
                seen[g.idx()] = true;
            }
            loops.push(lp);
        }
        loops
    }

    /// Connected components of the faces (joined across shared edges): the count and each
    /// face's component, numbered in order of their lowest face.
    pub fn face_components(&self) -> (u32, Vec<u32>) {
        let nf = self.face_count as usize;
        let mut parent: Vec<u32> = (0..nf as u32).collect();
        fn root(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                let p = parent[parent[x as usize] as usize];
                parent[x as usize] = p;
                x = p;
            }
            x
        }
        for e in 0..self.to.len() / 2 {
            let (f, g) = (self.face[2 * e], self.face[2 * e + 1]);
            if f.is_valid() && g.is_valid() {
                let (rf, rg) = (root(&mut parent, f.0), root(&mut parent, g.0));
                if rf != rg {
                    parent[rf.max(rg) as usize] = rf.min(rg);
                }
            }
        }
        // Tolerated defects split an edge into several with the same end vertices: join those.
        if !self.defects.non_manifold_edges.is_empty()
            || !self.defects.inconsistent_edges.is_empty()
        {
            let mut keyed: Vec<((u32, u32), u32)> = (0..self.to.len() / 2)
                .flat_map(|e| {
                    let (a, b) = (self.to[2 * e].0, self.to[2 * e + 1].0);
                    let key = (a.min(b), a.max(b));
                    [self.face[2 * e], self.face[2 * e + 1]]
                        .into_iter()
                        .filter(|f| f.is_valid())
                        .map(move |f| (key, f.0))
                })
                .collect();
            keyed.sort_unstable();
            for w in keyed.windows(2) {
                if w[0].0 == w[1].0 {
                    let (rf, rg) = (root(&mut parent, w[0].1), root(&mut parent, w[1].1));
                    if rf != rg {
                        parent[rf.max(rg) as usize] = rf.min(rg);
                    }
                }
            }
        }
        let mut label = vec![u32::MAX; nf];
        let mut comp = vec![0u32; nf];
        let mut count = 0;
        for f in 0..nf as u32 {
            let r = root(&mut parent, f) as usize;
            if label[r] == u32::MAX {
                label[r] = count;
                count += 1;
            }
            comp[f as usize] = label[r];
        }
        (count, comp)
    }

    /// Number of vertices used by at least one face.
    pub fn referenced_vertex_count(&self) -> u32 {
        self.vertex_out.iter().filter(|h| h.is_valid()).count() as u32
    }

    /// Euler characteristic of the surface the faces make: V − E + Σ_f (1 − holes(f)), with
    /// V counting only vertices used by a face. A face with h holes is a disk with h holes,
    /// whose characteristic is 1 − h.
    pub fn euler_characteristic(&self, mesh: &PolyMesh) -> i64 {
        let faces: i64 = mesh
            .faces()
            .map(|f| 2 - mesh.face_loop_count(f) as i64)
            .sum();
        self.referenced_vertex_count() as i64 - self.edge_count() as i64 + faces
    }
}

/// Number of fans of faces at `v`: the corners at `v`, joined when their faces share an edge
/// at `v` (the same neighbour vertex), however many faces that edge has.
fn fans_at(
    v: VertexId,
    at_v: &[u32],
    corners: &[VertexId],
    head: &[VertexId],
    loop_offsets: &[u32],
) -> u32 {
    let prev_vertex = |k: u32| {
        let l = loop_offsets.partition_point(|&o| o <= k) - 1;
        let first = loop_offsets[l];
        let kp = if k == first {
            loop_offsets[l + 1] - 1
        } else {
            k - 1
        };
        corners[kp as usize]
    };
    let ends: Vec<[VertexId; 2]> = at_v
        .iter()
        .map(|&k| [head[k as usize], prev_vertex(k)])
        .collect();
    debug_assert!(at_v.iter().all(|&k| corners[k as usize] == v));
    let mut group: Vec<usize> = (0..ends.len()).collect();
    fn root(g: &mut [usize], mut x: usize) -> usize {
        while g[x] != x {
            g[x] = g[g[x]];
            x = g[x];
        }
        x
    }
    for i in 0..ends.len() {
        for j in i + 1..ends.len() {
            if ends[i].iter().any(|x| ends[j].contains(x)) {
                let (a, b) = (root(&mut group, i), root(&mut group, j));
                group[a.max(b)] = a.min(b);
            }
        }
    }
    (0..ends.len())
        .filter(|&i| root(&mut group, i) == i)
        .count() as u32
}

/// A cursor on one half-edge; each step returns a new cursor.
#[derive(Clone, Copy)]
pub struct HalfedgeRef<'a> {
    topo: &'a Topology,
    h: HalfedgeId,
}

impl<'a> HalfedgeRef<'a> {
    /// The half-edge under the cursor.
    pub fn id(self) -> HalfedgeId {
        self.h
    }
    /// Step to the next half-edge of the loop.
    pub fn next(self) -> Self {
        HalfedgeRef {
            h: self.topo.next(self.h),
            ..self
        }
    }
    /// Step to the previous half-edge of the loop.
    pub fn prev(self) -> Self {
        HalfedgeRef {
            h: self.topo.prev(self.h),
            ..self
        }
    }
    /// Step to the opposite half-edge.
    pub fn twin(self) -> Self {
        HalfedgeRef {
            h: self.topo.twin(self.h),
            ..self
        }
    }
    /// The vertex pointed to.
    pub fn to(self) -> VertexId {
        self.topo.to(self.h)
    }
    /// The vertex left.
    pub fn from(self) -> VertexId {
        self.topo.from(self.h)
    }
    /// The face, [`FaceId::INVALID`] on the boundary.
    pub fn face(self) -> FaceId {
        self.topo.face(self.h)
    }
    /// The undirected edge.
    pub fn edge(self) -> EdgeId {
        self.topo.edge(self.h)
    }
    /// Whether there is no face.
    pub fn is_boundary(self) -> bool {
        self.topo.is_boundary(self.h)
    }
}

/// Iterator over the half-edges leaving a vertex, see [`Topology::outgoing`].
pub struct Outgoing<'a> {
    topo: &'a Topology,
    start: HalfedgeId,
    cur: HalfedgeId,
}

impl Iterator for Outgoing<'_> {
    type Item = HalfedgeId;
    fn next(&mut self) -> Option<HalfedgeId> {
        if !self.cur.is_valid() {
            return None;
        }
        let h = self.cur;
        let n = self.topo.next(self.topo.twin(h));
        self.cur = if n == self.start {
            HalfedgeId::INVALID
        } else {
            n
        };
        Some(h)
    }
}

/// Iterator over the half-edges of a face loop or boundary loop.
pub struct LoopWalk<'a> {
    topo: &'a Topology,
    start: HalfedgeId,
    cur: HalfedgeId,
}

impl Iterator for LoopWalk<'_> {
    type Item = HalfedgeId;
    fn next(&mut self) -> Option<HalfedgeId> {
        if !self.cur.is_valid() {
            return None;
        }
        let h = self.cur;
        let n = self.topo.next(h);
        self.cur = if n == self.start {
            HalfedgeId::INVALID
        } else {
            n
        };
        Some(h)
    }
}
