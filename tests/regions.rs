//! Planar-region extraction (`merge_coplanar_regions`, spec §7.5) and feature-angle sharp
//! edges (`feature_edges`, `tag_feature_edges`): boolean-like shapes built here with exact
//! expected counts, shared CAD models, determinism, attributes, bad input, and a property
//! test on random triangulated convex polygons.

use std::collections::BTreeSet;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

use katachi::mesh::{inspect, shapes, EdgeId, INFINITELY_SHARP};
use katachi::subdivide::features::{feature_edges, tag_feature_edges};
use katachi::subdivide::regions::{merge_coplanar_regions, MergeOptions, Merged};
use katachi::subdivide::{catmull_clark, SubdivideOptions};
use katachi::{DVec3, Error, FaceId, PolyMesh, VertexId};
use proptest::prelude::*;

mod support;
use support::models;
use support::property::counted_proptest;

// ---------------------------------------------------------------------------------------
// Building boolean-like meshes

/// How a planar polygon is cut into pieces, as booleans and exporters do.
#[derive(Clone, Copy, PartialEq)]
enum Cut {
    /// A fan of triangles from the first corner (convex polygons).
    Triangles,
    /// A fan of triangles around a new centre vertex.
    CentreFan,
}

struct Builder {
    positions: Vec<DVec3>,
    faces: Vec<Vec<u32>>,
}

impl Builder {
    fn new(positions: Vec<DVec3>) -> Self {
        Builder {
            positions,
            faces: Vec::new(),
        }
    }

    fn polygon(&mut self, poly: &[u32], cut: Cut) {
        match cut {
            Cut::Triangles => {
                for i in 1..poly.len() - 1 {
                    self.faces.push(vec![poly[0], poly[i], poly[i + 1]]);
                }
            }
            Cut::CentreFan => {
                let c = poly
                    .iter()
                    .map(|&v| self.positions[v as usize])
                    .sum::<DVec3>()
                    / poly.len() as f64;
                let ci = self.positions.len() as u32;
                self.positions.push(c);
                for i in 0..poly.len() {
                    self.faces
                        .push(vec![poly[i], poly[(i + 1) % poly.len()], ci]);
                }
            }
        }
    }

    fn build(self) -> PolyMesh {
        PolyMesh::from_polygons(self.positions, self.faces).unwrap()
    }
}

fn square(r: f64, z: f64) -> [DVec3; 4] {
    [(-r, -r), (r, -r), (r, r), (-r, r)].map(|(x, y)| DVec3::new(x, y, z))
}

/// The plate of `shapes::plate_with_hole(4, 2, 1).unwrap()` (same vertex ids 0..16) as a boolean
/// would give it: every planar face cut into triangles; the top and bottom annuli are cut
/// into four trapezoids, each triangulated (`Cut::Triangles`) or fanned around a centre
/// (`Cut::CentreFan`, adding 8 vertices).
fn boolean_plate(annulus: Cut) -> PolyMesh {
    let mut p = Vec::new();
    p.extend(square(2.0, 0.0)); // 0..4 outer bottom
    p.extend(square(2.0, 1.0)); // 4..8 outer top
    p.extend(square(1.0, 0.0)); // 8..12 inner bottom
    p.extend(square(1.0, 1.0)); // 12..16 inner top
    let mut b = Builder::new(p);
    for i in 0..4u32 {
        let j = (i + 1) % 4;
        // Top annulus (seen from +z) and bottom annulus (seen from -z).
        b.polygon(&[4 + i, 4 + j, 12 + j, 12 + i], annulus);
        b.polygon(&[j, i, 8 + i, 8 + j], annulus);
        // Outer wall and hole wall, two triangles each.
        b.polygon(&[i, j, 4 + j, 4 + i], Cut::Triangles);
        b.polygon(&[8 + j, 8 + i, 12 + i, 12 + j], Cut::Triangles);
    }
    b.build()
}

/// The union of a 4 × 4 × 1 box and a 2 × 2 × 1 boss standing on the middle of its top,
/// triangulated as a boolean gives it: 16 vertices, 0..8 the box, 8..12 the boss footprint,
/// 12..16 the boss top.
fn boolean_box_with_boss() -> PolyMesh {
    let mut p = Vec::new();
    p.extend(square(2.0, 0.0));
    p.extend(square(2.0, 1.0));
    p.extend(square(1.0, 1.0));
    p.extend(square(1.0, 2.0));
    let mut b = Builder::new(p);
    b.polygon(&[3, 2, 1, 0], Cut::Triangles);
    b.polygon(&[12, 13, 14, 15], Cut::Triangles);
    for i in 0..4u32 {
        let j = (i + 1) % 4;
        b.polygon(&[i, j, 4 + j, 4 + i], Cut::Triangles); // box wall
        b.polygon(&[4 + i, 4 + j, 8 + j, 8 + i], Cut::Triangles); // box top around the boss
        b.polygon(&[8 + i, 8 + j, 12 + j, 12 + i], Cut::Triangles); // boss wall
    }
    b.build()
}

