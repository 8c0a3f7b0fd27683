//! One Catmull-Clark step: child positions and child topology from a [`Level`].
//!
//! Positions follow seed 001 (which takes them from DeRose et al. 1998): face point §2.1,
//! edge point eq. (1), vertex point eq. (2); sharp edge point = midpoint; crease vertex
//! eq. (3); corner vertex eq. (4); semi-sharp edges and rule changes between levels blend the
//! masks as OpenSubdiv does (spec §7.1). Every sum is a scatter pass over corners or edges,
//! so the work is linear and no vertex ring is walked.
//!
//! Child numbering (OpenSubdiv's default for uniform refinement): vertices are the children
//! of vertices, then of faces, then of edges; edges are the face-interior edges (corner
//! order), then the two halves of each parent edge; faces are the children of each face in
//! corner order, a quad `(vertex, next edge, face, previous edge)` per corner.

// Loops index several parallel arrays by the same face or corner; iterators would hide that.
#![allow(clippy::needless_range_loop)]

use glam::DVec3;

use super::crease::{self, Rule, SemiSharpAtVertex, Transitions};
use super::level::Level;
use super::options::CreaseMethod;

/// A face point other than the vertex average, for method [a]'s virtual faces (seed 001
/// §3.1: the average of the two bridge ends on each loop).
pub(crate) type FacePointOverride<'a> = &'a dyn Fn(usize) -> Option<DVec3>;

#[derive(Clone, Copy, Default)]
struct VertexSums {
    /// Σ far ends of incident edges, and their count (eq. (2): Σ e_j, n).
    edge_sum: DVec3,
    edges: u32,
    /// Σ face points of incident faces, and their count (eq. (2): Σ f_j).
    face_sum: DVec3,
    faces: u32,
    /// Far ends of sharp edges in the parent, and of edges whose child is sharp.
    sharp_sum: DVec3,
    sharp: u32,
    child_sharp_sum: DVec3,
    child_sharp: u32,
    transitions: Transitions,
}

