//! One Catmull-Clark step, split in two: a [`Step`] decides everything that depends only on
//! topology and sharpness (which faces split, child sharpness, each vertex's rule and blend
//! weight), and [`interpolate`] applies it to values of any [`Primvar`] type.
//!
//! Rules follow seed 001 (which takes them from DeRose et al. 1998): face point (§2), edge
//! point eq. (1), vertex point eq. (2); sharp edge point = midpoint; crease vertex eq. (3);
//! corner vertex eq. (4); semi-sharp edges and rule changes between levels blend the masks
//! as OpenSubdiv does (spec §7.1). Every sum is a scatter pass over corners or edges, so the
//! work is linear and no vertex ring is walked.
//!
//! Child numbering (OpenSubdiv's default for uniform refinement): vertices are the children
//! of vertices, then of faces, then of edges; edges are the face-interior edges (corner
//! order), then the two halves of each parent edge; faces are the children of each face in
//! corner order, a quad `(vertex, next edge, face, previous edge)` per corner, rotated for
//! quads so that child j has its parent corner at position j; child edges run from the
//! face point or edge point outwards.

// Loops index several parallel arrays by the same face or corner; iterators would hide that.
#![allow(clippy::needless_range_loop)]

use super::crease::{self, Rule, SemiSharpAtVertex, Transitions};
use super::level::Level;
use super::options::CreaseMethod;
use super::primvar::Primvar;
use crate::mem::{self, Buf};
use rayon::prelude::*;

/// How a vertex point is made when the level has sharpness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VertexMask {
    pub rule: Rule,
    pub child_rule: Rule,
    /// Weight of `rule` when it differs from `child_rule` (OpenSubdiv's fractional weight).
    pub weight: f64,
}

/// What one level's refinement decided, for any interpolated data.
#[derive(Debug, Clone)]
pub(crate) struct Step {
    /// Parent face → index among the split faces, `u32::MAX` for kept faces.
    pub face_child: Buf<u32>,
    pub refined: usize,
    pub interior_edges: usize,
    /// Per parent edge, the sharpness of its two halves (zeros when the level is smooth).
    pub child_sharpness: Buf<[f32; 2]>,
    /// Per vertex: number of incident edges and of incident split faces.
    pub vertex_edges: Buf<u32>,
    pub vertex_faces: Buf<u32>,
    /// Per vertex, when the level has any sharpness.
    pub masks: Vec<VertexMask>,
    /// Per parent face, the vertices whose average is its face point when that is not the
    /// face's own vertex average (method `[a]`'s virtual faces, seed 001 §4).
    pub face_point_vertices: Vec<Option<Vec<u32>>>,
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

/// Decides one level's refinement.
pub(crate) fn plan(
    parent: &Level,
    method: CreaseMethod,
    face_point_vertices: Vec<Option<Vec<u32>>>,
) -> Step {
    let nv = parent.vertex_count as usize;
    let nf = parent.face_count() as usize;
    let ne = parent.edge_count() as usize;
    // Three independent passes, side by side.
    let faces_pass = || {
        let mut face_child = Buf::filled(nf, u32::MAX);
        let mut refined = 0usize;
        let mut interior_edges = 0usize;
        let mut vertex_faces = Buf::<u32>::zeroed(nv);
        for f in 0..nf {
            if !parent.is_kept(f) {
                face_child[f] = refined as u32;
                refined += 1;
                let cs = parent.face_corners(f);
                interior_edges += cs.len();
                for c in cs {
                    vertex_faces[parent.corner_verts[c] as usize] += 1;
                }
            }
        }
        (face_child, refined, interior_edges, vertex_faces)
    };
    let edges_pass = || {
        let mut vertex_edges = Buf::<u32>::zeroed(nv);
        for &[a, b] in parent.edge_verts.iter() {
            vertex_edges[a as usize] += 1;
            vertex_edges[b as usize] += 1;
        }
        vertex_edges
    };
    let sharp_pass = || {
        parent
            .edge_sharpness
            .par_iter()
            .any(|&s| crease::is_sharp(s))
            || parent.any_vertex_sharp
    };
    let ((face_child, refined, interior_edges, vertex_faces), (vertex_edges, any_sharp)) =
        rayon::join(faces_pass, || rayon::join(edges_pass, sharp_pass));
    // Read only where some edge is sharp: empty on smooth levels.
    let mut child_sharpness = Buf::<[f32; 2]>::zeroed(if any_sharp { ne } else { 0 });
    let mut masks = Vec::new();
    if any_sharp {
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
        let mut counts = vec![(0u32, 0u32, Transitions::default()); nv];
        for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
            let s = parent.edge_sharpness[e];
            if !crease::is_sharp(s) {
                continue;
            }
            let c = [
                crease::child_sharpness(method, s, semi[a as usize]),
                crease::child_sharpness(method, s, semi[b as usize]),
            ];
            child_sharpness[e] = c;
            for (end, v) in [a, b].into_iter().enumerate() {
                let t = &mut counts[v as usize];
                t.0 += 1;
                t.1 += crease::is_sharp(c[end]) as u32;
                t.2.add_edge(method, s, c[end]);
            }
        }
        masks = (0..nv)
            .map(|v| {
                let (sharp, child_sharp, transitions) = counts[v];
                let vsharp = parent.vertex_sharpness[v];
                let child_vsharp = crease::decrement(vsharp);
                let rule = crease::vertex_rule(vsharp, sharp);
                let child_rule = crease::vertex_rule(child_vsharp, child_sharp);
                let weight = if rule == Rule::Smooth || child_rule == rule {
                    1.0
                } else {
                    transitions.weight(vsharp, child_vsharp) as f64
                };
                VertexMask {
                    rule,
                    child_rule,
                    weight,
                }
            })
            .collect();
    }
    Step {
        face_child,
        refined,
        interior_edges,
        child_sharpness,
        vertex_edges,
        vertex_faces,
        masks,
        face_point_vertices,
    }
}

