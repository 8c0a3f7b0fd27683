//! Generated shapes with exact expected counts, and their refusal of bad parameters (mesh
//! module); the empty mesh.

use katachi::mesh::{inspect, shapes, Topology, TopologyOptions};
use katachi::{PolyMesh, VertexId};

mod support;

struct Expect {
    v: u32,
    f: u32,
    e: u32,
    boundary_loops: u32,
    euler: i64,
    genus: Option<i64>,
}

fn check(mesh: &PolyMesh, x: Expect) {
    let topo = mesh.connectivity().expect("valid shape");
    assert_eq!(mesh.vertex_count(), x.v, "vertices");
    assert_eq!(mesh.face_count(), x.f, "faces");
    assert_eq!(topo.edge_count(), x.e, "edges");
    assert_eq!(
        topo.boundary_loops().len() as u32,
        x.boundary_loops,
        "boundary loops"
    );
    assert_eq!(
        topo.euler_characteristic(mesh),
        x.euler,
        "Euler characteristic"
    );
    let r = inspect(mesh).unwrap();
    assert_eq!(r.genus, x.genus, "genus");
    assert!(r.is_manifold(), "{:?}", r.defects);
    assert_eq!(r.components, 1);
    // Every half-edge: next/prev inverse, twin involution, from(next) == to.
    for h in 0..topo.halfedge_count() {
        let h = katachi::HalfedgeId(h);
        assert_eq!(topo.prev(topo.next(h)), h);
        assert_eq!(topo.twin(topo.twin(h)), h);
        assert_eq!(topo.from(topo.next(h)), topo.to(h));
    }
}

#[test]
fn cube_counts() {
    check(
        &shapes::cube(2.0).unwrap(),
        Expect {
            v: 8,
            f: 6,
            e: 12,
            boundary_loops: 0,
            euler: 2,
            genus: Some(0),
        },
    );
    let c = shapes::cube(2.0).unwrap();
    let t = c.connectivity().unwrap();
    for v in c.vertices() {
        assert_eq!(t.valence(v), 3);
        assert_eq!(t.one_ring(v).count(), 3);
    }
}

#[test]
fn prism_counts() {
    for n in [3, 5, 8, 17] {
        check(
            &shapes::ngon_prism(n, 1.0, 1.0).unwrap(),
            Expect {
                v: 2 * n,
                f: n + 2,
                e: 3 * n,
                boundary_loops: 0,
                euler: 2,
                genus: Some(0),
            },
        );
    }
}

#[test]
fn torus_counts() {
    check(
        &shapes::torus(12, 8, 2.0, 0.5).unwrap(),
        Expect {
            v: 96,
            f: 96,
            e: 192,
            boundary_loops: 0,
            euler: 0,
            genus: Some(1),
        },
    );
    let t = shapes::torus(12, 8, 2.0, 0.5).unwrap();
    let topo = t.connectivity().unwrap();
    assert!(t.vertices().all(|v| topo.valence(v) == 4));
}

#[test]
fn open_grid_counts() {
    let g = shapes::grid(4, 3).unwrap();
    check(
        &g,
        Expect {
            v: 20,
            f: 12,
            e: 31,
            boundary_loops: 1,
            euler: 1,
            genus: None,
        },
    );
    let topo = g.connectivity().unwrap();
    let loops = topo.boundary_loops();
    assert_eq!(loops[0].len(), 14);
    assert_eq!(topo.valence(VertexId(0)), 2);
    assert!(topo.is_boundary_vertex(VertexId(0)));
    assert!(!topo.is_boundary_vertex(VertexId(6)));
    assert_eq!(topo.valence(VertexId(6)), 4);
}

#[test]
fn plate_with_hole_counts() {
    let p = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    check(
        &p,
        Expect {
            v: 16,
            f: 10,
            e: 24,
            boundary_loops: 0,
            euler: 0,
            genus: Some(1),
        },
    );
    assert_eq!(p.face_loop_count(katachi::FaceId(0)), 2);
    assert_eq!(inspect(&p).unwrap().faces_with_holes, 2);
}

