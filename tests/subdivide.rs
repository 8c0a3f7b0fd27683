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
        (shapes::cube(2.0).unwrap(), "cube"),
        (shapes::ngon_prism(7, 1.0, 1.0).unwrap(), "prism"),
        (shapes::torus(12, 8, 2.0, 0.5).unwrap(), "torus"),
        (shapes::grid(4, 3).unwrap(), "grid"),
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
    let out = catmull_clark(&shapes::cube(2.0).unwrap(), &SubdivideOptions::default()).unwrap();
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
    let mut cube = shapes::cube(2.0).unwrap();
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
    let g = shapes::grid(2, 2).unwrap();
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
fn errors_are_typed() {
    // (That the input is left unchanged needs no test: `catmull_clark` takes `&PolyMesh`.)
    let cube = shapes::cube(1.0).unwrap();
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
    let mut m = shapes::ngon_prism(5, 1.0, 2.0).unwrap();
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
    let m = shapes::torus(20, 12, 2.0, 0.5).unwrap();
    let a = catmull_clark(&m, &SubdivideOptions::with_levels(2)).unwrap();
    let b = catmull_clark(&m, &SubdivideOptions::with_levels(2)).unwrap();
    assert_eq!(a.mesh, b.mesh);
}

// ---------------------------------------------------------------------------------------
// Faces with holes (seed 001 §4).

use katachi::subdivide::HoleMethod;
use katachi::{Error, FaceId, PolyMesh};

fn with_holes(method: HoleMethod, levels: u32) -> SubdivideOptions {
    let mut o = SubdivideOptions::with_levels(levels);
    o.holes = method;
    o
}

/// The plate's top face (face 0) lies in z = thickness, its bottom (face 1) in z = 0.
#[test]
fn method_b_keeps_faces_planar_with_their_holes() {
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    for levels in 1..=3 {
        let out = catmull_clark(&plate, &with_holes(HoleMethod::Sharp, levels)).unwrap();
        let m = &out.mesh;
        let kept: Vec<FaceId> = m.faces().filter(|&f| m.face_loop_count(f) > 1).collect();
        assert_eq!(
            kept.len(),
            2,
            "both faces with holes stay whole, each with its hole"
        );
        for &f in &kept {
            let z0 = m.position(m.face_outer(f)[0]).z;
            for l in m.face_loops(f) {
                assert_eq!(
                    m.loop_vertices(l).len(),
                    4 << levels,
                    "4 · 2^L loop vertices"
                );
                for &v in m.loop_vertices(l) {
                    assert!((m.position(v).z - z0).abs() <= 1e-12 * 4.0, "planar");
                }
            }
        }
        assert!(out.report.fell_back_to_sharp.is_empty());
    }
}

/// Method [b]'s loops are the level-L control polygons of closed uniform cubic B-splines
/// (crease rule eq. (3) at loop vertices, midpoints at loop edges).
#[test]
fn method_b_loops_are_cubic_b_spline_curves() {
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    let levels = 3;
    let out = catmull_clark(&plate, &with_holes(HoleMethod::Sharp, levels)).unwrap();
    let m = &out.mesh;
    let top = m.faces().find(|&f| m.face_loop_count(f) > 1).unwrap();
    let orig_top = plate
        .faces()
        .find(|&f| plate.face_loop_count(f) > 1)
        .unwrap();
    for (lo, l) in plate.face_loops(orig_top).zip(m.face_loops(top)) {
        let mut curve: Vec<DVec3> = plate
            .loop_vertices(lo)
            .iter()
            .map(|&v| plate.position(v))
            .collect();
        for _ in 0..levels {
            let n = curve.len();
            let mut next = Vec::with_capacity(2 * n);
            for i in 0..n {
                let (a, v, b) = (curve[(i + n - 1) % n], curve[i], curve[(i + 1) % n]);
                next.push((a + 6.0 * v + b) / 8.0);
                next.push(0.5 * (v + b));
            }
            curve = next;
        }
        let got: Vec<DVec3> = m.loop_vertices(l).iter().map(|&v| m.position(v)).collect();
        assert_eq!(got.len(), curve.len());
        for (a, b) in got.iter().zip(&curve) {
            assert!(close(*a, *b), "{a} vs {b}");
        }
    }
}