fn loops_of(mesh: &PolyMesh, f: FaceId) -> Vec<Vec<u32>> {
    mesh.face_loops(f)
        .map(|l| mesh.loop_vertices(l).iter().map(|v| v.0).collect())
        .collect()
}

/// Signed area of a loop seen from `normal`.
fn signed_area(mesh: &PolyMesh, lp: &[u32], normal: DVec3) -> f64 {
    let mut a = DVec3::ZERO;
    for i in 0..lp.len() {
        let p = mesh.position(VertexId(lp[i]));
        let q = mesh.position(VertexId(lp[(i + 1) % lp.len()]));
        a += p.cross(q);
    }
    0.5 * a.dot(normal)
}

fn merge(mesh: &PolyMesh) -> Merged {
    merge_coplanar_regions(mesh, &MergeOptions::default()).unwrap()
}

/// The output face holding input face `f`.
fn face_of(m: &Merged, f: u32) -> FaceId {
    m.face_map[f as usize]
}

fn read_model(name: &str) -> PolyMesh {
    models::read_bundled(name)
}

fn diagonal(mesh: &PolyMesh) -> f64 {
    let (lo, hi) = mesh.bounding_box().unwrap();
    (hi - lo).length()
}

/// The largest distance of a face's vertices from its own best plane (unit Newell normal
/// through the mean of its vertices).
fn planarity(mesh: &PolyMesh, f: FaceId) -> f64 {
    let vs: Vec<DVec3> = mesh
        .face_loops(f)
        .flat_map(|l| mesh.loop_vertices(l).iter().map(|&v| mesh.position(v)))
        .collect();
    let c = vs.iter().sum::<DVec3>() / vs.len() as f64;
    let mut n = DVec3::ZERO;
    for l in mesh.face_loops(f) {
        let lp = mesh.loop_vertices(l);
        for i in 0..lp.len() {
            let p = mesh.position(lp[i]) - c;
            let q = mesh.position(lp[(i + 1) % lp.len()]) - c;
            n += p.cross(q);
        }
    }
    let n = n.normalize();
    vs.iter().map(|&p| (p - c).dot(n).abs()).fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------------------
// Boolean reconstruction (issue 3)

#[test]
fn triangulated_plate_with_through_hole_comes_back_as_faces_with_holes() {
    let plate = boolean_plate(Cut::Triangles);
    assert_eq!(plate.face_count(), 32);
    let m = merge(&plate);
    let r = inspect(&m.mesh).unwrap();
    assert_eq!(r.faces, 10);
    assert_eq!(r.vertices, 16);
    assert_eq!(r.edges, 24);
    assert_eq!(r.faces_with_holes, 2);
    assert_eq!(r.faces_by_size.get(&4), Some(&10));
    assert_eq!(r.genus, Some(1));
    assert!(r.is_manifold());
    assert!(m.pinched_vertices.is_empty());
    // Nothing removed: every vertex is a corner of some face.
    assert!(m
        .vertex_map
        .iter()
        .enumerate()
        .all(|(i, v)| *v == Some(VertexId(i as u32))));
    // Top (input face 0 is a top triangle): outer loop CCW from +z starting at its lowest
    // vertex, the hole CW, as in shapes::plate_with_hole.
    let top = face_of(&m, 0);
    assert_eq!(
        loops_of(&m.mesh, top),
        vec![vec![4, 5, 6, 7], vec![12, 15, 14, 13]]
    );
    assert!(signed_area(&m.mesh, &[4, 5, 6, 7], DVec3::Z) > 0.0);
    assert!(signed_area(&m.mesh, &[12, 15, 14, 13], DVec3::Z) < 0.0);
    let bottom = face_of(&m, 2);
    assert_eq!(
        loops_of(&m.mesh, bottom),
        vec![vec![0, 3, 2, 1], vec![8, 9, 10, 11]]
    );
    assert_eq!(m.face_origin[top.idx()].len(), 8);
    // Walls are quads made of two triangles.
    let walls: Vec<_> = m
        .mesh
        .faces()
        .filter(|&f| m.mesh.face_loop_count(f) == 1)
        .collect();
    assert_eq!(walls.len(), 8);
    assert!(walls.iter().all(|&f| m.face_origin[f.idx()].len() == 2));
    // Same surface as the hand-made plate with hole: same edge set.
    let edges = |mesh: &PolyMesh| {
        let t = mesh.connectivity().unwrap();
        (0..t.edge_count())
            .map(|e| {
                let [a, b] = t.edge_vertices(EdgeId(e));
                (a.min(b), a.max(b))
            })
            .collect::<BTreeSet<_>>()
    };
    assert_eq!(
        edges(&m.mesh),
        edges(&shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap())
    );
    // The maps agree with each other.
    for (out, srcs) in m.face_origin.iter().enumerate() {
        for s in srcs {
            assert_eq!(m.face_map[s.idx()], FaceId(out as u32));
        }
    }
}

#[test]
fn box_with_boss_top_face_gets_the_footprint_as_c_loop() {
    let mesh = boolean_box_with_boss();
    let m = merge(&mesh);
    let r = inspect(&m.mesh).unwrap();
    assert_eq!(r.faces, 11);
    assert_eq!(r.vertices, 16);
    assert_eq!(r.faces_with_holes, 1);
    assert_eq!(r.genus, Some(0));
    // Find the box top through an input triangle of it (faces 4..6 + 6k are box-top pieces).
    let top_piece = (0..mesh.face_count())
        .find(|&f| {
            let vs = mesh.face_outer(FaceId(f));
            vs.iter().all(|v| (4..12).contains(&v.0)) && vs.iter().any(|v| v.0 < 8)
        })
        .unwrap();
    let top = face_of(&m, top_piece);
    let loops = loops_of(&m.mesh, top);
    assert_eq!(loops, vec![vec![4, 5, 6, 7], vec![8, 11, 10, 9]]);
    assert!(signed_area(&m.mesh, &loops[0], DVec3::Z) > 0.0);
    assert!(signed_area(&m.mesh, &loops[1], DVec3::Z) < 0.0);
    assert_eq!(m.face_origin[top.idx()].len(), 8);
    // The boss top is a quad again.
    let boss_top = face_of(&m, 2);
    assert_eq!(loops_of(&m.mesh, boss_top), vec![vec![12, 13, 14, 15]]);
}

#[test]
fn centre_fans_lose_their_centres() {
    let plate = boolean_plate(Cut::CentreFan);
    assert_eq!(plate.vertex_count(), 24);
    assert_eq!(plate.face_count(), 8 * 4 + 16);
    let m = merge(&plate);
    let r = inspect(&m.mesh).unwrap();
    assert_eq!((r.faces, r.vertices, r.faces_with_holes), (10, 16, 2));
    assert_eq!(r.genus, Some(1));
    assert_eq!(r.unreferenced_vertices, 0);
    // The 16 plate vertices keep their ids; the 8 centres are gone.
    for v in 0..16 {
        assert_eq!(m.vertex_map[v], Some(VertexId(v as u32)));
    }
    assert!(m.vertex_map[16..].iter().all(Option::is_none));
    assert_eq!(m.vertex_origin(), (0..16).map(VertexId).collect::<Vec<_>>());
    // Same mesh as from the triangulated plate, faces aside from their order.
    let a = merge(&boolean_plate(Cut::Triangles)).mesh;
    let faces = |mesh: &PolyMesh| {
        mesh.faces()
            .map(|f| loops_of(mesh, f))
            .collect::<BTreeSet<_>>()
    };
    assert_eq!(faces(&a), faces(&m.mesh));
}

#[test]
fn collinear_t_junction_vertices_are_kept() {
    // A 4 × 4 × 1 box whose x = +2 wall is two quads (a vertical seam at y = 0, vertices 8
    // and 9); top and bottom include the seam vertices as collinear corners.
    let mut p = Vec::new();
    p.extend(square(2.0, 0.0));
    p.extend(square(2.0, 1.0));
    p.push(DVec3::new(2.0, 0.0, 0.0)); // 8, on edge 1-2
    p.push(DVec3::new(2.0, 0.0, 1.0)); // 9, on edge 5-6
    let mut b = Builder::new(p);
    b.polygon(&[0, 3, 2, 8, 1], Cut::Triangles); // bottom, seen from -z
    b.polygon(&[4, 5, 9, 6, 7], Cut::Triangles); // top
    b.polygon(&[1, 8, 9, 5], Cut::Triangles); // x = +2, lower half in y
    b.polygon(&[8, 2, 6, 9], Cut::Triangles); // x = +2, upper half in y
    for (i, j) in [(0, 1), (2, 3), (3, 0)] {
        b.polygon(&[i, j, 4 + j, 4 + i], Cut::Triangles);
    }
    let mesh = b.build();
    let m = merge(&mesh);
    let r = inspect(&m.mesh).unwrap();
    assert_eq!((r.faces, r.vertices), (6, 10));
    assert_eq!(r.genus, Some(0));
    assert_eq!(
        r.faces_by_size,
        [(4, 3), (5, 2), (6, 1)].into_iter().collect()
    );
    let top = face_of(&m, 3);
    assert_eq!(loops_of(&m.mesh, top), vec![vec![4, 5, 9, 6, 7]]);
    let wall = face_of(&m, 6);
    assert_eq!(loops_of(&m.mesh, wall), vec![vec![1, 8, 2, 6, 9, 5]]);
}

/// Unit squares (x, y) of a flat 3 × 3 grid, each two triangles; squares (1, 1) and (0, 2)
/// get label 1 (`with_notches`) or are left out. Either way the label-0 ring touches itself
/// at vertex (1, 2) = 9, so one merged face would visit that vertex twice.
fn pinched_ring(with_notches: bool) -> PolyMesh {
    let id = |x: u32, y: u32| y * 4 + x;
    let p = (0..4)
        .flat_map(|y| (0..4).map(move |x| DVec3::new(x as f64, y as f64, 0.0)))
        .collect();
    let mut b = Builder::new(p);
    let mut labels = Vec::new();
    for y in 0..3 {
        for x in 0..3 {
            let notch = (x, y) == (1, 1) || (x, y) == (0, 2);
            if notch && !with_notches {
                continue;
            }
            b.polygon(
                &[id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)],
                Cut::Triangles,
            );
            labels.extend([u32::from(notch); 2]);
        }
    }
    let mut mesh = b.build();
    mesh.set_face_labels(labels).unwrap();
    mesh
}

