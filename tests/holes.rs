//! Faces with holes: validation, and method [a]'s bridged virtual faces (seed 001 §3.1 [a],
//! spec §5, resolutions A1–A9).

use std::collections::{BTreeMap, BTreeSet};

use katachi::mesh::holes::{
    bridge_face, validate_faces_with_holes, BridgeChoice, BridgeFailure, Bridged,
};
use katachi::mesh::shapes;
use katachi::{DVec3, FaceId, PolyMesh, VertexId};
use proptest::prelude::*;

mod support;
use support::property::counted_proptest;

// ---------------------------------------------------------------------------------------------
// Building faces.

/// `n` points on a circle of radius `r` around `c`, the first at `phase` degrees,
/// counter-clockwise, or clockwise when `cw`.
fn ring(n: usize, r: f64, phase: f64, c: [f64; 2], cw: bool) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let s = if cw { -1.0 } else { 1.0 };
            let a = (phase + s * 360.0 * k as f64 / n as f64).to_radians();
            [c[0] + r * a.cos(), c[1] + r * a.sin()]
        })
        .collect()
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64, cw: bool) -> Vec<[f64; 2]> {
    let mut p = vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    if cw {
        p.reverse();
    }
    p
}

/// One face in the plane z = 0 whose loops are `loops` (outer first); vertices are numbered
/// loop after loop.
fn face_mesh(loops: &[Vec<[f64; 2]>]) -> PolyMesh {
    face_mesh_3d(loops, |p| DVec3::new(p[0], p[1], 0.0))
}

fn face_mesh_3d(loops: &[Vec<[f64; 2]>], place: impl Fn([f64; 2]) -> DVec3) -> PolyMesh {
    let mut pos = Vec::new();
    let mut face = Vec::new();
    for lp in loops {
        let ids: Vec<u32> = (pos.len() as u32..(pos.len() + lp.len()) as u32).collect();
        pos.extend(lp.iter().map(|&p| place(p)));
        face.push(ids);
    }
    PolyMesh::from_faces_with_holes(pos, vec![face]).unwrap()
}

fn v(i: u32) -> VertexId {
    VertexId(i)
}

// ---------------------------------------------------------------------------------------------
// Checking a bridged face.

fn area_vector(mesh: &PolyMesh, lp: &[VertexId]) -> DVec3 {
    let o = mesh.position(lp[0]);
    let mut a = DVec3::ZERO;
    for i in 1..lp.len() {
        let (p, q) = (
            mesh.position(lp[i]) - o,
            mesh.position(lp[(i + 1) % lp.len()]) - o,
        );
        a += 0.5 * p.cross(q);
    }
    a
}

fn orient(a: DVec3, b: DVec3, c: DVec3, n: DVec3) -> f64 {
    (b - a).cross(c - a).dot(n)
}

/// Whether segments `ab` and `cd` (coplanar, normal `n`) cross or touch away from shared ends.
fn segments_cross(a: DVec3, b: DVec3, c: DVec3, d: DVec3, n: DVec3) -> bool {
    let (o1, o2) = (orient(a, b, c, n), orient(a, b, d, n));
    let (o3, o4) = (orient(c, d, a, n), orient(c, d, b, n));
    o1 * o2 < 0.0 && o3 * o4 < 0.0
}