/// Spec §5.4, square in square: method [a] equals plain Catmull-Clark on the mesh whose
/// annuli are split into the four trapezoids.
#[test]
fn method_a_square_in_square_equals_the_explicitly_bridged_mesh() {
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    let explicit = shapes::bridged_plate(4.0, 2.0, 1.0).unwrap();
    for levels in 1..=3 {
        let a = catmull_clark(&plate, &with_holes(HoleMethod::Smooth, levels)).unwrap();
        assert!(a.report.fell_back_to_sharp.is_empty(), "{:?}", a.report);
        let b = catmull_clark(&explicit, &SubdivideOptions::with_levels(levels)).unwrap();
        let key = |m: &PolyMesh| {
            let mut k: Vec<[i64; 3]> = m
                .positions()
                .iter()
                .map(|p| p.to_array().map(|c| (c * 1e9).round() as i64))
                .collect();
            k.sort_unstable();
            k
        };
        assert_eq!(a.mesh.face_count(), b.mesh.face_count());
        assert_eq!(key(&a.mesh), key(&b.mesh), "level {levels}");
        assert!(a
            .face_origin
            .iter()
            .all(|f| f.idx() < plate.face_count() as usize));
    }
}

/// Spec §5.4, octagon in a square: the face point of each virtual face ignores the octagon
/// vertex in the middle of its arc, so method [a] differs from plain Catmull-Clark there.
#[test]
fn method_a_octagon_in_square_uses_four_vertex_face_points() {
    let mut p = vec![];
    for (x, y) in [(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)] {
        p.push(DVec3::new(x, y, 0.0));
    }
    for k in 0..8 {
        let t = std::f64::consts::TAU * k as f64 / 8.0;
        p.push(DVec3::new(t.cos(), t.sin(), 0.0));
    }
    // Hole clockwise: 4, 11, 10, ..., 5.
    let hole: Vec<u32> = std::iter::once(4).chain((5..12).rev()).collect();
    let face = PolyMesh::from_faces_with_holes(p, vec![vec![vec![0u32, 1, 2, 3], hole]]).unwrap();
    let out = catmull_clark(&face, &with_holes(HoleMethod::Smooth, 1)).unwrap();
    assert!(out.report.fell_back_to_sharp.is_empty(), "{:?}", out.report);
    assert_eq!(out.mesh.face_count(), 4 * 5, "four pentagon virtual faces");
    // The virtual face at the +x side joins corners (2,-2), (2,2) and octagon vertices at
    // -45° and +45°: its face point is their average, not the pentagon's.
    let (s, c) = (std::f64::consts::FRAC_1_SQRT_2, 2.0);
    let expect = (DVec3::new(c, -c, 0.0)
        + DVec3::new(c, c, 0.0)
        + DVec3::new(s, -s, 0.0)
        + DVec3::new(s, s, 0.0))
        / 4.0;
    assert!(
        out.mesh.positions().iter().any(|&q| close(q, expect)),
        "face point {expect}"
    );
    let pentagon_avg = (4.0 * expect + DVec3::new(1.0, 0.0, 0.0)) / 5.0;
    assert!(!out.mesh.positions().iter().any(|&q| close(q, pentagon_avg)));
}