/// Refines `parent` once. Returns the child level and its positions.
pub(crate) fn refine(
    parent: &Level,
    pos: &[DVec3],
    method: CreaseMethod,
    face_point: Option<FacePointOverride>,
) -> (Level, Vec<DVec3>) {
    let nv = parent.vertex_count as usize;
    let nf = parent.face_count() as usize;
    let ne = parent.edge_count() as usize;

    // Face points (§2.1: vertex average), for the faces that are split.
    let mut face_child = vec![u32::MAX; nf];
    let mut face_points = Vec::with_capacity(nf);
    let mut interior_edges = 0usize;
    for f in 0..nf {
        if parent.face_kept[f] {
            continue;
        }
        face_child[f] = face_points.len() as u32;
        let cs = parent.face_corners(f);
        interior_edges += cs.len();
        let p = face_point.and_then(|o| o(f)).unwrap_or_else(|| {
            let sum: DVec3 = cs
                .clone()
                .map(|c| pos[parent.corner_verts[c] as usize])
                .sum();
            sum / cs.len() as f64
        });
        face_points.push(p);
    }
    let nfp = face_points.len();

    // Scatter face points to vertices and edges.
    let mut vs = vec![VertexSums::default(); nv];
    let mut edge_face_sum = vec![DVec3::ZERO; ne];
    for f in 0..nf {
        let fc = face_child[f];
        if fc == u32::MAX {
            continue;
        }
        let fp = face_points[fc as usize];
        for c in parent.face_corners(f) {
            let v = &mut vs[parent.corner_verts[c] as usize];
            v.face_sum += fp;
            v.faces += 1;
            edge_face_sum[parent.corner_edges[c] as usize] += fp;
        }
    }

    // Chaikin needs, at each vertex, the sum and count of its semi-sharp edges.
    let mut semi = vec![SemiSharpAtVertex::default(); nv];
    if method == CreaseMethod::Chaikin {
        for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
            let s = parent.edge_sharpness[e];
            if crease::is_semi_sharp(s) {
                for v in [a, b] {
                    semi[v as usize].sum += s;
                    semi[v as usize].count += 1;
                }
            }
        }
    }

    // Edges: child sharpness, per-vertex sums, edge points (eq. (1), midpoint, or the blend).
    let mut child_sharpness = vec![[0f32; 2]; ne];
    let mut edge_points = Vec::with_capacity(ne);
    for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
        let s = parent.edge_sharpness[e];
        let (pa, pb) = (pos[a as usize], pos[b as usize]);
        let c = [
            crease::child_sharpness(method, s, semi[a as usize]),
            crease::child_sharpness(method, s, semi[b as usize]),
        ];
        child_sharpness[e] = c;
        for (end, (v, far)) in [(a, pb), (b, pa)].into_iter().enumerate() {
            let t = &mut vs[v as usize];
            t.edge_sum += far;
            t.edges += 1;
            if crease::is_sharp(s) {
                t.sharp_sum += far;
                t.sharp += 1;
            }
            if crease::is_sharp(c[end]) {
                t.child_sharp_sum += far;
                t.child_sharp += 1;
            }
            t.transitions.add_edge(method, s, c[end]);
        }
        let mid = 0.5 * (pa + pb);
        let p = if !crease::is_sharp(s) {
            0.25 * (pa + pb + edge_face_sum[e])
        } else if crease::is_sharp(c[0]) && crease::is_sharp(c[1]) {
            mid
        } else {
            // The child is not a crease: blend the smooth and sharp masks by the sharpness.
            let w = s as f64;
            let smooth = 0.25 * (pa + pb + edge_face_sum[e]);
            w * mid + (1.0 - w) * smooth
        };
        edge_points.push(p);
    }

    // Vertex points.
    let mut child_pos = Vec::with_capacity(nv + nfp + ne);
    for v in 0..nv {
        let t = &vs[v];
        let p = pos[v];
        let vsharp = parent.vertex_sharpness[v];
        let child_vsharp = crease::decrement(vsharp);
        let rule = crease::vertex_rule(vsharp, t.sharp);
        let smooth = |t: &VertexSums| {
            if t.edges == 0 || t.faces != t.edges {
                return p; // isolated, or a fan the smooth rule does not apply to
            }
            let n = t.edges as f64;
            (n - 2.0) / n * p + (t.edge_sum + t.face_sum) / (n * n)
        };
        let apply = |rule: Rule, sharp_sum: DVec3| match rule {
            Rule::Smooth => smooth(t),
            Rule::Crease => (sharp_sum + 6.0 * p) / 8.0,
            Rule::Corner => p,
        };
        let out = if rule == Rule::Smooth {
            smooth(t)
        } else {
            let parent_p = apply(rule, t.sharp_sum);
            let child_rule = crease::vertex_rule(child_vsharp, t.child_sharp);
            if child_rule == rule {
                parent_p
            } else {
                let w = t.transitions.weight(vsharp, child_vsharp) as f64;
                w * parent_p + (1.0 - w) * apply(child_rule, t.child_sharp_sum)
            }
        };
        child_pos.push(out);
    }
    child_pos.extend_from_slice(&face_points);
    child_pos.extend_from_slice(&edge_points);

    let child = refine_topology(parent, &face_child, nfp, interior_edges, &child_sharpness);
    (child, child_pos)
}

