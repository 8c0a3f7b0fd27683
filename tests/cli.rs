//! The `katachi` command-line tool, run as a user runs it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn katachi(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_katachi"))
        .args(args)
        .output()
        .expect("the katachi binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("katachi-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/models")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}
fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn info_reports_counts() {
    let o = katachi(&["info", &example("hole_capsule.off")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(s.contains("vertices:             89"), "{s}");
    assert!(s.contains("faces:                76 (76 quads)"), "{s}");
    assert!(s.contains("boundary:             3 loops, 28 edges"), "{s}");
    assert!(s.contains("manifold:             yes"), "{s}");
    let o = katachi(&["info", &example("rhombicosidodecahedron.obj")]);
    let s = stdout(&o);
    assert!(s.contains("62 (20 triangles, 30 quads, 12 5-gons)"), "{s}");
    assert!(s.contains("genus:                0"), "{s}");
}

#[test]
fn convert_round_trips() {
    let d = tmp("convert");
    let ply = d.join("c.ply");
    let o = katachi(&[
        "convert",
        &example("chamfer-cube.off"),
        ply.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let back = d.join("c.off");
    let o = katachi(&["convert", ply.to_str().unwrap(), back.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = katachi::io::read(Path::new(&example("chamfer-cube.off"))).unwrap();
    let b = katachi::io::read(&back).unwrap();
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.corners(), b.corners());
}

#[test]
fn demo_writes_results() {
    let d = tmp("demo");
    let o = katachi(&["demo", "--out", d.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [
        "fandisk_quads.ply",
        "chamfer-cube.obj",
        "cube_creased.obj",
        "torus_24x12.info.txt",
        "plate_with_hole_smooth_a.subdivided.obj",
        "plate_with_hole_sharp_b.subdivided.obj",
        "cube_creased.subdivided.obj",
    ] {
        assert!(d.join(f).is_file(), "demo did not write {f}");
    }
    // The creased cube keeps its sharpness through OBJ tags.
    let cube = katachi::io::read(&d.join("cube_creased.obj")).unwrap();
    assert_eq!(cube.sharp_edges().len(), 2);
}

#[test]
fn bad_input_is_one_line_and_status_2() {
    let d = tmp("bad");
    let cases: Vec<(PathBuf, &str, &str)> = vec![
        (d.join("missing.obj"), "", "missing.obj"),
        (
            d.join("bad.off"),
            "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
            "bad.off:6",
        ),
        (
            d.join("nan.obj"),
            "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
            "nan.obj",
        ),
        (d.join("x.stl"), "solid\n", "unknown file format"),
    ];
    for (path, content, expect) in cases {
        if !content.is_empty() {
            std::fs::write(&path, content).unwrap();
        }
        let o = katachi(&["info", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let e = stderr(&o);
        assert_eq!(e.lines().count(), 1, "one line: {e}");
        assert!(e.starts_with("error: "), "{e}");
        assert!(e.contains(expect), "{e} should name {expect}");
        assert!(!e.contains("panicked"), "{e}");
    }
}

#[test]
fn subdivide_command() {
    let d = tmp("subdivide");
    // A boolean's output (triangles) recovered as faces with holes, both methods.
    let soup = d.join("plate.obj");
    katachi::io::write(&soup, &katachi::mesh::shapes::boolean_plate(4.0, 2.0, 1.0)).unwrap();
    for method in ["smooth", "sharp"] {
        let out = d.join(format!("plate_{method}.obj"));
        let o = katachi(&[
            "subdivide",
            soup.to_str().unwrap(),
            out.to_str().unwrap(),
            "--levels",
            "2",
            "--solid",
            "--holes",
            method,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let m = katachi::io::read(&out).unwrap();
        let r = katachi::mesh::inspect(&m).unwrap();
        assert_eq!(r.genus, Some(1), "{method}");
        if method == "sharp" {
            assert!(stderr(&o).contains("faces with holes written as simple polygons"));
        }
    }
    let out = d.join("fandisk.ply");
    let o = katachi(&[
        "subdivide",
        &example("fandisk_quads.off"),
        out.to_str().unwrap(),
        "--feature-angle",
        "30",
        "--crease-method",
        "chaikin",
        "--boundary",
        "edge-and-corner",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("3056 faces"), "{}", stdout(&o));
    // Bad options are one line and status 2.
    let o = katachi(&[
        "subdivide",
        &example("fandisk_quads.off"),
        out.to_str().unwrap(),
        "--levels",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).starts_with("error: option levels"),
        "{}",
        stderr(&o)
    );
    let o = katachi(&[
        "subdivide",
        &example("fandisk_quads.off"),
        out.to_str().unwrap(),
        "--feature-angle",
        "200",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stderr(&o).lines().count(), 1);
}
