//! `cargo xtask deps`: installs the Debian packages the tests need.
//!
//! Idempotent: asks dpkg what is already there and installs only what is missing, printing
//! what it installs. Needs root on Debian or Ubuntu; elsewhere it says which packages to get.
//!
//! Also the `deb-src` entries the MeshLab plugin's headers come from ([`SourceApt`]): the
//! system's own suites (MeshLab 2020.09, Debian 12) and Debian unstable (MeshLab 2025.07), in
//! an apt configuration of the project's own under `target/apt`, so the system's apt is left
//! as it is and nothing from unstable can be installed.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::util::{self, have, is_root};

/// Debian packages, each with why it is needed.
pub const PACKAGES: &[(&str, &str)] = &[
    ("gcc", "C link tests (tests/c)"),
    ("g++", "C++ link tests (tests/c)"),
    ("valgrind", "memory checks of the C/C++ link tests"),
    (
        "pkg-config",
        "building C programs against the installed library",
    ),
    (
        "libosd-dev",
        "OpenSubdiv 3.5 (Far), the reference for subdivision in tests/reference",
    ),
    (
        "libopenmesh-dev",
        "OpenMesh 9 (CatmullClarkT), the second reference in tests/reference",
    ),
    (
        "libcgal-dev",
        "CGAL 5.5 (constrained Delaunay triangulation, exact kernel), the exact stroke cut in tests/reference",
    ),
    (
        "libgmp-dev",
        "GMP, which tests/reference links for CGAL's exact number types (also a dependency of libcgal-dev)",
    ),
    (
        "libmpfr-dev",
        "MPFR, which tests/reference links for CGAL's exact number types (also a dependency of libcgal-dev)",
    ),
    (
        "libclang-dev",
        "bindgen generates tests/reference's bindings with libclang",
    ),
    (
        "clang",
        "clang's resource headers (stddef.h, stdint.h) for bindgen in tests/reference",
    ),
    (
        "libgmsh-dev",
        "Gmsh 4.8 (C API gmshc.h + libgmsh): the peer for curved meshing in tests/reference (BAMG anisotropic mesher, AnalyseMeshQuality Jacobian check)",
    ),
    (
        "libboost-graph-dev",
        "Boost.Graph 1.74 (boykov_kolmogorov_max_flow), the max-flow reference for rough-model segmentation in tests/reference",
    ),
    (
        "blender",
        "Blender 3.4, where the add-on's tests run headless (cargo xtask blender-test)",
    ),
    (
        "python3-venv",
        "the venv into which cargo xtask blender-test installs bpy 5.0 from PyPI",
    ),
    (
        "xvfb",
        "an X server for Blender's UI when cargo xtask blender-test --screenshot renders it",
    ),
    (
        "xauth",
        "xvfb-run needs it to start Xvfb for the Blender screenshot",
    ),
    (
        "meshlab",
        "MeshLab 2020.09: libmeshlab-common.so the plugin links, meshlabserver and Debian's I/O plugins for its tests (xvfb, xauth: meshlabserver runs under xvfb-run)",
    ),
    (
        "dpkg-dev",
        "dpkg-source unpacks `apt-get source meshlab` (the plugin's headers); dpkg-architecture",
    ),
    ("cmake", "builds the MeshLab plugin (meshlab_plugin/CMakeLists.txt)"),
    ("make", "cmake's build tool for the MeshLab plugin"),
    (
        "qtbase5-dev",
        "Qt 5 headers and CMake files (Core, Gui, Widgets, Xml) for the MeshLab plugin",
    ),
    (
        "libqt5opengl5-dev",
        "Qt5::OpenGL, used by MeshLab's headers, for the MeshLab plugin",
    ),
    (
        "libeigen3-dev",
        "Eigen, included by vcglib's headers, for the MeshLab plugin",
    ),
    (
        "libglew-dev",
        "GL/glew.h and the GL headers, included by MeshLab's headers, for the MeshLab plugin",
    ),
    (
        "xdotool",
        "tests/meshlab/screenshot.sh drives MeshLab's GUI under Xvfb for the README's picture",
    ),
    (
        "imagemagick",
        "tests/meshlab/screenshot.sh captures the screen (`import`)",
    ),
    (
        "gcc-mingw-w64-x86-64",
        "the linker for Rust's x86_64-pc-windows-gnu target (katachi.dll, katachi.exe) and the C compiler of the C link tests for Windows (cargo xtask windows-test)",
    ),
    (
        "g++-mingw-w64-x86-64",
        "the C++ link test (tests/c/cpp_api.cpp) compiled for Windows (cargo xtask windows-test)",
    ),
    (
        "wine64",
        "Wine 8 runs the Windows C link tests, the Windows CLI and its tests (cargo xtask windows-test)",
    ),
    (
        "wine",
        "the `wine` launcher and Wine's support files for wine64 (without wine32: only 64-bit programs are run)",
    ),
];

