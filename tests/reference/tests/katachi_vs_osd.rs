//! katachi's Catmull-Clark against OpenSubdiv 3.5 (positions to 1e-12 of the bounding-box
//! diagonal, face lists identical) and OpenMesh 9 (agrees on closed uncreased meshes; its
//! boundary rule differs, asserted as a documented difference).
//!
//! Ordering: katachi numbers child vertices and faces as OpenSubdiv's uniform refinement does
//! by default (children of vertices, then of faces, then of edges; a face's children in corner
//! order, each quad starting at its parent corner), so vertices and faces compare index by index.

use katachi::mesh::{shapes, INFINITELY_SHARP};
use katachi::subdivide::{catmull_clark, BoundaryInterpolation, CreaseMethod, SubdivideOptions};
use katachi::{DVec3, PolyMesh, VertexId};
use katachi_reference as r;

// The test models and the record (tests/support), shared with the root crate's tests.
#[allow(dead_code)]
#[path = "../../support/models.rs"]
mod models;
#[allow(dead_code)]
#[path = "../../support/record.rs"]
mod record;

fn to_ref(mesh: &PolyMesh) -> (r::RefMesh, r::Creases) {
    let m = r::RefMesh {
        positions: mesh.positions().iter().map(|p| p.to_array()).collect(),
        face_sizes: mesh
            .faces()
            .map(|f| mesh.face_outer(f).len() as u32)
            .collect(),
        face_vertices: mesh
            .faces()
            .flat_map(|f| mesh.face_outer(f).iter().map(|v| v.0))
            .collect(),
    };
    let mut c = r::Creases::default();
    for (a, b, s) in mesh.sharp_edges() {
        c.edges.push([a.0, b.0]);
        c.edge_sharpness.push(s);
    }
    for (v, &s) in mesh.vertex_sharpness().iter().enumerate() {
        if s > 0.0 {
            c.corners.push(v as u32);
            c.corner_sharpness.push(s);
        }
    }
    (m, c)
}

fn diag(mesh: &PolyMesh) -> f64 {
    mesh.bounding_box()
        .map(|(lo, hi)| (hi - lo).length())
        .unwrap_or(1.0)
        .max(1e-300)
}

/// Compares katachi with OpenSubdiv at levels 1..=max_level; returns the largest relative error.
fn compare(name: &str, mesh: &PolyMesh, options: &SubdivideOptions, max_level: u32) -> f64 {
    let (rm, rc) = to_ref(mesh);
    let osd_opts = r::OsdOptions {
        boundary: match options.boundary {
            BoundaryInterpolation::EdgeOnly => r::Boundary::EdgeOnly,
            BoundaryInterpolation::EdgeAndCorner => r::Boundary::EdgeAndCorner,
        },
        crease: match options.crease_method {
            CreaseMethod::Uniform => r::CreaseMethod::Uniform,
            CreaseMethod::Chaikin => r::CreaseMethod::Chaikin,
        },
        ..Default::default()
    };
    let d = diag(mesh);
    let mut worst = 0.0f64;
    for level in 1..=max_level {
        let mut o = options.clone();
        o.levels = level;
        let ours = catmull_clark(mesh, &o).unwrap_or_else(|e| panic!("{name} L{level}: {e}"));
        let theirs = r::osd_catmark(&rm, &rc, &osd_opts, level)
            .unwrap_or_else(|e| panic!("{name} L{level}: OpenSubdiv: {e}"));
        assert_eq!(
            ours.mesh.vertex_count() as usize,
            theirs.positions.len(),
            "{name} L{level}: vertex count"
        );
        assert_eq!(
            ours.mesh.face_count() as usize,
            theirs.face_sizes.len(),
            "{name} L{level}: face count"
        );
        let ours_faces: Vec<u32> = ours.mesh.corners().iter().map(|v| v.0).collect();
        assert!(
            ours_faces == theirs.face_vertices,
            "{name} L{level}: face lists differ"
        );
        for (i, (p, q)) in ours
            .mesh
            .positions()
            .iter()
            .zip(&theirs.positions)
            .enumerate()
        {
            let e = (*p - DVec3::from_array(*q)).length() / d;
            assert!(e <= 1e-12, "{name} L{level}: vertex {i}: katachi {p}, OpenSubdiv {q:?} (error {e:e} of the diagonal)");
            worst = worst.max(e);
        }
    }
    worst
}