/// The virtual faces tile the face: each loop edge once in its direction, each bridge once
/// each way, nothing else; every virtual face a polygon of ≥ 3 distinct vertices turning
/// left; areas add up; bridges do not cross; face-point vertices are vertices of their face.
fn check_tiling(mesh: &PolyMesh, f: FaceId, b: &Bridged) {
    let loops: Vec<Vec<VertexId>> = mesh
        .face_loops(f)
        .map(|l| mesh.loop_vertices(l).to_vec())
        .collect();
    let n = area_vector(mesh, &loops[0]);
    let face_area = n.length();
    let n = n / face_area;
    let mut want: BTreeMap<(VertexId, VertexId), u32> = BTreeMap::new();
    for lp in &loops {
        for i in 0..lp.len() {
            *want.entry((lp[i], lp[(i + 1) % lp.len()])).or_default() += 1;
        }
    }
    for &(s, l) in &b.bridges {
        *want.entry((s, l)).or_default() += 1;
        *want.entry((l, s)).or_default() += 1;
    }
    let mut got: BTreeMap<(VertexId, VertexId), u32> = BTreeMap::new();
    let mut area = 0.0;
    assert_eq!(b.faces.len(), b.face_point_vertices.len());
    for (face, corners) in b.faces.iter().zip(&b.face_point_vertices) {
        assert!(face.len() >= 3, "{face:?}");
        let distinct: BTreeSet<_> = face.iter().collect();
        assert_eq!(distinct.len(), face.len(), "repeated vertex in {face:?}");
        for c in corners {
            assert!(face.contains(c), "face point vertex {c} not in {face:?}");
        }
        let cs: BTreeSet<_> = corners.iter().collect();
        assert_eq!(cs.len(), corners.len());
        assert!(corners.len() >= 3, "{corners:?}");
        for i in 0..face.len() {
            *got.entry((face[i], face[(i + 1) % face.len()]))
                .or_default() += 1;
        }
        let a = area_vector(mesh, face).dot(n);
        assert!(a > 0.0, "virtual face {face:?} has area {a}");
        area += a;
    }
    assert_eq!(got, want);
    let holes: f64 = loops[1..].iter().map(|l| area_vector(mesh, l).dot(n)).sum();
    let expected = face_area + holes; // holes run the other way: negative areas
    assert!(
        (area - expected).abs() <= 1e-9 * face_area,
        "areas {area} vs {expected}"
    );
    let p = |v: VertexId| mesh.position(v);
    for (i, &(a, bb)) in b.bridges.iter().enumerate() {
        for &(c, d) in &b.bridges[i + 1..] {
            assert!(
                !segments_cross(p(a), p(bb), p(c), p(d), n),
                "bridges {a}-{bb} and {c}-{d} cross"
            );
        }
    }
    let count: u32 = b.holes.iter().map(|h| h.bridge_count).sum();
    assert_eq!(count as usize, b.bridges.len());
}

/// The nearest-vertex bridges of the seed are cyclically monotone (go round once in order).
fn nearest_is_monotone(mesh: &PolyMesh, s: &[VertexId], l: &[VertexId]) -> bool {
    let m = l.len();
    let map: Vec<usize> = s
        .iter()
        .map(|&a| {
            (0..m)
                .min_by(|&i, &j| {
                    let di = (mesh.position(a) - mesh.position(l[i])).length_squared();
                    let dj = (mesh.position(a) - mesh.position(l[j])).length_squared();
                    di.total_cmp(&dj)
                })
                .unwrap()
        })
        .collect();
    let q = s.len();
    let turns: usize = (0..q).map(|a| (map[a] + m - map[(a + 1) % q]) % m).sum();
    turns == m
}

fn set<T: Ord + Clone>(x: &[T]) -> BTreeSet<T> {
    x.iter().cloned().collect()
}

// ---------------------------------------------------------------------------------------------
// Spec §5.4 worked examples.

#[test]
fn square_in_square_gives_four_trapezoids() {
    // P = p0..p3 counter-clockwise; C = c0..c3 clockwise, listed so that c_a is nearest p_a.
    let p = rect(-2.0, -2.0, 2.0, 2.0, false);
    let c = vec![[-1.0, -1.0], [-1.0, 1.0], [1.0, 1.0], [1.0, -1.0]];
    let mesh = face_mesh(&[p, c]);
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    // Equal counts: S = C (A8); bridges (c_a, p_a).
    assert_eq!(b.holes.len(), 1);
    assert!(b.holes[0].short_is_hole);
    assert_eq!(b.holes[0].choice, BridgeChoice::Nearest);
    assert_eq!(
        b.bridges,
        vec![(v(4), v(0)), (v(5), v(3)), (v(6), v(2)), (v(7), v(1))]
    );
    // G_a = (c_a, c_{a+1}, l(a+1), l(a)): four trapezoids, face points their vertex averages.
    assert_eq!(
        b.faces,
        vec![
            vec![v(4), v(5), v(3), v(0)],
            vec![v(5), v(6), v(2), v(3)],
            vec![v(6), v(7), v(1), v(2)],
            vec![v(7), v(4), v(0), v(1)],
        ]
    );
    assert_eq!(b.face_point_vertices, b.faces);
}