/// Boolean reconstruction: the plate triangulated (as a boolean outputs it) comes back as faces
/// with holes, and then subdivides exactly as the plate built with them.
#[test]
fn recovered_faces_with_holes_subdivide_like_the_original() {
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    let soup = shapes::boolean_plate(4.0, 2.0, 1.0).unwrap();
    assert!(soup.faces().all(|f| soup.face_outer(f).len() == 3));
    for method in [HoleMethod::Smooth, HoleMethod::Sharp] {
        let mut o = with_holes(method, 2);
        o.recover_faces_with_holes = true;
        let a = catmull_clark(&soup, &o).unwrap();
        let b = catmull_clark(&plate, &with_holes(method, 2)).unwrap();
        assert_eq!(a.mesh.face_count(), b.mesh.face_count(), "{method:?}");
        assert_eq!(
            a.mesh
                .faces()
                .filter(|&f| a.mesh.face_loop_count(f) > 1)
                .count(),
            b.mesh
                .faces()
                .filter(|&f| b.mesh.face_loop_count(f) > 1)
                .count()
        );
        // Face origins refer to the triangles of the input.
        assert!(a
            .face_origin
            .iter()
            .all(|f| f.idx() < soup.face_count() as usize));
        // Vertex data follow through the merge: refining x gives the positions' x.
        let r = katachi::subdivide::Refiner::new(&soup, &o).unwrap();
        let xs: Vec<f64> = soup.positions().iter().map(|p| p.x).collect();
        let rx = r.refine_vertex_data(&xs).unwrap();
        assert!(rx
            .iter()
            .zip(a.mesh.positions())
            .all(|(x, p)| (x - p.x).abs() < 1e-12));
    }
}

#[test]
fn bad_faces_with_holes_are_typed_errors_naming_the_face() {
    let sq =
        |r: f64, z: f64| [(-r, -r), (r, -r), (r, r), (-r, r)].map(|(x, y)| DVec3::new(x, y, z));
    let mk = |hole: [DVec3; 4]| {
        let mut p: Vec<DVec3> = sq(2.0, 0.0).to_vec();
        p.extend(hole);
        PolyMesh::from_faces_with_holes(p, vec![vec![vec![0u32, 1, 2, 3], vec![7, 6, 5, 4]]])
            .unwrap()
    };
    let outside = mk(sq(1.0, 0.0).map(|p| p + DVec3::new(5.0, 0.0, 0.0)));
    let tilted = mk(sq(1.0, 0.0).map(|p| DVec3::new(p.x, p.y, 0.3 * p.x)));
    let crossing = mk(sq(1.0, 0.0).map(|p| p + DVec3::new(1.5, 0.0, 0.0)));
    for (name, m) in [
        ("outside", outside),
        ("not coplanar", tilted),
        ("crossing", crossing),
    ] {
        for method in [HoleMethod::Smooth, HoleMethod::Sharp] {
            let err = catmull_clark(&m, &with_holes(method, 1)).unwrap_err();
            assert!(
                matches!(err, Error::InvalidFaceWithHoles { face: 0, .. }),
                "{name}: {err}"
            );
            assert!(err.to_string().starts_with("face 0: "), "{name}: {err}");
        }
    }
}

/// The same bits whatever the thread count (rayon pools of 1, 2 and 5 threads).
#[test]
fn same_bits_whatever_the_thread_count() {
    let mut m = shapes::torus(40, 24, 2.0, 0.5).unwrap();
    m.set_edge_sharpnesses([
        (VertexId(0), VertexId(1), 1.5),
        (VertexId(1), VertexId(2), 10.0),
    ])
    .unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut o = SubdivideOptions::with_levels(3);
            o.crease_method = CreaseMethod::Chaikin;
            catmull_clark(&m, &o).unwrap()
        })
    };
    let one = run(1);
    for t in [2, 5] {
        let other = run(t);
        assert_eq!(one.mesh, other.mesh, "{t} threads");
        assert_eq!(one.face_origin, other.face_origin);
    }
}