fn opts(boundary: BoundaryInterpolation, crease: CreaseMethod) -> SubdivideOptions {
    let mut o = SubdivideOptions::default();
    o.boundary = boundary;
    o.crease_method = crease;
    o
}

#[test]
fn generated_shapes_match_opensubdiv() {
    let d = SubdivideOptions::default();
    compare("cube", &shapes::cube(2.0).unwrap(), &d, 3);
    for n in [3, 5, 8] {
        compare(
            &format!("prism {n}"),
            &shapes::ngon_prism(n, 1.0, 1.5).unwrap(),
            &d,
            3,
        );
    }
    compare("torus", &shapes::torus(12, 8, 2.0, 0.5).unwrap(), &d, 3);
    for b in [
        BoundaryInterpolation::EdgeOnly,
        BoundaryInterpolation::EdgeAndCorner,
    ] {
        compare(
            &format!("grid {b:?}"),
            &shapes::grid(4, 3).unwrap(),
            &opts(b, CreaseMethod::Uniform),
            3,
        );
    }
}

fn creased_cube(s: f64) -> PolyMesh {
    let mut c = shapes::cube(2.0).unwrap();
    let v = VertexId;
    // A chain of three edges and a separate edge, so crease ends, crease interiors and
    // Chaikin's neighbour averaging all occur.
    c.set_edge_sharpnesses([
        (v(0), v(1), s),
        (v(1), v(3), s),
        (v(3), v(7), (s * 0.5).min(INFINITELY_SHARP)),
        (v(4), v(6), s),
    ])
    .unwrap();
    c
}

#[test]
fn creases_match_opensubdiv() {
    for s in [0.5, 1.0, 2.5, INFINITELY_SHARP] {
        for method in [CreaseMethod::Uniform, CreaseMethod::Chaikin] {
            let o = opts(BoundaryInterpolation::EdgeOnly, method);
            compare(
                &format!("creased cube s={s} {method:?}"),
                &creased_cube(s),
                &o,
                3,
            );
        }
    }
}

#[test]
fn corners_match_opensubdiv() {
    for s in [0.5, 1.5, INFINITELY_SHARP] {
        let mut c = creased_cube(2.0);
        c.set_vertex_sharpness(VertexId(5), s).unwrap();
        c.set_vertex_sharpness(VertexId(1), s).unwrap();
        compare(
            &format!("corners s={s}"),
            &c,
            &SubdivideOptions::default(),
            3,
        );
    }
}

#[test]
fn non_manifold_fan_matches_opensubdiv() {
    // Three quads sharing the edge 0-1 (a "book" with three pages).
    let p = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 1.0),
        DVec3::new(-0.5, 0.8, 0.0),
        DVec3::new(-0.5, 0.8, 1.0),
        DVec3::new(-0.5, -0.8, 0.0),
        DVec3::new(-0.5, -0.8, 1.0),
    ];
    let m = PolyMesh::from_polygons(p, [[0u32, 2, 3, 1], [1, 5, 4, 0], [0, 6, 7, 1]]).unwrap();
    compare("non-manifold fan", &m, &SubdivideOptions::default(), 3);
    let o = r::openmesh_catmull_clark(&to_ref(&m).0, 1);
    assert!(o.is_err(), "OpenMesh rejects a complex edge");
}

/// The model files (by extension) in `dir`, sorted.
fn model_files(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| katachi::io::Format::from_path(p).is_ok())
        .collect();
    v.sort();
    v
}

/// Compares every model in `dir` that OpenSubdiv accepts, levels 1 to 3; returns how many
/// were compared. A model OpenSubdiv refuses must be refused or handled by katachi without a
/// panic; a model with faces with holes (OpenSubdiv has none) is counted apart.
fn compare_folder(dir: &std::path::Path, corpus: bool) -> (usize, usize) {
    const TEST: &str = "katachi_vs_osd::models_match_opensubdiv";
    let (mut compared, mut refused) = (0, 0);
    for path in model_files(dir) {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let mesh = katachi::io::read(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            mesh.faces().all(|f| mesh.face_loop_count(f) == 1),
            "{name}: a file format holds no faces with holes"
        );
        let (rm, rc) = to_ref(&mesh);
        let osd_ok = r::osd_catmark(&rm, &rc, &r::OsdOptions::default(), 1).is_ok();
        if osd_ok {
            compare(&name, &mesh, &SubdivideOptions::default(), 3);
            println!("{name}: matches OpenSubdiv at levels 1-3");
            compared += 1;
        } else {
            // OpenSubdiv refuses it; katachi must then refuse or handle it without panicking.
            let ours = catmull_clark(&mesh, &SubdivideOptions::default());
            println!(
                "{name}: OpenSubdiv refuses it; katachi: {:?}",
                ours.map(|o| o.mesh.face_count())
            );
            refused += 1;
        }
        if corpus {
            models::ran(TEST, &name);
        }
    }
    (compared, refused)
}

