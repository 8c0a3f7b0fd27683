//! Segmentation from a rough band by a minimum cut on the dual graph (seed 003 §3, after Katz
//! and Tal 2003; spec `rough_model.md` §1).
//!
//! The user brushes a band of faces around a feature. Taking the band out of the mesh leaves
//! an inside (the feature's side) and an outside. The faces of the band, with the faces next
//! to it on either side, become the nodes of a flow network: the inner ring is tied to the
//! source and the outer ring to the sink by links no cut can afford, and each dual edge (two
//! faces sharing a mesh edge) gets a capacity that is small across a sharp, and smaller across
//! a concave, dihedral angle. The minimum cut is the feature's boundary.

use glam::DVec3;

use super::max_flow::FlowNetwork;
use crate::error::{Error, Result, RoughError};
use crate::mesh::{FaceId, HalfedgeId, PolyMesh, Topology, VertexId};

/// The faces a user brushed: the candidates for the feature's boundary.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Band {
    /// The band's faces, in any order; repeats are ignored.
    pub faces: Vec<FaceId>,
}

impl Band {
    /// A band of the given faces.
    pub fn new(faces: impl IntoIterator<Item = FaceId>) -> Self {
        Band {
            faces: faces.into_iter().collect(),
        }
    }
}

/// Options of [`segment_band`], defaulting to the paper's values.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct SegmentOptions {
    /// A face on the feature's side of the band (not in it). Default value: `None`, the side
    /// of smaller area is the feature (spec §1).
    pub seed: Option<FaceId>,
    /// η of the angular distance across a convex edge, seed 003 §3 ("凸領域では 0.1").
    /// Default value: `0.1`.
    pub eta_convex: f64,
    /// η across a concave edge, seed 003 §3 ("凹領域では 1.0"). Default value: `1.0`.
    pub eta_concave: f64,
    /// Multiply each capacity by the shared edge's length over the mean length, so that on flat
    /// parts the cut prefers the geometrically shortest boundary (spec §1's gap-fill, neither in
    /// the seed nor in Katz–Tal). Default value: `false`.
    pub weight_by_edge_length: bool,
}

impl Default for SegmentOptions {
    fn default() -> Self {
        SegmentOptions {
            seed: None,
            eta_convex: 0.1,
            eta_concave: 1.0,
            weight_by_edge_length: false,
        }
    }
}

impl SegmentOptions {
    /// Checks the values (η finite and positive).
    pub fn validate(&self) -> Result<()> {
        for (name, value) in [
            ("eta_convex", self.eta_convex),
            ("eta_concave", self.eta_concave),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::InvalidOption {
                    option: name,
                    message: format!("{value} is not a finite number above 0"),
                });
            }
        }
        Ok(())
    }
}

/// One connected piece of the feature's boundary: mesh edges between a feature face and a
/// face outside it, as the feature faces' half-edges, head to tail.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BoundaryLoop {
    /// The half-edges, each in a feature face, the next one starting where one ends.
    pub halfedges: Vec<HalfedgeId>,
    /// Whether the last half-edge ends where the first starts. A piece is open only where the
    /// feature reaches the mesh's own boundary.
    pub closed: bool,
}

impl BoundaryLoop {
    /// The vertices in order: the start of each half-edge, then, for an open piece, the end.
    pub fn vertices(&self, topo: &Topology) -> Vec<VertexId> {
        let mut v: Vec<VertexId> = self.halfedges.iter().map(|&h| topo.from(h)).collect();
        if let (false, Some(&last)) = (self.closed, self.halfedges.last()) {
            v.push(topo.to(last));
        }
        v
    }
}

/// The result of [`segment_band`].
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// Per face: in the feature.
    pub is_feature: Vec<bool>,
    /// The feature's faces, ascending.
    pub feature: Vec<FaceId>,
    /// The feature's boundary, one entry per connected piece (a feature may have several,
    /// seed 003 Fig. 6/7): open pieces first, then closed loops, each in the order of its
    /// lowest half-edge.
    pub boundary: Vec<BoundaryLoop>,
    /// The minimum cut's capacity in the solver's integer units (exact).
    pub cut_capacity: i64,
    /// The same in units of the spec's capacities (each dual edge's capacity at most 1).
    pub flow: f64,
}

