//! Catmull-Clark subdivision (seed 001): counts, hand-computed positions, creases, holes.

use katachi::mesh::{inspect, shapes};
use katachi::subdivide::{catmull_clark, BoundaryInterpolation, CreaseMethod, SubdivideOptions};
use katachi::{DVec3, VertexId};

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-12
}

#[test]
fn counts_follow_v_plus_e_plus_f() {
    for (mesh, name) in [
        (shapes::cube(2.0), "cube"),
        (shapes::ngon_prism(7, 1.0, 1.0), "prism"),
        (shapes::torus(12, 8, 2.0, 0.5), "torus"),
        (shapes::grid(4, 3), "grid"),
    ] {
        let r = inspect(&mesh).unwrap();
        let out = catmull_clark(&mesh, &SubdivideOptions::with_levels(1)).unwrap();
        let corners = mesh.corner_count();
        assert_eq!(
            out.mesh.vertex_count(),
            r.vertices + r.edges + r.faces,
            "{name}"
        );
        assert_eq!(out.mesh.face_count(), corners, "{name}");
        let r1 = inspect(&out.mesh).unwrap();
        assert_eq!(r1.edges, 2 * r.edges + corners, "{name}");
        assert_eq!(r1.euler_characteristic, r.euler_characteristic, "{name}");
        assert!(r1.is_manifold(), "{name}");
        assert!(out.mesh.faces_by_size_all_quads(), "{name}");
        let out3 = catmull_clark(&mesh, &SubdivideOptions::with_levels(3)).unwrap();
        assert_eq!(out3.mesh.face_count(), corners * 16, "{name}");
        assert_eq!(out3.face_origin.len(), out3.mesh.face_count() as usize);
    }
}

#[test]
fn cube_level_one_by_hand() {
    // Corner (1,1,1) of the ±1 cube: v/3 + (Σ neighbours + Σ face points)/9 = 5/9 (1,1,1).
    let out = catmull_clark(&shapes::cube(2.0), &SubdivideOptions::default()).unwrap();
    let p = out.mesh.position(VertexId(7));
    assert!(close(p, DVec3::splat(5.0 / 9.0)), "{p}");
    // Edge point of edge 0-1 ((-1,-1,-1)-(1,-1,-1)): faces z=-1 and y=-1 → (0,-0.75,-0.75).
    let found = out
        .mesh
        .positions()
        .iter()
        .any(|&q| close(q, DVec3::new(0.0, -0.75, -0.75)));
    assert!(found);
}

#[test]
fn infinitely_sharp_edge_gives_midpoints_and_crease_rule() {
    let mut cube = shapes::cube(2.0);
    // Crease around the bottom square 0-1-3-2.
    cube.set_edge_sharpnesses([
        (VertexId(0), VertexId(1), 10.0),
        (VertexId(1), VertexId(3), 10.0),
        (VertexId(3), VertexId(2), 10.0),
        (VertexId(2), VertexId(0), 10.0),
    ])
    .unwrap();
    let out = catmull_clark(&cube, &SubdivideOptions::default()).unwrap();
    // Vertex 0 has two sharp edges: (e_a + 6 v + e_b)/8 with e_a = v1, e_b = v2 (eq. (3)).
    let p = out.mesh.position(VertexId(0));
    let expect =
        (DVec3::new(1.0, -1.0, -1.0) + DVec3::new(-1.0, 1.0, -1.0) + 6.0 * DVec3::splat(-1.0))
            / 8.0;
    assert!(close(p, expect), "{p} vs {expect}");
    assert!(out
        .mesh
        .positions()
        .iter()
        .any(|&q| close(q, DVec3::new(0.0, -1.0, -1.0))));
    // Infinite creases survive into the output.
    assert_eq!(out.mesh.sharp_edges().len(), 8);
}

#[test]
fn boundary_rules() {
    // Open grid: corner vertex 0 has one face.
    let g = shapes::grid(2, 2);
    let out = catmull_clark(&g, &SubdivideOptions::default()).unwrap();
    // Edge-only: crease rule along the boundary: (v1 + 6 v0 + v3)/8 = (1/8, 1/8, 0).
    assert!(close(
        out.mesh.position(VertexId(0)),
        DVec3::new(0.125, 0.125, 0.0)
    ));
    let mut opts = SubdivideOptions::default();
    opts.boundary = BoundaryInterpolation::EdgeAndCorner;
    let out = catmull_clark(&g, &opts).unwrap();
    assert!(close(out.mesh.position(VertexId(0)), DVec3::ZERO));
    assert_eq!(
        out.mesh.sharp_edges().len(),
        0,
        "boundary sharpness is not a user crease"
    );
}

