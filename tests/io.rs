//! File I/O: OBJ, PLY and OFF readers and writers (the `io` module).
//!
//! Round trips on generated shapes, every form of each format the readers promise to
//! accept, every malformed-input error with its line or byte, and property tests that no
//! bytes make a reader panic.

use std::path::{Path, PathBuf};

use katachi::io::{self, obj, off, ply, Format, PlyEncoding, WriteOptions};
use katachi::mesh::shapes;
use katachi::{DVec3, Error, PolyMesh, VertexId};
use proptest::prelude::*;

mod support;
use support::property::counted_proptest;

// ---------------------------------------------------------------------------------------
// helpers

/// A fresh, empty directory for one test.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("katachi-io-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn read_obj(s: &str) -> katachi::Result<PolyMesh> {
    obj::read_bytes(s.as_bytes(), Path::new("t.obj"))
}
fn read_off(s: &str) -> katachi::Result<PolyMesh> {
    off::read_bytes(s.as_bytes(), Path::new("t.off"))
}
fn read_ply(b: &[u8]) -> katachi::Result<PolyMesh> {
    ply::read_bytes(b, Path::new("t.ply"))
}

/// The line, byte and message of a parse error; panics on any other result.
fn parse_err(r: katachi::Result<PolyMesh>) -> (usize, Option<u64>, String) {
    match r {
        Err(Error::Parse {
            line,
            byte,
            message,
            ..
        }) => (line, byte, message),
        Err(e) => panic!("expected a parse error, got {e:?}"),
        Ok(m) => panic!(
            "expected a parse error, got a mesh with {} vertices",
            m.vertex_count()
        ),
    }
}

fn assert_same(a: &PolyMesh, b: &PolyMesh, what: &str) {
    assert_eq!(a.vertex_count(), b.vertex_count(), "{what}: vertex count");
    for (i, (p, q)) in a.positions().iter().zip(b.positions()).enumerate() {
        assert_eq!(
            p.to_array().map(f64::to_bits),
            q.to_array().map(f64::to_bits),
            "{what}: vertex {i} is not bit-exact ({p} vs {q})"
        );
    }
    assert_eq!(
        a.face_loop_offsets(),
        b.face_loop_offsets(),
        "{what}: faces"
    );
    assert_eq!(a.loop_offsets(), b.loop_offsets(), "{what}: loops");
    assert_eq!(a.corners(), b.corners(), "{what}: corners");
}

const ALL_WRITERS: [(Format, PlyEncoding); 5] = [
    (Format::Obj, PlyEncoding::Ascii),
    (Format::Off, PlyEncoding::Ascii),
    (Format::Ply, PlyEncoding::Ascii),
    (Format::Ply, PlyEncoding::BinaryLittleEndian),
    (Format::Ply, PlyEncoding::BinaryBigEndian),
];

fn round_trip(mesh: &PolyMesh, format: Format, enc: PlyEncoding) -> PolyMesh {
    let mut buf = Vec::new();
    io::write_to(
        &mut buf,
        format,
        mesh,
        &WriteOptions::with_ply_encoding(enc),
    )
    .unwrap();
    io::read_bytes(&buf, format, Path::new("round-trip")).unwrap()
}

/// A triangle and a quad sharing an edge, positions that need all 17 digits.
fn awkward_mesh() -> PolyMesh {
    let p = vec![
        DVec3::new(0.1, 0.2, 0.30000000000000004),
        DVec3::new(1.0 / 3.0, -0.0, 1e-300),
        DVec3::new(-1.7976931348623157e308, 5e-324, 123456789.12345679),
        DVec3::new(2.0f64.sqrt(), std::f64::consts::PI, -1e16),
        DVec3::new(9.999999999999999e-6, 1e22, -5e-324),
    ];
    PolyMesh::from_polygons(p, [vec![0u32, 1, 2], vec![1, 3, 4, 2]]).unwrap()
}

// ---------------------------------------------------------------------------------------
// formats, paths and files

#[test]
fn format_comes_from_the_extension_case_insensitively() {
    for (name, f) in [
        ("a.obj", Format::Obj),
        ("a.OBJ", Format::Obj),
        ("dir.x/a.Ply", Format::Ply),
        ("a.off", Format::Off),
        ("a.OfF", Format::Off),
    ] {
        assert_eq!(Format::from_path(Path::new(name)).unwrap(), f, "{name}");
    }
    for name in ["a.stl", "a", "a.obj.gz", "obj"] {
        assert!(
            matches!(Format::from_path(Path::new(name)), Err(Error::UnknownFormat { ref path }) if path == Path::new(name)),
            "{name}"
        );
    }
}

#[test]
fn unknown_extension_is_refused_for_read_and_write() {
    let dir = temp_dir("unknown-ext");
    let path = dir.join("mesh.stl");
    std::fs::write(&path, b"solid x").unwrap();
    let e = io::read(&path).unwrap_err();
    assert!(matches!(e, Error::UnknownFormat { .. }), "{e:?}");
    assert!(e.to_string().contains("mesh.stl"), "{e}");
    let e = io::write(&dir.join("out.xyz"), &shapes::cube(1.0).unwrap()).unwrap_err();
    assert!(matches!(e, Error::UnknownFormat { .. }), "{e:?}");
    assert!(!dir.join("out.xyz").exists());
}