/// Applies `step` to per-vertex values of `parent`: returns the child level's values
/// (children of vertices, then of faces, then of edges). Face points and vertex points are
/// computed per element in parallel; the two scatter passes (vertex sums, edge points) run
/// side by side, each in a fixed order, so the result does not depend on the thread count.
/// `output`: the values are handed to the caller (an ordinary `Vec` inside the `Buf`).
pub(crate) fn interpolate<T: Primvar>(
    parent: &Level,
    step: &Step,
    values: &[T],
    output: bool,
) -> Buf<T> {
    let nv = parent.vertex_count as usize;
    let nf = parent.face_count() as usize;
    let ne = parent.edge_count() as usize;
    let n = nv + step.refined + ne;
    let mut out = if output {
        Buf::from(T::zeros(n))
    } else {
        Buf::filled(n, T::zero())
    };
    let (vertex_out, rest) = out.split_at_mut(nv);
    let (face_out, edge_out) = rest.split_at_mut(step.refined);

    // Face points (seed §2: vertex average, or method [a]'s four bridge ends).
    let face_point = |f: usize| {
        let mut p = T::zero();
        match step.face_point_vertices.get(f).and_then(Option::as_ref) {
            Some(vs) => {
                let w = 1.0 / vs.len() as f64;
                for &v in vs {
                    p.add_scaled(&values[v as usize], w);
                }
            }
            None => {
                let cs = parent.face_corners(f);
                let w = 1.0 / cs.len() as f64;
                for c in cs {
                    p.add_scaled(&values[parent.corner_verts[c] as usize], w);
                }
            }
        }
        p
    };
    if step.refined == nf {
        face_out
            .par_iter_mut()
            .with_min_len(4096)
            .enumerate()
            .for_each(|(f, p)| *p = face_point(f));
    } else {
        for f in 0..nf {
            let fc = step.face_child[f];
            if fc != u32::MAX {
                face_out[fc as usize] = face_point(f);
            }
        }
    }
    let face_out = &*face_out;
    let sharp = !step.masks.is_empty();

    // Σ e_j + Σ f_j per vertex (eq. (2)), and the far ends of sharp edges; beside it, the
    // edge points (eq. (1), midpoint, or the semi-sharp blend).
    let vertex_sums = || {
        let mut sum = Buf::filled(nv, T::zero());
        let (mut sharp_sum, mut child_sharp_sum) = if sharp {
            (Buf::filled(nv, T::zero()), Buf::filled(nv, T::zero()))
        } else {
            (Buf::default(), Buf::default())
        };
        for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
            let (va, vb) = (&values[a as usize], &values[b as usize]);
            sum[a as usize].add_scaled(vb, 1.0);
            sum[b as usize].add_scaled(va, 1.0);
            if sharp && crease::is_sharp(parent.edge_sharpness[e]) {
                let c = step.child_sharpness[e];
                sharp_sum[a as usize].add_scaled(vb, 1.0);
                sharp_sum[b as usize].add_scaled(va, 1.0);
                if crease::is_sharp(c[0]) {
                    child_sharp_sum[a as usize].add_scaled(vb, 1.0);
                }
                if crease::is_sharp(c[1]) {
                    child_sharp_sum[b as usize].add_scaled(va, 1.0);
                }
            }
        }
        for f in 0..nf {
            let fc = step.face_child[f];
            if fc == u32::MAX {
                continue;
            }
            let fp = &face_out[fc as usize];
            for c in parent.face_corners(f) {
                sum[parent.corner_verts[c] as usize].add_scaled(fp, 1.0);
            }
        }
        (sum, sharp_sum, child_sharp_sum)
    };
    let edge_points = |edge_out: &mut [T]| {
        for (e, &[a, b]) in parent.edge_verts.iter().enumerate() {
            let (va, vb) = (&values[a as usize], &values[b as usize]);
            let s = parent.edge_sharpness[e];
            let ep = &mut edge_out[e];
            let w = if !crease::is_sharp(s) {
                0.25
            } else if face_weight(s, step.child_sharpness[e]) == 0.0 {
                0.5
            } else {
                let sw = s as f64;
                sw * 0.5 + (1.0 - sw) * 0.25
            };
            ep.add_scaled(va, w);
            ep.add_scaled(vb, w);
        }
        for f in 0..nf {
            let fc = step.face_child[f];
            if fc == u32::MAX {
                continue;
            }
            let fp = &face_out[fc as usize];
            for c in parent.face_corners(f) {
                let e = parent.corner_edges[c] as usize;
                let w = if sharp {
                    face_weight(parent.edge_sharpness[e], step.child_sharpness[e])
                } else {
                    0.25
                };
                if w != 0.0 {
                    edge_out[e].add_scaled(fp, w);
                }
            }
        }
    };
    let ((sum, sharp_sum, child_sharp_sum), ()) =
        rayon::join(vertex_sums, || edge_points(edge_out));

    // Vertex points.
    vertex_out
        .par_iter_mut()
        .with_min_len(4096)
        .enumerate()
        .for_each(|(v, q)| {
            let p = &values[v];
            let smooth = |into: &mut T, w: f64| {
                let (edges, faces) = (step.vertex_edges[v], step.vertex_faces[v]);
                if edges == 0 || faces != edges {
                    into.add_scaled(p, w); // isolated, or a fan the smooth rule does not apply to
                    return;
                }
                let n = edges as f64;
                into.add_scaled(p, w * (n - 2.0) / n);
                into.add_scaled(&sum[v], w / (n * n));
            };
            let apply = |into: &mut T, rule: Rule, sharp_sum: &T, w: f64| match rule {
                Rule::Smooth => smooth(into, w),
                Rule::Crease => {
                    into.add_scaled(sharp_sum, w / 8.0);
                    into.add_scaled(p, w * 0.75);
                }
                Rule::Corner => into.add_scaled(p, w),
            };
            match step.masks.get(v) {
                None => smooth(q, 1.0),
                Some(m) if m.rule == Rule::Smooth => smooth(q, 1.0),
                Some(m) => {
                    apply(q, m.rule, &sharp_sum[v], m.weight);
                    if m.child_rule != m.rule {
                        apply(q, m.child_rule, &child_sharp_sum[v], 1.0 - m.weight);
                    }
                }
            }
        });
    out
}

