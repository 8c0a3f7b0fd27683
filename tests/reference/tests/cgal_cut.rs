//! Tests of the exact stroke cut (`cgal_stroke_cut`, CGAL 5 constrained Delaunay triangulation
//! with exact constructions): counts worked out by hand on single triangles, watertightness and
//! placement of the new vertices on a grid seen in perspective, a hand-checked minimum angle, bad
//! input; then the baseline figures on the shared models (issue 5: the kernel's cut is compared
//! with these).
//!
//! The baseline is printed: `cargo test -p katachi-reference --test cgal_cut -- --nocapture
//! shared_models`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use katachi::DVec3;
use katachi_reference::cut_setup::{
    look_at_bounds, model_setup, project, project_w, ref_mesh, triangle_min_angle_deg, Projection,
};
use katachi_reference::{cgal_stroke_cut, CutMode, CutView, ExactCut, NewVertexSource, RefMesh};

// ---------------------------------------------------------------------------------------------
// Fixtures

/// A view in which world `(x, y, 0)` is pixel `(x, y)` exactly for dyadic coordinates: an
/// orthographic matrix over a 16 x 16 viewport, with bottom = 16 and top = 0 (pixels run down).
fn pixel_view() -> CutView {
    let m = glam::DMat4::orthographic_rh_gl(0.0, 16.0, 16.0, 0.0, -1.0, 1.0);
    CutView {
        view_proj: m.to_cols_array(),
        viewport: [0.0, 0.0, 16.0, 16.0],
    }
}

fn tri_mesh(positions: Vec<[f64; 3]>, tris: &[[u32; 3]]) -> RefMesh {
    RefMesh {
        positions,
        face_sizes: vec![3; tris.len()],
        face_vertices: tris.iter().flatten().copied().collect(),
    }
}

/// The triangle (0,0), (8,0), (0,8) in the z = 0 plane.
fn one_triangle() -> RefMesh {
    tri_mesh(
        vec![[0.0, 0.0, 0.0], [8.0, 0.0, 0.0], [0.0, 8.0, 0.0]],
        &[[0, 1, 2]],
    )
}

/// An `n` x `n` grid of squares on [0, 1]^2, each split along its diagonal, lifted onto the
/// tilted plane z = 0.3 x + 0.1 y.
fn tilted_grid(n: u32) -> RefMesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            positions.push([x, y, 0.3 * x + 0.1 * y]);
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut tris = Vec::new();
    for j in 0..n {
        for i in 0..n {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    tri_mesh(positions, &tris)
}

fn p3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

fn sorted<T: PartialOrd>(mut v: Vec<T>) -> Vec<T> {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v
}

/// The position of the only new vertex from `source`.
fn vertex_from(c: &ExactCut, source: NewVertexSource) -> [f64; 3] {
    let found: Vec<usize> = (0..c.num_new_vertices())
        .filter(|&i| c.new_vertex_sources[i] == source)
        .collect();
    assert_eq!(found.len(), 1, "{source:?}: {:?}", c.new_vertex_sources);
    c.mesh.positions[c.mesh.num_vertices() - c.num_new_vertices() + found[0]]
}

fn cut(mesh: &RefMesh, view: &CutView, stroke: &[[f64; 2]]) -> ExactCut {
    cgal_stroke_cut(mesh, view, stroke, CutMode::ThroughAll).expect("exact cut")
}

// ---------------------------------------------------------------------------------------------
// Checks shared by the tests

/// Undirected edge -> number of faces.
fn edge_counts(tris: impl Iterator<Item = [u32; 3]>) -> BTreeMap<[u32; 2], usize> {
    let mut m = BTreeMap::new();
    for t in tris {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *m.entry([a.min(b), a.max(b)]).or_insert(0) += 1;
        }
    }
    m
}

fn input_tris(mesh: &RefMesh) -> impl Iterator<Item = [u32; 3]> + '_ {
    mesh.face_vertices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
}

