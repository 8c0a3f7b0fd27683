//! The test models: every bundled model (`tests/data/models`) reads, and its counts and
//! defects match the table in its README; with a corpus (`KATACHI_CORPUS`, or
//! `../shared/data/models` beside the checkout), every corpus model matches the corpus's
//! `MANIFEST.md` the same way (file I/O module, with `katachi::mesh::inspect`).
//!
//! The expected numbers are parsed from the tables themselves, so the tests and the tables
//! cannot drift apart, and a model added to a table is tested without editing this file.
//! tobj, the OBJ crate the project depends on, serves as an independent oracle for face
//! sizes and corner positions of the OBJ models.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use katachi::io::{self, Format, PlyEncoding, WriteOptions};
use katachi::mesh::{inspect, EdgeId, MeshReport, TopologyOptions};
use katachi::{PolyMesh, Topology};

mod support;
use support::models;

/// A folder of models and the table describing them.
struct Set {
    dir: PathBuf,
    table: &'static str,
    rows: Vec<Row>,
    corpus: bool,
}

/// The bundled models, and the corpus when one is given (else `test` is recorded as not run
/// over it).
fn sets(test: &str) -> Vec<Set> {
    let bundled = models::bundled_dir();
    let rows = table(&bundled, "README.md");
    assert!(
        rows.len() >= 9,
        "tests/data/models/README.md: only {} model rows",
        rows.len()
    );
    let mut v = vec![Set {
        dir: bundled,
        table: "README.md",
        rows,
        corpus: false,
    }];
    match models::corpus() {
        Some(dir) => {
            let rows = table(&dir, "MANIFEST.md");
            v.push(Set {
                dir,
                table: "MANIFEST.md",
                rows,
                corpus: true,
            });
        }
        None => models::not_run(test, "every corpus model in MANIFEST.md"),
    }
    v
}

fn table(dir: &Path, name: &str) -> Vec<Row> {
    let path = dir.join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (a model folder needs a table of its models, as ../shared/data/models/MANIFEST.md)",
            path.display()
        )
    });
    let rows = parse_manifest(&text);
    assert!(!rows.is_empty(), "{}: no model rows", path.display());
    rows
}

/// One row of MANIFEST.md, with the columns this test checks.
#[derive(Debug)]
struct Row {
    file: String,
    bytes: u64,
    vertices: u32,
    unreferenced: u32,
    faces: u32,
    kinds: BTreeMap<u32, u32>,
    closed: bool,
    genus: Option<i64>,
    boundary_loops: u32,
    boundary_edges: u32,
    non_manifold_edges: u32,
    non_manifold_vertices: u32,
    components: u32,
    coincident: u32,
    zero_area: u32,
}

/// The integer before `word` in `s` ("5 loops" → 5), if any.
fn number_before(s: &str, word: &str) -> Option<u32> {
    let i = s.find(word)?;
    s[..i]
        .split(|c: char| !c.is_ascii_digit())
        .rev()
        .find(|t| !t.is_empty())?
        .parse()
        .ok()
}

fn bad(line: &str, what: &str) -> ! {
    panic!("MANIFEST.md: cannot read {what} in row: {line}")
}

fn parse_manifest(text: &str) -> Vec<Row> {
    let mut rows = Vec::new();
    for line in text.lines() {
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        if cols.len() < 13 || !cols[1].contains('.') || cols[1] == "file" {
            continue;
        }
        let (v, unref) = match cols[5].split_once('(') {
            Some((v, u)) => (
                v,
                number_before(u, "unref").unwrap_or_else(|| bad(line, "V")),
            ),
            None => (cols[5], 0),
        };
        let kinds = cols[7]
            .split(',')
            .map(|k| {
                let (n, c) = k
                    .trim()
                    .split_once("-gon:")
                    .unwrap_or_else(|| bad(line, "kinds"));
                (n.parse().unwrap(), c.parse().unwrap())
            })
            .collect();
        let closed = cols[8].starts_with("yes");
        let genus = cols[8]
            .split_once("g=")
            .map(|(_, g)| g.trim_end_matches(')').parse().unwrap());
        let other = cols[11];
        rows.push(Row {
            file: cols[1].to_string(),
            bytes: cols[2].parse().unwrap_or_else(|_| bad(line, "bytes")),
            vertices: v.trim().parse().unwrap_or_else(|_| bad(line, "V")),
            unreferenced: unref,
            faces: cols[6].parse().unwrap_or_else(|_| bad(line, "F")),
            kinds,
            closed,
            genus,
            boundary_loops: number_before(cols[8], "loops").unwrap_or(0),
            boundary_edges: number_before(cols[8], "edges").unwrap_or(0),
            non_manifold_edges: if cols[9].starts_with("NO") {
                number_before(cols[9], "edges").unwrap_or_else(|| bad(line, "edge-manifold"))
            } else {
                0
            },
            non_manifold_vertices: if cols[10].starts_with("NO") {
                number_before(cols[10], "verts").unwrap_or_else(|| bad(line, "vertex-manifold"))
            } else {
                0
            },
            components: number_before(other, "components").unwrap_or(1),
            coincident: number_before(other, "coinc").unwrap_or(0),
            zero_area: number_before(other, "zero-area").unwrap_or(0),
        });
    }
    rows
}

