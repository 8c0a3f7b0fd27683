//! Tests of the exact stroke cut (`cgal_stroke_cut`, CGAL 5 constrained Delaunay triangulation
//! with exact constructions): counts worked out by hand on single triangles, watertightness and
//! placement of the new vertices on a grid seen in perspective, a hand-checked minimum angle, bad
//! input; then the baseline figures on fandisk (and the Stanford bunny from the corpus, when
//! one is given), and katachi's cut compared with them
//! (issue 5: fewer new triangles, larger minimum angle, paths that follow the exact cut).
//!
//! Both tables are printed: `cargo test -p katachi-reference --test cgal_cut -- --nocapture
//! shared_models katachi_cuts`.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::OnceLock;
use std::time::Instant;

use katachi::DVec3;

// The test models and the record (tests/support), shared with the root crate's tests.
#[allow(dead_code)]
#[path = "../../support/models.rs"]
mod models;
#[allow(dead_code)]
#[path = "../../support/record.rs"]
mod record;
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
// Baseline on the shared models, and katachi's cut against it

/// The models the baseline cuts: fandisk (bundled) always, the Stanford bunny when a corpus
/// is given (its license does not allow bundling it; without a corpus its cuts are recorded
/// as not run).
fn cut_models() -> Vec<(&'static str, katachi::PolyMesh)> {
    let mut v = vec![("fandisk.off", models::read_bundled("fandisk.off"))];
    if let Some(paths) = models::corpus_models("cgal_cut::shared_cuts", &["stanford-bunny.obj"]) {
        let m = katachi::io::read(&paths[0]).unwrap_or_else(|e| panic!("{e}"));
        models::ran("cgal_cut::shared_cuts", "stanford-bunny.obj");
        v.insert(0, ("stanford-bunny.obj", m));
    }
    v
}

/// One shared model seen one way, with the exact cut of its [`model_setup`] stroke.
struct SharedCut {
    name: &'static str,
    label: &'static str,
    model: katachi::PolyMesh,
    mesh: RefMesh,
    view: CutView,
    stroke: Vec<[f64; 2]>,
    exact: ExactCut,
}

/// The exact cuts of the shared models (bunny and fandisk, orthographic and perspective),
/// computed once per test binary: the baseline test and the comparison with katachi read the
/// same cuts (those on the bunny take a few seconds each in a debug build).
fn shared_cuts() -> &'static [SharedCut] {
    static CUTS: OnceLock<Vec<SharedCut>> = OnceLock::new();
    CUTS.get_or_init(|| {
        let mut out = Vec::new();
        for (name, model) in cut_models() {
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
                let exact = cut(&mesh, &view, &stroke);
                out.push(SharedCut {
                    name,
                    label,
                    model: model.clone(),
                    mesh: mesh.clone(),
                    view,
                    stroke,
                    exact,
                });
            }
        }
        out
    })
}