#[test]
fn octagon_in_square_bridges_the_corners_and_skips_the_arc_middles() {
    // Square corners at 45 + 90k degrees, octagon vertices at 0, 45, …, 315 (clockwise).
    let r2 = 2.0f64.sqrt();
    let p = ring(4, 2.0 * r2, 45.0, [0.0, 0.0], false);
    let c = ring(8, 1.0, 0.0, [0.0, 0.0], true); // c_k at -45k degrees
    let mesh = face_mesh(&[p, c]);
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    // S = P (4 < 8): each corner p_a (at 45 + 90a) bridges to the octagon vertex at its angle.
    assert!(!b.holes[0].short_is_hole);
    assert_eq!(b.holes[0].choice, BridgeChoice::Nearest);
    // The octagon vertex at θ degrees is c_k with -45k ≡ θ: 45° → c7, 135° → c5, 225° → c3.
    let oct = |deg: u32| v(4 + ((360 - deg % 360) / 45) % 8);
    assert_eq!(
        b.bridges,
        vec![
            (v(0), oct(45)),
            (v(1), oct(135)),
            (v(2), oct(225)),
            (v(3), oct(315))
        ]
    );
    assert_eq!(b.faces.len(), 4);
    for a in 0..4u32 {
        let (from, to) = (45 + 90 * a, 135 + 90 * a);
        let middle = oct(90 + 90 * a);
        // G_a = p_a, p_{a+1}, l(a+1), middle, l(a): five vertices, four in the face point.
        assert_eq!(
            b.faces[a as usize],
            vec![v(a), v((a + 1) % 4), oct(to), middle, oct(from)]
        );
        assert_eq!(
            b.face_point_vertices[a as usize],
            vec![v(a), v((a + 1) % 4), oct(to), oct(from)]
        );
    }
    // The octagon vertices at 0, 90, 180, 270 degrees have no bridge (A4).
    let bridged: BTreeSet<VertexId> = b.bridges.iter().map(|&(_, l)| l).collect();
    for deg in [0, 90, 180, 270] {
        assert!(!bridged.contains(&oct(deg)));
    }
}

#[test]
fn plate_with_hole_faces_bridge_into_trapezoids() {
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    validate_faces_with_holes(&plate).unwrap();
    for f in [FaceId(0), FaceId(1)] {
        let b = bridge_face(&plate, f).unwrap();
        check_tiling(&plate, f, &b);
        assert_eq!(b.faces.len(), 4);
        assert!(b.faces.iter().all(|g| g.len() == 4));
        assert_eq!(b.face_point_vertices, b.faces);
    }
    // A face without holes comes back as itself.
    let b = bridge_face(&plate, FaceId(2)).unwrap();
    assert_eq!(b.faces, vec![plate.face_outer(FaceId(2)).to_vec()]);
    assert!(b.bridges.is_empty());
}

// ---------------------------------------------------------------------------------------------
// A2: crossing nearest-vertex bridges.

