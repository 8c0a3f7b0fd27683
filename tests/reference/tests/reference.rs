//! Tests of the reference crate itself: that the shim drives OpenSubdiv and OpenMesh as intended,
//! with expected values computed by hand (spec/subdivision.md sections 2-4, 7.1), and that the
//! orderings and behaviours the kernel's tests rely on are what the crate docs say.

use std::collections::{BTreeMap, BTreeSet};

use std::time::Duration;

use katachi_reference::{
    openmesh_catmull_clark, openmesh_catmull_clark_timed, osd_catmark, osd_catmark_fvar,
    osd_catmark_timed, osd_level_info, Boundary, CreaseMethod, Creases, FVarLinear, OsdOptions,
    RefMesh, VertexRule, MAX_LEVEL,
};

// ---------------------------------------------------------------------------------------------
// Generated shapes

/// The cube [-1, 1]^3; vertex `i` has x = ±1 by bit 0, y by bit 1, z by bit 2. Faces outward.
fn cube() -> RefMesh {
    let positions = (0..8u32)
        .map(|i| {
            let c = |bit: u32| if i & bit != 0 { 1.0 } else { -1.0 };
            [c(1), c(2), c(4)]
        })
        .collect();
    let faces: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    RefMesh {
        positions,
        face_sizes: vec![4; 6],
        face_vertices: faces.iter().flatten().copied().collect(),
    }
}

/// A prism over a regular `n`-gon: two n-gon caps and `n` quads, closed, faces outward.
fn prism(n: u32) -> RefMesh {
    let mut positions = Vec::new();
    for z in [0.0, 1.5] {
        for i in 0..n {
            let a = std::f64::consts::TAU * f64::from(i) / f64::from(n);
            positions.push([a.cos(), a.sin(), z]);
        }
    }
    let mut face_sizes = vec![n, n];
    let mut face_vertices: Vec<u32> = (0..n).rev().collect();
    face_vertices.extend(n..2 * n);
    for i in 0..n {
        let j = (i + 1) % n;
        face_sizes.push(4);
        face_vertices.extend([i, j, n + j, n + i]);
    }
    RefMesh {
        positions,
        face_sizes,
        face_vertices,
    }
}

/// A torus of `nu` x `nv` quads.
fn torus(nu: u32, nv: u32) -> RefMesh {
    let mut positions = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let u = std::f64::consts::TAU * f64::from(i) / f64::from(nu);
            let v = std::f64::consts::TAU * f64::from(j) / f64::from(nv);
            let r = 2.0 + 0.7 * v.cos();
            positions.push([r * u.cos(), r * u.sin(), 0.7 * v.sin()]);
        }
    }
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    let mut face_vertices = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            face_vertices.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    RefMesh {
        positions,
        face_sizes: vec![4; (nu * nv) as usize],
        face_vertices,
    }
}

/// An open grid of `n` x `n` quads over [0, n]^2, with heights `z(i, j)`; vertex (i, j) is
/// `j * (n + 1) + i`.
fn grid(n: u32, z: impl Fn(u32, u32) -> f64) -> RefMesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push([f64::from(i), f64::from(j), z(i, j)]);
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut face_vertices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            face_vertices.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    RefMesh {
        positions,
        face_sizes: vec![4; (n * n) as usize],
        face_vertices,
    }
}

/// Three quads sharing the edge (0, 1): a non-manifold "fan" (book with three pages).
fn fan() -> RefMesh {
    RefMesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, -1.0, 0.0],
            [0.0, -1.0, 0.0],
            [1.0, 0.0, 1.0],
            [0.0, 0.0, 1.0],
        ],
        face_sizes: vec![4, 4, 4],
        face_vertices: vec![0, 1, 2, 3, 1, 0, 5, 4, 0, 1, 6, 7],
    }
}

// ---------------------------------------------------------------------------------------------
// Helpers

fn no_creases() -> Creases {
    Creases::default()
}

fn crease(edges: &[[u32; 2]], sharpness: &[f64]) -> Creases {
    Creases {
        edges: edges.to_vec(),
        edge_sharpness: sharpness.to_vec(),
        ..Creases::default()
    }
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

fn add_scaled(acc: &mut [f64; 3], p: [f64; 3], w: f64) {
    for (a, x) in acc.iter_mut().zip(p) {
        *a += w * x;
    }
}

/// The vertex average.
fn lerp3(points: &[[f64; 3]]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for &p in points {
        add_scaled(&mut s, p, 1.0 / points.len() as f64);
    }
    s
}

fn bbox_diagonal(m: &RefMesh) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &m.positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    dist(lo, hi)
}

fn assert_close(got: [f64; 3], want: [f64; 3], tol: f64, what: &str) {
    assert!(
        dist(got, want) <= tol,
        "{what}: got {got:?}, want {want:?} (tolerance {tol:e})"
    );
}