/// The flow network of a band (spec §1), before it is solved.
#[derive(Debug, Clone)]
pub struct BandGraph {
    /// Node → face: the band's faces and the rings beside it, ascending.
    pub faces: Vec<FaceId>,
    /// The network over those nodes: the inner ring linked to the source, the outer ring to
    /// the sink, each by more than all its edges carry.
    pub network: FlowNetwork,
    /// Integer units per unit of the spec's capacity.
    pub scale: f64,
    /// Per face: in the band.
    in_band: Vec<bool>,
    /// Per face: on the feature's side of the band (outside the band).
    inside: Vec<bool>,
}

/// Dihedral angles (radians) up to this are flat: far above the rounding of unit normals
/// (1e-16) and far below any crease a user means (a degree is 1.7e-2).
const FLAT_ANGLE: f64 = 1e-7;

/// Integer units of the largest capacity (spec §1: "scaled to integers by 1e6 / maxCap").
const UNITS: f64 = 1e6;

/// Finds the feature a band encloses: the minimum cut of the band's dual graph (seed 003 §3).
///
/// ```
/// use katachi::mesh::{shapes, FaceId};
/// use katachi::rough::{segment_band, Band, SegmentOptions};
/// // A 6 × 6 grid; the band is the ring of faces around the middle 2 × 2.
/// let grid = shapes::grid(6, 6).unwrap();
/// let ring = (0..36u32).filter(|f| {
///     let (x, y) = (f % 6, f / 6);
///     (1..=4).contains(&x) && (1..=4).contains(&y) && !((2..=3).contains(&x) && (2..=3).contains(&y))
/// });
/// let s = segment_band(&grid, &Band::new(ring.map(FaceId)), &SegmentOptions::default()).unwrap();
/// assert!(s.is_feature[14] && !s.is_feature[0]);
/// assert_eq!(s.boundary.len(), 1);
/// assert!(s.boundary[0].closed);
/// ```
pub fn segment_band(
    mesh: &PolyMesh,
    band: &Band,
    options: &SegmentOptions,
) -> Result<Segmentation> {
    let topo = mesh.connectivity()?;
    let graph = band_graph_with(mesh, &topo, band, options)?;
    let BandGraph {
        faces,
        network,
        scale,
        in_band,
        inside,
    } = graph;
    let cut = network.solve();
    let mut is_feature = inside;
    for (node, &f) in faces.iter().enumerate() {
        if in_band[f.idx()] && cut.source_side[node] {
            is_feature[f.idx()] = true;
        }
    }
    let feature = (0..is_feature.len() as u32)
        .filter(|&f| is_feature[f as usize])
        .map(FaceId)
        .collect();
    let boundary = boundary_loops(&topo, &is_feature)?;
    Ok(Segmentation {
        is_feature,
        feature,
        boundary,
        cut_capacity: cut.flow,
        flow: cut.flow as f64 / scale,
    })
}

/// The flow network [`segment_band`] solves, for inspection, tests and benchmarks.
pub fn band_graph(mesh: &PolyMesh, band: &Band, options: &SegmentOptions) -> Result<BandGraph> {
    let topo = mesh.connectivity()?;
    band_graph_with(mesh, &topo, band, options)
}