#[test]
fn off_centre_hole_gets_non_crossing_bridges() {
    // A diamond hole near the right of a 12-gon: its vertices' nearest 12-gon vertices go
    // 0°, -30°, 0°, 30° — not once round in order, and the bridge from the diamond's left
    // vertex to the 0° vertex would cut through the hole.
    let p = ring(12, 4.0, 0.0, [0.0, 0.0], false);
    let c = vec![[3.3, 0.0], [2.5, -0.8], [1.7, 0.0], [2.5, 0.8]];
    let mesh = face_mesh(&[p, c]);
    let outer = mesh.face_outer(FaceId(0)).to_vec();
    let hole = mesh
        .loop_vertices(mesh.face_loops(FaceId(0)).nth(1).unwrap())
        .to_vec();
    assert!(!nearest_is_monotone(&mesh, &hole, &outer));
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    assert_eq!(b.holes[0].choice, BridgeChoice::Optimised);
    assert!(b.holes[0].short_is_hole);
    assert_eq!(b.faces.len(), 4);
}

#[test]
fn skewed_hole_in_fine_outer_loop() {
    // A thin sheared quadrilateral hole inside a 24-gon, off centre: whatever the nearest map
    // does, the result tiles the face with non-crossing bridges.
    let p = ring(24, 5.0, 7.0, [0.0, 0.0], false);
    let c = vec![[2.5, 1.0], [-1.5, -0.2], [-2.0, -0.6], [2.0, 0.3]];
    let mut c = c;
    c.reverse(); // clockwise
    let mesh = face_mesh(&[p, c]);
    match bridge_face(&mesh, FaceId(0)) {
        Ok(b) => check_tiling(&mesh, FaceId(0), &b),
        Err(e) => assert!(matches!(e, BridgeFailure::NoBridgeSet { hole: 1 }), "{e}"),
    }
}

#[test]
fn hole_in_a_notch_needs_bridges_round_the_corner() {
    // Non-convex outer loop (a U): the hole sits in one arm; the nearest outer vertices of
    // some hole vertices are across the notch, where no bridge can go.
    let p = vec![
        [0.0, 0.0],
        [6.0, 0.0],
        [6.0, 6.0],
        [4.0, 6.0],
        [4.0, 2.0],
        [2.0, 2.0],
        [2.0, 6.0],
        [0.0, 6.0],
    ];
    let c = rect(0.5, 3.0, 1.5, 5.0, true);
    let mesh = face_mesh(&[p, c]);
    validate_faces_with_holes(&mesh).unwrap();
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
}

#[test]
fn hole_that_no_outer_corner_sees_fails_with_a_reason() {
    // An octagonal hole (8 > 4 vertices, so S = P) squeezed between the top of the plate and
    // a big rectangular hole: the lower corners of the plate see none of its vertices.
    let p = rect(0.0, 0.0, 10.0, 10.0, false);
    let small = ring(8, 0.4, 0.0, [5.0, 9.2], true);
    let big = rect(0.5, 0.5, 9.5, 8.6, true);
    let mesh = face_mesh(&[p, small, big]);
    validate_faces_with_holes(&mesh).unwrap();
    let e = bridge_face(&mesh, FaceId(0)).unwrap_err();
    assert_eq!(e, BridgeFailure::NoBridgeSet { hole: 1 });
    assert!(e.to_string().contains("hole (loop 1)"), "{e}");
}

// ---------------------------------------------------------------------------------------------
// A3: triangles.

