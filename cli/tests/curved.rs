//! `katachi curved-mesh`, run as a user runs it: the bundled examples, the three output
//! formats, the report, and input files that name the field at fault.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn katachi(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_katachi"))
        .args(args)
        .output()
        .expect("the katachi binary runs")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("katachi-curved-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The numbers after a MSH section header line, and the section's lines.
fn section<'a>(text: &'a str, name: &str) -> Vec<&'a str> {
    let start = text
        .find(&format!("${name}\n"))
        .unwrap_or_else(|| panic!("no ${name}"));
    let end = text[start..].find(&format!("$End{name}")).unwrap() + start;
    text[start..end].lines().skip(1).collect()
}

#[test]
fn meshes_the_examples_into_every_format() {
    let d = tmp("formats");
    for (name, regions) in [
        ("curved_square_hole.json", 1),
        ("curved_two_regions.json", 2),
    ] {
        let msh = d.join(name.replace(".json", ".msh"));
        let vtk = d.join(name.replace(".json", ".vtk"));
        let obj = d.join(name.replace(".json", ".obj"));
        let report = d.join(name.replace(".json", ".report.json"));
        let o = katachi(&[
            "curved-mesh",
            &example(name),
            msh.to_str().unwrap(),
            "--also",
            vtk.to_str().unwrap(),
            "--also",
            obj.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let out = stdout(&o);
        assert!(out.contains("of order 3"), "{out}");
        let text = std::fs::read_to_string(&msh).unwrap();
        assert!(text.starts_with("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"));
        // One element block per region, of 10-node triangles (type 21).
        let elements = section(&text, "Elements");
        let header: Vec<u64> = elements[0].split(' ').map(|x| x.parse().unwrap()).collect();
        assert_eq!(header[0], regions);
        let blocks: Vec<&str> = elements[1..]
            .iter()
            .filter(|l| l.starts_with("2 ") && l.split(' ').count() == 4)
            .copied()
            .collect();
        assert_eq!(blocks.len() as u64, regions);
        assert!(blocks.iter().all(|b| b.split(' ').nth(2) == Some("21")));
        let element_lines = elements.len() - 1 - blocks.len();
        assert_eq!(element_lines as u64, header[1]);
        assert!(text.contains("\"min metric angle (deg)\""));
        // The report agrees with the file.
        let r: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
        assert_eq!(r["elements"]["total"].as_u64(), Some(header[1]));
        let min = r["angles_deg"]["straight_min_in_vertex_metrics"]["min"]
            .as_f64()
            .unwrap();
        assert!(min >= r["angles_deg"]["guaranteed"].as_f64().unwrap());
        assert!(
            r["angles_deg"]["all_corner_angles"]["median"]
                .as_f64()
                .unwrap()
                > 50.0
        );
        // VTK: Lagrange triangles with cell data.
        let vtk = std::fs::read_to_string(&vtk).unwrap();
        assert!(vtk.contains("DATASET UNSTRUCTURED_GRID"));
        assert!(vtk.contains(&format!("CELL_TYPES {}", header[1])));
        assert!(vtk.contains("\n69\n"));
        assert!(vtk.contains("SCALARS min_metric_angle_deg double 1"));
        // OBJ preview: 9 flat triangles per cubic element.
        let obj = std::fs::read_to_string(&obj).unwrap();
        let faces = obj.lines().filter(|l| l.starts_with("f ")).count() as u64;
        assert_eq!(faces, 9 * header[1]);
    }
}

#[test]
fn order_and_parameter_space_from_the_command_line() {
    let d = tmp("order");
    let msh = d.join("q1.msh");
    let o = katachi(&[
        "curved-mesh",
        &example("curved_square_hole.json"),
        msh.to_str().unwrap(),
        "--order",
        "1",
        "--space",
        "parameter",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&msh).unwrap();
    let nodes = section(&text, "Nodes");
    // Every coordinate line has z = 0 in parameter space.
    let coords: Vec<&str> = nodes
        .iter()
        .filter(|l| l.split(' ').count() == 3 && l.contains('.'))
        .copied()
        .collect();
    assert!(!coords.is_empty());
    assert!(
        coords.iter().all(|l| l.ends_with(" 0")),
        "{:?}",
        &coords[..3]
    );
    assert!(section(&text, "Elements")
        .iter()
        .any(|l| l.starts_with("2 1 2 ")));
}

/// Writes `text` as an input file and returns the error line of `katachi curved-mesh`.
fn error_of(text: &str) -> String {
    let d = tmp("errors");
    let input = d.join("in.json");
    std::fs::write(&input, text).unwrap();
    let out = d.join("out.msh");
    let o = katachi(&[
        "curved-mesh",
        input.to_str().unwrap(),
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stdout(&o));
    assert!(!out.exists(), "a failed run wrote {}", out.display());
    stderr(&o)
}

const PATCH: &str = r#"{"degree": [1, 1], "points": [[0,0,0],[0,1,0],[1,0,0],[1,1,0]]}"#;
const TRIANGLE: &str = r#"[[[0.1,0.1],[0.9,0.1]], [[0.9,0.1],[0.5,0.9]], [[0.5,0.9],[0.1,0.1]]]"#;

#[test]
fn bad_input_names_the_field() {
    let doc = |patches: &str, curves: &str, regions: &str, metric: &str| {
        format!(
            r#"{{"patches": [{patches}], "curves": {curves}, "regions": {regions}, "metric": {metric}}}"#
        )
    };
    let ok_regions = r#"[{"patch": 0, "loops": [[0, 1, 2]]}]"#;
    let ok_metric = r#"{"type": "isotropic", "size": 0.2}"#;
    // The valid document meshes.
    let d = tmp("valid");
    let input = d.join("in.json");
    std::fs::write(&input, doc(PATCH, TRIANGLE, ok_regions, ok_metric)).unwrap();
    let o = katachi(&[
        "curved-mesh",
        input.to_str().unwrap(),
        d.join("o.msh").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for (text, expected) in [
        (
            doc(
                PATCH,
                TRIANGLE,
                r#"[{"patch": 0, "loops": [[0, 1, 7]]}]"#,
                ok_metric,
            ),
            "regions[0].loops[0][2]: curve 7 does not exist",
        ),
        (
            doc(
                PATCH,
                TRIANGLE,
                r#"[{"patch": 0, "loops": [[0, 1, {"curve": 2, "reversed": "yes"}]]}]"#,
                ok_metric,
            ),
            "regions[0].loops[0][2].reversed: expected true or false",
        ),
        (
            doc(
                PATCH,
                TRIANGLE,
                r#"[{"patch": 3, "loops": [[0, 1, 2]]}]"#,
                ok_metric,
            ),
            "regions[0].patch: patch 3 does not exist",
        ),
        (
            doc(
                PATCH,
                TRIANGLE,
                ok_regions,
                r#"{"type": "isotropic", "size": -1}"#,
            ),
            "metric.size: expected a positive number",
        ),
        (
            doc(PATCH, TRIANGLE, ok_regions, r#"{"type": "magic"}"#),
            "metric.type: unknown metric type",
        ),
        (
            doc(
                PATCH,
                TRIANGLE,
                ok_regions,
                r#"{"type": "tensor", "tensor": [1, 2, 0, 1, 0, 1]}"#,
            ),
            "metric.tensor: the tensor is not positive definite",
        ),
        (
            doc(
                PATCH,
                r#"[[[0.1,0.1],[0.9,0.1]], [[0.9,0.1],[0.5,"x"]], [[0.5,0.9],[0.1,0.1]]]"#,
                ok_regions,
                ok_metric,
            ),
            "curves[1][1][1]: expected a finite number",
        ),
        (
            doc(
                r#"{"degree": [1, 1], "points": [[0,0,0],[0,1,0],[1,0,0]]}"#,
                TRIANGLE,
                ok_regions,
                ok_metric,
            ),
            "patches[0].points: bidegree [1, 1] needs (m+1)(n+1) = 4 points, found 3",
        ),
        (
            format!(r#"{{"patches": [{PATCH}], "curves": {TRIANGLE}, "regions": {ok_regions}}}"#),
            "metric: missing",
        ),
        (
            format!(
                r#"{{"patches": [{PATCH}], "curves": {TRIANGLE}, "regions": {ok_regions}, "metric": {ok_metric}, "options": {{"order": 11}}}}"#
            ),
            "options.order: 11 is not in 1..=10",
        ),
        (
            format!(
                r#"{{"patches": [{PATCH}], "curves": {TRIANGLE}, "regions": {ok_regions}, "metric": {ok_metric}, "options": {{"speed": 1}}}}"#
            ),
            "options.speed: unknown option",
        ),
        (
            "{\"patches\": [\n  {\"degree\": [1, 1],\n".to_string(),
            ":3: EOF while parsing",
        ),
        // Kernel validation: a loop that does not close names region, loop and curves.
        (
            doc(
                PATCH,
                r#"[[[0.1,0.1],[0.9,0.1]], [[0.9,0.1],[0.5,0.9]], [[0.5,0.9],[0.1,0.2]]]"#,
                ok_regions,
                ok_metric,
            ),
            "region 0, loop 0 is not closed: use 2 (curve 2) ends at (0.1, 0.2)",
        ),
    ] {
        let e = error_of(&text);
        assert!(e.contains(expected), "expected {expected:?} in {e}");
        assert!(e.starts_with("error: "), "{e}");
    }
}
