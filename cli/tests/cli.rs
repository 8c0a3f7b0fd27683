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
        .join("../examples/models")
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
        "fandisk_quads.stroke.json",
        "fandisk_quads.cut.obj",
        "fandisk_quads.cut_open.obj",
    ] {
        assert!(d.join(f).is_file(), "demo did not write {f}");
    }
    assert!(
        stdout(&o).contains("fandisk_quads: stroke cut (visible-only)"),
        "{}",
        stdout(&o)
    );
    // The demo's stroke file cuts the same through `katachi cut`.
    let again = d.join("again.obj");
    let c = katachi(&[
        "cut",
        d.join("input/fandisk_quads.off").to_str().unwrap(),
        again.to_str().unwrap(),
        "--stroke",
        d.join("fandisk_quads.stroke.json").to_str().unwrap(),
    ]);
    assert!(c.status.success(), "{}", stderr(&c));
    assert_eq!(
        std::fs::read(&again).unwrap(),
        std::fs::read(d.join("fandisk_quads.cut.obj")).unwrap()
    );
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
    katachi::io::write(
        &soup,
        &katachi::mesh::shapes::boolean_plate(4.0, 2.0, 1.0).unwrap(),
    )
    .unwrap();
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

/// A stroke file for `katachi cut`: an orthographic view of [-1, 1]³ from `eye` (400 × 400
/// pixels) and a straight stroke from `a` to `b` sampled at 20 points.
fn stroke_file(path: &Path, eye: [f64; 3], a: [f64; 2], b: [f64; 2], extra: &str) {
    use glam::{DMat4, DVec3};
    let vp = DMat4::orthographic_rh_gl(-1.6, 1.6, -1.6, 1.6, 0.1, 20.0)
        * DMat4::look_at_rh(DVec3::from(eye).normalize() * 5.0, DVec3::ZERO, DVec3::Y);
    let points: Vec<String> = (0..20)
        .map(|i| {
            let t = i as f64 / 19.0;
            format!(
                "[{}, {}]",
                a[0] + t * (b[0] - a[0]),
                a[1] + t * (b[1] - a[1])
            )
        })
        .collect();
    let m: Vec<String> = vp.to_cols_array().iter().map(|x| x.to_string()).collect();
    std::fs::write(
        path,
        format!(
            "{{\"stroke\": [{}], \"view_proj\": [{}], \"viewport\": [0, 0, 400, 400]{extra}}}",
            points.join(", "),
            m.join(", ")
        ),
    )
    .unwrap();
}

/// `katachi cut` of the chamfer cube into `out` along the stroke file `stroke`, with `flags`.
fn cut_chamfer_cube(out: &Path, stroke: &Path, flags: &[&str]) -> Output {
    let model = example("chamfer-cube.off");
    let mut args = vec![
        "cut",
        &model,
        out.to_str().unwrap(),
        "--stroke",
        stroke.to_str().unwrap(),
    ];
    args.extend_from_slice(flags);
    katachi(&args)
}