#[test]
fn models_match_opensubdiv() {
    let bundled = models::bundled_dir();
    let n = model_files(&bundled).len();
    let (compared, refused) = compare_folder(&bundled, false);
    assert_eq!(
        (compared, refused),
        (n, 0),
        "every bundled model is a valid Catmull-Clark cage"
    );
    match models::corpus() {
        Some(dir) => {
            let (compared, _) = compare_folder(&dir, true);
            assert!(compared >= 15, "only {compared} corpus models compared");
        }
        None => models::not_run(
            "katachi_vs_osd::models_match_opensubdiv",
            "every corpus model",
        ),
    }
}

#[test]
fn openmesh_agrees_on_closed_meshes_and_differs_on_boundaries() {
    for (name, mesh) in [
        ("cube", shapes::cube(2.0).unwrap()),
        ("torus", shapes::torus(12, 8, 2.0, 0.5).unwrap()),
    ] {
        let ours = catmull_clark(&mesh, &SubdivideOptions::with_levels(2)).unwrap();
        let om = r::openmesh_catmull_clark(&to_ref(&mesh).0, 2).unwrap();
        assert_eq!(
            om.positions.len(),
            ours.mesh.vertex_count() as usize,
            "{name}"
        );
        // OpenMesh numbers vertices differently: compare as sets.
        let d = diag(&mesh);
        let mut a: Vec<[i64; 3]> = ours
            .mesh
            .positions()
            .iter()
            .map(|p| p.to_array().map(|c| (c / d * 1e9).round() as i64))
            .collect();
        let mut b: Vec<[i64; 3]> = om
            .positions
            .iter()
            .map(|p| p.map(|c| (c / d * 1e9).round() as i64))
            .collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(
            a, b,
            "{name}: katachi and OpenMesh agree on a closed uncreased mesh"
        );
    }
    // Spec §4.1: a boundary vertex at z = 0 between boundary neighbours at z = 1 goes to 0.25
    // with the standard rule (katachi, OpenSubdiv) and to 1/3 with OpenMesh's.
    let mut g = shapes::grid(2, 2).unwrap();
    let mut p = g.positions().to_vec();
    for v in [0usize, 2] {
        p[v].z = 1.0;
    }
    g.set_positions(p).unwrap();
    let ours = catmull_clark(&g, &SubdivideOptions::default()).unwrap();
    assert!((ours.mesh.position(VertexId(1)).z - 0.25).abs() < 1e-12);
    let om = r::openmesh_catmull_clark(&to_ref(&g).0, 1).unwrap();
    let x = ours.mesh.position(VertexId(1));
    let near = om
        .positions
        .iter()
        .min_by(|a, b| {
            let da = (DVec3::from_array(**a).truncate() - x.truncate()).length();
            let db = (DVec3::from_array(**b).truncate() - x.truncate()).length();
            da.total_cmp(&db)
        })
        .unwrap();
    assert!(
        (near[2] - 1.0 / 3.0).abs() < 1e-12,
        "OpenMesh's boundary rule gives 1/3, got {}",
        near[2]
    );
}

