//! Safe output and clear errors, as a user meets them: a write that fails (a file-size limit,
//! a full device) leaves the old file; a full or closed stdout is an I/O error with status 2;
//! the status is 0 or 2 and nothing else; an error is one line with the input's control
//! characters escaped; no operation writes non-finite coordinates.

use std::path::{Path, PathBuf};
#[cfg(unix)]
use std::process::Stdio;
use std::process::{Command, Output};

#[cfg(unix)]
use katachi::mesh::shapes;

fn exe() -> &'static str {
    env!("CARGO_BIN_EXE_katachi")
}

fn katachi(args: &[&str]) -> Output {
    Command::new(exe())
        .args(args)
        .output()
        .expect("the katachi binary runs")
}

/// A fresh, empty folder for one test.
fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("output-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[cfg(unix)]
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Status 2 and exactly one line on stderr, `error: …`, without control characters.
fn assert_one_error_line(o: &Output, what: &str) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{what}: {err}");
    assert_eq!(err.lines().count(), 1, "{what}: not one line: {err:?}");
    assert!(
        err.starts_with("error: ") && err.ends_with('\n'),
        "{what}: {err:?}"
    );
    let line = err.trim_end_matches('\n');
    assert!(
        !line.chars().any(char::is_control),
        "{what}: control characters in {line:?}"
    );
    assert!(!line.contains("internal error"), "{what}: {line}");
    line.to_string()
}

#[cfg(unix)]
fn big_off(dir: &Path) -> PathBuf {
    let path = dir.join("big.off");
    katachi::io::write(&path, &shapes::torus(200, 100, 2.0, 0.5).unwrap()).unwrap();
    path
}