/// The JSON file at `path`.
fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn cut_command() {
    let d = tmp("cut");
    let stroke = d.join("stroke.json");
    let out = d.join("cut.obj");
    let report = d.join("report.json");
    stroke_file(
        &stroke,
        [1.0, 0.8, 0.6],
        [10.0, 150.0],
        [390.0, 260.0],
        ", \"mode\": \"visible-only\"",
    );
    let o = cut_chamfer_cube(&out, &stroke, &["--report", report.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    for needle in [
        "(visible-only)",
        "faces: 26 -> ",
        "paths: 1 (",
        "moved vertices: ",
        "dropped stroke points: ",
        "off the mesh",
    ] {
        assert!(s.contains(needle), "{needle:?} missing from\n{s}");
    }
    // The chamfer cube (8 triangles, 18 quads) is cut as 44 triangles, some split.
    let mesh = katachi::io::read(&out).unwrap();
    assert!(mesh.face_count() > 44, "{}", mesh.face_count());
    let r = katachi::mesh::inspect(&mesh).unwrap();
    assert!(r.is_manifold() && r.is_closed() && r.genus == Some(0));
    let rep = read_json(&report);
    assert_eq!(rep["mode"], "visible-only");
    assert_eq!(rep["face_count"], mesh.face_count());
    assert_eq!(rep["paths"].as_array().unwrap().len(), 1);
    assert_eq!(rep["unjoined"].as_array().unwrap().len(), 0);
    let path = rep["paths"][0]["vertices"].as_array().unwrap();
    assert!(path.len() >= 3, "{path:?}");
    assert!(rep["dropped"]["off_mesh"]
        .as_array()
        .unwrap()
        .contains(&0.into()));
    for m in rep["moved"].as_array().unwrap() {
        assert!(m["pixels"].as_f64().unwrap() <= rep["max_move_px"].as_f64().unwrap());
    }

    // The flags override the file: through-all cuts the back too, and opened the cube falls
    // apart along the two paths, which meet at the silhouette.
    let o = cut_chamfer_cube(
        &out,
        &stroke,
        &[
            "--mode",
            "through-all",
            "--open",
            "--report",
            report.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("(through-all, opened)"),
        "{}",
        stdout(&o)
    );
    let rep = read_json(&report);
    assert_eq!(rep["mode"], "through-all");
    assert_eq!(rep["open"], true);
    assert_eq!(rep["paths"].as_array().unwrap().len(), 2, "front and back");
    let opened = katachi::io::read(&out).unwrap();
    let r = katachi::mesh::inspect(&opened).unwrap();
    assert!(opened.vertex_count() > mesh.vertex_count());
    assert!(r.boundary_loops >= 1, "opening makes boundaries");
}

#[test]
fn cut_snap_and_corner_flags() {
    let d = tmp("cut-snap");
    let stroke = d.join("stroke.json");
    let out = d.join("cut.obj");
    let report = d.join("report.json");
    stroke_file(&stroke, [1.0, 0.8, 0.6], [10.0, 150.0], [390.0, 260.0], "");
    let moved = |flags: &[&str]| {
        let mut f = vec!["--report", report.to_str().unwrap()];
        f.extend_from_slice(flags);
        let o = cut_chamfer_cube(&out, &stroke, &f);
        assert!(o.status.success(), "{}", stderr(&o));
        read_json(&report)["moved"].as_array().unwrap().len()
    };
    assert!(moved(&[]) > 0, "the default snaps move vertices");
    assert_eq!(moved(&["--snap-vertex", "0", "--snap-segment", "0"]), 0);
    // Out of its domain: a typed error naming the option, nothing written.
    std::fs::remove_file(&out).unwrap();
    for (flag, option) in [
        ("--snap-vertex=0.7", "snap_vertex_ratio"),
        ("--snap-segment=-1", "snap_segment_ratio"),
        ("--corner-angle=200", "corner_angle_deg"),
    ] {
        let o = cut_chamfer_cube(&out, &stroke, &[flag]);
        assert_eq!(o.status.code(), Some(2), "{flag}");
        assert!(stderr(&o).contains(option), "{}", stderr(&o));
        assert!(!out.exists());
    }
}

#[test]
fn cut_stroke_file_errors_name_the_field() {
    let d = tmp("cut-bad");
    let out = d.join("out.obj");
    let good = d.join("good.json");
    stroke_file(&good, [1.0, 0.8, 0.6], [10.0, 150.0], [390.0, 260.0], "");
    let text = std::fs::read_to_string(&good).unwrap();
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    let with = |f: &dyn Fn(&mut serde_json::Map<String, serde_json::Value>)| {
        let mut v = value.clone();
        f(v.as_object_mut().unwrap());
        v.to_string()
    };
    let cases: Vec<(&str, String, &str)> =
        vec![
        ("syntax.json", "{\"stroke\": [[1, 2],".into(), "syntax.json: not valid JSON"),
        ("array.json", "[1, 2]".into(), "expected a JSON object"),
        (
            "no_view.json",
            with(&|m| {
                m.remove("view_proj");
            }),
            "missing field \"view_proj\"",
        ),
        (
            "no_stroke.json",
            with(&|m| {
                m.remove("stroke");
            }),
            "missing field \"stroke\"",
        ),
        (
            "short_view.json",
            with(&|m| {
                m["view_proj"].as_array_mut().unwrap().pop();
            }),
            "\"view_proj\" must be an array of 16 numbers, the view-projection matrix column by \
             column, but it has 15 elements",
        ),
        (
            "text_in_view.json",
            with(&|m| m["viewport"][2] = "wide".into()),
            "\"viewport\"[2] is the string \"wide\", not a number",
        ),
        (
            "point.json",
            with(&|m| m["stroke"][3] = serde_json::json!([1.0])),
            "\"stroke[3]\" must be [x, y] (two numbers), but it has 1 elements",
        ),
        (
            "mode.json",
            with(&|m| {
                m.insert("mode".into(), "sideways".into());
            }),
            "\"mode\" is \"sideways\", which is not \"visible-only\" or \"through-all\"",
        ),
        (
            "open.json",
            with(&|m| {
                m.insert("open".into(), 1.into());
            }),
            "\"open\" must be true or false",
        ),
        (
            "typo.json",
            with(&|m| {
                m.insert("veiwport".into(), 1.into());
            }),
            "unknown field \"veiwport\"",
        ),
        (
            "crossing.json",
            with(&|m| {
                m["stroke"] = serde_json::json!([[10, 10], [300, 300], [300, 10], [10, 300]])
            }),
            "the stroke crosses itself",
        ),
        (
            "singular.json",
            with(&|m| m["view_proj"] = serde_json::Value::from(vec![0.0; 16])),
            "singular",
        ),
    ];
    for (name, content, expect) in cases {
        let path = d.join(name);
        std::fs::write(&path, content).unwrap();
        let o = cut_chamfer_cube(&out, &path, &[]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        let e = stderr(&o);
        assert_eq!(e.lines().count(), 1, "{name}: one line: {e}");
        assert!(e.starts_with("error: "), "{e}");
        assert!(e.contains(expect), "{name}: {e} should contain {expect}");
    }
    assert!(!out.exists(), "no output after a failure");
    // A missing stroke file, and a bad --mode.
    let o = cut_chamfer_cube(&out, &d.join("missing.json"), &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing.json"), "{}", stderr(&o));
    let o = cut_chamfer_cube(&out, &good, &["--mode", "sideways"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("visible-only") && stderr(&o).contains("through-all"),
        "{}",
        stderr(&o)
    );
}