#[test]
fn triangle_hole_in_twelve_gon() {
    // Two hole vertices share their nearest outer vertex (4, 0): G_0 is a triangle whose
    // face point averages its three distinct vertices.
    let p = ring(12, 4.0, 0.0, [0.0, 0.0], false);
    let c = vec![[3.0, 0.5], [3.0, -0.5], [-2.0, 0.0]]; // clockwise
    let mesh = face_mesh(&[p, c]);
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    assert_eq!(b.holes[0].choice, BridgeChoice::Nearest);
    assert_eq!(b.bridges, vec![(v(12), v(0)), (v(13), v(0)), (v(14), v(6))]);
    assert_eq!(b.faces[0], vec![v(12), v(13), v(0)]);
    assert_eq!(b.face_point_vertices[0], vec![v(12), v(13), v(0)]);
    // G_1 = c1, c2, then the lower half of the 12-gon from 180° to 360°.
    assert_eq!(b.faces[1].len(), 2 + 7);
    assert_eq!(b.face_point_vertices[1], vec![v(13), v(14), v(6), v(0)]);
    assert_eq!(b.faces[2].len(), 2 + 7);

    // A triangle hole whose three vertices all have the same nearest vertex cannot use the
    // nearest bridges at all (they would not go round the hole): optimised, still tiling.
    let p = ring(12, 4.0, 0.0, [0.0, 0.0], false);
    let c = vec![[3.0, 0.3], [3.0, -0.3], [2.2, 0.0]];
    let mesh = face_mesh(&[p, c]);
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    assert_eq!(b.holes[0].choice, BridgeChoice::Optimised);
    assert_eq!(b.faces.len(), 3);

    // A regular triangle hole at the centre: three bridges to three distinct vertices.
    let c = ring(3, 1.0, 90.0, [0.0, 0.0], true);
    let mesh = face_mesh(&[ring(12, 4.0, 0.0, [0.0, 0.0], false), c]);
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    assert_eq!(b.holes[0].choice, BridgeChoice::Nearest);
    assert!(b.face_point_vertices.iter().all(|c| c.len() == 4));
}

// ---------------------------------------------------------------------------------------------
// A6: several holes.

#[test]
fn two_holes_on_disjoint_arcs_are_both_bridged() {
    let p = rect(-6.0, -3.0, 6.0, 3.0, false);
    let left = rect(-4.0, -1.0, -2.0, 1.0, true);
    let right = rect(2.0, -1.0, 4.0, 1.0, true);
    let mesh = face_mesh(&[p, left, right]);
    validate_faces_with_holes(&mesh).unwrap();
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    assert_eq!(b.holes.len(), 2);
    assert!(b
        .holes
        .iter()
        .all(|h| h.short_is_hole && h.bridge_count == 4));
    // 8 bridges, 2 holes: 8 - 2 + 1 = 7 virtual faces; the one between the holes averages
    // the ends of its four bridges.
    assert_eq!(b.faces.len(), 7);
    let middle: Vec<_> = b
        .face_point_vertices
        .iter()
        .filter(|c| c.len() > 4)
        .collect();
    assert_eq!(middle.len(), 1);
    assert_eq!(
        set(middle[0]),
        set(&[v(0), v(1), v(2), v(3), v(5), v(6), v(8), v(11)])
    );
}

#[test]
fn two_holes_sharing_an_arc_fail_with_a_reason() {
    // Two small holes side by side under the top edge of a deep plate: each one's shortest
    // bridges go to both top corners, the one to the far corner passing over the other hole,
    // so the bridges of the two holes cross (they both need the top edge).
    let p = rect(-10.0, -30.0, 10.0, 10.0, false);
    let left = rect(-3.5, 7.5, -2.5, 8.3, true);
    let right = rect(2.5, 7.5, 3.5, 8.3, true);
    let mesh = face_mesh(&[p, left, right]);
    validate_faces_with_holes(&mesh).unwrap();
    let e = bridge_face(&mesh, FaceId(0)).unwrap_err();
    assert_eq!(
        e,
        BridgeFailure::BridgesCross {
            first: 1,
            second: 2
        }
    );
    assert!(e.to_string().contains("loops 1 and 2"), "{e}");
}