/// UVs on faces kept whole (method [b]): with one UV per vertex and no seams, the UV
/// topology is the mesh's, so smooth UVs are the refined positions' (x, y) exactly, and the
/// other modes give finite values for every output corner.
#[test]
fn face_varying_data_follows_faces_kept_whole() {
    use katachi::subdivide::{FaceVarying, Refiner};
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    let uv: Vec<[f64; 2]> = plate.positions().iter().map(|p| [p.x, p.y]).collect();
    let indices: Vec<u32> = plate.corners().iter().map(|v| v.0).collect();
    for levels in 1..=2 {
        let refiner = Refiner::new(&plate, &with_holes(HoleMethod::Sharp, levels)).unwrap();
        let positions = refiner.refine_vertex_data(plate.positions()).unwrap();
        let out = refiner.mesh(positions.clone()).unwrap();
        for mode in [
            FaceVarying::Smooth,
            FaceVarying::LinearCornersOnly,
            FaceVarying::LinearBoundaries,
            FaceVarying::LinearAll,
        ] {
            let refined = refiner
                .refine_face_varying(&uv, &indices, mode)
                .unwrap_or_else(|e| panic!("{mode:?}, {levels} levels: {e}"));
            assert_eq!(refined.len(), out.corner_count() as usize, "{mode:?}");
            assert!(refined.iter().flatten().all(|x| x.is_finite()), "{mode:?}");
            if mode == FaceVarying::Smooth {
                for (k, v) in out.corners().iter().enumerate() {
                    let p = positions[v.0 as usize];
                    let d = (refined[k][0] - p.x).abs() + (refined[k][1] - p.y).abs();
                    assert!(
                        d < 1e-12,
                        "{levels} levels, corner {k}: {:?} vs {p}",
                        refined[k]
                    );
                }
            }
        }
    }
}

#[test]
fn coordinates_near_the_f64_limit_are_a_typed_error_not_infinity() {
    use katachi::subdivide::Refiner;
    use katachi::Error;
    // A cube whose vertex 7 sits near f64::MAX: face and edge points sum such coordinates.
    let mut cube = shapes::cube(2.0).unwrap();
    let mut p = cube.positions().to_vec();
    p[7] = DVec3::new(1.0e308, 1.5e308, 1.7e308);
    p[6] = DVec3::new(-1.0e308, 1.6e308, 1.6e308);
    cube.set_positions(p).unwrap();
    for levels in [1, 3] {
        let e = catmull_clark(&cube, &SubdivideOptions::with_levels(levels)).unwrap_err();
        match &e {
            Error::CoordinateOverflow { vertex, value, .. } => {
                assert_eq!(*vertex, 7, "{e}");
                assert_eq!(*value, 1.7e308, "{e}");
            }
            other => panic!("not CoordinateOverflow: {other:?}"),
        }
        assert!(e.to_string().contains("vertex 7"), "{e}");
        assert_eq!(e.kind(), katachi::ErrorKind::BadInput);
    }
    // Large but representable coordinates subdivide to finite positions.
    let mut big = shapes::cube(2.0).unwrap();
    big.set_positions(big.positions().iter().map(|&q| q * 1e300).collect())
        .unwrap();
    let out = catmull_clark(&big, &SubdivideOptions::with_levels(2)).unwrap();
    assert!(out.mesh.positions().iter().all(|q| q.is_finite()));
    // The refiner refuses positions a caller hands it that are not finite or not one per
    // output vertex.
    let refiner = Refiner::new(&big, &SubdivideOptions::with_levels(1)).unwrap();
    let n = refiner.vertex_count() as usize;
    let mut positions = vec![DVec3::ZERO; n];
    assert!(matches!(
        refiner.mesh(positions[1..].to_vec()),
        Err(Error::AttributeLength { .. })
    ));
    positions[5].y = f64::INFINITY;
    assert!(matches!(
        refiner.mesh(positions),
        Err(Error::NonFiniteCoordinate { vertex: 5, .. })
    ));
}

// ---------------------------------------------------------------- Subdivision (read-out)

use katachi::subdivide::{FaceVarying, Subdivision};

fn subdivision(mesh: &PolyMesh, options: &SubdivideOptions) -> Subdivision {
    Subdivision::new(mesh, options, &mut |_, _| {}).unwrap()
}