/// For each vertex of `a`, the vertex of `b` at the same place (within `tol`); panics if there is
/// none or the match is not one-to-one.
fn match_vertices(a: &RefMesh, b: &RefMesh, tol: f64) -> Vec<u32> {
    assert_eq!(a.num_vertices(), b.num_vertices(), "vertex counts");
    let mut map = Vec::with_capacity(a.num_vertices());
    let mut used = vec![false; b.num_vertices()];
    for (i, &p) in a.positions.iter().enumerate() {
        let (j, d) = b
            .positions
            .iter()
            .enumerate()
            .map(|(j, &q)| (j, dist(p, q)))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("b has vertices");
        assert!(
            d <= tol,
            "vertex {i} at {p:?}: nearest vertex {j} is {d:e} away (tolerance {tol:e})"
        );
        assert!(!used[j], "vertex {j} of the second mesh matched twice");
        used[j] = true;
        map.push(j as u32);
    }
    map
}

/// A face as a cycle starting at its smallest vertex (orientation kept).
fn canonical(face: &[u32]) -> Vec<u32> {
    let start = (0..face.len()).min_by_key(|&i| face[i]).unwrap_or(0);
    face[start..]
        .iter()
        .chain(&face[..start])
        .copied()
        .collect()
}

/// The faces of `a`, renumbered by `map`, equal the faces of `b` up to face order and rotation.
fn assert_same_faces(a: &RefMesh, b: &RefMesh, map: &[u32]) {
    let mut fa: Vec<Vec<u32>> = a
        .faces()
        .map(|f| canonical(&f.iter().map(|&v| map[v as usize]).collect::<Vec<_>>()))
        .collect();
    let mut fb: Vec<Vec<u32>> = b.faces().map(canonical).collect();
    fa.sort();
    fb.sort();
    assert_eq!(fa, fb, "face lists differ");
}

// ---------------------------------------------------------------------------------------------
// OpenSubdiv: smooth rules, counts, orderings

#[test]
fn cube_level_1_has_the_hand_computed_positions() {
    let refined = osd_catmark(&cube(), &no_creases(), &OsdOptions::default(), 1).unwrap();
    assert_eq!(refined.num_vertices(), 26);
    assert_eq!(refined.num_faces(), 24);
    assert!(refined.face_sizes.iter().all(|&n| n == 4));

    // By hand (spec 2.1-2.3) for the cube [-1, 1]^3:
    // face point = face centre, e.g. (0, 0, -1);
    // edge point = (v + e + f1 + f2) / 4, e.g. ((-1,-1,-1) + (1,-1,-1) + (0,0,-1) + (0,-1,0)) / 4
    //            = (0, -3/4, -3/4);
    // vertex point, n = 3: (n-2)/n v + sum e / n^2 + sum f / n^2; for v = (-1,-1,-1) the
    //            neighbours sum to (-1,-1,-1) and the face points too, so each coordinate is
    //            -1/3 - 1/9 - 1/9 = -5/9.
    let mut want: Vec<[f64; 3]> = Vec::new();
    for i in 0..8u32 {
        let c = |bit: u32| if i & bit != 0 { 5.0 / 9.0 } else { -5.0 / 9.0 };
        want.push([c(1), c(2), c(4)]);
    }
    for axis in 0..3 {
        for s in [-1.0, 1.0] {
            let mut p = [0.0; 3];
            p[axis] = s;
            want.push(p);
        }
    }
    for zero in 0..3 {
        for s in [-0.75, 0.75] {
            for t in [-0.75, 0.75] {
                let mut p = [s, s, s];
                let others: Vec<usize> = (0..3).filter(|&k| k != zero).collect();
                p[zero] = 0.0;
                p[others[0]] = s;
                p[others[1]] = t;
                want.push(p);
            }
        }
    }
    let want = RefMesh {
        positions: want,
        ..RefMesh::default()
    };
    match_vertices(&refined, &want, 1e-15);

    // The original vertices come first, in input order (see the ordering test).
    for v in 0..8 {
        let c = cube().positions[v].map(|x| x * 5.0 / 9.0);
        assert_close(refined.positions[v], c, 1e-15, "vertex point");
    }
}