fn band_graph_with(
    mesh: &PolyMesh,
    topo: &Topology,
    band: &Band,
    options: &SegmentOptions,
) -> Result<BandGraph> {
    options.validate()?;
    let nf = mesh.face_count();
    let mut in_band = vec![false; nf as usize];
    for &f in &band.faces {
        if f.0 >= nf {
            return Err(RoughError::FaceOutOfRange {
                what: "band",
                face: f.0,
                face_count: nf,
            }
            .into());
        }
        in_band[f.idx()] = true;
    }
    if band.faces.is_empty() {
        return Err(RoughError::EmptyBand.into());
    }
    if let Some(s) = options.seed {
        if s.0 >= nf {
            return Err(RoughError::FaceOutOfRange {
                what: "seed",
                face: s.0,
                face_count: nf,
            }
            .into());
        }
        if in_band[s.idx()] {
            return Err(RoughError::SeedInBand { face: s.0 }.into());
        }
    }

    // The sides: connected parts of the mesh without the band.
    let (comp, comp_count) = components_without(topo, &in_band);
    let mut touches = vec![false; comp_count as usize];
    for e in 0..topo.edge_count() {
        let [f, g] = edge_faces(topo, e);
        if let (Some(f), Some(g)) = (f, g) {
            if in_band[f.idx()] != in_band[g.idx()] {
                let outside = if in_band[f.idx()] { g } else { f };
                touches[comp[outside.idx()] as usize] = true;
            }
        }
    }
    if touches.iter().filter(|&&t| t).count() < 2 {
        return Err(not_closed(topo, &in_band));
    }
    let feature_comp = match options.seed {
        Some(s) => {
            let c = comp[s.idx()];
            if !touches[c as usize] {
                return Err(RoughError::SeedNotNextToBand { face: s.0 }.into());
            }
            c
        }
        None => {
            let mut area = vec![0.0; comp_count as usize];
            for f in mesh.faces() {
                if !in_band[f.idx()] {
                    area[comp[f.idx()] as usize] += area_vector(mesh, f).length();
                }
            }
            (0..comp_count)
                .filter(|&c| touches[c as usize])
                .min_by(|&a, &b| area[a as usize].total_cmp(&area[b as usize]))
                .expect("two sides touch the band")
        }
    };
    let inside: Vec<bool> = (0..nf as usize)
        .map(|f| !in_band[f] && comp[f] == feature_comp)
        .collect();

    // Nodes: the band and the faces next to it, ascending.
    let mut is_node = in_band.clone();
    let mut graph_edges: Vec<(FaceId, FaceId, HalfedgeId)> = Vec::new();
    for e in 0..topo.edge_count() {
        let [f, g] = edge_faces(topo, e);
        if let (Some(f), Some(g)) = (f, g) {
            if f != g && (in_band[f.idx()] || in_band[g.idx()]) {
                is_node[f.idx()] = true;
                is_node[g.idx()] = true;
                graph_edges.push((f, g, HalfedgeId(2 * e)));
            }
        }
    }
    let mut node_of = vec![u32::MAX; nf as usize];
    let mut faces = Vec::new();
    for f in 0..nf {
        if is_node[f as usize] {
            node_of[f as usize] = faces.len() as u32;
            faces.push(FaceId(f));
        }
    }

    // Angular distance of each dual edge (Katz–Tal; seed 003 §3 d(i, j) = η(1 − cos α)).
    let (lo, hi) = mesh.bounding_box().unwrap_or((DVec3::ZERO, DVec3::ZERO));
    let eps = 1e-12 * (hi - lo).length();
    let mut normal = vec![DVec3::ZERO; faces.len()];
    let mut centroid = vec![DVec3::ZERO; faces.len()];
    for (node, &f) in faces.iter().enumerate() {
        normal[node] = area_vector(mesh, f).normalize_or_zero();
        let outer = mesh.face_outer(f);
        centroid[node] =
            outer.iter().map(|&v| mesh.position(v)).sum::<DVec3>() / outer.len() as f64;
    }
    let mut dist = Vec::with_capacity(graph_edges.len());
    let mut length = Vec::with_capacity(graph_edges.len());
    for &(f, g, h) in &graph_edges {
        let (i, j) = (node_of[f.idx()] as usize, node_of[g.idx()] as usize);
        // Concave iff the neighbour's centroid lies above this face's plane (ties convex).
        let (a, b) = if f < g { (i, j) } else { (j, i) };
        let concave = (centroid[b] - centroid[a]).dot(normal[a]) > eps;
        let eta = if concave {
            options.eta_concave
        } else {
            options.eta_convex
        };
        // 1 − cos α = |n_i − n_j|² / 2 for unit normals, without cancellation; angles below
        // FLAT_ANGLE count as flat, so rounding in the normals of a plane does not make the
        // scale-free capacities below (d / avg d) arbitrary.
        let one_minus_cos = 0.5 * normal[i].distance_squared(normal[j]);
        dist.push(if one_minus_cos <= 0.5 * FLAT_ANGLE * FLAT_ANGLE {
            0.0
        } else {
            eta * one_minus_cos
        });
        length.push(
            mesh.position(topo.to(h))
                .distance(mesh.position(topo.from(h))),
        );
    }
    let m = graph_edges.len().max(1) as f64;
    let mean_dist = dist.iter().sum::<f64>() / m;
    let mean_length = length.iter().sum::<f64>() / m;
    // Cap(i, j) = 1 / (1 + d / avg d) (spec §1; the seed's typeset formula is garbled).
    let caps: Vec<f64> = dist
        .iter()
        .zip(&length)
        .map(|(&d, &len)| {
            let c = if mean_dist > 0.0 {
                1.0 / (1.0 + d / mean_dist)
            } else {
                1.0
            };
            if options.weight_by_edge_length && mean_length > 0.0 {
                c * len / mean_length
            } else {
                c
            }
        })
        .collect();
    let max_cap = caps.iter().copied().fold(0.0, f64::max);
    let scale = if max_cap > 0.0 { UNITS / max_cap } else { 1.0 };

    let mut network = FlowNetwork::new(faces.len() as u32);
    // A terminal link worth more than all its node's edges together is never cut: an exact ∞.
    let mut incident = vec![0i64; faces.len()];
    for (k, &(f, g, _)) in graph_edges.iter().enumerate() {
        let c = ((caps[k] * scale).round() as i64).max(1);
        let (i, j) = (node_of[f.idx()], node_of[g.idx()]);
        network.add_edge(i, j, c, c)?;
        incident[i as usize] += c;
        incident[j as usize] += c;
    }
    for (node, &f) in faces.iter().enumerate() {
        if in_band[f.idx()] {
            continue;
        }
        let big = incident[node] + 1;
        if inside[f.idx()] {
            network.add_terminal(node as u32, big, 0)?;
        } else {
            network.add_terminal(node as u32, 0, big)?;
        }
    }
    Ok(BandGraph {
        faces,
        network,
        scale,
        in_band,
        inside,
    })
}

