//! The layers of `docs/ARCHITECTURE.md`, checked on the source: each top-level module of the
//! library uses only the modules its layer may use. The mesh knows no algorithm, algorithms
//! do not use each other (what two of them share belongs in `mesh`), and nothing but the C ABI
//! uses the C ABI. (That the C ABI calls only public kernel entry points is checked by the
//! compiler: `tests/ffi-public` builds `src/ffi` against the public API alone.)

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The frame and the mesh layer: what every algorithm may use.
const BASE: &[&str] = &["error", "mem", "mesh", "io"];

/// What `module` may use besides itself.
fn allowed(module: &str) -> Vec<&'static str> {
    match module {
        "error" => vec![],
        "mem" => vec!["error"],
        "mesh" => vec!["error", "mem"],
        "io" => vec!["error", "mem", "mesh"],
        // The C ABI is a front end: it may use any kernel module.
        "ffi" => vec![
            "error",
            "mem",
            "mesh",
            "io",
            "subdivide",
            "cut",
            "curved",
            "rough",
            "segment",
            "spline",
            "edit",
        ],
        // An algorithm (subdivide, cut, and any new one): the base, never another algorithm.
        _ => BASE.to_vec(),
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules named by `crate::NAME` in the code (not the comments) of `text`.
fn uses(text: &str) -> BTreeSet<String> {
    let mut found = BTreeSet::new();
    for line in text.lines() {
        let code = match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        };
        let mut rest = code;
        while let Some(i) = rest.find("crate::") {
            let name: String = rest[i + 7..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
                found.insert(name);
            }
            rest = &rest[i + 7..];
        }
    }
    found
}

#[test]
fn each_module_uses_only_its_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut faults = Vec::new();
    let mut checked = 0;
    for file in &files {
        let rel = file.strip_prefix(&src).unwrap();
        let mut parts = rel.iter().map(|p| p.to_string_lossy().into_owned());
        let first = parts.next().unwrap();
        if first == "lib.rs" {
            continue;
        }
        let module = first.trim_end_matches(".rs").to_string();
        let text = std::fs::read_to_string(file).unwrap();
        let may = allowed(&module);
        for used in uses(&text) {
            if used != module && !may.contains(&used.as_str()) {
                faults.push(format!(
                    "src/{}: {module} uses crate::{used}; its layer allows only {may:?}",
                    rel.display()
                ));
            }
        }
        checked += 1;
    }
    assert!(checked > 20, "only {checked} files looked at");
    assert!(
        faults.is_empty(),
        "layer violations (see docs/ARCHITECTURE.md):\n{}",
        faults.join("\n")
    );
}

#[test]
fn the_scan_sees_a_use_in_code_and_not_in_comments() {
    let text = "use crate::subdivide::Refiner; // crate::ffi\n/// [`crate::io`]\nlet x = crate::mesh::shapes::cube(1.0);";
    let found: Vec<String> = uses(text).into_iter().collect();
    assert_eq!(found, ["mesh", "subdivide"]);
}

#[test]
fn the_library_depends_on_no_front_end_crate() {
    // C programs, the Blender add-on and the MeshLab plugin link the library: the CLI's
    // argument parsing, progress bars and JSON stroke files belong to `cli/` alone.
    let manifest =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml")).unwrap();
    let mut section = String::new();
    let mut found = Vec::new();
    for line in manifest.lines() {
        let t = line.trim();
        if t.starts_with('[') {
            section = t.to_string();
            continue;
        }
        let normal = section == "[dependencies]"
            || (section.starts_with("[target.") && section.ends_with(".dependencies]"));
        if !normal {
            continue;
        }
        for name in ["clap", "indicatif", "serde_json", "serde"] {
            if t.split(['=', ' ', '.']).next() == Some(name) {
                found.push(format!("{section} {t}"));
            }
        }
    }
    assert!(
        found.is_empty(),
        "the library depends on front-end crates:\n{}",
        found.join("\n")
    );
}

#[test]
fn files_are_written_only_through_io_write() {
    // `io::write` and `io::write_bytes` write a temporary file beside the target and rename
    // it into place, so a failed write (a full disk, a file-size limit) leaves the old file.
    // A plain `fs::write` or `File::create` in the library or the tool would truncate it.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("cli/src"), &mut files);
    files.sort();
    let atomic = root.join("src/io/atomic.rs");
    let mut found = Vec::new();
    for file in files.iter().filter(|f| **f != atomic) {
        let text = std::fs::read_to_string(file).unwrap();
        // Unit tests inside a file may make scratch files.
        let code = text.split("#[cfg(test)]").next().unwrap_or("");
        for (n, line) in code.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for call in ["fs::write(", "File::create(", "OpenOptions::new("] {
                if code.contains(call) {
                    let rel = file.strip_prefix(root).unwrap();
                    found.push(format!("{}:{}: {}", rel.display(), n + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "write files through katachi::io::write / io::write_bytes:\n{}",
        found.join("\n")
    );
}