#[test]
fn the_default_mesh_is_the_valid_empty_mesh() {
    let m = PolyMesh::default();
    assert_eq!(m, PolyMesh::new());
    assert_eq!(
        (
            m.vertex_count(),
            m.face_count(),
            m.loop_count(),
            m.corner_count()
        ),
        (0, 0, 0, 0)
    );
    assert!(m.is_empty());
    assert_eq!(m.faces().count(), 0);
    assert_eq!(m.bounding_box(), None);
    let rebuilt = PolyMesh::from_flat(&[], &[], &[], &[]).unwrap();
    assert_eq!(m, rebuilt);
    // An operation refuses it with a typed error, not a panic.
    let e = katachi::subdivide::catmull_clark(&m, &Default::default()).unwrap_err();
    assert!(matches!(e, katachi::Error::EmptyMesh { .. }), "{e}");
}

#[test]
fn shapes_refuse_bad_parameters_naming_them() {
    use katachi::Error;
    let cases: Vec<(&str, Result<PolyMesh, Error>, &str)> = vec![
        ("cube(0)", shapes::cube(0.0), "size is 0"),
        ("cube(NaN)", shapes::cube(f64::NAN), "size is NaN"),
        ("cube(-1)", shapes::cube(-1.0), "size is -1"),
        ("prism n = 2", shapes::ngon_prism(2, 1.0, 1.0), "n is 2"),
        (
            "prism huge n",
            shapes::ngon_prism(u32::MAX, 1.0, 1.0),
            "32-bit",
        ),
        (
            "prism radius inf",
            shapes::ngon_prism(5, f64::INFINITY, 1.0),
            "radius is inf",
        ),
        (
            "prism height 0",
            shapes::ngon_prism(5, 1.0, 0.0),
            "height is 0",
        ),
        ("torus m = 2", shapes::torus(2, 8, 2.0, 0.5), "m is 2"),
        ("torus n = 0", shapes::torus(8, 0, 2.0, 0.5), "n is 0"),
        (
            "torus m·n overflows",
            shapes::torus(70_000, 70_000, 2.0, 0.5),
            "32-bit",
        ),
        (
            "torus major ≤ minor",
            shapes::torus(8, 8, 0.5, 0.5),
            "major is 0.5",
        ),
        (
            "torus minor NaN",
            shapes::torus(8, 8, 2.0, f64::NAN),
            "minor is NaN",
        ),
        (
            "torus past the largest f64",
            shapes::torus(8, 8, 1.7e308, 1.6e308),
            "past the largest f64",
        ),
        ("grid 0 × 3", shapes::grid(0, 3), "m is 0"),
        ("grid overflow", shapes::grid(u32::MAX, 1), "32-bit"),
        (
            "plate hole ≥ size",
            shapes::plate_with_hole(1.0, 1.0, 0.2),
            "hole is 1",
        ),
        (
            "plate thickness 0",
            shapes::plate_with_hole(2.0, 1.0, 0.0),
            "thickness is 0",
        ),
        (
            "bridged hole NaN",
            shapes::bridged_plate(2.0, f64::NAN, 0.5),
            "hole is NaN",
        ),
        (
            "boolean size inf",
            shapes::boolean_plate(f64::INFINITY, 1.0, 0.5),
            "size is inf",
        ),
    ];
    for (what, result, needle) in cases {
        match result {
            Err(e @ Error::InvalidArgument(_)) => {
                let m = e.to_string();
                assert!(m.contains(needle), "{what}: {m:?} does not say {needle:?}");
            }
            Err(e) => panic!("{what}: not InvalidArgument: {e:?}"),
            Ok(_) => panic!("{what}: accepted"),
        }
    }
}