#[test]
fn missing_file_is_an_io_error_naming_the_path() {
    let path = Path::new("/nonexistent/katachi/missing.obj");
    match io::read(path) {
        Err(e @ Error::Io { .. }) => {
            assert!(
                e.to_string().contains("/nonexistent/katachi/missing.obj"),
                "{e}"
            );
            assert_eq!(e.kind(), katachi::ErrorKind::Io);
        }
        other => panic!("{other:?}"),
    }
    let e = io::write(
        Path::new("/nonexistent/katachi/out.ply"),
        &shapes::cube(1.0).unwrap(),
    )
    .unwrap_err();
    assert!(
        matches!(e, Error::Io { ref path, .. } if path.ends_with("out.ply")),
        "{e:?}"
    );
}

#[test]
fn files_round_trip_through_disk_in_every_format() {
    let dir = temp_dir("disk");
    let mesh = shapes::ngon_prism(7, 1.3, 0.7).unwrap();
    for ext in ["obj", "OFF", "ply"] {
        let path = dir.join(format!("prism.{ext}"));
        io::write(&path, &mesh).unwrap();
        assert_same(&mesh, &io::read(&path).unwrap(), ext);
    }
    // .ply defaults to binary little-endian.
    let bytes = std::fs::read(dir.join("prism.ply")).unwrap();
    assert!(bytes.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
    let path = dir.join("ascii.ply");
    io::write_with(
        &path,
        &mesh,
        &WriteOptions::with_ply_encoding(PlyEncoding::Ascii),
    )
    .unwrap();
    assert!(std::fs::read(&path)
        .unwrap()
        .starts_with(b"ply\nformat ascii 1.0\n"));
    assert_same(&mesh, &io::read(&path).unwrap(), "ascii ply");
}

// ---------------------------------------------------------------------------------------
// round trips

#[test]
fn generated_shapes_round_trip_bit_exact_in_every_format() {
    let shapes = [
        ("cube", shapes::cube(2.0).unwrap()),
        ("prism", shapes::ngon_prism(9, 1.0, 2.5).unwrap()),
        ("torus", shapes::torus(12, 7, 2.0, 0.5).unwrap()),
        ("grid", shapes::grid(5, 3).unwrap()),
        ("awkward", awkward_mesh()),
        ("empty", PolyMesh::new()),
    ];
    for (name, mesh) in &shapes {
        for (format, enc) in ALL_WRITERS {
            let back = round_trip(mesh, format, enc);
            assert_same(mesh, &back, &format!("{name} as {format:?} {enc:?}"));
        }
    }
}

#[test]
fn big_faces_use_a_wide_list_count_in_ply() {
    // 300 corners do not fit a uchar count.
    let n = 300;
    let p: Vec<DVec3> = (0..n)
        .map(|i| {
            let t = i as f64 / n as f64 * std::f64::consts::TAU;
            DVec3::new(t.cos(), t.sin(), 0.0)
        })
        .collect();
    let mesh = PolyMesh::from_polygons(p, [(0..n).collect::<Vec<u32>>()]).unwrap();
    for (format, enc) in ALL_WRITERS {
        assert_same(
            &mesh,
            &round_trip(&mesh, format, enc),
            &format!("{format:?} {enc:?}"),
        );
    }
}

#[test]
fn obj_keeps_edge_and_vertex_sharpness() {
    let mut mesh = shapes::cube(1.0).unwrap();
    mesh.set_edge_sharpnesses([
        (VertexId(0), VertexId(2), 10.0),
        (VertexId(3), VertexId(2), 0.1),
        (VertexId(4), VertexId(5), 2.0 / 3.0),
    ])
    .unwrap();
    mesh.set_vertex_sharpness(VertexId(7), 3.25).unwrap();
    mesh.set_vertex_sharpness(VertexId(1), 1e-9).unwrap();
    let mut buf = Vec::new();
    obj::write_to(&mut buf, &mesh).unwrap();
    let text = String::from_utf8(buf.clone()).unwrap();
    assert!(text.contains("t crease 2/1/0 0 2 10\n"), "{text}");
    assert!(text.contains("t corner 1/1/0 7 3.25\n"), "{text}");
    let back = obj::read_bytes(&buf, Path::new("cube.obj")).unwrap();
    assert_same(&mesh, &back, "cube");
    assert_eq!(
        back.sharp_edges().collect::<Vec<_>>(),
        mesh.sharp_edges().collect::<Vec<_>>()
    );
    assert_eq!(back.vertex_sharpness(), mesh.vertex_sharpness());
}

#[test]
fn faces_with_holes_are_refused_naming_the_face_and_format() {
    let dir = temp_dir("holes");
    let plate = shapes::plate_with_hole(4.0, 2.0, 1.0).unwrap();
    for (format, enc) in ALL_WRITERS {
        let mut buf = Vec::new();
        let e = io::write_to(
            &mut buf,
            format,
            &plate,
            &WriteOptions::with_ply_encoding(enc),
        )
        .unwrap_err();
        let msg = e.to_string();
        assert!(matches!(e, Error::InvalidArgument(_)), "{e:?}");
        assert!(msg.contains("face 0 has 1 hole"), "{msg}");
        assert!(msg.contains(format.name()), "{msg}");
        assert!(buf.is_empty(), "nothing is written before the refusal");
    }
    // An existing file is left untouched.
    let path = dir.join("keep.obj");
    std::fs::write(&path, b"v 0 0 0\n").unwrap();
    assert!(io::write(&path, &plate).is_err());
    assert_eq!(std::fs::read(&path).unwrap(), b"v 0 0 0\n");
}

// ---------------------------------------------------------------------------------------
// OBJ

#[test]
fn obj_ignores_what_is_not_geometry_and_keeps_numbering() {
    let src = "\
# comment\r
mtllib missing.mtl\r
o first\r
v 0 0 0\r
v 1 0 0 1.0\r
v 1 1 0 0.5 0.5 0.5\r
v 9 9 9\r
v 0 1 0\r
vt 0 0\r
vt 1 0\r
vn 0 0 1\r
g group\r
usemtl none\r
s off\r
f 1/1/1 2/2/1 3/1/1\r
o second\r
f 1//1 3//1 5//1 # trailing comment\r
l 1 2\r
p 4\r
";
    let m = read_obj(src).unwrap();
    assert_eq!(m.vertex_count(), 5, "unreferenced vertex 3 is kept");
    assert_eq!(m.position(VertexId(3)), DVec3::new(9.0, 9.0, 9.0));
    assert_eq!(
        m.position(VertexId(1)),
        DVec3::new(1.0, 0.0, 0.0),
        "w is ignored"
    );
    assert_eq!(m.face_count(), 2, "lines and points are not faces");
    let ids = |f: u32| {
        m.face_outer(katachi::FaceId(f))
            .iter()
            .map(|v| v.0)
            .collect::<Vec<_>>()
    };
    assert_eq!(ids(0), vec![0, 1, 2]);
    assert_eq!(ids(1), vec![0, 2, 4]);
}

#[test]
fn obj_relative_indices_count_back_from_the_last_vertex() {
    let m = read_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4 -2/1 -1//2\n").unwrap();
    let ids = |f: u32| {
        m.face_outer(katachi::FaceId(f))
            .iter()
            .map(|v| v.0)
            .collect::<Vec<_>>()
    };
    assert_eq!(ids(0), vec![0, 1, 2]);
    assert_eq!(ids(1), vec![0, 2, 3]);
}

#[test]
fn obj_reads_every_opensubdiv_tag_form() {
    let src = "\
v 0 0 0
v 1 0 0
v 2 0 0
v 0 1 0
v 1 1 0
v 2 1 0
f 1 2 5 4
f 2 3 6 5
t interpolateboundary 1/0/0 2
t crease 2/1/0 0 1 10
t crease 3/1/0 3 4 5 2.5
t crease 3/2/0 2 5 4 0.5 0.75
t corner 1/1/0 0 1.5
t corner 2/1/0 2 5 4
t corner 2/2/0 3 4 6 7
t hole 1/0/0 0
";
    let m = read_obj(src).unwrap();
    let s = |a: u32, b: u32| m.edge_sharpness(VertexId(a), VertexId(b));
    assert_eq!(s(0, 1), 10.0);
    assert_eq!(
        (s(3, 4), s(4, 5)),
        (2.5, 0.75),
        "the chain's 2nd edge was re-tagged"
    );
    assert_eq!(s(2, 5), 0.5);
    assert_eq!(m.sharp_edges().len(), 4);
    assert_eq!(m.vertex_sharpness(), &[1.5, 0.0, 4.0, 6.0, 7.0, 4.0]);
}

#[test]
fn obj_tag_errors_name_the_line() {
    let base = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    for (tag, needle) in [
        (
            "t crease 2/1/0 0 2 1",
            "there is no edge between vertices 0 and 2",
        ),
        (
            "t crease 2/1/0 0 9 1",
            "there is no edge between vertices 0 and 9",
        ),
        (
            "t crease 3/1/0 0 1 3 1",
            "there is no edge between vertices 1 and 3",
        ),
        (
            "t crease 2/1/0 0 1",
            "1 sharpness values announced, only 0 given",
        ),
        ("t crease 2/1/0 0 1 -1", "sharpness -1 is invalid"),
        ("t crease 2/1/0 0 1 nan", "sharpness NaN is invalid"),
        (
            "t crease 3/3/0 0 1 2 1 1 1",
            "needs 1 or 2 sharpness values, got 3",
        ),
        ("t crease 1/1/0 0 1", "at least 2 vertices"),
        ("t crease 2/1 0 1 1", "expected argument counts like 2/1/0"),
        ("t crease 2/1/0 0 x 1", "'x' is not a vertex index"),
        ("t crease 2/1/0 -1 0 1", "vertex index -1 is out of range"),
        (
            "t corner 1/1/0 5 1",
            "vertex 5 is out of range (the mesh has 5 vertices)",
        ),
        (
            "t corner 2/3/0 0 1 1 1 1",
            "needs 1 or 2 sharpness values, got 3",
        ),
    ] {
        let (line, byte, msg) = parse_err(read_obj(&format!("{base}{tag}\nv 5 5 5\n")));
        assert_eq!((line, byte), (6, None), "{tag}: {msg}");
        assert!(msg.contains(needle), "{tag}: {msg}");
    }
}

#[test]
fn obj_errors_name_file_line_and_face() {
    let cases: &[(&str, usize, &str)] = &[
        ("v 0 0 0\nv 1 x 0\n", 2, "vertex 1: coordinate y 'x' is not a number"),
        ("v 0 0\n", 1, "needs 3 coordinates"),
        ("v 0 0 inf\n", 1, "coordinate z is inf, not a finite number"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 3\nf 1 2 4\n",
            6,
            "face 1, loop 0: vertex index 3 is out of range (the mesh has 3 vertices); OBJ indices count from 1",
        ),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", 4, "vertex index 0 is invalid"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4, "relative vertex index -4 reaches before the first vertex"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 a\n", 4, "'a' is not a vertex reference"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", 4, "face 0, loop 0: a loop needs at least 3 distinct vertices"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 2\n",
            5,
            "face 1, loop 0: vertex 1 appears more than once",
        ),
        ("v 0 0 0\n\u{1}\u{2} 1 2\n", 2, "is not an OBJ statement"),
    ];
    for &(src, line, needle) in cases {
        let r = read_obj(src);
        let e = r.as_ref().err().map(|e| e.to_string()).unwrap_or_default();
        let (l, byte, msg) = parse_err(r);
        assert_eq!((l, byte), (line, None), "{src:?}: {msg}");
        assert!(msg.contains(needle), "{src:?}: {msg}");
        assert!(e.starts_with(&format!("t.obj:{line}: ")), "{e}");
    }
}

