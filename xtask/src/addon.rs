//! `cargo xtask addon`: the Blender add-on's installable zip.
//!
//! Builds the release library (`cargo build --release -p katachi --lib`), stages
//! `blender_addon/katachi/*` with `libkatachi.so` (debug info stripped when `strip` is on the
//! PATH) and writes `<target>/addon/katachi-<version>.zip` (`<target>` is `$CARGO_TARGET_DIR`
//! or `target`). The zip holds one folder, `katachi/`, with both `bl_info` and
//! `blender_manifest.toml`, so the same file installs as a legacy add-on in Blender 3.4
//! (Preferences ▸ Add-ons ▸ Install) and as an extension in 4.2 to 5.0 (Install from Disk);
//! `cargo xtask blender-test` installs it both ways.
//!
//! The version in the manifest, in `bl_info` and in the katachi crate must agree: the task
//! fails naming the file that differs. The zip is written by Python's `zipfile` (the
//! `python3` package; Blender needs Python anyway) with fixed timestamps, so the same
//! sources give the same bytes.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::ctest::target_dir;
use crate::util::{have, root, run as run_cmd};

const USAGE: &str = "usage: cargo xtask addon";

pub fn run(args: &[&str]) -> Result<(), String> {
    if let Some(a) = args.first() {
        return Err(format!("unknown argument `{a}`\n{USAGE}"));
    }
    let zip = build()?;
    eprintln!("xtask: addon: wrote {}", zip.display());
    Ok(())
}

/// Builds the library and the zip; returns the zip's path.
pub fn build() -> Result<PathBuf, String> {
    if !have("python3") {
        return Err("`python3` is not on the PATH; it writes the add-on zip. \
             Install the Debian package `python3` (or run `cargo xtask deps`)."
            .into());
    }
    let version = check_versions()?;
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    run_cmd(Command::new(cargo).args(["build", "--release", "-p", "katachi", "--lib"]))?;
    let lib = target_dir().join("release").join("libkatachi.so");
    if !lib.is_file() {
        return Err(format!("{} is missing after the build", lib.display()));
    }

    let out_dir = target_dir().join("addon");
    let stage = out_dir.join("stage");
    if stage.exists() {
        std::fs::remove_dir_all(&stage).map_err(|e| format!("{}: {e}", stage.display()))?;
    }
    let pkg = stage.join("katachi");
    std::fs::create_dir_all(&pkg).map_err(|e| format!("{}: {e}", pkg.display()))?;
    let src = root().join("blender_addon").join("katachi");
    let mut files = Vec::new();
    for entry in std::fs::read_dir(&src).map_err(|e| format!("{}: {e}", src.display()))? {
        let path = entry.map_err(|e| format!("{}: {e}", src.display()))?.path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let wanted = path.is_file() && (name.ends_with(".py") || name == "blender_manifest.toml");
        if wanted {
            std::fs::copy(&path, pkg.join(name)).map_err(|e| format!("{}: {e}", path.display()))?;
            files.push(name.to_owned());
        }
    }
    for needed in ["__init__.py", "blender_manifest.toml", "ffi.py"] {
        if !files.iter().any(|f| f == needed) {
            return Err(format!("{} is missing", src.join(needed).display()));
        }
    }
    let staged_lib = pkg.join("libkatachi.so");
    if have("strip") {
        run_cmd(
            Command::new("strip")
                .arg("--strip-debug")
                .arg("-o")
                .arg(&staged_lib)
                .arg(&lib),
        )?;
    } else {
        eprintln!("xtask: addon: `strip` (binutils) is missing; the library keeps its debug info");
        std::fs::copy(&lib, &staged_lib).map_err(|e| format!("{}: {e}", lib.display()))?;
    }

    let zip = out_dir.join(format!("katachi-{version}.zip"));
    write_zip(&stage, &zip)?;
    Ok(zip)
}

/// Zips `stage/katachi/` into `zip` with fixed timestamps and modes.
fn write_zip(stage: &Path, zip: &Path) -> Result<(), String> {
    const SCRIPT: &str = r#"
import os, sys, zipfile
stage, out = sys.argv[1], sys.argv[2]
tmp = out + ".tmp"
with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as z:
    for name in sorted(os.listdir(os.path.join(stage, "katachi"))):
        path = os.path.join(stage, "katachi", name)
        info = zipfile.ZipInfo("katachi/" + name, date_time=(2024, 1, 1, 0, 0, 0))
        info.compress_type = zipfile.ZIP_DEFLATED
        info.external_attr = (0o755 if name.endswith(".so") else 0o644) << 16
        with open(path, "rb") as f:
            z.writestr(info, f.read())
os.replace(tmp, out)
"#;
    run_cmd(
        Command::new("python3")
            .args(["-c", SCRIPT])
            .arg(stage)
            .arg(zip),
    )
}

/// The add-on's version, after checking that the manifest, `bl_info` and the crate agree.
fn check_versions() -> Result<String, String> {
    let read = |p: &Path| std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()));
    let manifest_path = root().join("blender_addon/katachi/blender_manifest.toml");
    let manifest = read(&manifest_path)?;
    let version = toml_string(&manifest, "version")
        .ok_or_else(|| format!("{}: no `version = \"…\"` line", manifest_path.display()))?;
    let crate_toml = read(&root().join("Cargo.toml"))?;
    let crate_version = toml_string(&crate_toml, "version")
        .ok_or("Cargo.toml: no `version = \"…\"` line in [package]")?;
    if version != crate_version {
        return Err(format!(
            "{} says version {version}, but the katachi crate is {crate_version}",
            manifest_path.display()
        ));
    }
    let init_path = root().join("blender_addon/katachi/__init__.py");
    let init = read(&init_path)?;
    let tuple = format!("\"version\": ({}),", version.replace('.', ", "));
    if !init.contains(&tuple) {
        return Err(format!(
            "{}: bl_info has no `{tuple}` (the manifest says {version})",
            init_path.display()
        ));
    }
    Ok(version)
}

/// The value of the first `key = "value"` line.
fn toml_string(text: &str, key: &str) -> Option<String> {
    text.lines().find_map(|l| {
        let (k, v) = l.split_once('=')?;
        if k.trim() != key {
            return None;
        }
        Some(v.trim().strip_prefix('"')?.strip_suffix('"')?.to_owned())
    })
}

#[cfg(test)]
mod tests {
    use super::toml_string;

    #[test]
    fn reads_the_first_matching_line() {
        let t = "[package]\nname = \"katachi\"\nversion = \"0.1.0\"\n[x]\nversion = \"9\"\n";
        assert_eq!(toml_string(t, "version").as_deref(), Some("0.1.0"));
        assert_eq!(toml_string(t, "name").as_deref(), Some("katachi"));
        assert_eq!(toml_string(t, "edition"), None);
    }
}
