//! File names and line endings through the `katachi` binary, as Windows users meet them (and
//! the same on Linux): names with spaces and non-ASCII letters in folders with them; on
//! Windows, `\` and mixed separators; the OBJ and OFF it writes end their lines with LF on
//! every platform, and CRLF input reads as LF input. Run by `cargo test` and, with the
//! Windows `katachi.exe`, by `cargo xtask windows-test` under Wine.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use katachi::mesh::{shapes, PolyMesh};

fn katachi<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_katachi"))
        .args(args)
        .output()
        .expect("the katachi binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh folder for one test, its name with a space, a diaeresis and a CJK character.
fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("paths-{name} ü 形"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn same_mesh(a: &PolyMesh, b: &PolyMesh) -> bool {
    a.positions() == b.positions()
        && a.corners() == b.corners()
        && a.loop_offsets() == b.loop_offsets()
        && a.face_loop_offsets() == b.face_loop_offsets()
}

#[test]
fn names_with_spaces_and_non_ascii_letters_go_in_and_out_as_given() {
    let dir = folder("names");
    let cube = shapes::cube(1.0).unwrap();
    let input = dir.join("in put é 形状.off");
    katachi::io::write(&input, &cube).unwrap();
    for (command, output) in [
        ("convert", "Ελληνικά name.obj"),
        ("convert", "emoji 🙂.ply"),
        ("subdivide", "sub divided ü.off"),
    ] {
        let out = dir.join(output);
        let o = katachi(&[command.as_ref(), input.as_os_str(), out.as_os_str()]);
        assert!(o.status.success(), "{command} → {output}: {}", stderr(&o));
        let back = katachi::io::read(&out)
            .unwrap_or_else(|e| panic!("{output} is not there under that name: {e}"));
        if command == "convert" {
            assert!(same_mesh(&back, &cube), "{output} differs from the input");
        } else {
            assert_eq!(back.face_count(), 24, "{output}: one level of a cube");
        }
        let o = katachi(&["info".as_ref(), out.as_os_str()]);
        assert!(o.status.success(), "info {output}: {}", stderr(&o));
    }
    // A missing file with such a name: named verbatim in the one error line.
    let missing = dir.join("nicht da ü 形.obj");
    let o = katachi(&["info".as_ref(), missing.as_os_str()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("nicht da ü 形.obj"), "{err}");
}

#[cfg(windows)]
#[test]
fn backslash_and_mixed_separators_work() {
    let dir = folder("separators");
    let cube = shapes::cube(1.0).unwrap();
    let input = dir.join("cube.off");
    katachi::io::write(&input, &cube).unwrap();
    let forward = input.to_str().unwrap().replace('\\', "/");
    let back = input.to_str().unwrap().replace('/', "\\");
    assert!(!back.contains('/'), "{back}");
    let out_back = dir
        .join("out back.obj")
        .to_str()
        .unwrap()
        .replace('/', "\\");
    let out_mixed = format!(
        "{}\\sub\\..\\out mixed.ply",
        dir.to_str().unwrap().replace('\\', "/")
    );
    for (input, output) in [(&back, &out_back), (&forward, &out_mixed)] {
        let o = katachi(&["convert", input, output]);
        assert!(o.status.success(), "{input} → {output}: {}", stderr(&o));
    }
    for name in ["out back.obj", "out mixed.ply"] {
        let read = katachi::io::read(&dir.join(name)).unwrap();
        assert!(same_mesh(&read, &cube), "{name}");
    }
    // `sub\..` resolved by Windows without `sub` existing; no stray file elsewhere.
    assert!(!dir.join("sub").exists());
    let o = katachi(&["info", &format!("{back}\\..\\nowhere\\x.off")]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("\\nowhere\\x.off"), "{}", stderr(&o));
}

#[test]
fn written_lines_end_in_lf_and_crlf_input_reads_as_lf() {
    let dir = folder("line-ends");
    let cube = shapes::cube(1.0).unwrap();
    let input = dir.join("cube.ply");
    katachi::io::write(&input, &cube).unwrap();
    for ext in ["obj", "off"] {
        let out = dir.join(format!("cube.{ext}"));
        let o = katachi(&["convert".as_ref(), input.as_os_str(), out.as_os_str()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = std::fs::read(&out).unwrap();
        assert!(!text.contains(&b'\r'), "{ext}: a CR in what katachi wrote");
        assert_eq!(text.last(), Some(&b'\n'), "{ext}");
        let crlf = dir.join(format!("crlf.{ext}"));
        let mut windows = Vec::new();
        for &b in &text {
            if b == b'\n' {
                windows.push(b'\r');
            }
            windows.push(b);
        }
        std::fs::write(&crlf, windows).unwrap();
        let again = dir.join(format!("again.{ext}"));
        let o = katachi(&["convert".as_ref(), crlf.as_os_str(), again.as_os_str()]);
        assert!(o.status.success(), "{ext} with CRLF: {}", stderr(&o));
        assert_eq!(
            std::fs::read(&again).unwrap(),
            text,
            "{ext}: CRLF input converts to the same file as LF input"
        );
    }
}