#[test]
fn semi_sharp_crease_row() {
    // Spec §7.1: a crease row over z = (y-1)^2 gives z = 0.25 (1 - s) at level 1 for s < 1.
    let mut p = Vec::new();
    for y in 0..3 {
        for x in 0..4 {
            p.push(DVec3::new(x as f64, y as f64, ((y as f64) - 1.0).powi(2)));
        }
    }
    let id = |x: u32, y: u32| y * 4 + x;
    let mut faces = Vec::new();
    for y in 0..2 {
        for x in 0..3 {
            faces.push(vec![id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
        }
    }
    for (s, z) in [(0.25, 0.1875), (0.5, 0.125), (1.0, 0.0), (2.0, 0.0)] {
        let mut m = katachi::PolyMesh::from_polygons(p.clone(), &faces).unwrap();
        m.set_edge_sharpnesses((0..3).map(|x| (VertexId(id(x, 1)), VertexId(id(x + 1, 1)), s)))
            .unwrap();
        for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            let mut opts = SubdivideOptions::default();
            opts.crease_method = method;
            let out = catmull_clark(&m, &opts).unwrap();
            // Vertex (1,1) is interior to the crease row.
            let q = out.mesh.position(VertexId(id(1, 1)));
            assert!((q.z - z).abs() < 1e-12, "s = {s}, {method:?}: z = {}", q.z);
        }
    }
}

#[test]
fn input_is_untouched_and_errors_are_typed() {
    let cube = shapes::cube(1.0);
    let before = cube.clone();
    let _ = catmull_clark(&cube, &SubdivideOptions::with_levels(2)).unwrap();
    assert_eq!(cube, before);
    assert!(catmull_clark(&cube, &SubdivideOptions::with_levels(0)).is_err());
    assert!(catmull_clark(&katachi::PolyMesh::new(), &SubdivideOptions::default()).is_err());
}

trait AllQuads {
    fn faces_by_size_all_quads(&self) -> bool;
}
impl AllQuads for katachi::PolyMesh {
    fn faces_by_size_all_quads(&self) -> bool {
        self.faces().all(|f| self.face_outer(f).len() == 4)
    }
}

#[test]
fn stencils_and_vertex_data_follow_the_positions() {
    use katachi::subdivide::Refiner;
    let mut m = shapes::ngon_prism(5, 1.0, 2.0);
    m.set_edge_sharpness(VertexId(0), VertexId(1), 1.5).unwrap();
    for levels in 1..=3 {
        let o = SubdivideOptions::with_levels(levels);
        let out = catmull_clark(&m, &o).unwrap();
        let r = Refiner::new(&m, &o).unwrap();
        let st = r.stencils();
        assert_eq!(st.offsets.len() as u32, out.mesh.vertex_count() + 1);
        let via_stencils = st.apply(m.positions());
        for (a, b) in via_stencils.iter().zip(out.mesh.positions()) {
            assert!((*a - *b).length() < 1e-13, "{a} vs {b}");
        }
        // Each row is an affine combination (weights sum to 1).
        for w in st.offsets.windows(2) {
            let s: f64 = st.weights[w[0] as usize..w[1] as usize].iter().sum();
            assert!((s - 1.0).abs() < 1e-12);
        }
        // Scalar data refine like the x coordinate.
        let xs: Vec<f64> = m.positions().iter().map(|p| p.x).collect();
        let rx = r.refine_vertex_data(&xs).unwrap();
        for (a, b) in rx.iter().zip(out.mesh.positions()) {
            assert!((a - b.x).abs() < 1e-13);
        }
        assert!(
            r.refine_vertex_data(&xs[1..]).is_err(),
            "wrong length is an error"
        );
    }
}

#[test]
fn deterministic_bits() {
    let m = shapes::torus(20, 12, 2.0, 0.5);
    let a = catmull_clark(&m, &SubdivideOptions::with_levels(2)).unwrap();
    let b = catmull_clark(&m, &SubdivideOptions::with_levels(2)).unwrap();
    assert_eq!(a.mesh, b.mesh);
}