/// A torus with a UV map whose seams run along one meridian and one parallel: UV vertex
/// (i, j) for i in 0..=m, j in 0..=n, so the seam corners are UV boundaries.
fn uv_torus(m: u32, n: u32) -> (PolyMesh, Vec<[f64; 2]>, Vec<u32>) {
    let mesh = shapes::torus(m, n, 2.0, 0.5).unwrap();
    let uv: Vec<[f64; 2]> = (0..=m)
        .flat_map(|i| (0..=n).map(move |j| [i as f64 / m as f64, j as f64 / n as f64]))
        .collect();
    let id = |i: u32, j: u32| i * (n + 1) + j;
    let mut idx = Vec::new();
    for i in 0..m {
        for j in 0..n {
            idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (mesh, uv, idx)
}

#[test]
fn face_varying_matches_opensubdiv() {
    use katachi::subdivide::{FaceVarying, Refiner};
    let (torus, uv, idx) = uv_torus(8, 6);
    let mut creased = torus.clone();
    creased
        .set_edge_sharpnesses([
            (VertexId(0), VertexId(1), 2.0),
            (VertexId(1), VertexId(2), 2.0),
        ])
        .unwrap();
    // An open grid with a UV map equal to its xy coordinates (UV boundary = mesh boundary).
    let grid = shapes::grid(3, 2).unwrap();
    let guv: Vec<[f64; 2]> = grid
        .positions()
        .iter()
        .map(|p| [p.x * 0.3, p.y * 0.5])
        .collect();
    let gidx: Vec<u32> = grid.corners().iter().map(|v| v.0).collect();
    let cases = [
        ("uv torus", &torus, &uv, &idx),
        ("creased uv torus", &creased, &uv, &idx),
        ("grid", &grid, &guv, &gidx),
    ];
    let modes = [
        (FaceVarying::Smooth, r::FVarLinear::None),
        (FaceVarying::LinearCornersOnly, r::FVarLinear::CornersOnly),
        (FaceVarying::LinearBoundaries, r::FVarLinear::Boundaries),
        (FaceVarying::LinearAll, r::FVarLinear::All),
    ];
    for (name, mesh, uv, idx) in cases {
        let (rm, rc) = to_ref(mesh);
        for (ours_mode, osd_mode) in modes {
            for level in 1..=3 {
                let refiner = Refiner::new(mesh, &SubdivideOptions::with_levels(level)).unwrap();
                let uv2: Vec<glam_like::V2> = uv.iter().map(|p| glam_like::V2(*p)).collect();
                let ours = refiner.refine_face_varying(&uv2, idx, ours_mode).unwrap();
                let osd_opts = r::OsdOptions {
                    fvar: osd_mode,
                    ..Default::default()
                };
                let (_, theirs) = r::osd_catmark_fvar(&rm, &rc, &osd_opts, level, uv, idx).unwrap();
                assert_eq!(ours.len(), theirs.len(), "{name} {ours_mode:?} L{level}");
                for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
                    let e = ((a.0[0] - b[0]).powi(2) + (a.0[1] - b[1]).powi(2)).sqrt();
                    assert!(
                        e < 1e-12,
                        "{name} {ours_mode:?} L{level} corner {k}: katachi {:?}, OpenSubdiv {b:?}",
                        a.0
                    );
                }
            }
        }
    }
}

/// A 2-vector as a katachi primvar, without depending on glam here.
mod glam_like {
    #[derive(Clone, Debug)]
    pub struct V2(pub [f64; 2]);
    impl katachi::subdivide::Primvar for V2 {
        fn zero() -> Self {
            V2([0.0; 2])
        }
        fn add_scaled(&mut self, o: &Self, w: f64) {
            self.0[0] += w * o.0[0];
            self.0[1] += w * o.0[1];
        }
    }
}

/// Spec §5.4: method [a] on a square face with a square hole equals OpenSubdiv on the mesh in
/// which the annulus is split into the four trapezoids (compared as point sets: the bridged
/// faces are numbered differently).
#[test]
fn method_a_square_in_square_equals_opensubdiv_on_the_bridged_mesh() {
    use katachi::subdivide::HoleMethod;
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    let bridged = shapes::bridged_plate(4.0, 2.0, 1.0).unwrap();
    let (rm, rc) = to_ref(&bridged);
    let d = diag(&plate);
    let key = |p: [f64; 3]| p.map(|c| (c / d * 1e9).round() as i64);
    for level in 1..=3 {
        let mut o = SubdivideOptions::with_levels(level);
        o.holes = HoleMethod::Smooth;
        let ours = catmull_clark(&plate, &o).unwrap();
        assert!(ours.report.fell_back_to_sharp.is_empty());
        let theirs = r::osd_catmark(&rm, &rc, &r::OsdOptions::default(), level).unwrap();
        let mut a: Vec<_> = ours
            .mesh
            .positions()
            .iter()
            .map(|p| key(p.to_array()))
            .collect();
        let mut b: Vec<_> = theirs.positions.iter().map(|p| key(*p)).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b, "level {level}");
        assert_eq!(ours.mesh.face_count() as usize, theirs.face_sizes.len());
    }
}