#[test]
fn cube_level_1_matches_formulas_1_and_2_through_the_child_maps() {
    let mesh = cube();
    let info = osd_level_info(&mesh, &no_creases(), &OsdOptions::default(), 1).unwrap();
    let (l0, l1, r) = (&info.levels[0], &info.levels[1], &info.refinements[0]);
    let p = &l1.mesh.positions;
    let faces: Vec<&[u32]> = mesh.faces().collect();
    let face_point: Vec<[f64; 3]> = faces
        .iter()
        .map(|f| {
            lerp3(
                &f.iter()
                    .map(|&v| mesh.positions[v as usize])
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    for (f, &c) in r.face_child_vertex.iter().enumerate() {
        assert_close(p[c as usize], face_point[f], 1e-15, "face point, spec 2.1");
    }
    for (e, &[a, b]) in l0.edges.iter().enumerate() {
        let adjacent: Vec<usize> = (0..faces.len())
            .filter(|&f| faces[f].contains(&a) && faces[f].contains(&b))
            .collect();
        assert_eq!(adjacent.len(), 2);
        let want = lerp3(&[
            mesh.positions[a as usize],
            mesh.positions[b as usize],
            face_point[adjacent[0]],
            face_point[adjacent[1]],
        ]);
        let got = p[r.edge_child_vertex[e] as usize];
        assert_close(got, want, 1e-15, "edge point, formula (1)");
    }
    for v in 0..mesh.num_vertices() as u32 {
        let nbrs: Vec<u32> = l0
            .edges
            .iter()
            .filter_map(|&[a, b]| (a == v).then_some(b).or_else(|| (b == v).then_some(a)))
            .collect();
        let incident: Vec<usize> = (0..faces.len())
            .filter(|&f| faces[f].contains(&v))
            .collect();
        let n = nbrs.len() as f64;
        assert_eq!(incident.len(), nbrs.len());
        let mut want = mesh.positions[v as usize].map(|x| (n - 2.0) / n * x);
        for &u in &nbrs {
            add_scaled(&mut want, mesh.positions[u as usize], 1.0 / (n * n));
        }
        for &f in &incident {
            add_scaled(&mut want, face_point[f], 1.0 / (n * n));
        }
        let got = p[r.vertex_child_vertex[v as usize] as usize];
        assert_close(got, want, 1e-15, "vertex point, formula (2)");
    }
}

#[test]
fn cube_counts_per_level() {
    let info = osd_level_info(&cube(), &no_creases(), &OsdOptions::default(), 3).unwrap();
    let counts: Vec<[usize; 3]> = info
        .levels
        .iter()
        .map(|l| [l.num_vertices, l.num_edges, l.num_faces])
        .collect();
    // V' = V + E + F, E' = 2E + sum k_f, F' = sum k_f (spec 2.4).
    assert_eq!(
        counts,
        vec![[8, 12, 6], [26, 48, 24], [98, 192, 96], [386, 768, 384]]
    );
    for l in &info.levels {
        assert_eq!(l.mesh.num_vertices(), l.num_vertices);
        assert_eq!(l.mesh.num_faces(), l.num_faces);
        assert_eq!(l.edges.len(), l.num_edges);
        assert_eq!(l.mesh.edges().len(), l.num_edges);
    }
}

/// Documents OpenSubdiv's numbering (crate docs): children of vertices, then of faces, then of
/// edges, each in parent order; child faces in parent order, `k` per parent face; child face `j`
/// of a parent with corners `v_0..v_{k-1}` is built from `(v_j', e_j', f', e_{j-1}')` with
/// `e_j = (v_j, v_{j+1})`, rotated for quad parents so that `v_j'` is corner `j`.
#[test]
fn child_vertex_and_child_face_ordering() {
    // A quad, a triangle and a pentagon (open).
    let mesh = RefMesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 1.0, 0.0],
            [-1.0, 0.5, 0.0],
            [0.5, -1.0, 0.0],
        ],
        face_sizes: vec![4, 3, 5],
        face_vertices: vec![0, 1, 2, 3, 1, 4, 5, 0, 3, 6, 7, 1],
    };
    for level in 1..=2u32 {
        let info = osd_level_info(&mesh, &no_creases(), &OsdOptions::default(), level).unwrap();
        for (l, r) in info.refinements.iter().enumerate() {
            let parent = &info.levels[l];
            let child = &info.levels[l + 1];
            let (nv, ne, nf) = (
                parent.num_vertices as u32,
                parent.num_edges as u32,
                parent.num_faces as u32,
            );
            assert!(r.order.sequential);
            assert_eq!(r.order.from_vertices, 0..nv);
            assert_eq!(r.order.from_faces, nv..nv + nf);
            assert_eq!(r.order.from_edges, nv + nf..nv + nf + ne);

            // Base edges: walking the faces, first direction met.
            if l == 0 {
                let mut walked: Vec<[u32; 2]> = Vec::new();
                for face in parent.mesh.faces() {
                    for j in 0..face.len() {
                        let (a, b) = (face[j], face[(j + 1) % face.len()]);
                        if !walked
                            .iter()
                            .any(|&[x, y]| (x, y) == (b, a) || (x, y) == (a, b))
                        {
                            walked.push([a, b]);
                        }
                    }
                }
                assert_eq!(walked, parent.edges, "base edge order");
            }
            // Child edges: face-interior edges first (face point to the edge points of the face's
            // edges, in face and corner order), then the halves of each parent edge.
            let mut inner = 0usize;
            for (f, face) in parent.mesh.faces().enumerate() {
                for j in 0..face.len() {
                    let (a, b) = (face[j], face[(j + 1) % face.len()]);
                    let e = parent
                        .edges
                        .iter()
                        .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
                        .unwrap();
                    assert_eq!(
                        child.edges[inner],
                        [r.face_child_vertex[f], r.edge_child_vertex[e]]
                    );
                    inner += 1;
                }
            }
            let interior = parent.mesh.face_vertices.len() as u32;
            for (e, &[a, b]) in parent.edges.iter().enumerate() {
                let halves = r.edge_child_edges[e];
                assert_eq!(
                    halves,
                    [interior + 2 * e as u32, interior + 2 * e as u32 + 1]
                );
                let ec = r.edge_child_vertex[e];
                assert_eq!(
                    child.edges[halves[0] as usize],
                    [ec, r.vertex_child_vertex[a as usize]]
                );
                assert_eq!(
                    child.edges[halves[1] as usize],
                    [ec, r.vertex_child_vertex[b as usize]]
                );
            }

            let mut next_child = 0u32;
            let child_faces: Vec<&[u32]> = child.mesh.faces().collect();
            for (f, face) in parent.mesh.faces().enumerate() {
                let k = face.len();
                let children = &r.face_child_faces[f];
                assert_eq!(children.len(), k);
                let edge_child = |a: u32, b: u32| {
                    let e = parent
                        .edges
                        .iter()
                        .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
                        .expect("face edge exists");
                    r.edge_child_vertex[e]
                };
                for j in 0..k {
                    assert_eq!(children[j], next_child, "child faces follow parent order");
                    assert_eq!(r.child_face_parent[children[j] as usize], f as u32);
                    next_child += 1;
                    let vj = face[j];
                    let next = face[(j + 1) % k];
                    let prev = face[(j + k - 1) % k];
                    let mut want = [
                        r.vertex_child_vertex[vj as usize],
                        edge_child(vj, next),
                        r.face_child_vertex[f],
                        edge_child(prev, vj),
                    ];
                    if k == 4 {
                        want.rotate_right(j);
                    }
                    assert_eq!(
                        child_faces[children[j] as usize],
                        &want[..],
                        "level {l} face {f} ({k} corners) child {j}"
                    );
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Creases

#[test]
fn infinitely_sharp_crease_gives_midpoint_edge_point() {
    let mesh = cube();
    let info = osd_level_info(
        &mesh,
        &crease(&[[0, 1]], &[10.0]),
        &OsdOptions::default(),
        1,
    )
    .unwrap();
    let e = info.levels[0]
        .edges
        .iter()
        .position(|&[a, b]| [a.min(b), a.max(b)] == [0, 1])
        .unwrap();
    assert_eq!(info.levels[0].edge_sharpness[e], 10.0);
    assert!(info.levels[0].edge_tags[e].inf_sharp);
    let p = &info.levels[1].mesh.positions;
    let c = info.refinements[0].edge_child_vertex[e] as usize;
    assert_close(p[c], [0.0, -1.0, -1.0], 1e-15, "sharp edge point, spec 3.1");
    // Both halves stay infinitely sharp (spec 3.3); the vertices have one sharp edge: dart.
    assert_eq!(
        info.levels[1].edge_sharpness_between(0, c as u32),
        Some(10.0)
    );
    assert_eq!(
        info.levels[1].edge_sharpness_between(1, c as u32),
        Some(10.0)
    );
    assert_eq!(info.levels[0].vertex_rule[0], VertexRule::Dart);
    assert_eq!(info.levels[1].vertex_rule[c], VertexRule::Crease);
    // The other edge points are the smooth ones.
    let other = info.refinements[0].edge_child_vertex[(e + 1) % 12] as usize;
    let smooth = osd_catmark(&mesh, &no_creases(), &OsdOptions::default(), 1).unwrap();
    assert_close(
        p[other],
        smooth.positions[other],
        1e-15,
        "smooth edge point",
    );
}

#[test]
fn semi_sharp_crease_blends_smooth_and_sharp_edge_points() {
    // Sharpness 0.5: edge point = 0.5 smooth (0, -3/4, -3/4) + 0.5 sharp (0, -1, -1) (spec 7.1).
    let info = osd_level_info(
        &cube(),
        &crease(&[[1, 0]], &[0.5]),
        &OsdOptions::default(),
        1,
    )
    .unwrap();
    let e = info.levels[0]
        .edges
        .iter()
        .position(|&[a, b]| [a.min(b), a.max(b)] == [0, 1])
        .unwrap();
    assert!(info.levels[0].edge_tags[e].semi_sharp);
    let c = info.refinements[0].edge_child_vertex[e] as usize;
    assert_close(
        info.levels[1].mesh.positions[c],
        [0.0, -0.875, -0.875],
        1e-15,
        "semi-sharp edge point",
    );
    assert_eq!(
        info.levels[1].edge_sharpness_between(0, c as u32),
        Some(0.0)
    );
}

/// A crease chain 0-1 (2.5), 1-3 (1.0), 3-2 (3.0) on the cube; the child edge of parent edge
/// (a, b) at end `a` is (a', edge point of (a, b)).
#[test]
fn crease_sharpness_propagation_uniform_and_chaikin() {
    let creases = crease(&[[0, 1], [1, 3], [3, 2]], &[2.5, 1.0, 3.0]);
    let child_sharpness = |method: CreaseMethod| {
        let opts = OsdOptions {
            crease: method,
            ..OsdOptions::default()
        };
        let info = osd_level_info(&cube(), &creases, &opts, 2).unwrap();
        let (l0, l1, r) = (&info.levels[0], &info.levels[1], &info.refinements[0]);
        let at = |a: u32, b: u32| {
            let e = l0
                .edges
                .iter()
                .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
                .unwrap();
            let va = r.vertex_child_vertex[a as usize];
            l1.edge_sharpness_between(va, r.edge_child_vertex[e])
                .unwrap()
        };
        let level1 = [at(0, 1), at(1, 0), at(1, 3), at(3, 1), at(3, 2), at(2, 3)];
        let level2: BTreeSet<u64> = info.levels[2]
            .edge_sharpness
            .iter()
            .filter(|&&s| s > 0.0)
            .map(|s| (s * 1e6).round() as u64)
            .collect();
        (level1, level2)
    };

    // Uniform: s - 1 on both halves, 0 once s <= 1 (spec 7.1).
    let (uniform, uniform2) = child_sharpness(CreaseMethod::Uniform);
    assert_eq!(uniform, [1.5, 1.5, 0.0, 0.0, 2.0, 2.0]);
    assert_eq!(uniform2, BTreeSet::from([500_000, 1_000_000]));

    // Chaikin: at an end with other semi-sharp edges, 0.75 s + 0.25 avg(others) - 1, else s - 1.
    let (chaikin, chaikin2) = child_sharpness(CreaseMethod::Chaikin);
    let want = [
        2.5 - 1.0,                     // at 0: no other sharp edge
        0.75 * 2.5 + 0.25 * 1.0 - 1.0, // at 1: other edge (1,3) = 1.0 -> 1.125
        0.75 * 1.0 + 0.25 * 2.5 - 1.0, // at 1: other edge (0,1) = 2.5 -> 0.375
        0.75 * 1.0 + 0.25 * 3.0 - 1.0, // at 3: other edge (3,2) = 3.0 -> 0.5
        0.75 * 3.0 + 0.25 * 1.0 - 1.0, // at 3: other edge (1,3) = 1.0 -> 1.5
        3.0 - 1.0,                     // at 2: no other sharp edge
    ];
    for (got, want) in chaikin.iter().zip(want) {
        assert!(
            (got - want).abs() < 1e-7,
            "chaikin {chaikin:?}, want {want}"
        );
    }
    assert_ne!(chaikin2, uniform2);
}

#[test]
fn corner_sharpness_pins_a_vertex() {
    let creases = Creases {
        corners: vec![0],
        corner_sharpness: vec![10.0],
        ..Creases::default()
    };
    let info = osd_level_info(&cube(), &creases, &OsdOptions::default(), 2).unwrap();
    assert_eq!(info.levels[0].vertex_rule[0], VertexRule::Corner);
    assert_eq!(info.levels[0].vertex_sharpness[0], 10.0);
    assert_close(
        info.levels[2].mesh.positions[0],
        [-1.0, -1.0, -1.0],
        0.0,
        "corner, rule (4)",
    );
}

// ---------------------------------------------------------------------------------------------
// OpenMesh against OpenSubdiv

#[test]
fn openmesh_and_opensubdiv_agree_on_closed_meshes() {
    for (name, mesh, levels) in [
        ("cube", cube(), 3),
        ("pentagonal prism", prism(5), 2),
        ("triangular prism", prism(3), 2),
        ("torus", torus(8, 6), 2),
    ] {
        let tol = 1e-12 * bbox_diagonal(&mesh);
        for level in 1..=levels {
            let osd = osd_catmark(&mesh, &no_creases(), &OsdOptions::default(), level).unwrap();
            let om = openmesh_catmull_clark(&mesh, level).unwrap();
            assert_eq!(om.num_faces(), osd.num_faces(), "{name} level {level}");
            let map = match_vertices(&om, &osd, tol);
            assert_same_faces(&om, &osd, &map);
        }
    }
}

/// spec 4.1: OpenMesh smooths boundary vertices with (e_a + 4 v + e_b) / 6 (the B-spline limit
/// mask) and has no corner rule; OpenSubdiv uses the crease rule (e_a + 6 v + e_b) / 8, and with
/// EdgeAndCorner pins vertices that have a single face. A documented difference, not a bug of ours.
#[test]
fn openmesh_and_opensubdiv_differ_on_open_boundaries() {
    // Boundary vertex (1, 0) at z = 0, its boundary neighbours (0, 0) and (2, 0) at z = 1.
    let mesh = grid(2, |i, _| if i == 1 { 0.0 } else { 1.0 });
    let osd = osd_catmark(&mesh, &no_creases(), &OsdOptions::default(), 1).unwrap();
    let om = openmesh_catmull_clark(&mesh, 1).unwrap();
    // Both keep the original vertices first, in input order.
    assert!(
        (osd.positions[1][2] - 0.25).abs() < 1e-15,
        "{:?}",
        osd.positions[1]
    );
    assert!(
        (om.positions[1][2] - 1.0 / 3.0).abs() < 1e-15,
        "{:?}",
        om.positions[1]
    );

    // Everything else agrees at level 1: the differences are exactly the boundary vertices.
    let boundary: BTreeSet<u32> = (0..9).filter(|&v| v != 4).collect();
    let interior_osd: Vec<[f64; 3]> = (0..osd.num_vertices())
        .filter(|&v| !boundary.contains(&(v as u32)))
        .map(|v| osd.positions[v])
        .collect();
    for v in 0..om.num_vertices() {
        let differs = boundary.contains(&(v as u32));
        let p = om.positions[v];
        let found = interior_osd.iter().any(|&q| dist(p, q) < 1e-14);
        assert_eq!(!found, differs, "OpenMesh vertex {v} at {p:?}");
    }

    // A vertex with a single face: (0, 0, 4) with boundary neighbours (1, 0, 1) and (0, 1, 4).
    let mesh = grid(2, |i, j| match (i, j) {
        (0, 0) | (0, 1) => 4.0,
        _ => 1.0,
    });
    let edge_only = osd_catmark(&mesh, &no_creases(), &OsdOptions::default(), 1).unwrap();
    let corner = osd_catmark(
        &mesh,
        &no_creases(),
        &OsdOptions {
            boundary: Boundary::EdgeAndCorner,
            ..OsdOptions::default()
        },
        1,
    )
    .unwrap();
    let om = openmesh_catmull_clark(&mesh, 1).unwrap();
    assert_close(
        edge_only.positions[0],
        [0.125, 0.125, 3.625],
        1e-15,
        "EdgeOnly",
    );
    assert_close(corner.positions[0], [0.0, 0.0, 4.0], 0.0, "EdgeAndCorner");
    assert_close(
        om.positions[0],
        [1.0 / 6.0, 1.0 / 6.0, 3.5],
        1e-15,
        "OpenMesh",
    );
}

#[test]
fn non_manifold_fan_is_accepted_by_opensubdiv_and_rejected_by_openmesh() {
    let mesh = fan();
    let info = osd_level_info(&mesh, &no_creases(), &OsdOptions::default(), 2).unwrap();
    let l0 = &info.levels[0];
    let e = l0
        .edges
        .iter()
        .position(|&[a, b]| [a.min(b), a.max(b)] == [0, 1])
        .unwrap();
    assert!(l0.edge_tags[e].non_manifold);
    assert!(l0.edge_tags[e].inf_sharp);
    assert_eq!(l0.edge_sharpness[e], 10.0);
    assert!(l0.vertex_tags[0].non_manifold);
    assert_eq!(l0.vertex_rule[0], VertexRule::Corner);
    assert_eq!(l0.vertex_rule[1], VertexRule::Corner);
    assert_eq!(info.levels[2].num_faces, 3 * 16);
    // The end vertices of the non-manifold edge stay where they are.
    for v in [0usize, 1] {
        assert_close(
            info.levels[2].mesh.positions[v],
            mesh.positions[v],
            0.0,
            "pinned end vertex",
        );
    }
    let err = openmesh_catmull_clark(&mesh, 1).unwrap_err();
    assert!(err.contains("complex edge"), "{err}");
    assert!(err.contains("face 2"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// Face-varying data

/// One UV square per cube face (disjoint charts), value index = face corner index.
fn cube_uvs(mesh: &RefMesh) -> (Vec<[f64; 2]>, Vec<u32>) {
    let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let uv = (0..mesh.num_faces())
        .flat_map(|f| square.map(|[u, v]| [u + 2.0 * f as f64, v]))
        .collect();
    (uv, (0..mesh.face_vertices.len() as u32).collect())
}

#[test]
fn fvar_all_is_bilinear_on_the_cube() {
    let mesh = cube();
    let (uv, idx) = cube_uvs(&mesh);
    let opts = OsdOptions {
        fvar: FVarLinear::All,
        ..OsdOptions::default()
    };
    // Per corner of the parent face: its child vertex gets the corner's value, an edge child the
    // mean of the edge's two values, the face child the mean of the face's values.
    let mut parent_uv: Vec<[f64; 2]> = idx.iter().map(|&i| uv[i as usize]).collect();
    for level in 1..=2u32 {
        let info = osd_level_info(&mesh, &no_creases(), &opts, level).unwrap();
        let (refined, values) =
            osd_catmark_fvar(&mesh, &no_creases(), &opts, level, &uv, &idx).unwrap();
        assert_eq!(refined, info.levels[level as usize].mesh);
        assert_eq!(values.len(), refined.face_vertices.len());
        let parent = &info.levels[level as usize - 1];
        let r = &info.refinements[level as usize - 1];
        let mut starts = vec![0usize];
        for &n in &parent.mesh.face_sizes {
            starts.push(starts.last().unwrap() + n as usize);
        }
        let mut corner = 0usize;
        for (c, face) in refined.faces().enumerate() {
            let f = r.child_face_parent[c] as usize;
            let pf = &parent.mesh.face_vertices[starts[f]..starts[f + 1]];
            let puv = &parent_uv[starts[f]..starts[f + 1]];
            let k = pf.len();
            for &v in face {
                let want = if let Some(j) = pf
                    .iter()
                    .position(|&p| r.vertex_child_vertex[p as usize] == v)
                {
                    puv[j]
                } else if r.face_child_vertex[f] == v {
                    let s = puv
                        .iter()
                        .fold([0.0, 0.0], |a, b| [a[0] + b[0], a[1] + b[1]]);
                    [s[0] / k as f64, s[1] / k as f64]
                } else {
                    let j = (0..k)
                        .find(|&j| {
                            let (a, b) = (pf[j], pf[(j + 1) % k]);
                            let e = parent
                                .edges
                                .iter()
                                .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
                                .unwrap();
                            r.edge_child_vertex[e] == v
                        })
                        .expect("child vertex of a face edge");
                    let (a, b) = (puv[j], puv[(j + 1) % k]);
                    [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]
                };
                let got = values[corner];
                assert!(
                    (got[0] - want[0]).abs() < 1e-15 && (got[1] - want[1]).abs() < 1e-15,
                    "level {level} child face {c}: got {got:?}, want {want:?}"
                );
                corner += 1;
            }
        }
        parent_uv = values;
    }
}

#[test]
fn fvar_smooth_differs_from_linear_on_a_shared_chart() {
    // A 2x2 grid with UV = (x, y) / 2 shared across faces: the interior value is smoothed the
    // same either way (the grid is regular), but with FVarLinear::None the boundary corners are
    // smoothed along the boundary while All keeps them.
    let mesh = grid(2, |_, _| 0.0);
    let uv: Vec<[f64; 2]> = mesh
        .positions
        .iter()
        .map(|p| [p[0] / 2.0, p[1] / 2.0])
        .collect();
    let idx = mesh.face_vertices.clone();
    let run = |fvar| {
        let opts = OsdOptions {
            fvar,
            ..OsdOptions::default()
        };
        osd_catmark_fvar(&mesh, &no_creases(), &opts, 1, &uv, &idx).unwrap()
    };
    let (m_all, all) = run(FVarLinear::All);
    let (m_none, none) = run(FVarLinear::None);
    let (_, corners) = run(FVarLinear::CornersOnly);
    assert_eq!(m_all, m_none);
    // The UV of vertex 0 (a grid corner with one face) at level 1.
    let at = |values: &[[f64; 2]]| {
        let k = m_all.face_vertices.iter().position(|&v| v == 0).unwrap();
        values[k]
    };
    assert_eq!(at(&all), [0.0, 0.0]);
    assert_eq!(at(&corners), [0.0, 0.0]);
    assert_ne!(at(&none), [0.0, 0.0]);
}

// ---------------------------------------------------------------------------------------------
// Errors, edge cases, threads

#[test]
fn level_zero_returns_the_input() {
    let mesh = prism(5);
    let osd = osd_catmark(&mesh, &no_creases(), &OsdOptions::default(), 0).unwrap();
    assert_eq!(osd, mesh);
    let om = openmesh_catmull_clark(&mesh, 0).unwrap();
    assert_eq!(om.positions, mesh.positions);
    let map: Vec<u32> = (0..mesh.num_vertices() as u32).collect();
    assert_same_faces(&om, &mesh, &map);
}

/// `osd_catmark` refines without full topology in the last level, `osd_level_info` with it: the
/// meshes must be the same.
#[test]
fn plain_and_level_info_runs_give_the_same_mesh() {
    let mesh = grid(3, |i, j| f64::from(i * j % 3));
    let creases = Creases {
        edges: vec![[0, 1], [1, 2], [5, 6]],
        edge_sharpness: vec![1.5, 10.0, 0.7],
        corners: vec![15],
        corner_sharpness: vec![2.0],
    };
    for crease in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
        for boundary in [Boundary::None, Boundary::EdgeOnly, Boundary::EdgeAndCorner] {
            let opts = OsdOptions {
                boundary,
                crease,
                ..OsdOptions::default()
            };
            let plain = osd_catmark(&mesh, &creases, &opts, 3).unwrap();
            let info = osd_level_info(&mesh, &creases, &opts, 3).unwrap();
            assert_eq!(plain, info.levels[3].mesh, "{opts:?}");
        }
    }
}

#[test]
fn timed_runs_report_time_inside_the_libraries() {
    let mesh = torus(8, 6);
    let (osd, t) = osd_catmark_timed(&mesh, &no_creases(), &OsdOptions::default(), 2).unwrap();
    assert_eq!(osd.num_faces(), 48 * 16);
    assert!(t.build + t.refine > Duration::ZERO, "{t:?}");
    assert_eq!(t.total(), t.build + t.refine + t.interpolate);
    let (om, t) = openmesh_catmull_clark_timed(&mesh, 2).unwrap();
    assert_eq!(om.num_faces(), 48 * 16);
    assert!(t.refine > Duration::ZERO, "{t:?}");
    assert_eq!(t.interpolate, Duration::ZERO);
}

#[test]
fn bad_input_gives_errors_not_crashes() {
    let mesh = cube();
    let opts = OsdOptions::default();
    let mut bad = mesh.clone();
    bad.face_vertices[5] = 99;
    let e = osd_catmark(&bad, &no_creases(), &opts, 1).unwrap_err();
    assert!(e.contains("face 1 refers to vertex 99"), "{e}");
    let e = openmesh_catmull_clark(&bad, 1).unwrap_err();
    assert!(e.contains("face 1 refers to vertex 99"), "{e}");

    let mut bad = mesh.clone();
    bad.face_sizes[0] = 5;
    let e = osd_catmark(&bad, &no_creases(), &opts, 1).unwrap_err();
    assert!(e.contains("face sizes add up"), "{e}");

    let mut bad = mesh.clone();
    bad.positions[3][1] = f64::NAN;
    let e = osd_catmark(&bad, &no_creases(), &opts, 1).unwrap_err();
    assert!(e.contains("vertex 3 has a non-finite coordinate"), "{e}");

    // A crease on a diagonal, which is not an edge: OpenSubdiv only warns; the shim refuses.
    let e = osd_catmark(&mesh, &crease(&[[0, 3]], &[1.0]), &opts, 1).unwrap_err();
    assert!(e.contains("does not exist"), "{e}");
    let e = osd_catmark(&mesh, &crease(&[[0, 1]], &[-1.0]), &opts, 1).unwrap_err();
    assert!(e.contains("crease 0"), "{e}");
    let e = osd_catmark(&mesh, &crease(&[[0, 1]], &[]), &opts, 1).unwrap_err();
    assert!(e.contains("sharpness values"), "{e}");

    let e = osd_catmark(&mesh, &no_creases(), &opts, MAX_LEVEL + 1).unwrap_err();
    assert!(e.contains("level"), "{e}");

    let (uv, mut idx) = cube_uvs(&mesh);
    idx.pop();
    let e = osd_catmark_fvar(&mesh, &no_creases(), &opts, 1, &uv, &idx).unwrap_err();
    assert!(e.contains("face-varying indices"), "{e}");
    idx.push(1000);
    let e = osd_catmark_fvar(&mesh, &no_creases(), &opts, 1, &uv, &idx).unwrap_err();
    assert!(e.contains("face-varying value 1000"), "{e}");
}

#[test]
fn concurrent_calls_are_independent() {
    let handles: Vec<_> = (0..4)
        .map(|t| {
            std::thread::spawn(move || {
                let mesh = torus(6 + t, 5);
                let mut out = BTreeMap::new();
                // Each thread's error messages are its own (OpenSubdiv's warning sink is
                // thread-local, OpenMesh's calls are serialised).
                let fan_err = openmesh_catmull_clark(&fan(), 1).unwrap_err();
                assert!(fan_err.contains("complex edge"), "{fan_err}");
                for _ in 0..5 {
                    let osd = osd_catmark(&mesh, &no_creases(), &OsdOptions::default(), 2).unwrap();
                    let om = openmesh_catmull_clark(&mesh, 2).unwrap();
                    let bad =
                        osd_catmark(&mesh, &crease(&[[0, 7]], &[1.0]), &OsdOptions::default(), 1);
                    let bad = bad.unwrap_err();
                    assert!(bad.contains("Edge 0 specified to be sharp"), "{bad}");
                    assert!(!bad.contains("Edge 1"), "{bad}");
                    out.insert(osd.num_vertices(), om.num_vertices());
                }
                out
            })
        })
        .collect();
    for h in handles {
        let out = h.join().unwrap();
        assert_eq!(out.len(), 1);
        let (a, b) = out.into_iter().next().unwrap();
        assert_eq!(a, b);
    }
}