#[test]
fn region_touching_itself_at_a_vertex_is_split_not_refused() {
    for with_notches in [true, false] {
        let mesh = pinched_ring(with_notches);
        let m = merge(&mesh);
        assert_eq!(m.pinched_vertices, vec![VertexId(9)], "{with_notches}");
        let r = inspect(&m.mesh).unwrap();
        let r0 = inspect(&mesh).unwrap();
        // With the notches the surface is a manifold disk; without, vertex 9 is a
        // non-manifold vertex of the input already, and stays one.
        assert_eq!(r0.is_manifold(), with_notches);
        assert_eq!(r.defects, r0.defects);
        assert_eq!(r.euler_characteristic, r0.euler_characteristic);
        assert_eq!(r.boundary_edges, r0.boundary_edges);
        // Merged into a few faces, none visiting vertex 9 twice (PolyMesh would refuse it),
        // every outer loop counter-clockwise, and the area kept.
        let ring: Vec<FaceId> = m
            .mesh
            .faces()
            .filter(|&f| m.mesh.face_label(f) == 0)
            .collect();
        assert!(
            ring.len() >= 2 && ring.len() <= 4,
            "{with_notches}: {}",
            ring.len()
        );
        let mut area = 0.0;
        for &f in &ring {
            let lp = loops_of(&m.mesh, f);
            assert!(signed_area(&m.mesh, &lp[0], DVec3::Z) > 0.0);
            area += lp
                .iter()
                .map(|l| signed_area(&m.mesh, l, DVec3::Z))
                .sum::<f64>();
        }
        assert!((area - 7.0).abs() < 1e-12, "{area}");
        // The wedge of the lowest face keeps the region; only faces at vertex 9 leave it.
        let main = face_of(&m, 0);
        assert!(m.face_origin[main.idx()].len() >= 10);
        for &f in &ring {
            if f != main {
                assert!(m.face_origin[f.idx()]
                    .iter()
                    .all(|&g| mesh.face_outer(g).contains(&VertexId(9))));
            }
        }
        assert_eq!(merge(&mesh), m);
    }
}