/// Rust targets beyond the host's, each with why (installed with `rustup target add`).
pub const RUST_TARGETS: &[(&str, &str)] = &[
    (
        crate::windows::TARGET,
        "katachi.dll and katachi.exe for Windows, cross-built and tested under Wine (cargo xtask windows-test)",
    ),
    (
        crate::macos::TARGET,
        "the library and CLI type-checked for macOS (cargo xtask macos-check; linking needs Apple's SDK)",
    ),
];

fn installed(pkg: &str) -> bool {
    Command::new("dpkg-query")
        .args(["-W", "-f=${Status}", pkg])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains("install ok installed"))
        .unwrap_or(false)
}

pub fn run(_args: &[&str]) -> Result<(), String> {
    if !have("dpkg-query") || !have("apt-get") {
        let list: Vec<&str> = PACKAGES.iter().map(|p| p.0).collect();
        return Err(format!(
            "this is not a Debian/Ubuntu system (no dpkg-query/apt-get); install these packages by hand: {}",
            list.join(" ")
        ));
    }
    rust_targets()?;
    let missing: Vec<&(&str, &str)> = PACKAGES.iter().filter(|(p, _)| !installed(p)).collect();
    if missing.is_empty() {
        eprintln!("xtask deps: all {} packages are installed", PACKAGES.len());
        return remove_old_system_entries();
    }
    for (p, why) in &missing {
        eprintln!("xtask deps: will install {p} ({why})");
    }
    if !is_root() {
        return Err("installing packages needs root: run `sudo cargo xtask deps`".into());
    }
    util::run(
        Command::new("apt-get")
            .args(["update", "-q"])
            .env("DEBIAN_FRONTEND", "noninteractive"),
    )?;
    let mut cmd = Command::new("apt-get");
    // Several checkouts may run their deps step at once: wait for dpkg's lock instead of failing.
    cmd.args(["-o", "DPkg::Lock::Timeout=600"])
        .args(["install", "-y", "-q", "--no-install-recommends"])
        .env("DEBIAN_FRONTEND", "noninteractive");
    cmd.args(missing.iter().map(|(p, _)| *p));
    util::run(&mut cmd)?;
    let still: Vec<&str> = missing
        .iter()
        .map(|p| p.0)
        .filter(|p| !installed(p))
        .collect();
    if still.is_empty() {
        remove_old_system_entries()
    } else {
        Err(format!("apt-get did not install: {}", still.join(" ")))
    }
}