/// The torus with two rings of creases (one infinitely sharp, one semi-sharp), a grid (with
/// boundaries), a prism (n-gons) and a plate whose faces with holes stay whole (method [b]).
fn read_out_meshes() -> Vec<(&'static str, PolyMesh, HoleMethod)> {
    let mut torus = shapes::torus(12, 8, 2.0, 0.5).unwrap();
    let ring = |i: u32, s: f64| {
        (0..8).map(move |j| (VertexId(i * 8 + j), VertexId(i * 8 + (j + 1) % 8), s))
    };
    torus
        .set_edge_sharpnesses(ring(0, 10.0).chain(ring(6, 1.5)))
        .unwrap();
    vec![
        ("creased torus", torus, HoleMethod::Smooth),
        ("grid", shapes::grid(4, 3).unwrap(), HoleMethod::Smooth),
        (
            "prism",
            shapes::ngon_prism(7, 1.0, 1.0).unwrap(),
            HoleMethod::Smooth,
        ),
        (
            "plate, method [b]",
            shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap(),
            HoleMethod::Sharp,
        ),
    ]
}

/// The read-out's arrays are `catmull_clark`'s mesh; its edges are exactly the faces' sides,
/// each corner's edge joins it to the next corner, and the sharpness left on them is the
/// refined mesh's; the edge count is known before the edges are computed.
#[test]
fn subdivision_read_out_edges_are_the_faces_sides() {
    for (name, mesh, holes) in read_out_meshes() {
        for levels in 1..=3 {
            let o = with_holes(holes, levels);
            let s = subdivision(&mesh, &o);
            let reference = catmull_clark(&mesh, &o).unwrap();
            let m = &reference.mesh;
            assert_eq!(s.positions(), m.positions(), "{name} L{levels}");
            let corners: Vec<u32> = m.corners().iter().map(|v| v.0).collect();
            assert_eq!(s.corners(), &corners[..], "{name} L{levels}");
            assert_eq!(s.loop_offsets(), m.loop_offsets(), "{name} L{levels}");
            assert_eq!(
                s.face_origin(),
                &reference.face_origin[..],
                "{name} L{levels}"
            );
            let count = s.edge_count();
            let e = s.edges();
            assert_eq!(
                count as usize,
                e.verts.len(),
                "{name} L{levels}: edge count"
            );
            let mut sides = std::collections::BTreeSet::new();
            for w in s.loop_offsets().windows(2) {
                let (a, b) = (w[0] as usize, w[1] as usize);
                for c in a..b {
                    let (u, v) = (
                        s.corners()[c],
                        s.corners()[if c + 1 < b { c + 1 } else { a }],
                    );
                    let [x, y] = e.verts[e.corner_edges[c] as usize];
                    assert!(
                        (x, y) == (u, v) || (x, y) == (v, u),
                        "{name} L{levels}: corner {c}'s edge joins {x}-{y}, not {u}-{v}"
                    );
                    sides.insert((u.min(v), u.max(v)));
                }
            }
            assert_eq!(
                sides.len(),
                e.verts.len(),
                "{name} L{levels}: each side one edge"
            );
            let sharp: Vec<((u32, u32), f64)> =
                m.sharp_edges().map(|(a, b, s)| ((a.0, b.0), s)).collect();
            let mut ours: Vec<((u32, u32), f64)> = e
                .verts
                .iter()
                .zip(&e.sharpness)
                .filter(|(_, &s)| s > 0.0)
                .map(|(&[a, b], &s)| ((a.min(b), a.max(b)), s as f64))
                .collect();
            ours.sort_by_key(|x| x.0);
            assert_eq!(ours, sharp, "{name} L{levels}: sharpness left");
            assert_eq!(
                s.sharp_edge_count() as usize,
                sharp.len(),
                "{name} L{levels}"
            );
        }
    }
}