#[test]
fn zero_area_faces_join_by_distance() {
    // Square A B C D over a pentagon E F B M A, with a zero-area triangle B A M between
    // them (M on A B): all in z = 0, so one face; M is inside it and goes.
    let p = vec![
        DVec3::new(-1.0, 0.0, 0.0),  // 0 A
        DVec3::new(1.0, 0.0, 0.0),   // 1 B
        DVec3::new(1.0, 1.0, 0.0),   // 2 C
        DVec3::new(-1.0, 1.0, 0.0),  // 3 D
        DVec3::new(-1.0, -1.0, 0.0), // 4 E
        DVec3::new(1.0, -1.0, 0.0),  // 5 F
        DVec3::new(0.0, 0.0, 0.0),   // 6 M
    ];
    let faces: Vec<Vec<u32>> = vec![vec![1, 0, 6], vec![0, 1, 2, 3], vec![4, 5, 1, 6, 0]];
    let mesh = PolyMesh::from_polygons(p, faces).unwrap();
    let m = merge(&mesh);
    assert_eq!(m.mesh.face_count(), 1);
    assert_eq!(loops_of(&m.mesh, FaceId(0)), vec![vec![0, 4, 5, 1, 2, 3]]);
    assert_eq!(m.vertex_map[6], None);
    // Alone, a zero-area face is kept as it is.
    let lone =
        PolyMesh::from_polygons(vec![DVec3::ZERO, DVec3::X, 2.0 * DVec3::X], [[0, 1, 2]]).unwrap();
    assert_eq!(merge(&lone).mesh, lone);
}