/// The two faces of edge `e` (`None` on the mesh's boundary side).
fn edge_faces(topo: &Topology, e: u32) -> [Option<FaceId>; 2] {
    [HalfedgeId(2 * e), HalfedgeId(2 * e + 1)].map(|h| {
        let f = topo.face(h);
        f.is_valid().then_some(f)
    })
}

/// Newell's area vector of a face over all its loops (holes subtract themselves).
fn area_vector(mesh: &PolyMesh, f: FaceId) -> DVec3 {
    let origin = mesh.position(mesh.face_outer(f)[0]);
    let mut n = DVec3::ZERO;
    for l in mesh.face_loops(f) {
        let lp = mesh.loop_vertices(l);
        for (i, &a) in lp.iter().enumerate() {
            let b = lp[(i + 1) % lp.len()];
            n += (mesh.position(a) - origin).cross(mesh.position(b) - origin);
        }
    }
    0.5 * n
}

/// Connected parts of the faces not in `removed` (joined across shared edges), numbered in
/// order of their lowest face; removed faces get `u32::MAX`.
fn components_without(topo: &Topology, removed: &[bool]) -> (Vec<u32>, u32) {
    let nf = removed.len();
    let mut comp = vec![u32::MAX; nf];
    let mut count = 0;
    let mut stack = Vec::new();
    let faces_of = face_halfedges(topo, nf);
    for start in 0..nf {
        if removed[start] || comp[start] != u32::MAX {
            continue;
        }
        comp[start] = count;
        stack.push(start);
        while let Some(f) = stack.pop() {
            for &h in &faces_of.1[faces_of.0[f] as usize..faces_of.0[f + 1] as usize] {
                let g = topo.face(topo.twin(h));
                if g.is_valid() && !removed[g.idx()] && comp[g.idx()] == u32::MAX {
                    comp[g.idx()] = count;
                    stack.push(g.idx());
                }
            }
        }
        count += 1;
    }
    (comp, count)
}