/// Where `inspect` and the manifest count differently. Each entry is checked to still
/// hold, so a fix to `inspect` fails this test and asks for the entry to be removed.
/// (file, quantity, manifest's value, inspect's value, why)
const INSPECT_DISAGREES: &[(&str, &str, u32, u32, &str)] = &[];

fn check(file: &str, quantity: &str, manifest: u32, inspect: u32, errors: &mut Vec<String>) {
    let known = INSPECT_DISAGREES
        .iter()
        .find(|d| d.0 == file && d.1 == quantity);
    match known {
        None if manifest != inspect => errors.push(format!(
            "{file}: {quantity}: manifest {manifest}, inspect {inspect}"
        )),
        Some(d) if manifest != d.2 || inspect != d.3 => errors.push(format!(
            "{file}: {quantity}: known disagreement changed (manifest {manifest}, inspect \
             {inspect}; recorded {} and {}): if inspect was fixed, remove the entry from \
             INSPECT_DISAGREES",
            d.2, d.3
        )),
        _ => {}
    }
}

/// Boundary curves: connected components of the boundary edges, joined at vertices.
fn boundary_curves(mesh: &PolyMesh, topo: &Topology) -> u32 {
    let mut uf = UnionFind::new(mesh.vertex_count() as usize);
    let mut on_boundary = vec![false; mesh.vertex_count() as usize];
    for e in 0..topo.edge_count() {
        if topo.is_boundary_edge(EdgeId(e)) {
            let [a, b] = topo.edge_vertices(EdgeId(e));
            uf.union(a.idx(), b.idx());
            on_boundary[a.idx()] = true;
            on_boundary[b.idx()] = true;
        }
    }
    uf.count_roots((0..on_boundary.len()).filter(|&v| on_boundary[v]))
}

/// Face components joined by shared undirected edges (vertex pairs), however many faces
/// share them.
fn edge_joined_components(mesh: &PolyMesh) -> u32 {
    let mut uf = UnionFind::new(mesh.face_count() as usize);
    let mut first_face: std::collections::HashMap<(u32, u32), usize> = Default::default();
    for f in mesh.faces() {
        let lp = mesh.face_outer(f);
        for (i, a) in lp.iter().enumerate() {
            let b = lp[(i + 1) % lp.len()];
            let key = (a.0.min(b.0), a.0.max(b.0));
            let g = *first_face.entry(key).or_insert(f.idx());
            uf.union(g, f.idx());
        }
    }
    uf.count_roots(0..mesh.face_count() as usize)
}

struct UnionFind(Vec<usize>);

impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind((0..n).collect())
    }
    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        self.0[ra] = rb;
    }
    fn count_roots(&mut self, items: impl Iterator<Item = usize>) -> u32 {
        let roots: std::collections::BTreeSet<usize> = items.map(|i| self.find(i)).collect();
        roots.len() as u32
    }
}

fn check_row(row: &Row, mesh: &PolyMesh, r: &MeshReport, errors: &mut Vec<String>) {
    let f = row.file.as_str();
    let mut eq = |what: &str, manifest: u32, got: u32| check(f, what, manifest, got, errors);
    eq("vertices", row.vertices, r.vertices);
    eq(
        "unreferenced vertices",
        row.unreferenced,
        r.unreferenced_vertices,
    );
    eq("faces", row.faces, r.faces);
    eq("components", row.components, r.components);
    eq("coincident vertices", row.coincident, r.coincident_vertices);
    eq(
        "zero-area faces",
        row.zero_area,
        r.zero_area_faces.len() as u32,
    );
    eq("boundary edges", row.boundary_edges, r.boundary_edges);
    eq("boundary loops", row.boundary_loops, r.boundary_loops);
    eq(
        "non-manifold edges",
        row.non_manifold_edges,
        r.defects.non_manifold_edges.len() as u32,
    );
    eq(
        "non-manifold vertices",
        row.non_manifold_vertices,
        r.defects.non_manifold_vertices.len() as u32,
    );
    if r.faces_by_size != row.kinds {
        errors.push(format!(
            "{f}: face kinds: manifest {:?}, read {:?}",
            row.kinds, r.faces_by_size
        ));
    }
    if row.closed != r.is_closed() {
        errors.push(format!(
            "{f}: closed: manifest {}, read {}",
            row.closed,
            r.is_closed()
        ));
    }
    if row.genus.is_some() && row.genus != r.genus {
        errors.push(format!(
            "{f}: genus: manifest {:?}, read {:?}",
            row.genus, r.genus
        ));
    }
    // The manifest's own definitions, computed here from the mesh as read.
    let topo = Topology::build(mesh, &TopologyOptions::tolerant()).unwrap();
    let curves = boundary_curves(mesh, &topo);
    if curves != row.boundary_loops {
        errors.push(format!(
            "{f}: boundary curves: manifest {}, read {curves}",
            row.boundary_loops
        ));
    }
    let comps = edge_joined_components(mesh);
    if comps != row.components {
        errors.push(format!(
            "{f}: edge-joined components: manifest {}, read {comps}",
            row.components
        ));
    }
}