/// The child level's faces, edges and sharpness. For the last level (`last`), the child's
/// edges are not built: only faces and the creases that remain. The last level's faces are
/// handed to the caller, so they are ordinary `Vec`s; the other arrays are [`Buf`]s.
pub(crate) fn child_level(parent: &Level, step: &Step, last: bool) -> Level {
    let nv = parent.vertex_count;
    let ne = parent.edge_count() as usize;
    let face_points = step.refined as u32;
    let fv = |f: usize| nv + step.face_child[f];
    let ev = |e: u32| nv + face_points + e;
    let half = |e: u32, v: u32| {
        (step.interior_edges + 2 * e as usize) as u32
            + (parent.edge_verts[e as usize][0] != v) as u32
    };
    let mut child = Level {
        vertex_count: nv + face_points + ne as u32,
        ..Default::default()
    };
    // Child edges: the interior ones (face point to edge point) first, then the two halves
    // of each parent edge.
    let mut edge_verts: Buf<[u32; 2]>;
    let interior_count;

    if parent.face_kept.is_empty() {
        // Every face splits into quads, child face i = parent corner i: write the arrays by
        // index, in parallel over chunks of faces (disjoint output ranges). The quads are the
        // general path's below, written inline: a shared helper measured 8-25% slower here
        // (array rotation, edges computed for the last level).
        let n = step.interior_edges;
        interior_count = n;
        let output_or_buf = |len: usize| {
            if last {
                Buf::from(mem::filled(len, 0u32))
            } else {
                Buf::zeroed(len)
            }
        };
        child.corner_verts = output_or_buf(4 * n);
        child.face_origin = output_or_buf(n);
        edge_verts = Buf::default();
        if !last {
            child.corner_edges = Buf::zeroed(4 * n);
            edge_verts = Buf::zeroed(n + 2 * ne);
        }
        let nf = parent.face_count() as usize;
        let chunk = 8192;
        let mut verts_rest = &mut child.corner_verts[..];
        let mut edges_rest = &mut child.corner_edges[..];
        let mut origin_rest = &mut child.face_origin[..];
        let mut interior_rest = if last {
            &mut [][..]
        } else {
            &mut edge_verts[..n]
        };
        let mut jobs = Vec::with_capacity(nf / chunk + 1);
        for f0 in (0..nf).step_by(chunk) {
            let f1 = (f0 + chunk).min(nf);
            let (c0, c1) = (
                parent.face_corners(f0).start,
                parent.face_corners(f1 - 1).end,
            );
            let k = c1 - c0;
            let (v, vr) = std::mem::take(&mut verts_rest).split_at_mut(4 * k);
            let (e, er) = if last {
                (&mut [][..], &mut [][..])
            } else {
                std::mem::take(&mut edges_rest).split_at_mut(4 * k)
            };
            let (o, or) = std::mem::take(&mut origin_rest).split_at_mut(k);
            let (i, ir) = if last {
                (&mut [][..], &mut [][..])
            } else {
                std::mem::take(&mut interior_rest).split_at_mut(k)
            };
            (verts_rest, edges_rest, origin_rest, interior_rest) = (vr, er, or, ir);
            jobs.push((f0..f1, c0, v, e, o, i));
        }
        jobs.into_par_iter()
            .for_each(|(faces, c0, verts, edges, origin, inner)| {
                for f in faces {
                    let cs = parent.face_corners(f);
                    let k = cs.len();
                    let o = parent.face_origin[f];
                    for (j, c) in cs.clone().enumerate() {
                        let prev = if c == cs.start { cs.end - 1 } else { c - 1 };
                        let v = parent.corner_verts[c];
                        let (e, ep) = (parent.corner_edges[c], parent.corner_edges[prev]);
                        let q = 4 * (c - c0);
                        // OpenSubdiv rotates a quad's children so that child j has its parent
                        // corner at position j; other polygons' children start at the corner.
                        let r = if k == 4 { j } else { 0 };
                        for (t, x) in [v, ev(e), fv(f), ev(ep)].into_iter().enumerate() {
                            verts[q + (t + r) % 4] = x;
                        }
                        origin[c - c0] = o;
                        if !last {
                            let quad = [
                                half(e, v),
                                c as u32,
                                (cs.start + (j + k - 1) % k) as u32,
                                half(ep, v),
                            ];
                            for (t, x) in quad.into_iter().enumerate() {
                                edges[q + (t + r) % 4] = x;
                            }
                            inner[c - c0] = [fv(f), ev(e)];
                        }
                    }
                }
            });
        if last {
            let mut offsets = mem::with_capacity(n + 1);
            offsets.extend((0..=n as u32).map(|x| 4 * x));
            let mut loops = mem::with_capacity(n + 1);
            loops.extend(0..=n as u32);
            (child.loop_offsets, child.face_loops) = (offsets.into(), loops.into());
        } else {
            let mut offsets = Buf::<u32>::zeroed(n + 1);
            let mut loops = Buf::<u32>::zeroed(n + 1);
            for (i, (o, l)) in offsets.iter_mut().zip(loops.iter_mut()).enumerate() {
                (*o, *l) = (4 * i as u32, i as u32);
            }
            (child.loop_offsets, child.face_loops) = (offsets, loops);
        }
    } else {
        let mut face_loops = vec![0];
        let mut loop_offsets = vec![0];
        let mut corner_verts = Vec::new();
        let mut corner_edges = Vec::new();
        let mut face_origin = Vec::new();
        let mut interior = Vec::new();
        for f in 0..parent.face_count() as usize {
            let origin = parent.face_origin[f];
            if parent.is_kept(f) {
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
                        corner_verts.extend_from_slice(&[v, ev(e)]);
                        corner_edges.extend_from_slice(&[half(e, v), half(e, next)]);
                    }
                    loop_offsets.push(corner_verts.len() as u32);
                }
                face_loops.push(loop_offsets.len() as u32 - 1);
                child.face_kept.push(true);
                face_origin.push(origin);
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
                let mut verts = [v, ev(e), fv(f), ev(ep)];
                let mut edges = [half(e, v), base + j, base + (j + k - 1) % k, half(ep, v)];
                if k == 4 {
                    verts.rotate_right(j as usize);
                    edges.rotate_right(j as usize);
                }
                corner_verts.extend_from_slice(&verts);
                corner_edges.extend_from_slice(&edges);
                loop_offsets.push(corner_verts.len() as u32);
                face_loops.push(loop_offsets.len() as u32 - 1);
                child.face_kept.push(false);
                face_origin.push(origin);
            }
            for c in cs {
                interior.push([fv(f), ev(parent.corner_edges[c])]);
            }
        }
        interior_count = interior.len();
        if !last {
            interior.resize(interior_count + 2 * ne, [0; 2]);
            child.corner_edges = corner_edges.into();
        }
        edge_verts = interior.into();
        child.face_loops = face_loops.into();
        child.loop_offsets = loop_offsets.into();
        child.corner_verts = corner_verts.into();
        child.face_origin = face_origin.into();
    }

    let n = child.vertex_count as usize;
    if parent.any_vertex_sharp {
        let mut sharpness = Vec::with_capacity(n);
        sharpness.extend(
            parent
                .vertex_sharpness
                .iter()
                .map(|&s| crease::decrement(s)),
        );
        sharpness.resize(n, 0.0);
        let mut forced = parent.vertex_forced.to_vec();
        forced.resize(n, false);
        child.any_vertex_sharp = sharpness.iter().any(|&s| s > 0.0);
        child.vertex_sharpness = sharpness.into();
        child.vertex_forced = forced.into();
    } else {
        // Zeroed arrays cost nothing until touched.
        child.vertex_sharpness = Buf::zeroed(n);
        child.vertex_forced = Buf::zeroed(n);
    }

    if last {
        // Only the creases that remain, for the output mesh (none after a smooth level).
        let sharp = !step.masks.is_empty();
        for (e, &[a, b]) in parent.edge_verts.iter().enumerate().filter(|_| sharp) {
            if parent.edge_forced[e] {
                continue;
            }
            let m = ev(e as u32);
            for (end, v) in [a, b].into_iter().enumerate() {
                let s = step.child_sharpness[e][end];
                if crease::is_sharp(s) {
                    child.last_creases.push(([v, m], s));
                }
            }
        }
        return child;
    }

    let total = interior_count + 2 * ne;
    debug_assert_eq!(edge_verts.len(), total);
    edge_verts[interior_count..]
        .par_chunks_mut(2)
        .with_min_len(4096)
        .zip(parent.edge_verts.par_iter())
        .enumerate()
        .for_each(|(e, (halves, &[a, b]))| {
            let m = ev(e as u32);
            halves.copy_from_slice(&[[m, a], [m, b]]);
        });
    child.edge_verts = edge_verts;
    if step.masks.is_empty() {
        // No sharp or forced edge in the parent (forced edges are infinitely sharp), so none
        // in the child: zeroed arrays, untouched.
        child.edge_sharpness = Buf::zeroed(total);
        child.edge_forced = Buf::zeroed(total);
    } else {
        let mut sharpness = vec![0.0; interior_count];
        sharpness.reserve(2 * ne);
        let mut forced = vec![false; interior_count];
        forced.reserve(2 * ne);
        for e in 0..ne {
            sharpness.extend_from_slice(&step.child_sharpness[e]);
            let f = parent.edge_forced[e];
            forced.extend_from_slice(&[f, f]);
        }
        child.edge_sharpness = sharpness.into();
        child.edge_forced = forced.into();
    }
    child
}