#[test]
fn faces_with_holes_in_the_input_merge_too() {
    // A face with a hole (square 2 with a square-1 hole) inside a ring of four trapezoids
    // out to square 3, all in z = 0: one face, outer square 3, the hole kept, the square-2
    // vertices gone.
    let mut p = Vec::new();
    p.extend(square(1.0, 0.0)); // 0..4 hole
    p.extend(square(2.0, 0.0)); // 4..8
    p.extend(square(3.0, 0.0)); // 8..12
    let mut faces: Vec<Vec<Vec<u32>>> = vec![vec![vec![4, 5, 6, 7], vec![3, 2, 1, 0]]];
    for i in 0..4u32 {
        let j = (i + 1) % 4;
        faces.push(vec![vec![8 + i, 8 + j, 4 + j, 4 + i]]);
    }
    let mesh = PolyMesh::from_faces_with_holes(p, faces).unwrap();
    let m = merge(&mesh);
    assert_eq!(m.mesh.face_count(), 1);
    // New ids: the hole keeps 0..4, the outer square becomes 4..8.
    assert_eq!(
        loops_of(&m.mesh, FaceId(0)),
        vec![vec![4, 5, 6, 7], vec![0, 3, 2, 1]]
    );
    assert_eq!(m.mesh.vertex_count(), 8);
    assert!(m.vertex_map[4..8].iter().all(Option::is_none));
}

#[test]
fn f32_rounded_rotated_plate_still_merges() {
    // Blender hands meshes over in f32: rotate the triangulated plate off the axes, move it
    // away from the origin and round every coordinate to f32.
    let plate = boolean_plate(Cut::Triangles);
    let positions: Vec<DVec3> = plate
        .positions()
        .iter()
        .map(|&p| {
            let q = place(p, 0.7, 2.1, DVec3::new(3.0, -5.0, 2.0));
            DVec3::new(q.x as f32 as f64, q.y as f32 as f64, q.z as f32 as f64)
        })
        .collect();
    let faces: Vec<Vec<u32>> = plate
        .faces()
        .map(|f| plate.face_outer(f).iter().map(|v| v.0).collect())
        .collect();
    let rounded = PolyMesh::from_polygons(positions, faces).unwrap();
    let m = merge(&rounded);
    let r = inspect(&m.mesh).unwrap();
    assert_eq!((r.faces, r.vertices, r.faces_with_holes), (10, 16, 2));
    assert_eq!(r.genus, Some(1));
}

#[test]
fn faces_with_different_labels_stay_apart() {
    let mut grid = shapes::grid(3, 2).unwrap();
    let mut labels = vec![0; 6];
    labels[5] = 7;
    grid.set_face_labels(labels).unwrap();
    let m = merge(&grid);
    assert_eq!(m.mesh.face_count(), 2);
    assert_eq!(m.mesh.face_labels(), &[0, 7]);
    let mut opts = MergeOptions::default();
    opts.respect_face_labels = false;
    let m = merge_coplanar_regions(&grid, &opts).unwrap();
    assert_eq!(m.mesh.face_count(), 1);
}

#[test]
fn merging_twice_changes_nothing() {
    for mesh in [boolean_plate(Cut::Triangles), boolean_box_with_boss()] {
        let once = merge(&mesh);
        let twice = merge(&once.mesh);
        assert_eq!(twice.mesh, once.mesh);
        assert!(twice.face_origin.iter().all(|o| o.len() == 1));
    }
    // Already-merged shapes: nothing to do.
    for mesh in [
        shapes::cube(1.0).unwrap(),
        shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap(),
    ] {
        assert_eq!(merge(&mesh).mesh, mesh);
    }
}