#[test]
fn every_model_matches_its_table() {
    const TEST: &str = "io_models::every_model_matches_its_table";
    let mut errors = Vec::new();
    for set in sets(TEST) {
        // Every model file in the folder has a row, and the other way round.
        let mut on_disk: Vec<String> = std::fs::read_dir(&set.dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| Format::from_path(Path::new(n)).is_ok())
            .collect();
        on_disk.sort();
        let mut listed: Vec<String> = set.rows.iter().map(|r| r.file.clone()).collect();
        listed.sort();
        assert_eq!(
            on_disk,
            listed,
            "{}: model files and {} rows differ",
            set.dir.display(),
            set.table
        );
        for row in &set.rows {
            let path = set.dir.join(&row.file);
            let size = std::fs::metadata(&path).unwrap().len();
            if size != row.bytes {
                errors.push(format!(
                    "{}: {} bytes, {} says {}",
                    row.file, size, set.table, row.bytes
                ));
            }
            let mesh = match io::read(&path) {
                Ok(m) => m,
                Err(e) => {
                    errors.push(format!("{}: does not read: {e}", row.file));
                    continue;
                }
            };
            let report = inspect(&mesh).unwrap();
            check_row(row, &mesh, &report, &mut errors);
            if set.corpus {
                models::ran(TEST, &row.file);
            }
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// The corpus's broken models (their licenses do not allow bundling them).
#[test]
fn defective_models_report_their_defects() {
    let Some(paths) = models::corpus_models(
        "io_models::defective_models_report_their_defects",
        &[
            "degenerated.obj",
            "teapot.obj",
            "cgal_all_degen.off",
            "cgal_non_manifold_face_graph.off",
        ],
    ) else {
        return;
    };
    let dir = paths[0].parent().unwrap().to_path_buf();
    // degenerated.obj: 12 triangles, each also written reversed; the 6 edges at vertex 0
    // carry 8 face sides each, so 12 directed half-edges occur more than once.
    let m = io::read(&dir.join("degenerated.obj")).unwrap();
    let r = inspect(&m).unwrap();
    assert_eq!(r.defects.non_manifold_edges.len(), 6);
    assert!(r
        .defects
        .non_manifold_edges
        .iter()
        .all(|&(_, _, uses)| uses == 8));
    let mut directed: BTreeMap<(u32, u32), u32> = BTreeMap::new();
    for f in m.faces() {
        let lp = m.face_outer(f);
        for (i, a) in lp.iter().enumerate() {
            *directed.entry((a.0, lp[(i + 1) % lp.len()].0)).or_default() += 1;
        }
    }
    assert_eq!(directed.values().filter(|&&n| n > 1).count(), 12);
    assert!(
        m.connectivity().is_err(),
        "the strict topology must refuse it"
    );

    let m = io::read(&dir.join("teapot.obj")).unwrap();
    let r = inspect(&m).unwrap();
    assert_eq!(r.defects.non_manifold_vertices.len(), 38);
    assert_eq!(r.components, 19);
    assert_eq!(r.coincident_vertices, 403);
    assert_eq!(r.boundary_edges, 1036);
    assert!(r.defects.non_manifold_edges.is_empty());

    let m = io::read(&dir.join("cgal_all_degen.off")).unwrap();
    let r = inspect(&m).unwrap();
    assert_eq!(r.zero_area_faces.len(), 7);
    assert_eq!(r.defects.non_manifold_vertices.len(), 1);
    assert_eq!(r.coincident_vertices, 3);

    let m = io::read(&dir.join("cgal_non_manifold_face_graph.off")).unwrap();
    let r = inspect(&m).unwrap();
    assert_eq!(
        (r.components, r.boundary_loops, r.coincident_vertices),
        (3, 3, 3)
    );
    for p in &paths {
        models::ran(
            "io_models::defective_models_report_their_defects",
            &p.file_name().unwrap().to_string_lossy(),
        );
    }
}

/// Face sizes and corner positions agree with tobj (which renumbers vertices and reads
/// `f32`, so corners are compared by position, to `f32` precision).
#[test]
fn obj_models_agree_with_tobj() {
    const TEST: &str = "io_models::obj_models_agree_with_tobj";
    let opts = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ..Default::default()
    };
    let mut checked = 0;
    for set in sets(TEST) {
        for row in set.rows.iter().filter(|r| r.file.ends_with(".obj")) {
            let path = set.dir.join(&row.file);
            obj_agrees_with_tobj(&path, &row.file, &opts);
            checked += 1;
            if set.corpus {
                models::ran(TEST, &row.file);
            }
        }
    }
    assert!(checked >= 3, "only {checked} OBJ models");
}

fn obj_agrees_with_tobj(path: &Path, file: &str, opts: &tobj::LoadOptions) {
    {
        let mesh = io::read(path).unwrap();
        let (objects, _) = tobj::load_obj(path, opts).unwrap();
        let mut face = 0u32;
        for model in &objects {
            let tm = &model.mesh;
            let nf = if tm.face_arities.is_empty() {
                tm.indices.len() / 3
            } else {
                tm.face_arities.len()
            };
            let mut k = 0usize;
            for i in 0..nf {
                let arity = tm.face_arities.get(i).copied().unwrap_or(3) as usize;
                let ours = mesh.face_outer(katachi::FaceId(face));
                assert_eq!(ours.len(), arity, "{}: face {face} size", file);
                for (j, v) in ours.iter().enumerate() {
                    let t = tm.indices[k + j] as usize;
                    let p = mesh.position(*v);
                    for (c, ours) in [p.x, p.y, p.z].into_iter().enumerate() {
                        let theirs = tm.positions[3 * t + c] as f64;
                        assert!(
                            (ours - theirs).abs() <= 1e-6 * ours.abs().max(1.0),
                            "{}: face {face} corner {j}: {ours} vs tobj {theirs}",
                            file
                        );
                    }
                }
                k += arity;
                face += 1;
            }
        }
        assert_eq!(face, mesh.face_count(), "{}: face count", file);
    }
}

fn assert_same(a: &PolyMesh, b: &PolyMesh, what: &str) {
    assert_eq!(a.vertex_count(), b.vertex_count(), "{what}: vertex count");
    for (i, (p, q)) in a.positions().iter().zip(b.positions()).enumerate() {
        assert_eq!(
            p.to_array().map(f64::to_bits),
            q.to_array().map(f64::to_bits),
            "{what}: vertex {i} is not bit-exact"
        );
    }
    assert_eq!(a.loop_offsets(), b.loop_offsets(), "{what}: loops");
    assert_eq!(
        a.face_loop_offsets(),
        b.face_loop_offsets(),
        "{what}: faces"
    );
    assert_eq!(a.corners(), b.corners(), "{what}: corners");
}

/// Models written in every format read back bit-exact, unreferenced vertices, n-gons,
/// components and PLY input included (the corpus's bunny, beast, teapot and PLY).
#[test]
fn models_round_trip_in_every_format() {
    const TEST: &str = "io_models::models_round_trip_in_every_format";
    let mut paths: Vec<PathBuf> = [
        "L.off",
        "greek_helmet.obj",
        "rhombicosidodecahedron.obj",
        "hole_capsule.off",
    ]
    .iter()
    .map(|n| models::bundled(n))
    .collect();
    let corpus = [
        "stanford-bunny.obj",
        "beast.obj",
        "teapot.obj",
        "two-boxes-bad-self-union.ply",
    ];
    if let Some(more) = models::corpus_models(TEST, &corpus) {
        paths.extend(more);
    }
    for path in &paths {
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        let mesh = io::read(path).unwrap();
        for (format, enc) in [
            (Format::Obj, PlyEncoding::Ascii),
            (Format::Off, PlyEncoding::Ascii),
            (Format::Ply, PlyEncoding::Ascii),
            (Format::Ply, PlyEncoding::BinaryLittleEndian),
            (Format::Ply, PlyEncoding::BinaryBigEndian),
        ] {
            let mut buf = Vec::new();
            io::write_to(
                &mut buf,
                format,
                &mesh,
                &WriteOptions::with_ply_encoding(enc),
            )
            .unwrap();
            let back = io::read_bytes(&buf, format, Path::new(&file)).unwrap();
            assert_same(&mesh, &back, &format!("{file} as {format:?} {enc:?}"));
        }
        if corpus.contains(&file.as_str()) {
            models::ran(TEST, &file);
        }
    }
}