/// Each face's half-edges (all loops), as offsets and a flat list.
fn face_halfedges(topo: &Topology, nf: usize) -> (Vec<u32>, Vec<HalfedgeId>) {
    let mut start = vec![0u32; nf + 1];
    for h in 0..topo.halfedge_count() {
        let f = topo.face(HalfedgeId(h));
        if f.is_valid() {
            start[f.idx() + 1] += 1;
        }
    }
    for i in 0..nf {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut list = vec![HalfedgeId::INVALID; start[nf] as usize];
    for h in 0..topo.halfedge_count() {
        let f = topo.face(HalfedgeId(h));
        if f.is_valid() {
            list[fill[f.idx()] as usize] = HalfedgeId(h);
            fill[f.idx()] += 1;
        }
    }
    (start, list)
}

/// The error for a band that leaves one side: at the mesh boundary if the band reaches it,
/// else naming one end of the band (an end of a longest shortest path through its faces,
/// which for an open strip is where its gap is).
fn not_closed(topo: &Topology, in_band: &[bool]) -> Error {
    let nf = in_band.len();
    for h in 0..topo.halfedge_count() {
        let h = HalfedgeId(h);
        let f = topo.face(h);
        if f.is_valid() && in_band[f.idx()] && topo.is_boundary(topo.twin(h)) {
            let lowest = (0..topo.halfedge_count())
                .map(HalfedgeId)
                .filter(|&g| {
                    let f = topo.face(g);
                    f.is_valid() && in_band[f.idx()] && topo.is_boundary(topo.twin(g))
                })
                .map(|g| topo.face(g).0)
                .min()
                .unwrap_or(f.0);
            return RoughError::BandOpenAtBoundary { face: lowest }.into();
        }
    }
    let faces_of = face_halfedges(topo, nf);
    let farthest = |from: usize| -> usize {
        let mut seen = vec![false; nf];
        let mut queue = std::collections::VecDeque::from([from]);
        seen[from] = true;
        let mut last = from;
        while let Some(f) = queue.pop_front() {
            last = f;
            let mut next: Vec<usize> = faces_of.1
                [faces_of.0[f] as usize..faces_of.0[f + 1] as usize]
                .iter()
                .map(|&h| topo.face(topo.twin(h)))
                .filter(|g| g.is_valid() && in_band[g.idx()] && !seen[g.idx()])
                .map(|g| g.idx())
                .collect();
            next.sort_unstable();
            next.dedup();
            for g in next {
                seen[g] = true;
                queue.push_back(g);
            }
        }
        last
    };
    let first = in_band.iter().position(|&b| b).unwrap_or(0);
    let end = farthest(farthest(first));
    RoughError::BandNotClosed { face: end as u32 }.into()
}

/// The boundary of the feature: its half-edges whose twin lies in a face outside it, chained
/// head to tail by turning around each vertex inside the feature.
fn boundary_loops(topo: &Topology, is_feature: &[bool]) -> Result<Vec<BoundaryLoop>> {
    let cut = |h: HalfedgeId| {
        let (f, g) = (topo.face(h), topo.face(topo.twin(h)));
        f.is_valid() && g.is_valid() && is_feature[f.idx()] && !is_feature[g.idx()]
    };
    let n = topo.halfedge_count();
    // The cut half-edge after h, or None where the feature meets the mesh boundary.
    let successor = |h: HalfedgeId| -> Result<Option<HalfedgeId>> {
        let mut g = topo.next(h);
        for _ in 0..n {
            if cut(g) {
                return Ok(Some(g));
            }
            let t = topo.twin(g);
            if topo.is_boundary(t) {
                return Ok(None);
            }
            g = topo.next(t);
        }
        Err(Error::Internal(format!(
            "feature boundary: turning around vertex {} did not end",
            topo.to(h)
        )))
    };
    let mut next = vec![HalfedgeId::INVALID; n as usize];
    let mut has_pred = vec![false; n as usize];
    let mut cuts = Vec::new();
    for h in (0..n).map(HalfedgeId) {
        if cut(h) {
            cuts.push(h);
            if let Some(s) = successor(h)? {
                next[h.idx()] = s;
                has_pred[s.idx()] = true;
            }
        }
    }
    let mut used = vec![false; n as usize];
    let mut loops = Vec::new();
    // Open pieces first, from their starts; then the closed loops.
    for pass in 0..2 {
        for &h in &cuts {
            if used[h.idx()] || (pass == 0 && has_pred[h.idx()]) {
                continue;
            }
            let mut halfedges = Vec::new();
            let mut g = h;
            let closed = loop {
                used[g.idx()] = true;
                halfedges.push(g);
                let s = next[g.idx()];
                if !s.is_valid() {
                    break false;
                }
                if s == h {
                    break true;
                }
                if used[s.idx()] {
                    return Err(Error::Internal(format!(
                        "feature boundary: half-edge {} continues into a piece already walked",
                        g.0
                    )));
                }
                g = s;
            };
            loops.push(BoundaryLoop { halfedges, closed });
        }
    }
    Ok(loops)
}