// ---------------------------------------------------------------------------------------
// PLY

/// A PLY header for `body` elements, in the given format.
fn ply_header(format: &str, elements: &str) -> Vec<u8> {
    format!("ply\nformat {format} 1.0\ncomment test\n{elements}end_header\n").into_bytes()
}

#[test]
fn ply_ascii_with_extra_properties_any_order_and_other_elements() {
    let mut f = ply_header(
        "ascii",
        "element material 1\nproperty list uchar float rgb\nproperty uchar id\n\
         element vertex 4\nproperty float nx\nproperty double z\nproperty list uchar int tags\n\
         property float y\nproperty float x\n\
         element face 2\nproperty uchar flags\nproperty list ushort uint vertex_index\n\
         property list uchar float texcoord\n\
         element edge 1\nproperty int vertex1\nproperty int vertex2\n",
    );
    f.extend_from_slice(
        b"3 0.5 0.5 0.5 7\n\
          9 0 0 0 0\n9 0 2 1 2 0 1\n9 0.5 0 1 1\n9 0 0 0 1\n\
          0 3 0 1 2 6 0 0 1 0 1 1\n1 3 0 2 3 0\n\
          0 1\n",
    );
    let m = read_ply(&f).unwrap();
    assert_eq!(m.positions()[1], DVec3::new(1.0, 0.0, 0.0));
    assert_eq!(m.positions()[2], DVec3::new(1.0, 1.0, 0.5));
    assert_eq!(m.face_count(), 2);
    assert_eq!(
        m.face_outer(katachi::FaceId(1)),
        &[VertexId(0), VertexId(2), VertexId(3)]
    );
}