#[test]
fn sharpness_survives_on_surviving_edges() {
    let mut plate = boolean_plate(Cut::Triangles);
    let v = VertexId;
    plate
        .set_edge_sharpnesses([
            (v(0), v(4), INFINITELY_SHARP), // outer vertical corner edge
            (v(5), v(4), 2.5),              // top outer edge
            (v(0), v(5), 1.0),              // diagonal inside outer wall 0: goes away
        ])
        .unwrap();
    plate.set_vertex_sharpness(v(5), 3.0).unwrap();
    let m = merge(&plate);
    let sharp: Vec<_> = m.mesh.sharp_edges().collect();
    assert_eq!(
        sharp,
        vec![(v(0), v(4), INFINITELY_SHARP), (v(4), v(5), 2.5)]
    );
    assert_eq!(m.dropped_sharp_edges, vec![(v(0), v(5), 1.0)]);
    assert_eq!(m.mesh.vertex_sharpness()[5], 3.0);
    // With centre fans the vertices move ids only after the centres, which go: same result.
    let mut fan = boolean_plate(Cut::CentreFan);
    fan.set_edge_sharpness(v(12), v(13), 4.0).unwrap();
    let m = merge(&fan);
    assert_eq!(
        m.mesh.sharp_edges().collect::<Vec<_>>(),
        vec![(v(12), v(13), 4.0)]
    );
}