/// Per-corner data welded by vertex and value refines exactly as the same data given as
/// values and indices, in every mode.
#[test]
fn subdivision_corner_data_welds_like_indexed_values() {
    // A torus whose UV map has seams along one meridian and one parallel.
    let (m, n) = (8u32, 6u32);
    let torus = shapes::torus(m, n, 2.0, 0.5).unwrap();
    let uv: Vec<[f64; 2]> = (0..=m)
        .flat_map(|i| (0..=n).map(move |j| [i as f64 / m as f64, j as f64 / n as f64]))
        .collect();
    let id = |i: u32, j: u32| i * (n + 1) + j;
    let indices: Vec<u32> = (0..m)
        .flat_map(|i| {
            (0..n).flat_map(move |j| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
        })
        .collect();
    let per_corner: Vec<f64> = indices.iter().flat_map(|&i| uv[i as usize]).collect();
    for levels in 1..=2 {
        let s = subdivision(&torus, &SubdivideOptions::with_levels(levels));
        for mode in [
            FaceVarying::Smooth,
            FaceVarying::LinearCornersOnly,
            FaceVarying::LinearBoundaries,
            FaceVarying::LinearAll,
        ] {
            let expected: Vec<f64> = s
                .refine_face_varying(&uv, &indices, mode)
                .unwrap()
                .into_iter()
                .flatten()
                .collect();
            let welded = s.refine_corner_data(&per_corner, 2, mode).unwrap();
            assert_eq!(welded, expected, "{mode:?} L{levels}");
            // Five components (the general path) agree with two.
            let five: Vec<f64> = per_corner
                .chunks(2)
                .flat_map(|c| [c[0], c[1], c[0], c[1], c[0]])
                .collect();
            let r5 = s.refine_corner_data(&five, 5, mode).unwrap();
            for (k, c) in r5.chunks(5).enumerate() {
                assert_eq!(
                    [c[0], c[1]],
                    [expected[2 * k], expected[2 * k + 1]],
                    "{mode:?}"
                );
            }
        }
        assert!(matches!(
            s.refine_corner_data(&per_corner[1..], 2, FaceVarying::Smooth),
            Err(Error::AttributeLength { .. })
        ));
    }
}

/// With `split_faces_with_holes`, method [b]'s faces with holes come back as the simple
/// polygons `split_faces_with_holes` makes of them, with their origins, edges and corner
/// data (smooth UVs equal to the positions' x, y follow the positions exactly).
#[test]
fn subdivision_splits_faces_with_holes_for_hosts() {
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    let uv: Vec<f64> = plate
        .corners()
        .iter()
        .flat_map(|v| {
            let p = plate.position(*v);
            [p.x, p.y]
        })
        .collect();
    for levels in 1..=2 {
        let mut o = with_holes(HoleMethod::Sharp, levels);
        let whole = subdivision(&plate, &o);
        assert!(whole.has_faces_with_holes());
        o.split_faces_with_holes = true;
        let s = subdivision(&plate, &o);
        assert!(!s.has_faces_with_holes());
        let reference = catmull_clark(&plate, &o).unwrap();
        assert_eq!(reference.mesh.loop_count(), reference.mesh.face_count());
        assert_eq!(s.face_count(), reference.mesh.face_count(), "L{levels}");
        assert_eq!(s.face_origin(), &reference.face_origin[..], "L{levels}");
        let corners: Vec<u32> = reference.mesh.corners().iter().map(|v| v.0).collect();
        assert_eq!(s.corners(), &corners[..], "L{levels}");
        assert_eq!(s.mesh(), reference.mesh, "L{levels}");
        assert_eq!(s.edge_count() as usize, s.edges().verts.len());
        let refined = s.refine_corner_data(&uv, 2, FaceVarying::Smooth).unwrap();
        assert_eq!(refined.len(), 2 * s.corner_count() as usize);
        for (k, &v) in s.corners().iter().enumerate() {
            let p = s.positions()[v as usize];
            let d = (refined[2 * k] - p.x).abs() + (refined[2 * k + 1] - p.y).abs();
            assert!(
                d < 1e-12,
                "L{levels}, corner {k}: {:?} vs {p}",
                &refined[2 * k..2 * k + 2]
            );
        }
    }
}