/// Little- or big-endian bytes of scalars, for hand-made binary bodies.
struct Body {
    big: bool,
    bytes: Vec<u8>,
}

impl Body {
    fn u8(&mut self, v: u8) -> &mut Self {
        self.bytes.push(v);
        self
    }
    fn u16(&mut self, v: u16) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.bytes.extend_from_slice(&b);
        self
    }
    fn i32(&mut self, v: i32) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.bytes.extend_from_slice(&b);
        self
    }
    fn f32(&mut self, v: f32) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.bytes.extend_from_slice(&b);
        self
    }
    fn f64(&mut self, v: f64) -> &mut Self {
        let b = if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        };
        self.bytes.extend_from_slice(&b);
        self
    }
}

/// A binary PLY that exercises skipping: an element with lists before the vertices,
/// vertices with a list and mixed types, faces with extra properties.
fn mixed_binary_ply(big: bool) -> Vec<u8> {
    let format = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut f = ply_header(
        format,
        "element material 2\nproperty list uchar float rgb\nproperty short id\n\
         element vertex 4\nproperty uchar flag\nproperty float y\nproperty list int uchar junk\n\
         property double x\nproperty short z\n\
         element face 2\nproperty list ushort int vertex_indices\nproperty float quality\n\
         property list uchar uchar more\n",
    );
    let mut b = Body {
        big,
        bytes: Vec::new(),
    };
    // materials: 3 floats + id, then an empty list + id
    b.u8(3).f32(0.1).f32(0.2).f32(0.3).u16(1).u8(0).u16(2);
    // vertices: flag, y, junk list, x, z
    for (i, (x, y, z)) in [(0.0, 0.0, 0), (1.5, 0.0, 0), (1.5, 1.0, 2), (0.0, 1.0, -3)]
        .into_iter()
        .enumerate()
    {
        b.u8(7).f32(y as f32).i32(i as i32);
        for k in 0..i {
            b.u8(k as u8);
        }
        b.f64(x).u16(z as i16 as u16);
    }
    // faces
    b.u16(3).i32(0).i32(1).i32(2).f32(0.5).u8(2).u8(9).u8(9);
    b.u16(3).i32(0).i32(2).i32(3).f32(0.5).u8(0);
    f.extend_from_slice(&b.bytes);
    f
}