#[test]
#[cfg(unix)] // a shell's `ulimit -f`
fn a_write_past_a_file_size_limit_leaves_the_old_file() {
    let dir = folder("fsize");
    let big = big_off(&dir);
    // The file to be replaced, valid and small.
    let small = dir.join("small.off");
    katachi::io::write(&small, &shapes::cube(1.0).unwrap()).unwrap();
    let out = dir.join("out.ply");
    let o = katachi(&["convert", small.to_str().unwrap(), out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(&out).unwrap();
    for command in ["convert", "subdivide"] {
        // 64 blocks of the shell's `ulimit -f` (at most 64 KiB): the new file is ~1 MB.
        let o = Command::new("sh")
            .args(["-c", "ulimit -f 64 && exec \"$0\" \"$@\"", exe(), command])
            .arg(&big)
            .arg(&out)
            .output()
            .unwrap();
        let line = assert_one_error_line(&o, command);
        assert!(
            line.contains("out.ply") && line.contains("File too large"),
            "{line}"
        );
        assert_eq!(
            std::fs::read(&out).unwrap(),
            before,
            "{command}: out.ply changed"
        );
        assert_eq!(
            listing(&dir),
            ["big.off", "out.ply", "small.off"],
            "{command}: a temporary file was left"
        );
    }
}

#[test]
#[cfg(unix)] // /dev/full
fn a_mesh_written_to_a_full_device_is_an_error_and_the_device_stays() {
    let dir = folder("devfull");
    let link = dir.join("full.ply");
    std::os::unix::fs::symlink("/dev/full", &link).unwrap();
    let cube = dir.join("cube.off");
    katachi::io::write(&cube, &shapes::cube(1.0).unwrap()).unwrap();
    let o = katachi(&["convert", cube.to_str().unwrap(), link.to_str().unwrap()]);
    let line = assert_one_error_line(&o, "convert to /dev/full");
    assert!(line.contains("No space left on device"), "{line}");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata("/dev/full")
        .unwrap()
        .file_type()
        .is_char_device());
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(listing(&dir), ["cube.off", "full.ply"]);
}

#[test]
#[cfg(unix)] // /dev/full; a closed pipe is Broken pipe (EPIPE)
fn a_full_or_closed_stdout_is_an_io_error_with_status_2() {
    let dir = folder("stdout");
    let cube = dir.join("cube.off");
    katachi::io::write(&cube, &shapes::cube(1.0).unwrap()).unwrap();
    let cube = cube.to_str().unwrap();
    // A full stdout (`> /dev/full`).
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let o = Command::new(exe())
        .args(["info", cube])
        .stdout(Stdio::from(full))
        .output()
        .unwrap();
    let line = assert_one_error_line(&o, "info > /dev/full");
    assert!(
        line.contains("<stdout>") && line.contains("No space left"),
        "{line}"
    );
    // A closed stdout (`| head -1` once head has gone): the pipe's reader is closed first.
    for args in [vec!["info", cube], vec!["--help"], vec!["--version"]] {
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = Command::new(exe())
            .args(&args)
            .stdout(Stdio::from(writer))
            .output()
            .unwrap();
        let line = assert_one_error_line(&o, &format!("{args:?} into a closed pipe"));
        assert!(line.contains("Broken pipe"), "{line}");
    }
}

#[test]
fn the_status_is_0_or_2() {
    for (args, code) in [
        (vec!["--help"], 0),
        (vec!["--version"], 0),
        (vec!["frobnicate"], 2),
        (vec!["info"], 2),
        (vec!["subdivide", "a.off"], 2),
        (vec!["subdivide", "a.off", "b.off", "--levels", "many"], 2),
        (vec!["info", "/nonexistent/x.off"], 2),
        (vec!["info", "x.unknown"], 2),
    ] {
        let o = katachi(&args);
        assert_eq!(o.status.code(), Some(code), "{args:?}: {}", stderr(&o));
    }
}

#[test]
fn control_characters_from_the_input_are_escaped_in_the_error_line() {
    let dir = folder("escapes");
    // A PLY element name carrying a terminal escape code and a bell.
    let ply = dir.join("evil.ply");
    std::fs::write(
        &ply,
        b"ply\nformat ascii 1.0\nelement \x1b[31mred\x07 x\nend_header\n",
    )
    .unwrap();
    let o = katachi(&["info", ply.to_str().unwrap()]);
    let line = assert_one_error_line(&o, "PLY element name");
    assert!(line.contains(r"\u{1b}[31mred\u{7}"), "{line}");
    // A file name with a newline and an escape code.
    let o = katachi(&["info", "no\nsuch\x1b[2J.off"]);
    let line = assert_one_error_line(&o, "file name");
    assert!(line.contains(r"no\nsuch\u{1b}[2J.off"), "{line}");
}

#[test]
fn subdividing_coordinates_near_the_f64_limit_is_an_error_naming_the_vertex() {
    let dir = folder("overflow");
    let input = dir.join("huge.off");
    std::fs::write(
        &input,
        "OFF\n8 6 0\n-1 -1 -1\n1 -1 -1\n-1 1 -1\n1 1 -1\n-1 -1 1\n1 -1 1\n-1 1 1\n1.5e308 1.7e308 1\n\
         4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n",
    )
    .unwrap();
    let out = dir.join("out.off");
    let o = katachi(&["subdivide", input.to_str().unwrap(), out.to_str().unwrap()]);
    let line = assert_one_error_line(&o, "subdivide near f64::MAX");
    assert!(
        line.contains("overflows") && line.contains("vertex 7"),
        "{line}"
    );
    assert!(!out.exists(), "a result was written");
}

/// The subcommands `katachi --help` lists.
#[cfg(unix)]
fn subcommands() -> Vec<String> {
    let o = katachi(&["--help"]);
    let help = String::from_utf8_lossy(&o.stdout).into_owned();
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect()
}

#[test]
#[cfg(unix)] // /dev/full; a closed pipe is Broken pipe (EPIPE)
fn every_subcommand_reports_a_full_or_closed_stdout_with_status_2() {
    let dir = folder("stdout-everywhere");
    let cube = dir.join("cube.off");
    katachi::io::write(&cube, &shapes::cube(1.0).unwrap()).unwrap();
    // A stroke across the middle of the cube seen straight on (identity view-projection).
    let stroke = dir.join("stroke.json");
    std::fs::write(
        &stroke,
        r#"{"stroke": [[10, 47], [90, 53]],
            "view_proj": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],
            "viewport": [0, 0, 100, 100]}"#,
    )
    .unwrap();
    let (cube, stroke) = (cube.to_str().unwrap(), stroke.to_str().unwrap());
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    // One run of each subcommand that prints results; `demo` is checked whole in cli.rs.
    let runs: Vec<(&str, Vec<String>)> = vec![
        ("info", vec![cube.into()]),
        ("convert", vec![cube.into(), out("c.ply")]),
        ("subdivide", vec![cube.into(), out("s.obj")]),
        (
            "cut",
            vec![cube.into(), out("k.obj"), "--stroke".into(), stroke.into()],
        ),
        ("demo", vec!["--out".into(), out("demo")]),
        (
            "curved-mesh",
            vec![
                concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../examples/curved_square_hole.json"
                )
                .into(),
                out("m.msh"),
            ],
        ),
        ("help", vec!["info".into()]),
    ];
    let listed = subcommands();
    let missing: Vec<&String> = listed
        .iter()
        .filter(|s| !runs.iter().any(|(n, _)| n == s))
        .collect();
    assert!(
        missing.is_empty(),
        "subcommands with no run in this test (add one): {missing:?}"
    );
    for (name, rest) in &runs {
        let mut args = vec![name.to_string()];
        args.extend(rest.iter().cloned());
        if *name != "demo" {
            // It succeeds with a stdout that works, and prints something there.
            let o = Command::new(exe()).args(&args).output().unwrap();
            assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
            assert!(!o.stdout.is_empty(), "{args:?} printed nothing");
            let full = std::fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .unwrap();
            let o = Command::new(exe())
                .args(&args)
                .stdout(Stdio::from(full))
                .output()
                .unwrap();
            let line = assert_one_error_line(&o, &format!("{args:?} > /dev/full"));
            assert!(line.contains("<stdout>"), "{line}");
        }
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = Command::new(exe())
            .args(&args)
            .stdout(Stdio::from(writer))
            .output()
            .unwrap();
        let line = assert_one_error_line(&o, &format!("{args:?} into a closed pipe"));
        assert!(line.contains("Broken pipe"), "{line}");
    }
}

/// Rust files under `dir`, recursively.
fn rust_files(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, found);
        } else if path.extension().is_some_and(|e| e == "rs") {
            found.push(path);
        }
    }
}

#[test]
fn the_tool_prints_only_through_out() {
    // `println!` panics on a closed stdout ("failed printing to stdout"), which would be an
    // internal error; `out::line` makes it an I/O error with status 2, and escapes the text.
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut found = Vec::new();
    for file in &files {
        if file.ends_with("out.rs") {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for macro_name in ["print!", "println!", "eprint!", "eprintln!", "dbg!"] {
                let hit = code
                    .match_indices(macro_name)
                    .any(|(i, _)| !code[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_'));
                if hit {
                    found.push(format!("{}:{}: {}", file.display(), n + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "print through crate::out::line / out::note instead:\n{}",
        found.join("\n")
    );
}