#[test]
fn shared_models() {
    // One print at the end: the comparison test runs beside this one and prints its own table.
    let mut table = format!(
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
    for s in shared_cuts() {
        let (name, label, mesh, c) = (s.name, s.label, &s.mesh, &s.exact);
        assert_eq!(s.stroke.len(), 50);
        assert!(c.crossed_faces > 0 && c.split_faces > 0, "{name} {label}");
        assert_eq!(c.faces_behind_eye, 0);
        let worst = check_cut(mesh, &s.view, &s.stroke, c);
        assert!(worst < 1e-9, "{name} {label}: {worst} px off the stroke");
        let angles = &c.new_face_min_angles;
        let mean = angles.iter().sum::<f64>() / angles.len() as f64;
        table += &format!(
            "\n{:<20} {:<12} {:>7} {:>7} {:>6} {:>7} {:>6} {:>9.4} {:>9.3} {:>5} {:>5} {:>8.1}",
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
    println!("{table}");
}

/// A triangle up to rotation (orientation kept): its smallest vertex first.
fn canonical(t: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| t[k]).unwrap();
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

/// What the comparison measures of one cut.
#[derive(Debug)]
struct CutQuality {
    /// Output triangles that are not input triangles (see [`quality`]).
    new: usize,
    /// Output faces minus input faces.
    added: usize,
    /// The smallest angle over the new triangles, degrees.
    min_angle: f64,
    /// The new triangle with that angle.
    worst: [u32; 3],
    /// Input triangles kept (same vertices) but reshaped because a corner moved.
    reshaped: usize,
    /// The smallest angle over the reshaped triangles (`f64::INFINITY` if none).
    reshaped_min_angle: f64,
}

/// New triangles, measured identically on both cuts: an output triangle is *new* when its
/// vertex triple (up to rotation) is not the vertex triple of an input triangle. Both cuts keep
/// the input's vertex ids and append their new vertices, so a triangle that survived the cut is
/// recognised by its ids whatever its slot; every piece of a split triangle has a new vertex or
/// a new pairing of old ones, so it is new. For the exact cut these are exactly its `new_faces`
/// (every piece of every split face, so the count is `new_triangles + split_faces`); for
/// katachi, the faces in split faces' places. The count is of faces present after the cut,
/// not of faces added (`added` is that, `new - split`).
///
/// Katachi also moves vertices onto the stroke, so an input triangle around a moved vertex
/// keeps its ids but changes shape: those are counted apart (`reshaped`), with their own
/// minimum angle, so that a sliver made by snapping cannot hide from the comparison. The exact
/// cut moves nothing.
fn quality(
    input: &[[u32; 3]],
    output: &[[u32; 3]],
    positions: &[DVec3],
    moved: &BTreeSet<u32>,
) -> CutQuality {
    let old: BTreeSet<[u32; 3]> = input.iter().map(|&t| canonical(t)).collect();
    let angle = |t: [u32; 3]| {
        let p = |v: u32| positions[v as usize];
        triangle_min_angle_deg(p(t[0]), p(t[1]), p(t[2]))
    };
    let mut q = CutQuality {
        new: 0,
        added: output.len() - input.len(),
        min_angle: f64::INFINITY,
        worst: [0; 3],
        reshaped: 0,
        reshaped_min_angle: f64::INFINITY,
    };
    for &t in output {
        if !old.contains(&canonical(t)) {
            q.new += 1;
            let a = angle(t);
            if a < q.min_angle {
                (q.min_angle, q.worst) = (a, t);
            }
        } else if t.iter().any(|v| moved.contains(v)) {
            q.reshaped += 1;
            q.reshaped_min_angle = q.reshaped_min_angle.min(angle(t));
        }
    }
    q
}

fn poly_triangles(mesh: &katachi::PolyMesh) -> Vec<[u32; 3]> {
    mesh.faces()
        .map(|f| {
            let l = mesh.face_outer(f);
            assert_eq!(l.len(), 3, "face {} is a triangle", f.0);
            [l[0].0, l[1].0, l[2].0]
        })
        .collect()
}

/// The distance from `p` to the nearest of `paths` (closed ones include their closing edge).
fn dist_to_paths(p: [f64; 2], paths: &[(Vec<[f64; 2]>, bool)]) -> f64 {
    paths
        .iter()
        .map(|(pts, closed)| {
            if pts.len() == 1 {
                return (glam::DVec2::from(p) - glam::DVec2::from(pts[0])).length();
            }
            let mut d = dist_to_polyline(p, pts);
            if *closed {
                d = d.min(dist_to_polyline(p, &[pts[pts.len() - 1], pts[0]]));
            }
            d
        })
        .fold(f64::INFINITY, f64::min)
}

/// Issue 5: katachi's cut (seed 002: snapping and normalization instead of exact constraints)
/// against the exact cut (every stroke segment a constraint of CGAL's constrained Delaunay
/// triangulation of each crossed face) on the shared models, same view and stroke, through
/// all sheets. The paper's claim, checked on every setup: fewer new triangles, and a larger
/// minimum angle over them. Also checked: katachi moves vertices by at most
/// `max(snap ratios)` × L on screen, and its cut paths follow the exact cut — every point the
/// exact cut inserts (the stroke's crossings with the mesh's edges and its points inside faces,
/// i.e. the stroke clipped to the mesh) lies within that snap distance of katachi's projected
/// paths, and every path vertex within it of the stroke (a screen Hausdorff distance).
///
/// Printed: `cargo test -p katachi-reference --test cgal_cut -- --nocapture katachi_cuts`.
#[test]
fn katachi_cuts_with_fewer_and_better_shaped_triangles_than_the_exact_cut() {
    use katachi::cut::{cut_by_stroke, CutMode, CutOptions, Stroke, View};

    // Columns: in° = smallest angle of the input triangles katachi split; k_ = katachi, c_ =
    // exact cut; new = new triangles ([`quality`]), add = faces added, min° = smallest angle of
    // the new triangles, rsh / rsh° = katachi's reshaped triangles and their smallest angle;
    // new_r, ang_r = katachi / exact for the count and the angle; moved, max_px = vertices
    // snapped and the largest move (pixels); L_px = mean edge length on screen; snap =
    // max(snap ratios) × L; c→k_px = farthest exact-cut vertex from katachi's paths, k→s_px =
    // farthest path vertex from the stroke; ms = katachi's time (this build).
    // One print at the end: the baseline test runs beside this one and prints its own table.
    let mut table = format!(
        "{:<20} {:<12} {:>7} | {:>6} {:>6} {:>8} {:>6} {:>8} | {:>6} {:>6} {:>8} | {:>6} {:>6} | {:>5} {:>6} {:>6} {:>6} {:>7} {:>7} {:>6}",
        "model",
        "view",
        "in°",
        "k_new",
        "k_add",
        "k_min°",
        "k_rsh",
        "k_rsh°",
        "c_new",
        "c_add",
        "c_min°",
        "new_r",
        "ang_r",
        "moved",
        "max_px",
        "L_px",
        "snap",
        "c→k_px",
        "k→s_px",
        "ms",
    );
    let mut failures = Vec::new();
    for s in shared_cuts() {
        let setup = format!("{} {}", s.name, s.label);
        let options = CutOptions::with_mode(CutMode::ThroughAll);
        let view = View::new(
            glam::DMat4::from_cols_array(&s.view.view_proj),
            s.view.viewport,
        );
        let stroke = Stroke::new(s.stroke.iter().map(|&p| glam::DVec2::from(p)).collect());
        let start = Instant::now();
        let out = cut_by_stroke(&s.model, &stroke, &view, &options)
            .unwrap_or_else(|e| panic!("{setup}: katachi's cut failed: {e}"));
        let ms = start.elapsed().as_secs_f64() * 1e3;
        let r = &out.report;
        assert!(r.unjoined.is_empty(), "{setup}: {:?}", r.unjoined);
        assert!(r.clipped_faces.is_empty(), "{setup}");

        // Both sides measured the same way.
        let input: Vec<[u32; 3]> = input_tris(&s.mesh).collect();
        let k_out = poly_triangles(&out.mesh);
        let moved: BTreeSet<u32> = r.moved.iter().map(|m| m.vertex.0).collect();
        let k = quality(&input, &k_out, out.mesh.positions(), &moved);
        let c_out: Vec<[u32; 3]> = s.exact.triangles().collect();
        let c_pos: Vec<DVec3> = s.exact.mesh.positions.iter().map(|&p| p3(p)).collect();
        let c = quality(&input, &c_out, &c_pos, &BTreeSet::new());
        // For scale: the smallest angle of the input triangles katachi split.
        let kept: BTreeSet<[u32; 3]> = k_out.iter().map(|&t| canonical(t)).collect();
        let split_min_angle = input
            .iter()
            .filter(|&&t| !kept.contains(&canonical(t)))
            .map(|t| {
                let p = |v: u32| s.model.position(katachi::VertexId(v));
                triangle_min_angle_deg(p(t[0]), p(t[1]), p(t[2]))
            })
            .fold(f64::INFINITY, f64::min);
        // The definition agrees with each cut's own account of itself.
        assert_eq!(c.new, s.exact.new_faces.len(), "{setup}");
        assert_eq!(c.added, s.exact.new_triangles, "{setup}");
        assert!((c.min_angle - s.exact.min_angle().unwrap()).abs() < 1e-9);
        assert_eq!(k.added, r.new_faces as usize, "{setup}");
        assert_eq!(k.new, (r.new_faces + r.split_faces) as usize, "{setup}");

        // Snapping moved no vertex further than the snap distance, on screen.
        let snap =
            options.snap_vertex_ratio.max(options.snap_segment_ratio) * r.mean_edge_length_px;
        for m in &r.moved {
            let from = project(&s.view, m.from).unwrap();
            let to = project(&s.view, m.to).unwrap();
            let px = (glam::DVec2::from(to) - glam::DVec2::from(from)).length();
            assert!(
                (px - m.pixels).abs() <= 1e-6 * snap.max(1.0),
                "{setup}: {m:?} is {px} px"
            );
            assert!(
                m.pixels <= snap * (1.0 + 1e-9),
                "{setup}: vertex {} moved {} px > {snap} px",
                m.vertex.0,
                m.pixels
            );
        }
        assert!(r.max_move_px <= snap * (1.0 + 1e-9), "{setup}");

        // The cut paths against the exact cut, in pixels.
        let paths: Vec<(Vec<[f64; 2]>, bool)> = r
            .paths
            .iter()
            .map(|p| {
                let pts = p
                    .vertices
                    .iter()
                    .map(|&v| project(&s.view, out.mesh.position(v)).unwrap())
                    .collect();
                (pts, p.closed)
            })
            .collect();
        let nv = s.mesh.num_vertices();
        let exact_to_katachi = (nv..s.exact.mesh.num_vertices())
            .map(|v| dist_to_paths(project(&s.view, c_pos[v]).unwrap(), &paths))
            .fold(0.0, f64::max);
        let katachi_to_stroke = paths
            .iter()
            .flat_map(|(pts, _)| pts.iter())
            .map(|&p| dist_to_polyline(p, &s.stroke))
            .fold(0.0, f64::max);

        table += &format!(
            "\n{:<20} {:<12} {:>7.3} | {:>6} {:>6} {:>8.3} {:>6} {:>8.3} | {:>6} {:>6} {:>8.4} | {:>6.3} {:>6.0} | {:>5} {:>6.3} {:>6.3} {:>6.3} {:>7.3} {:>7.3} {:>6.0}",
            s.name,
            s.label,
            split_min_angle,
            k.new,
            k.added,
            k.min_angle,
            k.reshaped,
            k.reshaped_min_angle,
            c.new,
            c.added,
            c.min_angle,
            k.new as f64 / c.new as f64,
            k.min_angle / c.min_angle,
            r.moved.len(),
            r.max_move_px,
            r.mean_edge_length_px,
            snap,
            exact_to_katachi,
            katachi_to_stroke,
            ms,
        );

        let mut fail = |what: String| {
            let t = k.worst;
            let p = |v: u32| out.mesh.position(katachi::VertexId(v));
            let px = |v: u32| project(&s.view, p(v)).unwrap();
            failures.push(format!(
                "{setup}: {what}; katachi's worst new triangle {t:?} ({:.4}°): \
                 screen {:?} {:?} {:?}, moved corners {:?}, new corners {:?}",
                k.min_angle,
                px(t[0]),
                px(t[1]),
                px(t[2]),
                t.iter().filter(|v| moved.contains(v)).collect::<Vec<_>>(),
                t.iter().filter(|&&v| v as usize >= nv).collect::<Vec<_>>(),
            ));
        };
        if k.new >= c.new {
            fail(format!("{} new triangles, exact cut {}", k.new, c.new));
        }
        if k.min_angle <= c.min_angle {
            fail(format!(
                "min angle {}°, exact cut {}°",
                k.min_angle, c.min_angle
            ));
        }
        if k.reshaped_min_angle <= c.min_angle {
            fail(format!(
                "a reshaped triangle's min angle {}°, exact cut {}°",
                k.reshaped_min_angle, c.min_angle
            ));
        }
        if exact_to_katachi > snap || katachi_to_stroke > snap {
            fail(format!(
                "paths {exact_to_katachi} px (exact → katachi), {katachi_to_stroke} px \
                 (katachi → stroke) apart, snap distance {snap} px"
            ));
        }
    }
    println!("{table}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