#[test]
fn ply_binary_skips_other_elements_lists_and_properties_in_both_byte_orders() {
    for big in [false, true] {
        let m = read_ply(&mixed_binary_ply(big)).unwrap();
        assert_eq!(
            m.positions(),
            &[
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.5, 0.0, 0.0),
                DVec3::new(1.5, 1.0, 2.0),
                DVec3::new(0.0, 1.0, -3.0)
            ],
            "big-endian: {big}"
        );
        assert_eq!(m.face_count(), 2);
        assert_eq!(
            m.face_outer(katachi::FaceId(1)),
            &[VertexId(0), VertexId(2), VertexId(3)]
        );
    }
}

#[test]
fn ply_reads_float_vertices_and_narrow_index_types() {
    for (count_ty, index_ty) in [
        ("uchar", "uchar"),
        ("int", "ushort"),
        ("uint", "int"),
        ("char", "uint"),
    ] {
        let mut f = ply_header(
            "binary_little_endian",
            &format!(
                "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                 element face 1\nproperty list {count_ty} {index_ty} vertex_indices\n"
            ),
        );
        let mut b = Body {
            big: false,
            bytes: Vec::new(),
        };
        for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.25, 0.0]] {
            b.f32(v[0]).f32(v[1]).f32(v[2]);
        }
        let size = |t: &str| match t {
            "uchar" | "char" => 1,
            "ushort" => 2,
            _ => 4,
        };
        for (ty, v) in
            [(count_ty, 3u32)]
                .into_iter()
                .chain([(index_ty, 2), (index_ty, 0), (index_ty, 1)])
        {
            b.bytes.extend_from_slice(&v.to_le_bytes()[..size(ty)]);
        }
        f.extend_from_slice(&b.bytes);
        let m = read_ply(&f).unwrap_or_else(|e| panic!("{count_ty} {index_ty}: {e}"));
        assert_eq!(m.positions()[2], DVec3::new(0.0, 0.25, 0.0));
        assert_eq!(
            m.face_outer(katachi::FaceId(0)),
            &[VertexId(2), VertexId(0), VertexId(1)]
        );
    }
}

/// Regression: an element with no properties and a huge count holds no data; reading it
/// must not loop over its records.
#[test]
fn ply_elements_without_properties_cost_nothing() {
    for format in ["ascii", "binary_little_endian"] {
        let f = ply_header(
            format,
            "element nothing 18446744073709551615\nelement vertex 0\nproperty float x\n\
             property float y\nproperty float z\n",
        );
        let m = read_ply(&f).unwrap();
        assert_eq!(m.vertex_count(), 0, "{format}");
    }
}

#[test]
fn ply_header_tolerates_crlf_and_stops_after_vertex_and_face() {
    let mut f = b"ply\r\nformat ascii 1.0\r\nobj_info x\r\nelement vertex 3\r\nproperty double x\r\n\
property double y\r\nproperty double z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n\
element trailer 5\r\nproperty int junk\r\nend_header\r\n"
        .to_vec();
    f.extend_from_slice(b"0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n");
    let m = read_ply(&f).unwrap();
    assert_eq!((m.vertex_count(), m.face_count()), (3, 1));
}

fn triangle_binary_ply() -> (Vec<u8>, usize) {
    let mut f = ply_header(
        "binary_little_endian",
        "element vertex 3\nproperty double x\nproperty double y\nproperty double z\n\
         element face 2\nproperty list uchar int vertex_indices\n",
    );
    let body = f.len();
    let mut b = Body {
        big: false,
        bytes: Vec::new(),
    };
    for v in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        b.f64(v[0]).f64(v[1]).f64(v[2]);
    }
    b.u8(3).i32(0).i32(1).i32(2);
    b.u8(3).i32(2).i32(1).i32(0);
    f.extend_from_slice(&b.bytes);
    (f, body)
}

