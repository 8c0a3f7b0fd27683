//! `cargo xtask header [--check]`: generates `include/katachi.h` from `src/ffi` with the
//! cbindgen pinned in `xtask/Cargo.toml` (a library dependency, so every machine runs the
//! same version and no `cbindgen` binary needs installing), using `cbindgen.toml`.
//!
//! `--check` generates into memory and fails when the committed header differs, with the
//! first differing line as a hint; `cargo xtask test` calls [`check`].

use std::path::PathBuf;

use crate::util::root;

const USAGE: &str = "usage: cargo xtask header [--check]";

pub fn run(args: &[&str]) -> Result<(), String> {
    match args {
        [] => write(),
        ["--check"] => check(),
        _ => Err(USAGE.into()),
    }
}

fn header_path() -> PathBuf {
    root().join("include").join("katachi.h")
}

/// The header as the pinned cbindgen generates it from `src/ffi` now.
pub fn generate() -> Result<String, String> {
    let root = root();
    let config_path = root.join("cbindgen.toml");
    let config = cbindgen::Config::from_file(&config_path)
        .map_err(|e| format!("{}: {e}", config_path.display()))?;
    // Only the C ABI's module tree is parsed, so no other `pub const` of the crate leaks
    // into the header.
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(root.join("src").join("ffi").join("mod.rs"))
        .generate()
        .map_err(|e| format!("cbindgen failed on src/ffi: {e}"))?;
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).map_err(|e| format!("cbindgen wrote invalid UTF-8: {e}"))
}

/// Regenerates `include/katachi.h`.
fn write() -> Result<(), String> {
    let text = generate()?;
    let path = header_path();
    let old = std::fs::read_to_string(&path).ok();
    if old.as_deref() == Some(text.as_str()) {
        eprintln!("xtask: {} is up to date", path.display());
        return Ok(());
    }
    std::fs::create_dir_all(path.parent().expect("include/ has a parent"))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    std::fs::write(&path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!(
        "xtask: wrote {} ({} lines)",
        path.display(),
        text.lines().count()
    );
    Ok(())
}

/// Fails when the committed `include/katachi.h` is not what `src/ffi` generates.
pub fn check() -> Result<(), String> {
    let fresh = generate()?;
    let path = header_path();
    let committed = std::fs::read_to_string(&path).map_err(|e| {
        format!(
            "{}: {e}\n  generate it with `cargo xtask header` and commit it",
            path.display()
        )
    })?;
    if committed == fresh {
        eprintln!("xtask: {} is up to date", path.display());
        return Ok(());
    }
    Err(format!(
        "{} is stale: it is not what src/ffi and cbindgen.toml generate.\n{}\n  \
         run `cargo xtask header` and commit include/katachi.h",
        path.display(),
        diff_hint(&committed, &fresh)
    ))
}

/// Where two texts first differ, as a few lines of `-` committed / `+` generated.
fn diff_hint(committed: &str, fresh: &str) -> String {
    let old: Vec<&str> = committed.lines().collect();
    let new: Vec<&str> = fresh.lines().collect();
    let first = old
        .iter()
        .zip(&new)
        .position(|(a, b)| a != b)
        .unwrap_or(old.len().min(new.len()));
    let mut s = format!(
        "  first difference at line {} (committed {} lines, generated {} lines):",
        first + 1,
        old.len(),
        new.len()
    );
    for line in old.iter().skip(first).take(3) {
        s.push_str(&format!("\n  - {line}"));
    }
    for line in new.iter().skip(first).take(3) {
        s.push_str(&format!("\n  + {line}"));
    }
    if old.len() == new.len() && first == old.len() {
        s.push_str("\n  (the texts differ only in line endings or a final newline)");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::diff_hint;

    #[test]
    fn hint_shows_the_first_difference() {
        let h = diff_hint("a\nb\nc\n", "a\nB\nc\n");
        assert!(h.contains("line 2"), "{h}");
        assert!(h.contains("- b") && h.contains("+ B"), "{h}");
        let h = diff_hint("a\n", "a\nb\n");
        assert!(h.contains("line 2") && h.contains("+ b"), "{h}");
    }
}