/// The child level's faces, edges and sharpness.
fn refine_topology(
    parent: &Level,
    face_child: &[u32],
    face_points: usize,
    interior_edges: usize,
    child_sharpness: &[[f32; 2]],
) -> Level {
    let nv = parent.vertex_count;
    let ne = parent.edge_count() as usize;
    let fv = |f: usize| nv + face_child[f];
    let ev = |e: u32| nv + face_points as u32 + e;
    let half = |e: u32, v: u32| {
        (interior_edges + 2 * e as usize) as u32 + (parent.edge_verts[e as usize][0] != v) as u32
    };

    let mut child = Level {
        vertex_count: nv + face_points as u32 + ne as u32,
        ..Default::default()
    };
    let child_faces = interior_edges + parent.face_kept.iter().filter(|&&k| k).count();
    let child_corners = 4 * interior_edges + 2 * (parent.corner_verts.len() - interior_edges);
    child.face_loops.reserve(child_faces + 1);
    child.loop_offsets.reserve(child_faces + 1);
    child.corner_verts.reserve(child_corners);
    child.corner_edges.reserve(child_corners);
    child.face_origin.reserve(child_faces);
    child.face_kept.reserve(child_faces);
    child.face_loops.push(0);
    child.loop_offsets.push(0);

    let mut interior = Vec::with_capacity(interior_edges);
    for f in 0..parent.face_count() as usize {
        let origin = parent.face_origin[f];
        if face_child[f] == u32::MAX {
            // Kept face: one child face, each loop refined (every loop edge split in two).
            let (l0, l1) = (
                parent.face_loops[f] as usize,
                parent.face_loops[f + 1] as usize,
            );
            for l in l0..l1 {
                let (a, b) = (
                    parent.loop_offsets[l] as usize,
                    parent.loop_offsets[l + 1] as usize,
                );
                for c in a..b {
                    let v = parent.corner_verts[c];
                    let next = parent.corner_verts[if c + 1 < b { c + 1 } else { a }];
                    let e = parent.corner_edges[c];
                    child.corner_verts.extend_from_slice(&[v, ev(e)]);
                    child
                        .corner_edges
                        .extend_from_slice(&[half(e, v), half(e, next)]);
                }
                child.loop_offsets.push(child.corner_verts.len() as u32);
            }
            child.face_loops.push(child.loop_offsets.len() as u32 - 1);
            child.face_kept.push(true);
            child.face_origin.push(origin);
            continue;
        }
        let cs = parent.face_corners(f);
        let base = interior.len() as u32;
        let k = cs.len() as u32;
        for (j, c) in cs.clone().enumerate() {
            let j = j as u32;
            let prev = if c == cs.start { cs.end - 1 } else { c - 1 };
            let v = parent.corner_verts[c];
            let (e, ep) = (parent.corner_edges[c], parent.corner_edges[prev]);
            child
                .corner_verts
                .extend_from_slice(&[v, ev(e), fv(f), ev(ep)]);
            child.corner_edges.extend_from_slice(&[
                half(e, v),
                base + j,
                base + (j + k - 1) % k,
                half(ep, v),
            ]);
            child.loop_offsets.push(child.corner_verts.len() as u32);
            child.face_loops.push(child.loop_offsets.len() as u32 - 1);
            child.face_kept.push(false);
            child.face_origin.push(origin);
        }
        for c in cs {
            interior.push([ev(parent.corner_edges[c]), fv(f)]);
        }
    }

    child.edge_verts = interior;
    child.edge_verts.reserve(2 * ne);
    child.edge_sharpness = vec![0.0; interior_edges];
    child.edge_sharpness.reserve(2 * ne);
    child.edge_forced = vec![false; interior_edges];
    child.edge_forced.reserve(2 * ne);
    for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
        let m = ev(e as u32);
        child.edge_verts.extend_from_slice(&[[a, m], [m, b]]);
        child.edge_sharpness.extend_from_slice(&child_sharpness[e]);
        let forced = parent.edge_forced[e];
        child.edge_forced.extend_from_slice(&[forced, forced]);
    }

    let n = child.vertex_count as usize;
    child.vertex_sharpness = Vec::with_capacity(n);
    child.vertex_sharpness.extend(
        parent
            .vertex_sharpness
            .iter()
            .map(|&s| crease::decrement(s)),
    );
    child.vertex_sharpness.resize(n, 0.0);
    child.vertex_forced = parent.vertex_forced.clone();
    child.vertex_forced.resize(n, false);
    child
}