#[test]
fn ply_binary_errors_give_the_byte_offset_of_the_record() {
    let (good, body) = triangle_binary_ply();
    read_ply(&good).unwrap();
    let face0 = body + 72;
    let face1 = face0 + 13;

    // Truncated inside vertex 2, inside face 1, and right after the header.
    let (line, byte, msg) = parse_err(read_ply(&good[..body + 60]));
    assert_eq!((line, byte), (0, Some(body as u64 + 48)), "{msg}");
    assert!(msg.contains("the file ends inside vertex 2 of 3"), "{msg}");
    let (_, byte, msg) = parse_err(read_ply(&good[..good.len() - 1]));
    assert_eq!(byte, Some(face1 as u64), "{msg}");
    assert!(msg.contains("the file ends inside face 1 of 2"), "{msg}");
    let (_, byte, _) = parse_err(read_ply(&good[..body]));
    assert_eq!(byte, Some(body as u64));

    // An index out of range: validation's message at the face's offset.
    let mut bad = good.clone();
    bad[face1 + 1..face1 + 5].copy_from_slice(&7i32.to_le_bytes());
    let e = read_ply(&bad).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!("t.ply: byte {face1}: face 1, loop 0: vertex index 7 is out of range (the mesh has 3 vertices)")
    );
    // A negative index.
    let mut bad = good.clone();
    bad[face0 + 5..face0 + 9].copy_from_slice(&(-2i32).to_le_bytes());
    let (_, byte, msg) = parse_err(read_ply(&bad));
    assert_eq!(byte, Some(face0 as u64));
    assert!(msg.contains("face 0: vertex index -2 is negative"), "{msg}");
    // A NaN coordinate: the vertex's offset.
    let mut bad = good.clone();
    bad[body + 24 + 8..body + 24 + 16].copy_from_slice(&f64::NAN.to_le_bytes());
    let (_, byte, msg) = parse_err(read_ply(&bad));
    assert_eq!(byte, Some(body as u64 + 24));
    assert!(msg.contains("vertex 1: coordinate y is NaN"), "{msg}");
}

