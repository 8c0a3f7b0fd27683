//! `cargo xtask deps`: installs the Debian packages the tests need.
//!
//! Idempotent: asks dpkg what is already there and installs only what is missing, printing
//! what it installs. Needs root on Debian or Ubuntu; elsewhere it says which packages to get.
//!
//! Also the `deb-src` entries the MeshLab plugin's headers come from ([`ensure_source_entries`]):
//! the system's own suites (MeshLab 2020.09, Debian 12) and Debian unstable (MeshLab 2025.07),
//! source packages only, so nothing from unstable can be installed.

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
    let missing: Vec<&(&str, &str)> = PACKAGES.iter().filter(|(p, _)| !installed(p)).collect();
    if missing.is_empty() {
        eprintln!("xtask deps: all {} packages are installed", PACKAGES.len());
        return ensure_source_entries();
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
    cmd.args(["install", "-y", "-q", "--no-install-recommends"])
        .env("DEBIAN_FRONTEND", "noninteractive");
    cmd.args(missing.iter().map(|(p, _)| *p));
    util::run(&mut cmd)?;
    let still: Vec<&str> = missing
        .iter()
        .map(|p| p.0)
        .filter(|p| !installed(p))
        .collect();
    if still.is_empty() {
        ensure_source_entries()
    } else {
        Err(format!("apt-get did not install: {}", still.join(" ")))
    }
}

// ---------------------------------------------------------------------------------------
// Source packages (`apt-get source`)

const APT_DIR: &str = "/etc/apt";
/// Our entries, beside the system's: `<APT_DIR>/sources.list.d/katachi-deb-src.{sources,list}`.
const OUR_SOURCES: &str = "katachi-deb-src";

/// The suite whose source package holds MeshLab 2025.07 (`meshlab` 2025.07~dfsg-4).
const UNSTABLE: &str = "unstable";

/// Makes sure apt has `deb-src` entries (source packages only) for the system's own
/// Debian/Ubuntu suites, when it has none, and for Debian unstable; writes them to
/// `katachi-deb-src.sources` (or `.list`) beside the system's entries and runs
/// `apt-get update` when that file changes. Idempotent. The unstable entry is Debian's
/// (`deb.debian.org`, its archive keyring); `apt-get source meshlab=2025.07~dfsg-4` needs it.
pub fn ensure_source_entries() -> Result<(), String> {
    let apt = Path::new(APT_DIR);
    let mut files = vec![apt.join("sources.list")];
    if let Ok(entries) = std::fs::read_dir(apt.join("sources.list.d")) {
        let mut more: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        more.sort();
        files.extend(more);
    }
    let mut has_src = false;
    let mut stanzas = Vec::new();
    let mut lines = Vec::new();
    for f in &files {
        let name = f.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.starts_with(OUR_SOURCES) {
            continue;
        }
        let Ok(text) = std::fs::read_to_string(f) else {
            continue;
        };
        if name.ends_with(".sources") {
            has_src |= has_deb_src_deb822(&text);
            // Only the distribution's own archive: third-party repositories often have no
            // source packages and would make `apt-get update` fail.
            if name == "debian.sources" || name == "ubuntu.sources" {
                stanzas.extend(deb_src_stanzas(&text));
            }
        } else if name == "sources.list" || name.ends_with(".list") {
            has_src |= has_deb_src_list(&text);
            if name == "sources.list" {
                lines.extend(deb_src_lines(&text));
            }
        }
    }
    if has_src {
        stanzas.clear();
        lines.clear();
    } else if stanzas.is_empty() && lines.is_empty() {
        return Err(
            "apt has no deb-src entry and no Debian/Ubuntu archive entry (debian.sources, \
             ubuntu.sources or sources.list) to make one from; add a deb-src entry by hand"
                .into(),
        );
    }
    let keyring = "/usr/share/keyrings/debian-archive-keyring.gpg";
    let header = "# Written by `cargo xtask deps` (katachi): source packages for the MeshLab \
                  plugin's headers (`apt-get source meshlab=...`). Sources only: nothing from \
                  these entries can be installed.\n";
    let (path, body) = if lines.is_empty() {
        stanzas.push(format!(
            "Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: {UNSTABLE}\n\
             Components: main\nSigned-By: {keyring}\n"
        ));
        (
            apt.join("sources.list.d")
                .join(format!("{OUR_SOURCES}.sources")),
            stanzas.join("\n"),
        )
    } else {
        lines.push(format!(
            "deb-src [signed-by={keyring}] http://deb.debian.org/debian {UNSTABLE} main"
        ));
        (
            apt.join("sources.list.d")
                .join(format!("{OUR_SOURCES}.list")),
            lines.join("\n") + "\n",
        )
    };
    let text = format!("{header}{body}");
    if std::fs::read_to_string(&path).is_ok_and(|old| old == text) {
        return Ok(());
    }
    if !Path::new(keyring).is_file() {
        return Err(format!(
            "{keyring} is missing (the Debian package debian-archive-keyring); the deb-src \
             entry for Debian {UNSTABLE} needs it"
        ));
    }
    if !is_root() {
        return Err(format!(
            "apt needs deb-src entries for `apt-get source meshlab=...`; run `sudo cargo xtask \
             deps` once, or write {} with:\n{body}",
            path.display()
        ));
    }
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!("xtask deps: wrote the deb-src entries {}", path.display());
    util::run(
        Command::new("apt-get")
            .args(["update", "-q"])
            .env("DEBIAN_FRONTEND", "noninteractive"),
    )
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

fn has_deb_src_deb822(text: &str) -> bool {
    deb822_stanzas(text).iter().any(|s| {
        enabled(s)
            && field(s, "Types").is_some_and(|t| t.split_whitespace().any(|t| t == "deb-src"))
    })
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

fn has_deb_src_list(text: &str) -> bool {
    text.lines().any(|l| l.trim_start().starts_with("deb-src "))
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
        assert!(!has_deb_src_deb822(text));
        let st = deb_src_stanzas(text);
        assert_eq!(st.len(), 1);
        assert!(st[0].starts_with("Types: deb-src\nURIs: http://deb.debian.org/debian\n"));
        assert!(has_deb_src_deb822(&st[0]));
        assert!(has_deb_src_list("deb http://a b c\ndeb-src http://a b c\n"));
        assert_eq!(
            deb_src_lines("deb http://a bookworm main\n# deb x\n"),
            vec!["deb-src http://a bookworm main"]
        );
    }
}