/// V - E + F over the vertices that faces use.
fn euler(tris: &[[u32; 3]]) -> i64 {
    let verts: BTreeSet<u32> = tris.iter().flatten().copied().collect();
    let edges = edge_counts(tris.iter().copied());
    verts.len() as i64 - edges.len() as i64 + tris.len() as i64
}

fn dist_to_polyline(p: [f64; 2], stroke: &[[f64; 2]]) -> f64 {
    stroke
        .windows(2)
        .map(|s| {
            let (a, b) = (glam::DVec2::from(s[0]), glam::DVec2::from(s[1]));
            let q = glam::DVec2::from(p);
            let d = b - a;
            let t = if d.length_squared() > 0.0 {
                ((q - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + d * t - q).length()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Everything that must hold of any exact cut; returns the largest screen distance of a new vertex
/// from the stroke (pixels).
fn check_cut(input: &RefMesh, view: &CutView, stroke: &[[f64; 2]], c: &ExactCut) -> f64 {
    let nv = input.num_vertices();
    let out_tris: Vec<[u32; 3]> = c.triangles().collect();
    let in_tris: Vec<[u32; 3]> = input_tris(input).collect();
    assert_eq!(c.mesh.face_sizes.len(), out_tris.len());
    assert!(c.mesh.face_sizes.iter().all(|&s| s == 3));
    assert_eq!(
        c.mesh.positions[..nv],
        input.positions[..],
        "input vertices unchanged"
    );
    assert_eq!(c.mesh.num_vertices(), nv + c.num_new_vertices());

    // Faces: origin in range and in order; unsplit faces copied; counts add up.
    assert_eq!(c.face_origin.len(), out_tris.len());
    assert!(c.face_origin.windows(2).all(|w| w[0] <= w[1]));
    let mut pieces = vec![0usize; in_tris.len()];
    for (o, &f) in c.face_origin.iter().enumerate() {
        pieces[f as usize] += 1;
        if !c.new_faces.contains(&(o as u32)) {
            assert_eq!(out_tris[o], in_tris[f as usize], "unsplit face {f} copied");
        }
    }
    assert!(pieces.iter().all(|&n| n >= 1));
    let split = pieces.iter().filter(|&&n| n > 1).count();
    assert_eq!(c.split_faces, split);
    assert_eq!(c.new_triangles, out_tris.len() - in_tris.len());
    assert_eq!(c.new_faces.len(), c.new_triangles + c.split_faces);
    assert!(c
        .new_faces
        .iter()
        .all(|&o| pieces[c.face_origin[o as usize] as usize] > 1));

    // Same orientation and positive area: each piece's normal agrees with its source face's.
    let pos = |v: u32| p3(c.mesh.positions[v as usize]);
    for (o, t) in out_tris.iter().enumerate() {
        let s = in_tris[c.face_origin[o] as usize];
        let n_in = (pos(s[1]) - pos(s[0])).cross(pos(s[2]) - pos(s[0]));
        let n_out = (pos(t[1]) - pos(t[0])).cross(pos(t[2]) - pos(t[0]));
        if n_in.length() > 0.0 {
            assert!(
                n_out.dot(n_in) > 0.0,
                "face {o} (from {}) is flipped or flat",
                c.face_origin[o]
            );
        }
    }

    // Minimum angles as the helper measures them.
    for (&o, &a) in c.new_faces.iter().zip(&c.new_face_min_angles) {
        let t = out_tris[o as usize];
        let expected = triangle_min_angle_deg(pos(t[0]), pos(t[1]), pos(t[2]));
        assert!((a - expected).abs() < 1e-9, "face {o}: {a} vs {expected}");
    }

    // No cracks: an edge has at most as many faces as the input edge it lies on; the output's
    // boundary is the input's, subdivided by the new vertices on it; Euler characteristic kept.
    let in_edges = edge_counts(in_tris.iter().copied());
    let out_edges = edge_counts(out_tris.iter().copied());
    assert!(out_edges.values().all(|&n| n <= 2) || in_edges.values().any(|&n| n > 2));
    let mut directed = BTreeSet::new();
    for t in &out_tris {
        for k in 0..3 {
            assert!(
                directed.insert((t[k], t[(k + 1) % 3])),
                "directed edge {:?} twice: orientation or manifoldness broken",
                (t[k], t[(k + 1) % 3])
            );
        }
    }
    let in_boundary = in_edges.values().filter(|&&n| n == 1).count();
    let new_on_boundary = c
        .new_vertex_sources
        .iter()
        .filter(|s| matches!(s, NewVertexSource::Edge(u, v) if in_edges[&[*u, *v]] == 1))
        .count();
    let out_boundary = out_edges.values().filter(|&&n| n == 1).count();
    assert_eq!(
        out_boundary,
        in_boundary + new_on_boundary,
        "boundary edges"
    );
    assert_eq!(euler(&out_tris), euler(&in_tris), "Euler characteristic");
    let used: BTreeSet<u32> = out_tris.iter().flatten().copied().collect();
    for i in 0..c.num_new_vertices() {
        assert!(used.contains(&((nv + i) as u32)), "new vertex {i} unused");
    }

    // New vertices: on the stroke on screen, and on their source face (plane) or edge (segment).
    let mut worst: f64 = 0.0;
    for (i, src) in c.new_vertex_sources.iter().enumerate() {
        let p = pos((nv + i) as u32);
        let (sx, sy, w) = project_w(view, p);
        assert!(w > 0.0);
        worst = worst.max(dist_to_polyline([sx, sy], stroke));
        match *src {
            NewVertexSource::Face(f) => {
                let t = in_tris[f as usize];
                let (a, b, cc) = (pos(t[0]), pos(t[1]), pos(t[2]));
                let n = (b - a).cross(cc - a).normalize();
                let scale = (b - a).length().max((cc - a).length());
                assert!(
                    n.dot(p - a).abs() <= 1e-12 * scale.max(a.abs().max_element()),
                    "new vertex {i} off the plane of face {f}"
                );
                // Inside the face: barycentrics in [0, 1].
                let area = (b - a).cross(cc - a).length();
                let l: f64 = [(b, cc), (cc, a), (a, b)]
                    .iter()
                    .map(|&(u, v)| (u - p).cross(v - p).length() / area)
                    .sum();
                assert!((l - 1.0).abs() < 1e-9, "new vertex {i} outside face {f}");
            }
            NewVertexSource::Edge(u, v) => {
                assert!(
                    u < v && in_edges.contains_key(&[u, v]),
                    "({u}, {v}) is no edge"
                );
                let (a, b) = (pos(u), pos(v));
                let d = b - a;
                let t = (p - a).dot(d) / d.length_squared();
                assert!((-1e-12..=1.0 + 1e-12).contains(&t), "vertex {i}: t = {t}");
                let off = (a + d * t - p).length();
                assert!(off <= 1e-12 * d.length().max(a.abs().max_element()));
            }
        }
    }
    worst
}

// ---------------------------------------------------------------------------------------------
// Single triangles: counts by hand

#[test]
fn edge_to_edge_gives_three_for_one() {
    let m = one_triangle();
    // x = 1 crosses y = 0 at (1, 0) and x + y = 8 at (1, 7).
    let stroke = [[1.0, -1.0], [1.0, 9.0]];
    let c = cut(&m, &pixel_view(), &stroke);
    assert_eq!(c.crossed_faces, 1);
    assert_eq!(c.split_faces, 1);
    assert_eq!(c.mesh.num_faces(), 3);
    assert_eq!(c.new_triangles, 2);
    assert_eq!(c.num_new_vertices(), 2);
    assert_eq!(
        sorted(c.mesh.positions[3..].to_vec()),
        [[1.0, 0.0, 0.0], [1.0, 7.0, 0.0]],
        "the two crossings, lifted"
    );
    assert_eq!(
        sorted(c.new_vertex_sources.clone()),
        [NewVertexSource::Edge(0, 1), NewVertexSource::Edge(1, 2)]
    );
    let worst = check_cut(&m, &pixel_view(), &stroke, &c);
    assert!(worst < 1e-9);
}

#[test]
fn minimum_angle_by_hand() {
    // Same cut: the right part (1,0), (8,0), (1,7) is right-angled isosceles (45°); the left
    // quad (0,0), (1,0), (1,7), (0,8) is split along (0,0)-(1,7) (the Delaunay diagonal: the
    // opposite angles 90° at (1,0) and 45° at (0,8) add up to less than 180°), giving two
    // triangles whose smallest angle is atan(1/7) (at (1,7) in the first, at (0,0) in the other).
    let m = one_triangle();
    let c = cut(&m, &pixel_view(), &[[1.0, -1.0], [1.0, 9.0]]);
    let atan17 = (1.0f64 / 7.0).atan().to_degrees();
    let mut angles = c.new_face_min_angles.clone();
    angles.sort_by(f64::total_cmp);
    assert_eq!(angles.len(), 3);
    assert!((angles[0] - atan17).abs() < 1e-12, "{angles:?}");
    assert!((angles[1] - atan17).abs() < 1e-12, "{angles:?}");
    assert!((angles[2] - 45.0).abs() < 1e-12, "{angles:?}");
    assert!((c.min_angle().unwrap() - 8.130_102_354_155_978).abs() < 1e-12);
    // The diagonal is (0,0)-(1,7): vertices 0 and 4.
    let edges = edge_counts(c.triangles());
    assert_eq!(edges.get(&[0, 4]), Some(&2));
    assert_eq!(edges.get(&[2, 3]), None);
}

#[test]
fn stroke_ending_inside_gives_four_for_one() {
    let m = one_triangle();
    // Enters through y = 0 at (4/3, 0), ends at (2, 2) inside: 5 vertices, 4 on the hull,
    // 2 * 5 - 4 - 2 = 4 triangles.
    let stroke = [[1.0, -1.0], [2.0, 2.0]];
    let c = cut(&m, &pixel_view(), &stroke);
    assert_eq!(c.mesh.num_faces(), 4);
    assert_eq!(c.new_triangles, 3);
    let e = vertex_from(&c, NewVertexSource::Edge(0, 1));
    assert!((e[0] - 4.0 / 3.0).abs() < 1e-15 && e[1] == 0.0);
    assert_eq!(vertex_from(&c, NewVertexSource::Face(0)), [2.0, 2.0, 0.0]);
    check_cut(&m, &pixel_view(), &stroke, &c);
}

#[test]
fn stroke_inside_one_triangle_gives_five_for_one() {
    // Both ends inside: 5 vertices, 3 on the hull, 2 * 5 - 3 - 2 = 5 triangles.
    let m = one_triangle();
    let stroke = [[1.0, 1.0], [2.0, 3.0]];
    let c = cut(&m, &pixel_view(), &stroke);
    assert_eq!((c.mesh.num_faces(), c.new_triangles), (5, 4));
    check_cut(&m, &pixel_view(), &stroke, &c);
}

#[test]
fn stroke_through_a_corner_and_along_an_edge() {
    let m = one_triangle();
    // Through corner (0,0) and out through (4,4): one new vertex, 1 -> 2.
    let c = cut(&m, &pixel_view(), &[[-1.0, -1.0], [5.0, 5.0]]);
    assert_eq!((c.mesh.num_faces(), c.num_new_vertices()), (2, 1));
    assert_eq!(c.mesh.positions[3], [4.0, 4.0, 0.0]);
    // Along the edge y = 0 from beyond one corner to beyond the other: nothing to insert.
    let c = cut(&m, &pixel_view(), &[[-1.0, 0.0], [9.0, 0.0]]);
    assert_eq!(c.crossed_faces, 1);
    assert_eq!(
        (c.split_faces, c.new_triangles, c.num_new_vertices()),
        (0, 0, 0)
    );
    assert_eq!(c.mesh, m);
    // Missing the triangle: nothing crossed.
    let c = cut(&m, &pixel_view(), &[[9.0, 9.0], [15.0, 1.0]]);
    assert_eq!((c.crossed_faces, c.split_faces), (0, 0));
    assert_eq!(c.mesh, m);
    assert_eq!(c.min_angle(), None);
}

#[test]
fn self_crossing_stroke_gets_its_crossing_vertex() {
    let m = tri_mesh(
        vec![[0.0, 0.0, 0.0], [16.0, 0.0, 0.0], [0.0, 16.0, 0.0]],
        &[[0, 1, 2]],
    );
    // (1,1)-(4,4) and (4,1)-(1,4) cross at (2.5, 2.5): 4 stroke points + 1 crossing inside,
    // 8 vertices, 3 on the hull: 2 * 8 - 3 - 2 = 11 triangles.
    let stroke = [[1.0, 1.0], [4.0, 4.0], [4.0, 1.0], [1.0, 4.0]];
    let c = cut(&m, &pixel_view(), &stroke);
    assert_eq!(c.mesh.num_faces(), 11);
    assert_eq!(c.num_new_vertices(), 5);
    assert!(c.mesh.positions.contains(&[2.5, 2.5, 0.0]));
    check_cut(&m, &pixel_view(), &stroke, &c);
}

#[test]
fn both_faces_of_a_crossed_edge_share_its_point() {
    // Two triangles sharing edge (1, 2); a stroke across both.
    let m = tri_mesh(
        vec![
            [0.0, 0.0, 0.0],
            [8.0, 0.0, 0.0],
            [0.0, 8.0, 0.0],
            [8.0, 8.0, 0.0],
        ],
        &[[0, 1, 2], [1, 3, 2]],
    );
    let stroke = [[1.0, 2.0], [7.0, 5.0]];
    let c = cut(&m, &pixel_view(), &stroke);
    let on_shared: Vec<_> = c
        .new_vertex_sources
        .iter()
        .filter(|s| **s == NewVertexSource::Edge(1, 2))
        .collect();
    assert_eq!(on_shared.len(), 1, "one point on the shared edge");
    // Face 0: end (1,2) inside + crossing on its edge: 4 triangles; face 1: crossing on the edge
    // + end (7,5) inside: 4 triangles.
    assert_eq!((c.mesh.num_faces(), c.new_triangles), (8, 6));
    check_cut(&m, &pixel_view(), &stroke, &c);
}

// ---------------------------------------------------------------------------------------------
// A grid crossed diagonally, in perspective

#[test]
fn grid_crossed_diagonally_is_watertight_and_on_the_stroke() {
    let m = tilted_grid(8);
    let lo = DVec3::new(0.0, 0.0, 0.0);
    let hi = DVec3::new(1.0, 1.0, 0.4);
    for projection in [
        Projection::Perspective { fov_y_deg: 50.0 },
        Projection::Orthographic,
    ] {
        let view = look_at_bounds(lo, hi, DVec3::new(0.2, -0.3, 1.0), projection, 800, 600);
        let a = project(&view, DVec3::new(0.0, 0.0, 0.0)).unwrap();
        let b = project(&view, DVec3::new(1.0, 1.0, 0.4)).unwrap();
        let (a, b) = (glam::DVec2::from(a), glam::DVec2::from(b));
        let d = b - a;
        let normal = glam::DVec2::new(-d.y, d.x) * 0.03;
        // From outside one corner to outside the opposite one, wiggling.
        let stroke: Vec<[f64; 2]> = (0..=8)
            .map(|i| {
                let u = -0.07 + 1.14 * f64::from(i) / 8.0;
                let wiggle = if i % 2 == 0 { 1.0 } else { -1.0 };
                (a + d * u + normal * wiggle).to_array()
            })
            .collect();
        let c = cut(&m, &view, &stroke);
        assert!(c.crossed_faces >= 16, "{projection:?}: {}", c.crossed_faces);
        assert_eq!(c.split_faces, c.crossed_faces);
        assert!(c.new_triangles > c.split_faces);
        assert_eq!(c.faces_behind_eye, 0);
        let worst = check_cut(&m, &view, &stroke, &c);
        assert!(
            worst < 1e-9,
            "{projection:?}: a new vertex {worst} px off the stroke"
        );
        // The stroke starts and ends outside: it enters and leaves through the boundary.
        let on_boundary = c
            .new_vertex_sources
            .iter()
            .filter(|s| match s {
                NewVertexSource::Edge(u, v) => {
                    let (p, q) = (m.positions[*u as usize], m.positions[*v as usize]);
                    (p[0] == q[0] && (p[0] == 0.0 || p[0] == 1.0))
                        || (p[1] == q[1] && (p[1] == 0.0 || p[1] == 1.0))
                }
                NewVertexSource::Face(_) => false,
            })
            .count();
        assert_eq!(on_boundary, 2, "{projection:?}");
    }
}

#[test]
fn face_behind_the_eye_is_split_by_its_neighbour() {
    // Eye at the origin looking down -z. Face 0 in front; face 1 shares edge (0, 1) with it and
    // has corner 3 behind the eye. A vertical stroke crosses face 0 and the shared edge.
    let m = tri_mesh(
        vec![
            [-1.0, -1.0, -5.0],
            [1.0, -1.0, -5.0],
            [0.0, 1.0, -5.0],
            [0.0, -1.0, 5.0],
        ],
        &[[0, 1, 2], [1, 0, 3]],
    );
    let vp = glam::DMat4::perspective_rh_gl(1.0, 1.0, 0.1, 100.0)
        * glam::DMat4::look_at_rh(DVec3::ZERO, -DVec3::Z, DVec3::Y);
    let view = CutView {
        view_proj: vp.to_cols_array(),
        viewport: [0.0, 0.0, 500.0, 500.0],
    };
    let top = project(&view, DVec3::new(0.1, 0.5, -5.0)).unwrap();
    let below = project(&view, DVec3::new(0.1, -1.5, -5.0)).unwrap();
    let stroke = [top, below];
    let c = cut(&m, &view, &stroke);
    assert_eq!(c.faces_behind_eye, 1);
    assert_eq!(c.faces_split_by_neighbours, 1);
    assert_eq!(c.crossed_faces, 1);
    // Face 0: end inside + one edge point: 4; face 1: its edge split: 2.
    assert_eq!((c.mesh.num_faces(), c.new_triangles), (6, 4));
    assert_eq!(c.num_new_vertices(), 2);
    vertex_from(&c, NewVertexSource::Face(0));
    let e = vertex_from(&c, NewVertexSource::Edge(0, 1));
    assert!((e[0] - 0.1).abs() < 1e-12 && (e[1] + 1.0).abs() < 1e-15 && e[2] == -5.0);
    check_cut(&m, &view, &stroke, &c);
}

// ---------------------------------------------------------------------------------------------
// Bad input

#[test]
fn bad_input_is_an_error() {
    let m = one_triangle();
    let view = pixel_view();
    let err = |mesh: &RefMesh, view: &CutView, stroke: &[[f64; 2]]| {
        let e = cgal_stroke_cut(mesh, view, stroke, CutMode::ThroughAll).unwrap_err();
        assert!(e.starts_with("bad argument: "), "{e}");
        e
    };
    assert!(err(&m, &view, &[]).contains("0 points"));
    assert!(err(&m, &view, &[[1.0, 1.0]]).contains("1 points"));
    assert!(err(&m, &view, &[[1.0, 1.0], [1.0, 1.0]]).contains("zero length"));
    assert!(err(&m, &view, &[[1.0, 1.0], [f64::NAN, 2.0]]).contains("stroke"));
    assert!(err(&m, &view, &[[1.0, f64::INFINITY], [3.0, 2.0]]).contains("stroke"));
    let mut v = view;
    v.view_proj[5] = f64::NAN;
    assert!(err(&m, &v, &[[1.0, 1.0], [3.0, 2.0]]).contains("matrix"));
    let mut v = view;
    v.viewport[2] = 0.0;
    assert!(err(&m, &v, &[[1.0, 1.0], [3.0, 2.0]]).contains("viewport"));
    let mut bad = m.clone();
    bad.positions[1][2] = f64::NAN;
    assert!(err(&bad, &view, &[[1.0, 1.0], [3.0, 2.0]]).contains("non-finite"));
    let mut bad = m.clone();
    bad.face_vertices[2] = 7;
    assert!(err(&bad, &view, &[[1.0, 1.0], [3.0, 2.0]]).contains("vertex 7"));
    let quad = RefMesh {
        positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        face_sizes: vec![4],
        face_vertices: vec![0, 1, 2, 3],
    };
    assert!(err(&quad, &view, &[[1.0, 1.0], [3.0, 2.0]]).contains("triangles"));
    // Still usable afterwards.
    assert_eq!(cut(&m, &view, &[[1.0, -1.0], [1.0, 9.0]]).new_triangles, 2);
}

// ---------------------------------------------------------------------------------------------
// Baseline on the shared models

fn shared_model(name: &str) -> Option<katachi::PolyMesh> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/models")
        .join(name);
    if !path.is_file() {
        eprintln!("skipping {name}: {} is missing", path.display());
        return None;
    }
    Some(katachi::io::read(&path).unwrap_or_else(|e| panic!("reading {name}: {e}")))
}

#[test]
fn shared_models() {
    println!(
        "{:<20} {:<12} {:>7} {:>7} {:>6} {:>7} {:>6} {:>9} {:>9} {:>5} {:>5} {:>8}",
        "model",
        "view",
        "faces",
        "crossed",
        "split",
        "new_tri",
        "new_v",
        "min_deg",
        "mean_deg",
        "<5",
        "<10",
        "ms"
    );
    for name in ["stanford-bunny.obj", "fandisk.off"] {
        let Some(model) = shared_model(name) else {
            continue;
        };
        let mesh = ref_mesh(&model).unwrap();
        assert!(
            mesh.face_sizes.iter().all(|&n| n == 3),
            "{name} is a triangle mesh"
        );
        for (label, projection) in [
            ("orthographic", Projection::Orthographic),
            ("perspective", Projection::Perspective { fov_y_deg: 40.0 }),
        ] {
            let (view, stroke) = model_setup(&model, projection).unwrap();
            assert_eq!(stroke.len(), 50);
            let c = cut(&mesh, &view, &stroke);
            assert!(c.crossed_faces > 0 && c.split_faces > 0, "{name} {label}");
            assert_eq!(c.faces_behind_eye, 0);
            let worst = check_cut(&mesh, &view, &stroke, &c);
            assert!(worst < 1e-9, "{name} {label}: {worst} px off the stroke");
            let angles = &c.new_face_min_angles;
            let mean = angles.iter().sum::<f64>() / angles.len() as f64;
            println!(
                "{:<20} {:<12} {:>7} {:>7} {:>6} {:>7} {:>6} {:>9.4} {:>9.3} {:>5} {:>5} {:>8.1}",
                name,
                label,
                mesh.num_faces(),
                c.crossed_faces,
                c.split_faces,
                c.new_triangles,
                c.num_new_vertices(),
                c.min_angle().unwrap(),
                mean,
                angles.iter().filter(|&&a| a < 5.0).count(),
                angles.iter().filter(|&&a| a < 10.0).count(),
                c.time.as_secs_f64() * 1e3,
            );
        }
    }
}