#[test]
fn ply_header_and_ascii_errors_give_the_line() {
    let v3 = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    let face = "element face 1\nproperty list uchar int vertex_indices\n";
    let cases: Vec<(Vec<u8>, usize, &str)> = vec![
        (b"PLY\nformat ascii 1.0\nend_header\n".to_vec(), 1, "the first line must be 'ply'"),
        (b"".to_vec(), 1, "the first line must be 'ply'"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\n".to_vec(), 3, "no 'end_header'"),
        (b"ply\nformat ascii 2.0\nend_header\n".to_vec(), 2, "version '2.0'"),
        (b"ply\nformat utf8 1.0\nend_header\n".to_vec(), 2, "unknown format 'utf8'"),
        (b"ply\nend_header\n".to_vec(), 2, "no 'format' line"),
        (b"ply\nformat ascii 1.0\nproperty float x\nend_header\n".to_vec(), 3, "'property' before any 'element'"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n".to_vec(), 4, "unknown property type 'float128'"),
        (b"ply\nformat ascii 1.0\nelement vertex -1\nend_header\n".to_vec(), 3, "count '-1' is not a non-negative integer"),
        (b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n".to_vec(), 3, "has no property 'z'"),
        (format!("ply\nformat ascii 1.0\n{v3}element face 1\nproperty list uchar float vertex_indices\nend_header\n").into_bytes(), 7, "must be a list of integers"),
        (format!("ply\nformat ascii 1.0\n{v3}element face 1\nproperty int vertex_indices\nend_header\n").into_bytes(), 7, "must be a list of integers"),
        (format!("ply\nformat ascii 1.0\n{v3}bogus\nend_header\n").into_bytes(), 7, "'bogus' is not a PLY header keyword"),
        (format!("ply\nformat ascii 1.0\n{v3}{face}end_header\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n").into_bytes(), 11, "vertex 1: z 'x' is not a number"),
        (format!("ply\nformat ascii 1.0\n{v3}{face}end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n").into_bytes(), 13, "face 0, loop 0: vertex index 3 is out of range"),
        (format!("ply\nformat ascii 1.0\n{v3}{face}end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n").into_bytes(), 13, "'-1' is not a valid vertex index"),
        (format!("ply\nformat ascii 1.0\n{v3}{face}end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n").into_bytes(), 13, "the file ends inside face 0 of 1"),
        (format!("ply\nformat ascii 1.0\n{v3}{face}end_header\n0 0 0\n1 0 0\n0 1 0\nx 0 1 2\n").into_bytes(), 13, "list length 'x'"),
        (format!("ply\nformat ascii 1.0\n{v3}end_header\n0 0 0\n1 0 inf\n0 1 0\n").into_bytes(), 9, "vertex 1: z is inf"),
        (b"ply\nformat ascii 1.0\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n".to_vec(), 3, "'tristrips') are not supported"),
    ];
    for (bytes, line, needle) in cases {
        let (l, byte, msg) = parse_err(read_ply(&bytes));
        let shown = String::from_utf8_lossy(&bytes);
        assert_eq!((l, byte), (line, None), "{shown}: {msg}");
        assert!(msg.contains(needle), "{shown}: {msg}");
    }
}

// ---------------------------------------------------------------------------------------
// OFF

#[test]
fn off_variants_comments_and_colours() {
    let m = read_off(
        "# leading comment\n\nCOFF 4 2 0 # counts on the header line\n\
         0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 9 9 9 9\n\
         3 0 1 2 1.0 0.0 0.0\n# between\n3   0 2 3\n",
    )
    .unwrap();
    assert_eq!((m.vertex_count(), m.face_count()), (4, 2));
    assert_eq!(
        m.face_outer(katachi::FaceId(1)),
        &[VertexId(0), VertexId(2), VertexId(3)]
    );
    for header in ["NOFF", "CNOFF", "STOFF", "STCNOFF", "nOFF 3", "OFF\r"] {
        let m = read_off(&format!(
            "{header}\n3 1\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 1 1 1\n3 0 1 2\n"
        ))
        .unwrap_or_else(|e| panic!("{header}: {e}"));
        assert_eq!(m.face_count(), 1, "{header}");
    }
}

#[test]
fn off_errors_name_the_line() {
    let cases: &[(&str, usize, &str)] = &[
        ("", 1, "the file is empty"),
        ("3 1 0\n0 0 0\n", 1, "not an OFF file: it starts with '3'"),
        ("PLY\n", 1, "not an OFF file"),
        ("4OFF\n", 1, "4-dimensional OFF"),
        ("nOFF 2\n", 1, "nOFF with dimension '2'"),
        ("XOFF\n", 1, "unknown OFF variant 'XOFF'"),
        ("OFF BINARY\n", 1, "binary OFF is not supported"),
        ("OFF\n", 1, "the file ends before the counts line"),
        (
            "OFF\n# c\n3 x 0\n",
            3,
            "the face count 'x' is not a non-negative integer",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n",
            4,
            "the file ends after 2 of 3 vertices",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n",
            4,
            "vertex 1: expected 3 coordinates",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e 0\n3 0 1 2\n",
            5,
            "vertex 2: coordinate y '1e' is not a number",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n",
            5,
            "coordinate y is NaN",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
            6,
            "face 0, loop 0: vertex index 3 is out of range (the mesh has 3 vertices)",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
            6,
            "face 0: 3 corners announced, only 2 given",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
            6,
            "'-1' is not a valid vertex index",
        ),
        (
            "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
            6,
            "the file ends after 1 of 2 faces",
        ),
        (
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n\n2 0 1\n",
            7,
            "face 0, loop 0: a loop needs at least 3 distinct vertices",
        ),
    ];
    for &(src, line, needle) in cases {
        let (l, byte, msg) = parse_err(read_off(src));
        assert_eq!((l, byte), (line, None), "{src:?}: {msg}");
        assert!(msg.contains(needle), "{src:?}: {msg}");
    }
}

// ---------------------------------------------------------------------------------------
// never panic

fn valid_files() -> Vec<(Format, Vec<u8>)> {
    let mut mesh = shapes::ngon_prism(5, 1.0, 1.0).unwrap();
    mesh.set_edge_sharpness(VertexId(0), VertexId(1), 2.0)
        .unwrap();
    mesh.set_vertex_sharpness(VertexId(3), 1.0).unwrap();
    let mut out = Vec::new();
    for (format, enc) in ALL_WRITERS {
        let mut buf = Vec::new();
        io::write_to(
            &mut buf,
            format,
            &mesh,
            &WriteOptions::with_ply_encoding(enc),
        )
        .unwrap();
        out.push((format, buf));
    }
    out.push((Format::Ply, mixed_binary_ply(false)));
    out.push((Format::Ply, mixed_binary_ply(true)));
    out
}

/// Reads bytes as every format: any result is fine, a panic is not.
fn read_all_formats(bytes: &[u8]) {
    for format in [Format::Obj, Format::Ply, Format::Off] {
        let _ = io::read_bytes(bytes, format, Path::new("fuzz"));
    }
}

counted_proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        read_all_formats(&bytes);
    }

    #[test]
    fn random_text_never_panics(
        lines in proptest::collection::vec(
            "(v|f|t|vt|l|#|OFF|ply|format ascii 1.0|element vertex|property|end_header|crease|corner)? ?[-0-9 ./eEnaif]{0,20}",
            0..30,
        )
    ) {
        read_all_formats(lines.join("\n").as_bytes());
    }

    #[test]
    fn mutated_valid_files_never_panic(
        file in 0usize..7,
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..4), 1..8),
    ) {
        let files = valid_files();
        let (format, mut bytes) = files[file].clone();
        for (at, value, op) in edits {
            if bytes.is_empty() { break; }
            let i = at.index(bytes.len());
            match op {
                0 => bytes[i] = value,
                1 => { bytes.remove(i); }
                2 => bytes.insert(i, value),
                _ => bytes.truncate(i),
            }
        }
        let _ = io::read_bytes(&bytes, format, Path::new("fuzz"));
        read_all_formats(&bytes);
    }

    #[test]
    fn random_positions_round_trip_bit_exact(
        coords in proptest::collection::vec(any::<f64>().prop_filter("finite", |x| x.is_finite()), 9..30),
    ) {
        let n = coords.len() / 3;
        let p: Vec<DVec3> = coords.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
        let faces: Vec<Vec<u32>> = (0..n as u32 - 2).map(|i| vec![i, i + 1, i + 2]).collect();
        let mesh = PolyMesh::from_polygons(p, faces).unwrap();
        for (format, enc) in ALL_WRITERS {
            let back = round_trip(&mesh, format, enc);
            for (a, b) in mesh.positions().iter().zip(back.positions()) {
                prop_assert_eq!(a.to_array().map(f64::to_bits), b.to_array().map(f64::to_bits));
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Safe writes

/// A fresh, empty folder for one test.
fn fresh_dir(name: &str) -> std::path::PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("io-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// `io::write` past a file-size limit (RLIMIT_FSIZE, in a child process: this test's own
/// binary run again) fails with the OS's error and leaves the old file byte for byte, with no
/// temporary file beside it.
#[test]
fn a_failed_write_leaves_the_old_file_intact() {
    const CHILD: &str = "KATACHI_TEST_WRITE_UNDER_A_LIMIT";
    if let Some(path) = std::env::var_os(CHILD) {
        // SAFETY: plain system calls on this process's own limits and signal disposition.
        unsafe {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            let limit = libc::rlimit {
                rlim_cur: 64 * 1024,
                rlim_max: 64 * 1024,
            };
            assert_eq!(libc::setrlimit(libc::RLIMIT_FSIZE, &limit), 0);
        }
        let big = shapes::torus(200, 100, 2.0, 0.5).unwrap();
        for ext in ["obj", "ply", "off"] {
            let target = Path::new(&path).with_extension(ext);
            match io::write(&target, &big) {
                Err(e) => println!("refused {ext}: {e}"),
                Ok(()) => println!("written {ext}"),
            }
        }
        return;
    }
    let dir = fresh_dir("fsize");
    let cube = shapes::cube(1.0).unwrap();
    let mut before = Vec::new();
    for ext in ["obj", "ply", "off"] {
        let p = dir.join(format!("old.{ext}"));
        io::write(&p, &cube).unwrap();
        before.push(std::fs::read(&p).unwrap());
    }
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "a_failed_write_leaves_the_old_file_intact",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, dir.join("old.obj"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    for (ext, old) in ["obj", "ply", "off"].iter().zip(&before) {
        assert!(
            text.contains(&format!("refused {ext}: "))
                && text.contains(&format!("old.{ext}: File too large")),
            "{ext}: {text}"
        );
        assert_eq!(
            &std::fs::read(dir.join(format!("old.{ext}"))).unwrap(),
            old,
            "old.{ext} changed"
        );
    }
    assert_eq!(names_in(&dir), ["old.obj", "old.off", "old.ply"]);
}

/// A write replaces the file a symlink points to (the link stays a link), keeps the old
/// file's permissions, and writes a device in place.
#[test]
fn writes_replace_the_real_file_and_keep_its_permissions() {
    use std::os::unix::fs::PermissionsExt;
    let dir = fresh_dir("links");
    let real = dir.join("real.off");
    io::write(&real, &shapes::cube(1.0).unwrap()).unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).unwrap();
    let link = dir.join("link.off");
    std::os::unix::fs::symlink("real.off", &link).unwrap();
    let prism = shapes::ngon_prism(5, 1.0, 1.0).unwrap();
    io::write(&link, &prism).unwrap();
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(io::read(&real).unwrap().vertex_count(), 10);
    let mode = std::fs::metadata(&real).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o640);
    assert_eq!(names_in(&dir), ["link.off", "real.off"]);
    // A device is written in place: /dev/null takes it, /dev/full refuses it.
    let null = dir.join("null.off");
    std::os::unix::fs::symlink("/dev/null", &null).unwrap();
    io::write(&null, &prism).unwrap();
    let full = dir.join("full.off");
    std::os::unix::fs::symlink("/dev/full", &full).unwrap();
    let e = io::write(&full, &prism).unwrap_err().to_string();
    assert!(e.contains("No space left on device"), "{e}");
    assert_eq!(
        names_in(&dir),
        ["full.off", "link.off", "null.off", "real.off"]
    );
    // write_bytes, for reports and strokes, is the same.
    io::write_bytes(&real, b"not a mesh").unwrap();
    assert_eq!(std::fs::read(&real).unwrap(), b"not a mesh");
}
