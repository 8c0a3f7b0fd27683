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

/// Per-vertex sums for the smooth rule, eq. (2): Σ e_j + Σ f_j and the counts.
#[derive(Clone, Copy, Default)]
struct SmoothSums {
    sum: DVec3,
    edges: u32,
    faces: u32,
}

/// Per-vertex sums for the crease and corner rules (only where the level has sharpness).
#[derive(Clone, Copy, Default)]
struct SharpSums {
    /// Far ends of the sharp edges in the parent, and of the edges whose child is sharp.
    sharp_sum: DVec3,
    sharp: u32,
    child_sharp_sum: DVec3,
    child_sharp: u32,
    transitions: Transitions,
}

/// Weight of a face point in an edge point: ¼ for a smooth edge (eq. (1)), 0 for a sharp
/// one (midpoint), (1 − s)·¼ for a semi-sharp edge whose child is not a crease.
#[inline]
fn face_weight(s: f32, child: [f32; 2]) -> f64 {
    if !crease::is_sharp(s) {
        0.25
    } else if crease::is_sharp(child[0]) && crease::is_sharp(child[1]) {
        0.0
    } else {
        (1.0 - s as f64) * 0.25
    }
}

/// Refines `parent` once. Returns the child level and its positions. For the last level
/// (`last`), the child's edges are not built: only faces and the remaining creases.
pub(crate) fn refine(
    parent: &Level,
    pos: &[DVec3],
    method: CreaseMethod,
    face_point: Option<FacePointOverride>,
    last: bool,
) -> (Level, Vec<DVec3>) {
    let nv = parent.vertex_count as usize;
    let nf = parent.face_count() as usize;
    let ne = parent.edge_count() as usize;

    let mut face_child = vec![u32::MAX; nf];
    let mut refined = 0usize;
    let mut interior_edges = 0usize;
    for f in 0..nf {
        if !parent.face_kept[f] {
            face_child[f] = refined as u32;
            refined += 1;
            interior_edges += parent.face_corners(f).len();
        }
    }
    let (f0, e0) = (nv, nv + refined);
    let mut child_pos = vec![DVec3::ZERO; nv + refined + ne];

    // Face points (§2.1: vertex average), for the faces that are split.
    for f in 0..nf {
        let fc = face_child[f];
        if fc == u32::MAX {
            continue;
        }
        let cs = parent.face_corners(f);
        child_pos[f0 + fc as usize] = face_point.and_then(|o| o(f)).unwrap_or_else(|| {
            let sum: DVec3 = cs
                .clone()
                .map(|c| pos[parent.corner_verts[c] as usize])
                .sum();
            sum / cs.len() as f64
        });
    }

    let any_sharp = parent.edge_sharpness.iter().any(|&s| crease::is_sharp(s))
        || parent.vertex_sharpness.iter().any(|&s| crease::is_sharp(s));

    // Chaikin needs, at each vertex, the sum and count of its semi-sharp edges.
    let mut semi = Vec::new();
    if any_sharp && method == CreaseMethod::Chaikin {
        semi = vec![SemiSharpAtVertex::default(); nv];
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

    // Edges: child sharpness, per-vertex sums, and the vertex part of the edge points.
    let mut smooth = vec![SmoothSums::default(); nv];
    let mut sharp = if any_sharp {
        vec![SharpSums::default(); nv]
    } else {
        Vec::new()
    };
    let mut child_sharpness = vec![[0f32; 2]; ne];
    for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
        let (pa, pb) = (pos[a as usize], pos[b as usize]);
        for (v, far) in [(a, pb), (b, pa)] {
            let t = &mut smooth[v as usize];
            t.sum += far;
            t.edges += 1;
        }
        let s = parent.edge_sharpness[e];
        if !crease::is_sharp(s) {
            child_pos[e0 + e] = 0.25 * (pa + pb);
            continue;
        }
        let at = |v: u32| semi.get(v as usize).copied().unwrap_or_default();
        let c = [
            crease::child_sharpness(method, s, at(a)),
            crease::child_sharpness(method, s, at(b)),
        ];
        child_sharpness[e] = c;
        for (end, (v, far)) in [(a, pb), (b, pa)].into_iter().enumerate() {
            let t = &mut sharp[v as usize];
            t.sharp_sum += far;
            t.sharp += 1;
            if crease::is_sharp(c[end]) {
                t.child_sharp_sum += far;
                t.child_sharp += 1;
            }
            t.transitions.add_edge(method, s, c[end]);
        }
        // Midpoint, or the blend of smooth and sharp masks by the sharpness (the face part
        // is added below).
        let vertex_weight = if face_weight(s, c) == 0.0 {
            0.5
        } else {
            let sw = s as f64;
            sw * 0.5 + (1.0 - sw) * 0.25
        };
        child_pos[e0 + e] = vertex_weight * (pa + pb);
    }

    // Scatter face points to vertices (eq. (2)) and edges (eq. (1)).
    for f in 0..nf {
        let fc = face_child[f];
        if fc == u32::MAX {
            continue;
        }
        let fp = child_pos[f0 + fc as usize];
        for c in parent.face_corners(f) {
            let t = &mut smooth[parent.corner_verts[c] as usize];
            t.sum += fp;
            t.faces += 1;
            let e = parent.corner_edges[c] as usize;
            let w = face_weight(parent.edge_sharpness[e], child_sharpness[e]);
            child_pos[e0 + e] += w * fp;
        }
    }

    // Vertex points.
    for v in 0..nv {
        let t = smooth[v];
        let p = pos[v];
        let smooth_rule = || {
            if t.edges == 0 || t.faces != t.edges {
                return p; // isolated, or a fan the smooth rule does not apply to
            }
            let n = t.edges as f64;
            (n - 2.0) / n * p + t.sum / (n * n)
        };
        let vsharp = parent.vertex_sharpness[v];
        let Some(x) = sharp.get(v) else {
            child_pos[v] = smooth_rule();
            continue;
        };
        let rule = crease::vertex_rule(vsharp, x.sharp);
        let apply = |rule: Rule, sharp_sum: DVec3| match rule {
            Rule::Smooth => smooth_rule(),
            Rule::Crease => (sharp_sum + 6.0 * p) / 8.0,
            Rule::Corner => p,
        };
        child_pos[v] = if rule == Rule::Smooth {
            smooth_rule()
        } else {
            let child_vsharp = crease::decrement(vsharp);
            let parent_p = apply(rule, x.sharp_sum);
            let child_rule = crease::vertex_rule(child_vsharp, x.child_sharp);
            if child_rule == rule {
                parent_p
            } else {
                let w = x.transitions.weight(vsharp, child_vsharp) as f64;
                w * parent_p + (1.0 - w) * apply(child_rule, x.child_sharp_sum)
            }
        };
    }

    let child = refine_topology(
        parent,
        &face_child,
        refined,
        interior_edges,
        &child_sharpness,
        last,
    );
    (child, child_pos)
}

/// The child level's faces, edges and sharpness.
fn refine_topology(
    parent: &Level,
    face_child: &[u32],
    face_points: usize,
    interior_edges: usize,
    child_sharpness: &[[f32; 2]],
    last: bool,
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

    let mut interior = Vec::with_capacity(if last { 0 } else { interior_edges });
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
        if !last {
            for c in cs {
                interior.push([ev(parent.corner_edges[c]), fv(f)]);
            }
        }
    }

    if last {
        // Only the creases that remain, for the output mesh.
        for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
            if parent.edge_forced[e] {
                continue;
            }
            let m = ev(e as u32);
            for (end, v) in [a, b].into_iter().enumerate() {
                let s = child_sharpness[e][end];
                if crease::is_sharp(s) {
                    child.last_creases.push(([v, m], s));
                }
            }
        }
        child.vertex_sharpness = parent
            .vertex_sharpness
            .iter()
            .map(|&s| crease::decrement(s))
            .collect();
        child
            .vertex_sharpness
            .resize(child.vertex_count as usize, 0.0);
        child.vertex_forced = parent.vertex_forced.clone();
        child
            .vertex_forced
            .resize(child.vertex_count as usize, false);
        return child;
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