/// Adds the [`RUST_TARGETS`] rustup lacks (rustup's own download, no root needed).
fn rust_targets() -> Result<(), String> {
    if !have("rustup") {
        let list: Vec<&str> = RUST_TARGETS.iter().map(|t| t.0).collect();
        return Err(format!(
            "rustup is not on the PATH: install these Rust targets for the toolchain by hand: {}",
            list.join(" ")
        ));
    }
    let out = Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .map_err(|e| format!("cannot run `rustup target list --installed`: {e}"))?;
    let have_targets = String::from_utf8_lossy(&out.stdout).into_owned();
    for (target, why) in RUST_TARGETS {
        if have_targets.lines().any(|l| l.trim() == *target) {
            continue;
        }
        eprintln!("xtask deps: will add the Rust target {target} ({why})");
        util::run(Command::new("rustup").args(["target", "add", target]))?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Source packages (`apt-get source`)

const APT_DIR: &str = "/etc/apt";
/// The machine-wide entries earlier versions of this task wrote
/// (`<APT_DIR>/sources.list.d/katachi-deb-src.{sources,list}`); removed when found.
const OLD_SOURCES: &str = "katachi-deb-src";

/// The suite whose source package holds MeshLab 2025.07 (`meshlab` 2025.07~dfsg-4).
const UNSTABLE: &str = "unstable";
const DEBIAN_KEYRING: &str = "/usr/share/keyrings/debian-archive-keyring.gpg";

/// apt for source packages only, in a configuration of the project's own under
/// `<target>/apt/`: `sources.list.d/katachi.sources` holds `deb-src` entries for the system's
/// own Debian/Ubuntu suites (MeshLab 2020.09's source) and for Debian unstable (2025.07's),
/// and `lists/` and `cache/` are its own. `apt-get source` and `apt-cache showsrc` run with
/// `-o Dir::…` pointing there, so the system's apt (its sources, lists and cache) is never
/// changed, `apt-get install` never sees unstable, and no root is needed.
pub struct SourceApt {
    dir: PathBuf,
}

impl SourceApt {
    /// Writes the configuration and runs `apt-get update` in it when the entries changed or
    /// it has no lists yet.
    pub fn open() -> Result<SourceApt, String> {
        let apt = SourceApt {
            dir: crate::ctest::target_dir().join("apt"),
        };
        let parts = apt.dir.join("sources.list.d");
        let lists = apt.dir.join("lists");
        for d in [
            parts.clone(),
            lists.join("partial"),
            apt.dir.join("cache/archives/partial"),
        ] {
            std::fs::create_dir_all(&d).map_err(|e| format!("{}: {e}", d.display()))?;
        }
        let empty = apt.dir.join("sources.list");
        std::fs::write(&empty, "").map_err(|e| format!("{}: {e}", empty.display()))?;
        let text = source_entries()?;
        let path = parts.join("katachi.sources");
        let has_lists = std::fs::read_dir(&lists).is_ok_and(|mut d| {
            d.any(|e| e.is_ok_and(|e| e.file_name().to_string_lossy().ends_with("_Sources")))
        });
        if has_lists && std::fs::read_to_string(&path).is_ok_and(|old| old == text) {
            return Ok(apt);
        }
        std::fs::write(&path, &text).map_err(|e| format!("{}: {e}", path.display()))?;
        eprintln!(
            "xtask deps: source-package entries in {} (apt's own configuration is untouched)",
            path.display()
        );
        util::run(apt.command("apt-get").args(["update", "-q"]))?;
        Ok(apt)
    }

    /// `program` (`apt-get`, `apt-cache`) in this configuration.
    pub fn command(&self, program: &str) -> Command {
        let d = |p: &str| self.dir.join(p).display().to_string();
        let mut c = Command::new(program);
        for (key, value) in [
            ("Dir::Etc::SourceList", d("sources.list")),
            ("Dir::Etc::SourceParts", d("sources.list.d")),
            ("Dir::State::Lists", d("lists")),
            ("Dir::Cache", d("cache")),
            // Its own directories, which apt's unprivileged download user may not write.
            ("APT::Sandbox::User", "root".to_owned()),
        ] {
            c.arg("-o").arg(format!("{key}={value}"));
        }
        c.env("DEBIAN_FRONTEND", "noninteractive");
        c
    }
}

/// The `deb-src` entries (deb822): the system's Debian/Ubuntu archive entries turned into
/// `deb-src` ones, and Debian unstable's main.
fn source_entries() -> Result<String, String> {
    let apt = Path::new(APT_DIR);
    let deb822 = std::fs::read_to_string(apt.join("sources.list.d/debian.sources"))
        .or_else(|_| std::fs::read_to_string(apt.join("sources.list.d/ubuntu.sources")))
        .ok();
    let list = std::fs::read_to_string(apt.join("sources.list")).ok();
    let mut stanzas = system_source_stanzas(deb822.as_deref(), list.as_deref());
    if stanzas.is_empty() {
        return Err(
            "apt has no Debian/Ubuntu archive entry (sources.list.d/debian.sources, \
             ubuntu.sources or sources.list) to take the source packages from"
                .into(),
        );
    }
    if !Path::new(DEBIAN_KEYRING).is_file() {
        return Err(format!(
            "{DEBIAN_KEYRING} is missing (the Debian package debian-archive-keyring); the \
             deb-src entry for Debian {UNSTABLE} needs it"
        ));
    }
    stanzas.push(format!(
        "Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: {UNSTABLE}\n\
         Components: main\nSigned-By: {DEBIAN_KEYRING}\n"
    ));
    Ok(format!(
        "# Written by `cargo xtask` (katachi, xtask/src/deps.rs): source packages for the MeshLab \
         plugin's headers, in a configuration of its own.\n{}",
        stanzas.join("\n")
    ))
}

/// The system's Debian/Ubuntu archive entries (its deb822 `debian.sources` or
/// `ubuntu.sources`, and one-line `sources.list`) as `deb-src` deb822 stanzas.
fn system_source_stanzas(deb822: Option<&str>, list: Option<&str>) -> Vec<String> {
    let mut stanzas = deb822.map(deb_src_stanzas).unwrap_or_default();
    for l in list.map(deb_src_lines).unwrap_or_default() {
        let mut words = l.split_whitespace().skip(1).filter(|w| !w.starts_with('['));
        let (Some(uri), Some(suite)) = (words.next(), words.next()) else {
            continue;
        };
        let components: Vec<&str> = words.collect();
        stanzas.push(format!(
            "Types: deb-src\nURIs: {uri}\nSuites: {suite}\nComponents: {}\n",
            components.join(" ")
        ));
    }
    stanzas
}

/// Removes the machine-wide `deb-src` entries earlier versions wrote (they made a plain
/// `apt-get source meshlab` on the machine fetch unstable's 2025.07). Only files that say they
/// are ours.
fn remove_old_system_entries() -> Result<(), String> {
    let mut removed = false;
    for ext in ["sources", "list"] {
        let path = Path::new(APT_DIR)
            .join("sources.list.d")
            .join(format!("{OLD_SOURCES}.{ext}"));
        let ours = std::fs::read_to_string(&path)
            .is_ok_and(|t| t.starts_with("# Written by `cargo xtask") && t.contains("katachi"));
        if ours && is_root() {
            std::fs::remove_file(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!(
                "xtask deps: removed {} (now private to the project)",
                path.display()
            );
            removed = true;
        }
    }
    if removed {
        util::run(
            Command::new("apt-get")
                .args(["update", "-q"])
                .env("DEBIAN_FRONTEND", "noninteractive"),
        )?;
    }
    Ok(())
}

/// Splits deb822 text into stanzas (blank-line separated), comment lines dropped.
fn deb822_stanzas(text: &str) -> Vec<Vec<&str>> {
    let mut out = vec![Vec::new()];
    for line in text.lines() {
        if line.trim().is_empty() {
            if !out.last().is_some_and(Vec::is_empty) {
                out.push(Vec::new());
            }
        } else if !line.trim_start().starts_with('#') {
            out.last_mut().expect("never empty").push(line);
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

/// The value of field `name` in a stanza (single-line fields only).
fn field<'a>(stanza: &[&'a str], name: &str) -> Option<&'a str> {
    stanza.iter().find_map(|l| {
        let (k, v) = l.split_once(':')?;
        k.trim().eq_ignore_ascii_case(name).then(|| v.trim())
    })
}

fn enabled(stanza: &[&str]) -> bool {
    field(stanza, "Enabled").is_none_or(|v| !v.eq_ignore_ascii_case("no"))
}

/// For each enabled `Types: deb` stanza, the same stanza with `Types: deb-src`.
fn deb_src_stanzas(text: &str) -> Vec<String> {
    deb822_stanzas(text)
        .into_iter()
        .filter(|s| {
            enabled(s)
                && field(s, "Types").is_some_and(|t| t.split_whitespace().any(|t| t == "deb"))
        })
        .map(|s| {
            let mut out = String::new();
            for l in s {
                let is_types = l
                    .split_once(':')
                    .is_some_and(|(k, _)| k.trim().eq_ignore_ascii_case("Types"));
                let _ = writeln!(out, "{}", if is_types { "Types: deb-src" } else { l });
            }
            out
        })
        .collect()
}

/// `deb …` lines of a one-line-style list turned into `deb-src …`.
fn deb_src_lines(text: &str) -> Vec<String> {
    text.lines()
        .filter_map(|l| l.trim_start().strip_prefix("deb "))
        .map(|rest| format!("deb-src {rest}"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deb_src_from_deb822() {
        let text = "Types: deb\n# c\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\n\nTypes: deb\nURIs: http://x\nSuites: s\nEnabled: no\n";
        let st = deb_src_stanzas(text);
        assert_eq!(st.len(), 1);
        assert!(st[0].starts_with("Types: deb-src\nURIs: http://deb.debian.org/debian\n"));
        assert_eq!(
            deb_src_lines("deb http://a bookworm main\n# deb x\n"),
            vec!["deb-src http://a bookworm main"]
        );
        let from_list = system_source_stanzas(
            None,
            Some("deb [arch=amd64] http://archive.ubuntu.com/ubuntu noble main universe\n"),
        );
        assert_eq!(
            from_list,
            vec!["Types: deb-src\nURIs: http://archive.ubuntu.com/ubuntu\nSuites: noble\nComponents: main universe\n"]
        );
        assert_eq!(system_source_stanzas(Some(text), None), st);
    }
}