/// The edges of a last level built without them ([`child_level`] with `last`), as
/// [`child_level`] numbers them for the levels before: the face-interior edges (one per
/// parent corner, from the face point to the edge point), then the two halves of each parent
/// edge. Returns each child corner's edge (the edge to the next corner of its face) and each
/// edge's two vertices. Only for parents whose faces all split (no face kept whole): the
/// child faces are then the quads [`child_level`] writes by index.
pub(crate) fn child_edges(parent: &Level, step: &Step) -> (Vec<u32>, Vec<[u32; 2]>) {
    let (corners, edges) = child_edge_counts(parent, step);
    let mut corner_edges: Vec<u32> = mem::filled(corners, 0u32);
    let mut edge_verts: Vec<[u32; 2]> = mem::filled(edges, [0u32; 2]);
    child_edges_into(parent, step, Some(&mut corner_edges), Some(&mut edge_verts));
    (corner_edges, edge_verts)
}

/// The numbers of corners and edges of the last level [`child_edges`] describes.
pub(crate) fn child_edge_counts(parent: &Level, step: &Step) -> (usize, usize) {
    let n = step.interior_edges;
    (4 * n, n + 2 * parent.edge_count() as usize)
}

/// [`child_edges`] written into the caller's arrays (of the lengths
/// [`child_edge_counts`] gives), either of which may be left out.
pub(crate) fn child_edges_into(
    parent: &Level,
    step: &Step,
    corner_edges: Option<&mut [u32]>,
    edge_verts: Option<&mut [[u32; 2]]>,
) {
    debug_assert!(parent.face_kept.is_empty());
    let nv = parent.vertex_count;
    let n = step.interior_edges;
    let face_points = step.refined as u32;
    let fv = |f: usize| nv + step.face_child[f];
    let ev = |e: u32| nv + face_points + e;
    let half = |e: u32, v: u32| {
        (n + 2 * e as usize) as u32 + (parent.edge_verts[e as usize][0] != v) as u32
    };
    let nf = parent.face_count() as usize;
    let (interior, halves) = match edge_verts {
        Some(ev) => {
            let (i, h) = ev.split_at_mut(n);
            (Some(i), Some(h))
        }
        None => (None, None),
    };
    let chunk = 8192;
    let mut jobs = Vec::with_capacity(nf / chunk + 1);
    let mut edges_rest = corner_edges;
    let mut inner_rest = interior;
    for f0 in (0..nf).step_by(chunk) {
        let f1 = (f0 + chunk).min(nf);
        let (c0, c1) = (
            parent.face_corners(f0).start,
            parent.face_corners(f1 - 1).end,
        );
        let k = c1 - c0;
        let e = edges_rest.take().map(|r| {
            let (a, b) = r.split_at_mut(4 * k);
            edges_rest = Some(b);
            a
        });
        let i = inner_rest.take().map(|r| {
            let (a, b) = r.split_at_mut(k);
            inner_rest = Some(b);
            a
        });
        jobs.push((f0..f1, c0, e, i));
    }
    rayon::join(
        || {
            jobs.into_par_iter()
                .for_each(|(faces, c0, mut edges, mut inner)| {
                    for f in faces {
                        let cs = parent.face_corners(f);
                        let k = cs.len();
                        for (j, c) in cs.clone().enumerate() {
                            let prev = if c == cs.start { cs.end - 1 } else { c - 1 };
                            let v = parent.corner_verts[c];
                            let (e, ep) = (parent.corner_edges[c], parent.corner_edges[prev]);
                            if let Some(edges) = edges.as_deref_mut() {
                                let q = 4 * (c - c0);
                                // As child_level: a quad's children rotated so child j has
                                // its parent corner at position j.
                                let r = if k == 4 { j } else { 0 };
                                let quad = [
                                    half(e, v),
                                    c as u32,
                                    (cs.start + (j + k - 1) % k) as u32,
                                    half(ep, v),
                                ];
                                for (t, x) in quad.into_iter().enumerate() {
                                    edges[q + (t + r) % 4] = x;
                                }
                            }
                            if let Some(inner) = inner.as_deref_mut() {
                                inner[c - c0] = [fv(f), ev(e)];
                            }
                        }
                    }
                })
        },
        || {
            if let Some(halves) = halves {
                halves
                    .par_chunks_mut(2)
                    .with_min_len(4096)
                    .zip(parent.edge_verts.par_iter())
                    .enumerate()
                    .for_each(|(e, (h, &[a, b]))| {
                        let m = ev(e as u32);
                        h.copy_from_slice(&[[m, a], [m, b]]);
                    })
            }
        },
    );
}

/// The sharpness left on each edge of a last level numbered as [`child_edges`] numbers them:
/// the user's creases not yet spent (topology's forced creases are not the user's), 0
/// elsewhere.
pub(crate) fn child_edge_sharpness(parent: &Level, step: &Step) -> Vec<f32> {
    let mut out: Vec<f32> = mem::filled(child_edge_counts(parent, step).1, 0.0f32);
    for_each_child_edge_sharpness(parent, step, |e, s| out[e] = s);
    out
}

/// Calls `f(edge, sharpness)` for each edge of [`child_edge_sharpness`] with sharpness left.
pub(crate) fn for_each_child_edge_sharpness(
    parent: &Level,
    step: &Step,
    mut f: impl FnMut(usize, f32),
) {
    if step.masks.is_empty() {
        return;
    }
    let n = step.interior_edges;
    for e in 0..parent.edge_count() as usize {
        if parent.edge_forced[e] {
            continue;
        }
        for (end, &s) in step.child_sharpness[e].iter().enumerate() {
            if crease::is_sharp(s) {
                f(n + 2 * e + end, s);
            }
        }
    }
}
