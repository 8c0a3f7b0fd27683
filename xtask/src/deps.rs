//! `cargo xtask deps`: installs the Debian packages the tests need.
//!
//! Idempotent: asks dpkg what is already there and installs only what is missing, printing
//! what it installs. Needs root on Debian or Ubuntu; elsewhere it says which packages to get.

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
        return Ok(());
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
        Ok(())
    } else {
        Err(format!("apt-get did not install: {}", still.join(" ")))
    }
}