#[test]
fn bad_input_is_typed() {
    // (That the input is left unchanged needs no test: the merge takes `&PolyMesh`.)
    let plate = boolean_plate(Cut::Triangles);
    for (angle, dist) in [
        (-1e-3, 1e-6),
        (f64::NAN, 1e-6),
        (FRAC_PI_2, 1e-6),
        (1e-3, -1.0),
        (1e-3, f64::INFINITY),
        (1e-3, f64::NAN),
    ] {
        let e = merge_coplanar_regions(&plate, &MergeOptions::with_tolerances(angle, dist));
        assert!(
            matches!(e, Err(Error::InvalidOption { .. })),
            "{angle} {dist}: {e:?}"
        );
    }
    assert!(matches!(
        merge_coplanar_regions(&PolyMesh::new(), &MergeOptions::default()),
        Err(Error::EmptyMesh { .. })
    ));
    // Three triangles on one edge; two faces running the same way along an edge.
    let p = vec![
        DVec3::ZERO,
        DVec3::X,
        DVec3::Y,
        DVec3::new(0.5, -1.0, 0.0),
        DVec3::new(0.5, 0.0, 1.0),
    ];
    let fin = PolyMesh::from_polygons(p.clone(), [[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
    let e = merge_coplanar_regions(&fin, &MergeOptions::default()).unwrap_err();
    assert!(
        matches!(
            e,
            Error::NonManifoldEdge {
                a: 0,
                b: 1,
                uses: 3
            }
        ),
        "{e}"
    );
    let flipped = PolyMesh::from_polygons(p, [[0, 1, 2], [0, 1, 3]]).unwrap();
    let e = merge_coplanar_regions(&flipped, &MergeOptions::default()).unwrap_err();
    assert!(matches!(e, Error::InconsistentOrientation { .. }), "{e}");
    assert!(matches!(
        feature_edges(&fin, 30.0),
        Err(Error::NonManifoldEdge { .. })
    ));
}

#[test]
fn isolated_input_vertices_are_kept() {
    let mut p = shapes::grid(2, 1).unwrap().positions().to_vec();
    p.push(DVec3::new(9.0, 9.0, 9.0)); // 6, used by no face
    let mesh = PolyMesh::from_polygons(p, [[0, 1, 4, 3], [1, 2, 5, 4]]).unwrap();
    let m = merge(&mesh);
    assert_eq!(m.mesh.face_count(), 1);
    assert_eq!(loops_of(&m.mesh, FaceId(0)), vec![vec![0, 1, 2, 5, 4, 3]]);
    assert_eq!(m.mesh.vertex_count(), 7);
    assert_eq!(m.vertex_map[6], Some(VertexId(6)));
}

// ---------------------------------------------------------------------------------------
// Shared models

#[test]
fn fandisk_merges_into_far_fewer_planar_faces() {
    let mesh = read_model("fandisk.off");
    let m = merge(&mesh);
    let (nin, nout) = (mesh.face_count(), m.mesh.face_count());
    // Flat sides of thousands of triangles become single faces, and the two triangles of
    // each planar quad of the ruled (cylindrical) parts become one quad.
    assert!(nout * 2 < nin, "{nin} faces became {nout}");
    assert!(m.face_origin.iter().any(|o| o.len() > 1000));
    let tol = MergeOptions::default().distance_tolerance * diagonal(&mesh);
    let mut merged = 0;
    for f in m.mesh.faces() {
        if m.face_origin[f.idx()].len() > 1 {
            merged += 1;
            let d = planarity(&m.mesh, f);
            assert!(
                d <= 2.0 * tol,
                "face {f}: {d} from its plane (tolerance {tol})"
            );
        }
    }
    assert!(merged >= 10, "{merged} merged faces");
    let r = inspect(&m.mesh).unwrap();
    let r0 = inspect(&mesh).unwrap();
    assert!(r.is_manifold() && r.is_closed());
    assert_eq!(r.genus, r0.genus);
    // Determinism: the same bits every run.
    assert_eq!(merge(&mesh), m);
}

#[test]
fn curved_models_merge_nothing_at_a_tiny_tolerance() {
    let tiny = MergeOptions::with_tolerances(1e-9, 1e-12);
    for (name, mesh) in [
        ("trim-star", read_model("trim-star.off")),
        ("torus", shapes::torus(48, 24, 2.0, 0.5).unwrap()),
    ] {
        let m = merge_coplanar_regions(&mesh, &tiny).unwrap();
        assert_eq!(m.mesh, mesh, "{name}");
        assert!(m.face_origin.iter().all(|o| o.len() == 1), "{name}");
    }
    // And the default tolerances do not flatten a smooth torus either.
    let torus = shapes::torus(48, 24, 2.0, 0.5).unwrap();
    assert_eq!(merge(&torus).mesh, torus);
}

// ---------------------------------------------------------------------------------------
// Feature angle

/// Edges with a dihedral angle above `deg`, counted here from the topology and the faces'
/// Newell normals, independently of the library's code.
fn count_dihedral_above(mesh: &PolyMesh, deg: f64) -> usize {
    let topo = mesh.connectivity().unwrap();
    let normal = |f: FaceId| {
        let lp = mesh.face_outer(f);
        let mut n = DVec3::ZERO;
        for i in 0..lp.len() {
            n += mesh
                .position(lp[i])
                .cross(mesh.position(lp[(i + 1) % lp.len()]));
        }
        n.normalize()
    };
    (0..topo.edge_count())
        .filter(|&e| {
            let [h, t] = topo.edge_halfedges(EdgeId(e));
            if topo.is_boundary(h) || topo.is_boundary(t) {
                return false;
            }
            let c = normal(topo.face(h))
                .dot(normal(topo.face(t)))
                .clamp(-1.0, 1.0);
            c.acos().to_degrees() > deg
        })
        .count()
}

#[test]
fn fandisk_feature_edges_match_an_independent_count() {
    let mesh = read_model("fandisk.off");
    for deg in [20.0, 30.0, 45.0] {
        let edges = feature_edges(&mesh, deg).unwrap();
        assert_eq!(edges.len(), count_dihedral_above(&mesh, deg), "{deg}°");
        assert!(
            edges.len() > 100 && edges.len() < 2000,
            "{deg}°: {}",
            edges.len()
        );
        assert!(edges.windows(2).all(|w| w[0] < w[1]));
        assert!(edges.iter().all(|(a, b)| a < b));
    }
    let tagged = tag_feature_edges(&mesh, 30.0).unwrap();
    let edges = feature_edges(&mesh, 30.0).unwrap();
    assert_eq!(tagged.sharp_edges().len(), edges.len());
    assert!(tagged
        .sharp_edges()
        .zip(&edges)
        .all(|((a, b, s), &(x, y))| (a, b) == (x, y) && s == INFINITELY_SHARP));
    // Everything else is the input's.
    let mut plain = tagged.clone();
    plain.clear_edge_sharpness();
    assert_eq!(plain, mesh);
}

#[test]
fn cube_edges_are_all_features_at_30_degrees() {
    let cube = shapes::cube(2.0).unwrap();
    assert_eq!(feature_edges(&cube, 30.0).unwrap().len(), 12);
    assert_eq!(feature_edges(&cube, 89.0).unwrap().len(), 12);
    assert_eq!(feature_edges(&cube, 91.0).unwrap().len(), 0);
    let tagged = tag_feature_edges(&cube, 30.0).unwrap();
    assert_eq!(inspect(&tagged).unwrap().sharp_edges, 12);
    // A value above INFINITELY_SHARP stays; a smaller one is raised.
    let mut cube = shapes::cube(2.0).unwrap();
    cube.set_edge_sharpness(VertexId(0), VertexId(1), 12.0)
        .unwrap();
    cube.set_edge_sharpness(VertexId(0), VertexId(2), 0.5)
        .unwrap();
    let tagged = tag_feature_edges(&cube, 30.0).unwrap();
    assert_eq!(tagged.edge_sharpness(VertexId(1), VertexId(0)), 12.0);
    assert_eq!(
        tagged.edge_sharpness(VertexId(2), VertexId(0)),
        INFINITELY_SHARP
    );
}

#[test]
fn smooth_torus_has_no_features_at_60_degrees() {
    let torus = shapes::torus(12, 8, 2.0, 0.5).unwrap();
    let smooth = catmull_clark(&torus, &SubdivideOptions::with_levels(2))
        .unwrap()
        .mesh;
    assert!(feature_edges(&smooth, 60.0).unwrap().is_empty());
    assert_eq!(tag_feature_edges(&smooth, 60.0).unwrap(), smooth);
}

#[test]
fn boundary_edges_are_not_features() {
    // An open box (no lid): the rim is boundary, the 8 other edges fold at 90°.
    let cube = shapes::cube(2.0).unwrap();
    let faces: Vec<Vec<u32>> = cube
        .faces()
        .filter(|&f| f.0 != 1)
        .map(|f| cube.face_outer(f).iter().map(|v| v.0).collect())
        .collect();
    let open = PolyMesh::from_polygons(cube.positions().to_vec(), faces).unwrap();
    assert_eq!(feature_edges(&open, 30.0).unwrap().len(), 8);
    // A flat grid has none.
    assert!(feature_edges(&shapes::grid(3, 3).unwrap(), 1.0)
        .unwrap()
        .is_empty());
}

#[test]
fn bad_feature_angle_is_an_invalid_option() {
    let cube = shapes::cube(1.0).unwrap();
    for deg in [0.0, 180.0, -10.0, 200.0, f64::NAN, f64::INFINITY] {
        assert!(
            matches!(feature_edges(&cube, deg), Err(Error::InvalidOption { .. })),
            "{deg}"
        );
        assert!(matches!(
            tag_feature_edges(&cube, deg),
            Err(Error::InvalidOption { .. })
        ));
    }
    assert!(matches!(
        feature_edges(&PolyMesh::new(), 30.0),
        Err(Error::EmptyMesh { .. })
    ));
}

// ---------------------------------------------------------------------------------------
// Property test: random triangulated convex polygons merge back into their outline

/// A rotation taking +z to the direction (theta, phi), then a translation.
fn place(p: DVec3, theta: f64, phi: f64, shift: DVec3) -> DVec3 {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    // Rotate about y by theta, then about z by phi.
    let q = DVec3::new(ct * p.x + st * p.z, p.y, -st * p.x + ct * p.z);
    DVec3::new(cp * q.x - sp * q.y, sp * q.x + cp * q.y, q.z) + shift
}

counted_proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_convex_polygon_merges_into_its_outline(
        gaps in proptest::collection::vec(0.05f64..1.0, 3..40),
        radius in 0.01f64..100.0,
        theta in 0.0f64..PI,
        phi in 0.0f64..TAU,
        shift in proptest::array::uniform3(-1e3f64..1e3),
        centre_fan in any::<bool>(),
    ) {
        let n = gaps.len() as u32;
        let total: f64 = gaps.iter().sum();
        let mut acc = 0.0;
        let mut positions = Vec::new();
        for g in &gaps {
            let t = TAU * acc / total;
            acc += g;
            let p = DVec3::new(radius * t.cos(), radius * t.sin(), 0.0);
            positions.push(place(p, theta, phi, DVec3::from_array(shift)));
        }
        let mut b = Builder::new(positions);
        let outline: Vec<u32> = (0..n).collect();
        b.polygon(&outline, if centre_fan { Cut::CentreFan } else { Cut::Triangles });
        let mesh = b.build();
        let m = merge(&mesh);
        prop_assert_eq!(m.mesh.face_count(), 1);
        prop_assert_eq!(loops_of(&m.mesh, FaceId(0)), vec![outline]);
        prop_assert_eq!(m.mesh.vertex_count(), n);
        prop_assert_eq!(m.face_origin[0].len() as u32, mesh.face_count());
        prop_assert!(m.mesh.positions() == &mesh.positions()[..n as usize]);
    }
}