#[test]
fn tolerant_build_lists_defects() {
    // Three triangles on edge 0-1: non-manifold.
    let p = vec![katachi::DVec3::ZERO; 5];
    let m = PolyMesh::from_polygons(p, [[0u32, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
    let err = m.connectivity().unwrap_err();
    assert!(
        matches!(
            err,
            katachi::Error::NonManifoldEdge {
                a: 0,
                b: 1,
                uses: 3
            }
        ),
        "{err}"
    );
    let t = Topology::build(&m, &TopologyOptions::tolerant()).unwrap();
    assert_eq!(t.defects().non_manifold_edges.len(), 1);
}

// ---------------------------------------------------------------------------------------
// Property tests over random polygon soups.

mod props {
    use crate::support::property::counted_proptest;
    use katachi::mesh::{inspect, LoopId, Topology, TopologyOptions};
    use katachi::{DVec3, Error, HalfedgeId, PolyMesh};
    use proptest::prelude::*;

    /// A random soup: `nv` finite positions and faces of 1–3 loops, each loop 3–7 distinct
    /// in-range vertices.
    fn soup() -> impl Strategy<Value = (Vec<f64>, Vec<Vec<Vec<u32>>>)> {
        (4u32..40).prop_flat_map(|nv| {
            let positions = prop::collection::vec(-1e3f64..1e3, (3 * nv) as usize);
            let lp =
                prop::sample::subsequence((0..nv).collect::<Vec<_>>(), 3..=7usize.min(nv as usize))
                    .prop_shuffle();
            let face = prop::collection::vec(lp, 1..=3);
            (positions, prop::collection::vec(face, 0..30))
        })
    }

    fn flat(faces: &[Vec<Vec<u32>>]) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        let face_loop_counts = faces.iter().map(|f| f.len() as u32).collect();
        let loop_sizes = faces.iter().flatten().map(|l| l.len() as u32).collect();
        let corners = faces.iter().flatten().flatten().copied().collect();
        (loop_sizes, face_loop_counts, corners)
    }

    fn check_invariants(mesh: &PolyMesh, topo: &Topology) {
        for h in 0..topo.halfedge_count() {
            let h = HalfedgeId(h);
            assert_eq!(topo.prev(topo.next(h)), h);
            assert_eq!(topo.next(topo.prev(h)), h);
            assert_eq!(topo.from(topo.next(h)), topo.to(h));
            assert_eq!(topo.twin(topo.twin(h)), h);
            assert!(!(topo.is_boundary(h) && topo.is_boundary(topo.twin(h))));
        }
        // Every corner's half-edge starts at the corner's vertex and belongs to its face.
        for l in 0..mesh.loop_count() {
            let l = LoopId(l);
            let walk: Vec<_> = topo.loop_halfedges(mesh, l).collect();
            let verts = mesh.loop_vertices(l);
            assert_eq!(walk.len(), verts.len());
            for (h, v) in walk.iter().zip(verts) {
                assert_eq!(topo.from(*h), *v);
                assert_eq!(topo.face(*h), topo.loop_face(l));
            }
        }
        let boundary: usize = topo.boundary_loops().iter().map(Vec::len).sum();
        let boundary_hes = (0..topo.halfedge_count())
            .filter(|&h| topo.is_boundary(HalfedgeId(h)))
            .count();
        assert_eq!(boundary, boundary_hes);
    }

    counted_proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Valid input always builds, in every constructor, and the tolerant topology keeps
        /// the half-edge invariants.
        #[test]
        fn valid_soups_build((pos, faces) in soup()) {
            let (ls, flc, c) = flat(&faces);
            let a = PolyMesh::from_flat(&pos, &ls, &flc, &c).unwrap();
            let p: Vec<DVec3> = pos.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
            let b = PolyMesh::from_faces_with_holes(p, faces.clone()).unwrap();
            prop_assert_eq!(&a, &b);
            let topo = Topology::build(&a, &TopologyOptions::tolerant()).unwrap();
            check_invariants(&a, &topo);
            let r = inspect(&a).unwrap();
            prop_assert_eq!(r.faces as usize, faces.len());
            // The strict build either succeeds with the same edges or names a defect.
            match a.connectivity() {
                Ok(t) => {
                    prop_assert_eq!(t.edge_count(), topo.edge_count());
                    prop_assert!(r.defects.non_manifold_edges.is_empty() && r.defects.inconsistent_edges.is_empty());
                }
                Err(Error::NonManifoldEdge { .. }) | Err(Error::InconsistentOrientation { .. }) => {
                    prop_assert!(!(r.defects.non_manifold_edges.is_empty() && r.defects.inconsistent_edges.is_empty()));
                }
                Err(e) => prop_assert!(false, "unexpected error {}", e),
            }
        }

        /// An index past the end gives VertexOutOfRange naming the face and loop.
        #[test]
        fn out_of_range_index((pos, mut faces) in soup(), pick in any::<prop::sample::Index>(), extra in 0u32..1000) {
            prop_assume!(!faces.is_empty());
            let nv = (pos.len() / 3) as u32;
            let f = pick.index(faces.len());
            faces[f][0][0] = nv + extra;
            let (ls, flc, c) = flat(&faces);
            let err = PolyMesh::from_flat(&pos, &ls, &flc, &c).unwrap_err();
            let is_oor = matches!(err, Error::VertexOutOfRange { face, loop_index: 0, .. } if face as usize == f);
            prop_assert!(is_oor, "{}", err);
            prop_assert!(err.to_string().contains("out of range"));
        }

        /// A NaN or infinite coordinate gives NonFiniteCoordinate naming the vertex.
        #[test]
        fn non_finite_coordinate((mut pos, faces) in soup(), pick in any::<prop::sample::Index>(), bad in prop::sample::select(vec![f64::NAN, f64::INFINITY, f64::NEG_INFINITY])) {
            let i = pick.index(pos.len());
            pos[i] = bad;
            let (ls, flc, c) = flat(&faces);
            let err = PolyMesh::from_flat(&pos, &ls, &flc, &c).unwrap_err();
            let ok = matches!(err, Error::NonFiniteCoordinate { vertex, .. } if vertex as usize == i / 3);
            prop_assert!(ok, "{}", err);
        }

        /// A loop with fewer than three distinct vertices gives DegenerateLoop; a repeated
        /// vertex in an otherwise good loop gives RepeatedVertex.
        #[test]
        fn degenerate_and_repeated((pos, mut faces) in soup(), pick in any::<prop::sample::Index>()) {
            prop_assume!(!faces.is_empty());
            let f = pick.index(faces.len());
            let mut faces2 = faces.clone();
            let lp = &mut faces[f][0];
            let v = lp[0];
            lp.truncate(2);
            lp.push(v);
            let (ls, flc, c) = flat(&faces);
            let err = PolyMesh::from_flat(&pos, &ls, &flc, &c).unwrap_err();
            let ok = matches!(err, Error::DegenerateLoop { face, distinct: 2, .. } if face as usize == f);
            prop_assert!(ok, "{}", err);

            let lp = &mut faces2[f][0];
            let v = lp[1];
            lp.push(v);
            let (ls, flc, c) = flat(&faces2);
            let err = PolyMesh::from_flat(&pos, &ls, &flc, &c).unwrap_err();
            let ok = matches!(err, Error::RepeatedVertex { face, vertex, .. } if face as usize == f && vertex == v);
            prop_assert!(ok, "{}", err);
        }

        /// Arbitrary flat arrays never panic: they build or give an error.
        #[test]
        fn arbitrary_arrays_never_panic(
            pos in prop::collection::vec(prop::num::f64::ANY, 0..40),
            ls in prop::collection::vec(0u32..8, 0..12),
            flc in prop::collection::vec(0u32..4, 0..8),
            c in prop::collection::vec(0u32..16, 0..60),
        ) {
            if let Ok(m) = PolyMesh::from_flat(&pos, &ls, &flc, &c) {
                let topo = Topology::build(&m, &TopologyOptions::tolerant()).unwrap();
                check_invariants(&m, &topo);
                inspect(&m).unwrap();
            }
        }
    }

    #[test]
    fn face_without_loops_and_inconsistent_arrays() {
        let pos = [0.0; 9];
        let err = PolyMesh::from_flat(&pos, &[3], &[1, 0], &[0, 1, 2]).unwrap_err();
        assert!(matches!(err, Error::FaceWithoutLoops { face: 1 }), "{err}");
        let err = PolyMesh::from_flat(&pos, &[3], &[1], &[0, 1]).unwrap_err();
        assert!(matches!(err, Error::InconsistentArrays { .. }), "{err}");
        let err = PolyMesh::from_flat(&pos[..8], &[3], &[1], &[0, 1, 2]).unwrap_err();
        assert!(matches!(err, Error::InconsistentArrays { .. }), "{err}");
    }

    #[test]
    fn message_names_the_element() {
        let pos = vec![0.0; 3 * 1200];
        let mut faces = vec![vec![vec![0u32, 1, 2]]; 18];
        faces[17][0][1] = 1203;
        let (ls, flc, c) = flat(&faces);
        let err = PolyMesh::from_flat(&pos, &ls, &flc, &c).unwrap_err();
        assert_eq!(
            err.to_string(),
            "face 17, loop 0: vertex index 1203 is out of range (the mesh has 1200 vertices)"
        );
    }

    #[test]
    fn empty_mesh_where_one_is_needed() {
        let m = PolyMesh::new();
        assert!(m.connectivity().is_ok());
        let err = m.require_faces("subdivision").unwrap_err();
        assert!(matches!(err, Error::EmptyMesh { .. }));
        assert_eq!(
            err.to_string(),
            "the mesh is empty: subdivision needs at least one face"
        );
    }
}

#[test]
fn sharpness_attributes() {
    let mut c = shapes::cube(1.0).unwrap();
    let v = |i| VertexId(i);
    c.set_edge_sharpness(v(1), v(0), 2.5).unwrap();
    assert_eq!(c.edge_sharpness(v(0), v(1)), 2.5);
    assert!(matches!(
        c.set_edge_sharpness(v(0), v(7), 1.0),
        Err(katachi::Error::NoSuchEdge { a: 0, b: 7 })
    ));
    assert!(matches!(
        c.set_edge_sharpness(v(0), v(1), f64::NAN),
        Err(katachi::Error::InvalidSharpness { .. })
    ));
    assert!(c.set_edge_sharpness(v(0), v(1), -1.0).is_err());
    assert_eq!(
        c.edge_sharpness(v(0), v(1)),
        2.5,
        "a failed set changes nothing"
    );
    c.set_edge_sharpness(v(0), v(1), 0.0).unwrap();
    assert_eq!(c.sharp_edges().len(), 0);
    c.set_vertex_sharpness(v(3), 10.0).unwrap();
    assert_eq!(c.vertex_sharpness()[3], 10.0);
    assert!(c.set_vertex_sharpness(v(8), 1.0).is_err());
    assert!(c.set_face_labels(vec![1; 5]).is_err());
    c.set_face_labels(vec![7; 6]).unwrap();
    assert_eq!(c.face_label(katachi::FaceId(2)), 7);
}

#[test]
fn messages_write_huge_numbers_with_an_exponent() {
    let mut cube = shapes::cube(1.0).unwrap();
    let e = cube
        .set_edge_sharpness(VertexId(0), VertexId(1), -1e300)
        .unwrap_err()
        .to_string();
    assert!(e.contains("sharpness -1e300 is invalid"), "{e}");
    let e = cube
        .set_vertex_sharpness(VertexId(0), -2.5)
        .unwrap_err()
        .to_string();
    assert!(e.contains("sharpness -2.5 is invalid"), "{e}");
}
