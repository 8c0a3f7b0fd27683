//! Generated shapes with exact expected counts (mesh module).

use katachi::mesh::{inspect, shapes, Topology, TopologyOptions};
use katachi::{PolyMesh, VertexId};

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
        &shapes::cube(2.0),
        Expect {
            v: 8,
            f: 6,
            e: 12,
            boundary_loops: 0,
            euler: 2,
            genus: Some(0),
        },
    );
    let c = shapes::cube(2.0);
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
            &shapes::ngon_prism(n, 1.0, 1.0),
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
        &shapes::torus(12, 8, 2.0, 0.5),
        Expect {
            v: 96,
            f: 96,
            e: 192,
            boundary_loops: 0,
            euler: 0,
            genus: Some(1),
        },
    );
    let t = shapes::torus(12, 8, 2.0, 0.5);
    let topo = t.connectivity().unwrap();
    assert!(t.vertices().all(|v| topo.valence(v) == 4));
}

#[test]
fn open_grid_counts() {
    let g = shapes::grid(4, 3);
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
    let p = shapes::plate_with_hole(4.0, 2.0, 1.0);
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