#[test]
fn holes_in_two_virtual_faces_of_another_hole_fail_with_a_reason() {
    // A big central hole bridged to the four corners, and one small hole in its left and one
    // in its right trapezoid: the big hole shares arcs with both.
    let p = rect(-10.0, -10.0, 10.0, 10.0, false);
    let big = rect(-3.0, -3.0, 3.0, 3.0, true);
    let left = rect(-8.0, -0.5, -7.0, 0.5, true);
    let right = rect(7.0, -0.5, 8.0, 0.5, true);
    let mesh = face_mesh(&[p.clone(), big.clone(), left, right.clone()]);
    validate_faces_with_holes(&mesh).unwrap();
    let e = bridge_face(&mesh, FaceId(0)).unwrap_err();
    assert!(
        matches!(
            e,
            BridgeFailure::SharedArc {
                first: 1,
                second: 2 | 3
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("hole (loop 1)"), "{e}");
    // With only one small hole, it sits in the big hole's one remaining virtual face.
    let mesh = face_mesh(&[p, big, right]);
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    assert_eq!(b.faces.len(), 4 + 4 - 2 + 1);
}

// ---------------------------------------------------------------------------------------------
// Validation.

fn invalid(loops: &[Vec<[f64; 2]>]) -> String {
    let mesh = face_mesh(loops);
    let e = validate_faces_with_holes(&mesh).unwrap_err();
    let m = e.to_string();
    assert!(m.starts_with("face 0: "), "{m}");
    // bridge_face refuses the same face with the same reason.
    match bridge_face(&mesh, FaceId(0)) {
        Err(BridgeFailure::InvalidFace(r)) => assert_eq!(r, m),
        other => panic!("{other:?}"),
    }
    m
}

#[test]
fn hole_outside_the_face_is_rejected() {
    let m = invalid(&[
        rect(0.0, 0.0, 4.0, 4.0, false),
        rect(5.0, 1.0, 6.0, 2.0, true),
    ]);
    assert!(
        m.contains("hole (loop 1) lies outside the outer loop"),
        "{m}"
    );
}

#[test]
fn holes_crossing_each_other_are_rejected() {
    let m = invalid(&[
        rect(0.0, 0.0, 10.0, 10.0, false),
        rect(1.0, 1.0, 5.0, 5.0, true),
        rect(3.0, 3.0, 7.0, 7.0, true),
    ]);
    assert!(m.contains("holes (loops 1 and 2) cross or touch"), "{m}");
}

#[test]
fn hole_crossing_the_outer_loop_is_rejected() {
    let m = invalid(&[
        rect(0.0, 0.0, 4.0, 4.0, false),
        rect(3.0, 1.0, 5.0, 2.0, true),
    ]);
    assert!(
        m.contains("hole (loop 1) crosses or touches the outer loop"),
        "{m}"
    );
}

#[test]
fn hole_touching_the_outer_loop_is_rejected() {
    // Touching at a point of an edge, and sharing a vertex.
    let m = invalid(&[
        rect(0.0, 0.0, 4.0, 4.0, false),
        vec![[4.0, 2.0], [3.0, 1.0], [2.0, 2.0], [3.0, 3.0]],
    ]);
    assert!(m.contains("touches the outer loop"), "{m}");
    let pos = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(4.0, 0.0, 0.0),
        DVec3::new(4.0, 4.0, 0.0),
        DVec3::new(0.0, 4.0, 0.0),
        DVec3::new(2.0, 1.0, 0.0),
        DVec3::new(1.0, 2.0, 0.0),
    ];
    let mesh =
        PolyMesh::from_faces_with_holes(pos, vec![vec![vec![0, 1, 2, 3], vec![2, 4, 5]]]).unwrap();
    let m = validate_faces_with_holes(&mesh).unwrap_err().to_string();
    assert!(m.contains("share vertex 2"), "{m}");
}

#[test]
fn nested_holes_are_rejected() {
    let m = invalid(&[
        rect(0.0, 0.0, 10.0, 10.0, false),
        rect(1.0, 1.0, 9.0, 9.0, true),
        rect(4.0, 4.0, 6.0, 6.0, true),
    ]);
    assert!(m.contains("hole (loop 2) lies inside hole (loop 1)"), "{m}");
}

#[test]
fn hole_not_coplanar_is_rejected() {
    let mut pos: Vec<DVec3> = rect(0.0, 0.0, 4.0, 4.0, false)
        .iter()
        .map(|p| DVec3::new(p[0], p[1], 0.0))
        .collect();
    pos.extend(
        rect(1.0, 1.0, 3.0, 3.0, true)
            .iter()
            .map(|p| DVec3::new(p[0], p[1], 0.2)),
    );
    let mesh = PolyMesh::from_faces_with_holes(pos, vec![vec![vec![0, 1, 2, 3], vec![4, 5, 6, 7]]])
        .unwrap();
    let m = validate_faces_with_holes(&mesh).unwrap_err().to_string();
    assert!(
        m.starts_with(
            "face 0: hole (loop 1) is not coplanar with the face: vertex 4 is 0.2 from its plane"
        ),
        "{m}"
    );
}

#[test]
fn hole_with_the_outer_loops_orientation_is_rejected() {
    let m = invalid(&[
        rect(0.0, 0.0, 4.0, 4.0, false),
        rect(1.0, 1.0, 3.0, 3.0, false),
    ]);
    assert!(
        m.contains("hole (loop 1) runs the same way as the outer loop"),
        "{m}"
    );
}

#[test]
fn self_crossing_hole_is_rejected() {
    let m = invalid(&[
        rect(0.0, 0.0, 4.0, 4.0, false),
        vec![[1.0, 1.0], [3.0, 3.0], [3.0, 1.0], [1.0, 3.0]],
    ]);
    assert!(m.contains("hole (loop 1) crosses or touches itself"), "{m}");
}

#[test]
fn errors_name_the_face() {
    // The second face of a mesh is the faulty one.
    let mut pos: Vec<DVec3> = Vec::new();
    let mut faces = Vec::new();
    for (k, dz) in [(0u32, 0.0), (1, 10.0)] {
        let base = pos.len() as u32;
        pos.extend(
            rect(0.0, 0.0, 4.0, 4.0, false)
                .iter()
                .map(|p| DVec3::new(p[0], p[1], dz)),
        );
        let hole = rect(1.0, 1.0, 3.0, 3.0, k == 0);
        pos.extend(hole.iter().map(|p| DVec3::new(p[0], p[1], dz)));
        faces.push(vec![
            (base..base + 4).collect::<Vec<_>>(),
            (base + 4..base + 8).collect(),
        ]);
    }
    let mesh = PolyMesh::from_faces_with_holes(pos, faces).unwrap();
    let m = validate_faces_with_holes(&mesh).unwrap_err().to_string();
    assert!(m.starts_with("face 1: "), "{m}");
    assert!(bridge_face(&mesh, FaceId(0)).is_ok());
}

#[test]
fn valid_plate_passes() {
    validate_faces_with_holes(&shapes::plate_with_hole(3.0, 1.0, 0.5).unwrap()).unwrap();
    validate_faces_with_holes(&shapes::cube(1.0).unwrap()).unwrap();
}

#[test]
fn tilted_face_is_handled_in_its_plane() {
    // The octagon-in-square example, rotated and moved in space.
    let r2 = 2.0f64.sqrt();
    let p = ring(4, 2.0 * r2, 45.0, [0.0, 0.0], false);
    let c = ring(8, 1.0, 0.0, [0.0, 0.0], true);
    let (u, w) = (
        DVec3::new(0.6, 0.0, -0.8),
        DVec3::new(0.48, 0.6, 0.36), // orthonormal to u
    );
    let mesh = face_mesh_3d(&[p, c], |q| {
        DVec3::new(1.0, -2.0, 3.0) + q[0] * u + q[1] * w
    });
    validate_faces_with_holes(&mesh).unwrap();
    let b = bridge_face(&mesh, FaceId(0)).unwrap();
    check_tiling(&mesh, FaceId(0), &b);
    assert!(b.face_point_vertices.iter().all(|c| c.len() == 4));
    assert!(b.faces.iter().all(|g| g.len() == 5));
}

// ---------------------------------------------------------------------------------------------
// Property test: convex annuli.

fn convex_polygon(angles: &[f64], radius: f64, c: [f64; 2], cw: bool) -> Vec<[f64; 2]> {
    let mut a: Vec<f64> = angles.to_vec();
    a.sort_by(f64::total_cmp);
    a.dedup_by(|x, y| (*x - *y).abs() < 1e-3);
    let mut pts: Vec<[f64; 2]> = a
        .iter()
        .map(|t| [c[0] + radius * t.cos(), c[1] + radius * t.sin()])
        .collect();
    if cw {
        pts.reverse();
    }
    pts
}

/// Distance from the origin to the nearest edge line of a convex polygon around it.
fn inradius(poly: &[[f64; 2]]) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            (a[0] * dy - a[1] * dx).abs() / (dx * dx + dy * dy).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

counted_proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn convex_annuli_tile_or_fail_with_a_reason(
        outer_angles in prop::collection::vec(0.0..std::f64::consts::TAU, 3..20),
        hole_angles in prop::collection::vec(0.0..std::f64::consts::TAU, 3..20),
        hole_scale in 0.05..0.9f64,
        offset in (0.0..1.0f64, 0.0..std::f64::consts::TAU),
        tilt in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
    ) {
        let outer = convex_polygon(&outer_angles, 3.0, [0.0, 0.0], false);
        prop_assume!(outer.len() >= 3);
        // The origin strictly inside: no angular gap of half a turn or more.
        let mut a = outer_angles.clone();
        a.sort_by(f64::total_cmp);
        let wrap = a[0] + std::f64::consts::TAU - a[a.len() - 1];
        let gaps = a.windows(2).map(|w| w[1] - w[0]).chain([wrap]);
        prop_assume!(gaps.fold(0.0, f64::max) < 0.9 * std::f64::consts::PI);
        let r_in = inradius(&outer);
        prop_assume!(r_in > 0.3);
        let rho = hole_scale * r_in;
        let room = (r_in - rho) * 0.95;
        let c = [room * offset.0 * offset.1.cos(), room * offset.0 * offset.1.sin()];
        let hole = convex_polygon(&hole_angles, rho, c, true);
        prop_assume!(hole.len() >= 3);
        let centred: Vec<[f64; 2]> = hole.iter().map(|p| [p[0] - c[0], p[1] - c[1]]).collect();
        prop_assume!(inradius(&centred) > 1e-3 * rho);
        // Place the plane in space.
        let n = DVec3::new(tilt.0, tilt.1, tilt.2 + 1.5).normalize();
        let u = n.any_orthonormal_vector();
        let w = n.cross(u);
        let origin = DVec3::new(tilt.2, -tilt.0, 2.0 * tilt.1);
        let mesh = face_mesh_3d(&[outer, hole], |q| origin + q[0] * u + q[1] * w);
        validate_faces_with_holes(&mesh).unwrap();
        match bridge_face(&mesh, FaceId(0)) {
            Ok(b) => {
                check_tiling(&mesh, FaceId(0), &b);
                let q = b.holes[0].bridge_count as usize;
                prop_assert_eq!(b.faces.len(), q);
                prop_assert!(b.face_point_vertices.iter().all(|c| c.len() == 3 || c.len() == 4));
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}

#[test]
fn split_faces_with_holes_keeps_geometry_and_adds_bridges() {
    use katachi::mesh::holes::split_faces_with_holes;
    let plate = katachi::mesh::shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    let (split, origin) = split_faces_with_holes(&plate).unwrap();
    assert!(split.faces().all(|f| split.face_loop_count(f) == 1));
    assert_eq!(
        split.face_count(),
        8 + 2 * 4,
        "each annulus becomes four trapezoids"
    );
    assert_eq!(origin.len(), split.face_count() as usize);
    assert_eq!(split.positions(), plate.positions());
    let r = katachi::mesh::inspect(&split).unwrap();
    assert_eq!(r.genus, Some(1));
    assert!(r.is_manifold());
}
