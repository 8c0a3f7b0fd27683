//! `cargo xtask meshlab-plugin [--test] [--only 2020.09|2025.07] [-k NAME]`: builds the
//! MeshLab filter plugin (`meshlab_plugin/`) for MeshLab 2020.09 and MeshLab 2025.07 and, with
//! `--test`, runs its tests (`tests/meshlab/`) in both. This file only fetches, builds,
//! installs and invokes; the test cases live in `tests/meshlab/`.
//!
//! Build:
//! 1. MeshLab's sources into `<target>/meshlab/src` (kept and reused; `<target>` is
//!    `$CARGO_TARGET_DIR` or `<root>/target`): `apt-get source meshlab=<the installed
//!    version>` (Debian 12's 2020.09+dfsg1-2) and `apt-get source --tar-only
//!    meshlab=2025.07~dfsg-4` (Debian unstable: only the upstream tarball, which holds
//!    `src/common` and `src/vcglib`), both through the project's own apt configuration
//!    (`deps::SourceApt`, `<target>/apt`: deb-src entries only; the system's apt is untouched);
//! 2. `cargo build --release -p katachi` (the library the plugin links, the CLI the tests
//!    compare with);
//! 3. for 2025.07, `pymeshlab==2025.7.post1` from PyPI into the venv `<target>/pymeshlab-venv`
//!    (made once with `python3.11 -m venv`, a 106 MB wheel and numpy, 380 MB installed;
//!    reused): its `lib/` holds MeshLab 2025.07's `libmeshlab-common.so` (built with double
//!    scalars) and Qt 5.15.2, which the plugin links;
//! 4. CMake in `<target>/meshlab/build-2020.09` (with the harness) and `build-2025.07`.
//!
//! Test (`--test`, and `cargo xtask test`):
//! 1. 2020.09: a private MeshLab prefix `<target>/meshlab/prefix` (`bin/meshlabserver`
//!    copied, as MeshLab looks for plugins beside its executable in
//!    `../lib/<multiarch>/meshlab/plugins`; `libmeshlab-common.so` and Debian's plugins
//!    symlinked; ours installed by `cmake --install`), so the system's MeshLab is untouched;
//!    `tests/meshlab/plugin_harness.cpp` (in memory: layers, faux edges, errors, unchanged
//!    layers) and `tests/meshlab/run_meshlabserver.py` (`xvfb-run -a meshlabserver`);
//! 2. 2025.07: `tests/meshlab/run_pymeshlab.py` with the venv's Python (`load_plugin`,
//!    `apply_filter`).
//!
//! Each test program prints one line per check and closes with `N passed, M failed`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::ctest::target_dir;
use crate::util::{describe, have, parse_summary, root, run as run_cmd, run_in};

const USAGE: &str = "usage: cargo xtask meshlab-plugin [--test] [--only 2020.09|2025.07] [-k NAME]";

/// Tools needed, with the Debian package that provides each.
const BUILD_TOOLS: [(&str, &str); 5] = [
    ("apt-get", "apt"),
    ("dpkg-source", "dpkg-dev"),
    ("cmake", "cmake"),
    ("make", "make"),
    ("g++", "g++"),
];
pub(crate) const TEST_TOOLS: [(&str, &str); 3] = [
    ("meshlabserver", "meshlab"),
    ("xvfb-run", "xvfb"),
    ("python3", "python3"),
];

/// MeshLab 2020.09: Debian 12's package (2020.09+dfsg1-2), whose source the 2020.09 build
/// compiles against: the installed version's, see [`source_2020`].
const MESHLAB_2020: &str = "2020.09";
/// MeshLab 2025.07: the source package in Debian unstable (source only), 2025.07~dfsg-4, or
/// a later Debian revision of the same upstream tarball once unstable has moved on.
const SOURCE_2025: &str = "2025.07~dfsg-4";
const UPSTREAM_2025: &str = "2025.07~dfsg";
/// pymeshlab 2025.7: MeshLab 2025.07's libraries (Python 3.11 wheel, manylinux_2_35).
const PYMESHLAB: &str = "pymeshlab==2025.7.post1";
const PYMESHLAB_VERSION: &str = "2025.7.post1";

/// Which MeshLab versions to build and test.
#[derive(Clone, Copy)]
pub(crate) struct Versions {
    pub(crate) v2020: bool,
    pub(crate) v2025: bool,
}

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut versions = Versions {
        v2020: true,
        v2025: true,
    };
    let (mut test_too, mut filter) = (false, None);
    let mut it = args.iter().copied();
    while let Some(a) = it.next() {
        match a {
            "--test" => test_too = true,
            "--only" => match it.next() {
                Some("2020.09") => versions.v2025 = false,
                Some("2025.07") => versions.v2020 = false,
                _ => return Err(format!("--only takes 2020.09 or 2025.07\n{USAGE}")),
            },
            "-k" => filter = Some(it.next().ok_or(USAGE)?),
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    if test_too {
        test_versions(versions, filter)
    } else {
        build(versions).map(|_| ())
    }
}

/// Where things go: all under `<target>/meshlab` (and the venv beside it).
pub(crate) struct Dirs {
    base: PathBuf,
    pub(crate) build2020: PathBuf,
    build2025: PathBuf,
    prefix: PathBuf,
    release: PathBuf,
    /// The pymeshlab venv's Python (2025.07 only).
    python: Option<PathBuf>,
}

/// Builds the plugin for the chosen versions; returns the directories for the tests.
pub(crate) fn build(versions: Versions) -> Result<Dirs, String> {
    check_tools(&BUILD_TOOLS)?;
    let base = target_dir().join("meshlab");
    let src = base.join("src");
    // Fail early, before the long builds, on a missing source or wheel.
    let source2020 = if versions.v2020 {
        Some(meshlab_source(
            &src,
            &source_2020()?,
            "meshlab-2020.09",
            false,
        )?)
    } else {
        None
    };
    let (source2025, python) = if versions.v2025 {
        let source_2025 = source_2025()?;
        (
            Some(meshlab_source(&src, &source_2025, "meshlab-2025.07", true)?),
            Some(pymeshlab_python()?),
        )
    } else {
        (None, None)
    };
    // The library the plugin links, and the `katachi` CLI (crate katachi-cli) the tests compare with.
    run_cmd(Command::new(crate::util::cargo()).args([
        "build",
        "--release",
        "-p",
        "katachi",
        "-p",
        "katachi-cli",
    ]))?;
    let release = target_dir().join("release");
    let lib = release.join("libkatachi.so");
    if !lib.is_file() {
        return Err(format!(
            "{} is missing after the release build",
            lib.display()
        ));
    }
    let dirs = Dirs {
        build2020: base.join("build-2020.09"),
        build2025: base.join("build-2025.07"),
        prefix: base.join("prefix"),
        base,
        release,
        python,
    };
    if let Some(source) = source2020 {
        let plugin_dir = dirs.prefix.join(plugin_subdir()?);
        let common = system_meshlab_lib_dir()?.join("libmeshlab-common.so");
        cmake_build(
            &dirs.build2020,
            &source,
            &lib,
            &[
                format!("-DMESHLAB_COMMON_LIBRARY={}", common.display()),
                format!("-DMESHLAB_PLUGIN_DIR={}", plugin_dir.display()),
                "-DMESHLAB_SCALAR=float".into(),
                "-DKATACHI_BUILD_TESTS=ON".into(),
            ],
        )?;
    }
    if let (Some(source), Some(python)) = (source2025, &dirs.python) {
        let wheel_lib = pymeshlab_lib_dir(python)?;
        cmake_build(
            &dirs.build2025,
            &source,
            &lib,
            &[
                format!(
                    "-DMESHLAB_COMMON_LIBRARY={}",
                    wheel_lib.join("libmeshlab-common.so").display()
                ),
                format!("-DMESHLAB_QT_LIBRARY_DIR={}", wheel_lib.display()),
                // pymeshlab's MeshLab is built with double scalars ("2025.07d").
                "-DMESHLAB_SCALAR=double".into(),
            ],
        )?;
    }
    Ok(dirs)
}

/// Configures and builds `meshlab_plugin/` in `build` against the MeshLab source `source`.
fn cmake_build(build: &Path, source: &Path, lib: &Path, extra: &[String]) -> Result<(), String> {
    let mut configure = Command::new("cmake");
    configure
        .arg("-S")
        .arg(root().join("meshlab_plugin"))
        .arg("-B")
        .arg(build)
        .arg("-DCMAKE_BUILD_TYPE=Release")
        .arg(format!("-DMESHLAB_SOURCE_DIR={}", source.display()))
        .arg(format!(
            "-DKATACHI_INCLUDE_DIR={}",
            root().join("include").display()
        ))
        .arg(format!("-DKATACHI_LIBRARY={}", lib.display()))
        .args(extra);
    run_cmd(&mut configure)?;
    run_cmd(
        Command::new("cmake")
            .arg("--build")
            .arg(build)
            .args(["-j", "2"]),
    )?;
    let so = build.join("libfilter_katachi.so");
    if !so.is_file() {
        return Err(format!("{} is missing after the build", so.display()));
    }
    eprintln!("xtask: meshlab-plugin: built {}", so.display());
    Ok(())
}

pub(crate) fn check_tools(tools: &[(&str, &str)]) -> Result<(), String> {
    let missing: Vec<&(&str, &str)> = tools.iter().filter(|(t, _)| !have(t)).collect();
    if missing.is_empty() {
        return Ok(());
    }
    let what: Vec<String> = missing
        .iter()
        .map(|(t, p)| format!("`{t}` (Debian package {p})"))
        .collect();
    let pkgs: Vec<&str> = missing.iter().map(|(_, p)| *p).collect();
    Err(format!(
        "the MeshLab plugin needs {} on the PATH.\n  Install: `apt-get install {}` (as root), or run `cargo xtask deps`.",
        what.join(", "),
        pkgs.join(" ")
    ))
}

/// Debian's multiarch triplet (`x86_64-linux-gnu`), where MeshLab keeps its libraries.
fn multiarch() -> Result<String, String> {
    let out = Command::new("dpkg-architecture")
        .arg("-qDEB_HOST_MULTIARCH")
        .output()
        .map_err(|e| format!("cannot run dpkg-architecture (package dpkg-dev): {e}"))?;
    let s = String::from_utf8_lossy(&out.stdout).trim().to_owned();
    if out.status.success() && !s.is_empty() {
        Ok(s)
    } else {
        Err("dpkg-architecture -qDEB_HOST_MULTIARCH gave nothing".into())
    }
}

/// `lib/<multiarch>/meshlab/plugins`, relative to a prefix.
fn plugin_subdir() -> Result<PathBuf, String> {
    Ok(Path::new("lib")
        .join(multiarch()?)
        .join("meshlab")
        .join("plugins"))
}

/// `/usr/lib/<multiarch>/meshlab`: the installed MeshLab's library directory.
pub(crate) fn system_meshlab_lib_dir() -> Result<PathBuf, String> {
    let dir = Path::new("/usr/lib").join(multiarch()?).join("meshlab");
    if dir.join("libmeshlab-common.so").is_file() {
        Ok(dir)
    } else {
        Err(format!(
            "{} has no libmeshlab-common.so: install the Debian package meshlab (`cargo xtask deps`)",
            dir.display()
        ))
    }
}

// ---------------------------------------------------------------------------------------
// MeshLab's sources and pymeshlab

/// The unpacked source of `spec` under `dir/<name>`, fetched when not there yet. With
/// `tar_only`, only the upstream tarball is fetched (`apt-get source --tar-only`) and
/// unpacked with tar: the headers are all in it, and Debian's packaging is not needed.
fn meshlab_source(dir: &Path, spec: &str, name: &str, tar_only: bool) -> Result<PathBuf, String> {
    let dir = dir.join(name);
    if let Some(found) = find_source(&dir) {
        eprintln!(
            "xtask: meshlab-plugin: reusing MeshLab's source in {}",
            found.display()
        );
        return Ok(found);
    }
    let apt = crate::deps::SourceApt::open()?;
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut cmd = apt.command("apt-get");
    cmd.args(["source", "-q"]);
    if tar_only {
        cmd.arg("--tar-only");
    }
    run_in(&dir, cmd.arg(spec))?;
    if tar_only {
        let tarballs: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.to_string_lossy().contains(".orig.tar."))
            .collect();
        let [tarball] = &tarballs[..] else {
            return Err(format!(
                "`apt-get source --tar-only {spec}` left {} upstream tarballs in {}",
                tarballs.len(),
                dir.display()
            ));
        };
        run_in(&dir, Command::new("tar").arg("xf").arg(tarball))?;
    }
    find_source(&dir).ok_or_else(|| {
        format!(
            "`apt-get source {spec}` left no MeshLab source tree (src/common) in {}",
            dir.display()
        )
    })
}

/// The directory under `dir` holding MeshLab's `src/common` (2020.09's or the 2022+ layout).
fn find_source(dir: &Path) -> Option<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.join("src/common/interfaces.h").is_file()
                || p.join("src/common/plugins/interfaces/filter_plugin.h")
                    .is_file()
        })
        .collect();
    found.sort();
    found.pop()
}

/// `meshlab=<version>` of the installed MeshLab: its headers are the ones that match the
/// `libmeshlab-common.so` the 2020.09 build links (not the newest source apt knows, which the
/// unstable entry makes 2025.07's).
fn source_2020() -> Result<String, String> {
    let out = Command::new("dpkg-query")
        .args(["-W", "-f=${Version}", "meshlab"])
        .output()
        .map_err(|e| format!("cannot run dpkg-query: {e}"))?;
    let version = String::from_utf8_lossy(&out.stdout).trim().to_owned();
    if out.status.success() && version.starts_with(MESHLAB_2020) {
        Ok(format!("meshlab={version}"))
    } else {
        Err(format!(
            "the installed MeshLab is {:?}, not {MESHLAB_2020}: install Debian 12's package \
             `meshlab` (`cargo xtask deps`)",
            version
        ))
    }
}

/// `meshlab=2025.07~dfsg-4`, or the latest `2025.07~dfsg-N` apt knows when unstable has
/// replaced revision 4 (every revision has the same upstream tarball, the only part used).
fn source_2025() -> Result<String, String> {
    let out = crate::deps::SourceApt::open()?
        .command("apt-cache")
        .args(["showsrc", "meshlab"])
        .output()
        .map_err(|e| format!("cannot run apt-cache: {e}"))?;
    pick_2025(&String::from_utf8_lossy(&out.stdout)).ok_or_else(|| {
        format!(
            "apt knows no source package meshlab {UPSTREAM_2025}-* (`apt-cache showsrc \
             meshlab`) in the project's apt configuration (<target>/apt)"
        )
    })
}

/// From `apt-cache showsrc meshlab`'s text: `meshlab=<SOURCE_2025>` when listed, else the
/// highest Debian revision of the same upstream version.
fn pick_2025(showsrc: &str) -> Option<String> {
    let mut versions: Vec<&str> = showsrc
        .lines()
        .filter_map(|l| l.strip_prefix("Version: "))
        .map(str::trim)
        .filter(|v| v.starts_with(&format!("{UPSTREAM_2025}-")))
        .collect();
    if versions.contains(&SOURCE_2025) {
        return Some(format!("meshlab={SOURCE_2025}"));
    }
    versions.sort_by_key(|v| {
        v.rsplit('-')
            .next()
            .and_then(|r| r.parse::<u32>().ok())
            .unwrap_or(0)
    });
    versions.last().map(|v| format!("meshlab={v}"))
}

/// The Python of `<target>/pymeshlab-venv` with pymeshlab 2025.7 installed (once).
fn pymeshlab_python() -> Result<PathBuf, String> {
    let venv = target_dir().join("pymeshlab-venv");
    let python = venv.join("bin").join("python");
    if python.is_file() && has_pymeshlab(&python) {
        return Ok(python);
    }
    if !python.is_file() {
        let base = ["/usr/bin/python3.11", "python3.11"]
            .into_iter()
            .find(|p| Path::new(p).is_file() || have(p))
            .ok_or(
                "pymeshlab 2025.7 needs Python 3.11 (`python3.11`), which is missing. Install \
                 the Debian packages `python3.11` and `python3-venv` (as root), or run `cargo \
                 xtask deps`.",
            )?;
        if venv.exists() {
            std::fs::remove_dir_all(&venv).map_err(|e| format!("{}: {e}", venv.display()))?;
        }
        run_cmd(Command::new(base).args(["-m", "venv"]).arg(&venv)).map_err(|e| {
            format!("{e}\n  creating the pymeshlab venv failed: install the Debian package `python3-venv`")
        })?;
    }
    eprintln!(
        "xtask: meshlab-plugin: installing {PYMESHLAB} into {} (once; a 106 MB wheel)",
        venv.display()
    );
    run_cmd(Command::new(&python).args([
        "-m",
        "pip",
        "install",
        "--disable-pip-version-check",
        "-q",
        PYMESHLAB,
    ]))
    .map_err(|e| format!("{e}\n  pip could not install {PYMESHLAB} (PyPI unreachable?)"))?;
    if !has_pymeshlab(&python) {
        return Err(format!(
            "{PYMESHLAB} is still not importable from {}",
            python.display()
        ));
    }
    Ok(python)
}

fn has_pymeshlab(python: &Path) -> bool {
    Command::new(python)
        .args([
            "-c",
            "import sys, importlib.metadata as m, pymeshlab; \
             sys.exit(m.version('pymeshlab') != sys.argv[1])",
        ])
        .arg(PYMESHLAB_VERSION)
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// The wheel's `pymeshlab/lib`: MeshLab 2025.07's libraries and the Qt they use.
fn pymeshlab_lib_dir(python: &Path) -> Result<PathBuf, String> {
    let out = Command::new(python)
        .args([
            "-c",
            "import os, pymeshlab; print(os.path.join(os.path.dirname(pymeshlab.__file__), 'lib'))",
        ])
        .output()
        .map_err(|e| format!("{}: {e}", python.display()))?;
    let dir = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    if out.status.success() && dir.join("libmeshlab-common.so").is_file() {
        Ok(dir)
    } else {
        Err(format!(
            "pymeshlab's lib/ ({}) has no libmeshlab-common.so",
            dir.display()
        ))
    }
}

// ---------------------------------------------------------------------------------------
// Tests

/// Builds and runs every MeshLab test (`cargo xtask test`).
pub fn test() -> Result<(), String> {
    test_versions(
        Versions {
            v2020: true,
            v2025: true,
        },
        None,
    )
}

fn test_versions(versions: Versions, filter: Option<&str>) -> Result<(), String> {
    if versions.v2020 {
        check_tools(&TEST_TOOLS)?;
    }
    let dirs = build(versions)?;
    let katachi = dirs.release.join("katachi");
    let lib = dirs.release.join("libkatachi.so");
    // The bundled models (tests/data/models): the MeshLab tests need nothing outside the checkout.
    let models = root().join("tests").join("data").join("models");
    let common = |cmd: &mut Command, work: &Path| {
        cmd.arg("--katachi")
            .arg(&katachi)
            .arg("--lib")
            .arg(&lib)
            .arg("--models")
            .arg(&models)
            .arg("--work")
            .arg(work);
        if let Some(k) = filter {
            cmd.args(["-k", k]);
        }
    };
    let mut summary = Vec::new();
    if versions.v2020 {
        let meshlabserver = make_prefix(&dirs)?;
        let plugin = dirs
            .prefix
            .join(plugin_subdir()?)
            .join("libfilter_katachi.so");
        let n = run_harness(&dirs.build2020.join("plugin_harness"), &plugin)?;
        summary.push(format!("2020.09 harness: {n} passed"));
        let work = fresh(&dirs.base.join("test-2020.09"))?;
        let mut cmd = Command::new("python3");
        cmd.arg(root().join("tests/meshlab/run_meshlabserver.py"))
            .arg("--meshlabserver")
            .arg(&meshlabserver);
        common(&mut cmd, &work);
        let n = run_test_program("MeshLab 2020.09 (meshlabserver)", &mut cmd)?;
        summary.push(format!("2020.09 meshlabserver: {n} passed"));
    }
    if let Some(python) = &dirs.python {
        let work = fresh(&dirs.base.join("test-2025.07"))?;
        let mut cmd = Command::new(python);
        cmd.arg(root().join("tests/meshlab/run_pymeshlab.py"))
            .arg("--plugin")
            .arg(dirs.build2025.join("libfilter_katachi.so"));
        common(&mut cmd, &work);
        let n = run_test_program("MeshLab 2025.07 (pymeshlab)", &mut cmd)?;
        summary.push(format!("2025.07 pymeshlab: {n} passed"));
    }
    eprintln!("xtask: meshlab-plugin: {}", summary.join("; "));
    Ok(())
}

/// An emptied directory.
fn fresh(dir: &Path) -> Result<PathBuf, String> {
    if dir.exists() {
        std::fs::remove_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    Ok(dir.to_path_buf())
}

/// Runs a test program, echoing its output; it passes when it exits 0 and closes with
/// `N passed, 0 failed`, N > 0. Returns N.
fn run_test_program(label: &str, cmd: &mut Command) -> Result<u64, String> {
    let out = capture(cmd)?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    print!("{stdout}");
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    match (
        out.status.success(),
        stdout.lines().rev().find_map(parse_summary),
    ) {
        (true, Some((passed, 0))) if passed > 0 => Ok(passed),
        (_, Some((passed, failed))) => Err(format!(
            "{label}: {passed} passed, {failed} failed (see FAIL above)"
        )),
        (_, None) => Err(format!(
            "{label} ended ({}) without its closing `N passed, M failed` line: a crash?",
            out.status
        )),
    }
}

/// Recreates `<prefix>`: meshlabserver copied into `bin/` (a copy, as MeshLab resolves its
/// own path through symlinks), libmeshlab-common.so and Debian's plugins symlinked, and the
/// plugin installed by `cmake --install`. Returns the prefix's meshlabserver.
fn make_prefix(dirs: &Dirs) -> Result<PathBuf, String> {
    let p = &dirs.prefix;
    if p.exists() {
        std::fs::remove_dir_all(p).map_err(|e| format!("{}: {e}", p.display()))?;
    }
    let plugins = p.join(plugin_subdir()?);
    let bin = p.join("bin");
    for d in [&plugins, &bin] {
        std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    }
    let system = system_meshlab_lib_dir()?;
    let server = which("meshlabserver")?;
    let ours = bin.join("meshlabserver");
    std::fs::copy(&server, &ours).map_err(|e| format!("copying {}: {e}", server.display()))?;
    symlink(
        &system.join("libmeshlab-common.so"),
        &plugins
            .parent()
            .expect("plugins has a parent")
            .join("libmeshlab-common.so"),
    )?;
    let entries = std::fs::read_dir(system.join("plugins"))
        .map_err(|e| format!("{}: {e}", system.join("plugins").display()))?;
    let mut linked = 0;
    for e in entries {
        let path = e.map_err(|e| e.to_string())?.path();
        if path.extension().is_some_and(|x| x == "so") {
            symlink(&path, &plugins.join(path.file_name().expect("a file name")))?;
            linked += 1;
        }
    }
    if linked == 0 {
        return Err(format!(
            "no plugins in {}",
            system.join("plugins").display()
        ));
    }
    run_cmd(Command::new("cmake").arg("--install").arg(&dirs.build2020))?;
    for f in ["libfilter_katachi.so", "katachi/libkatachi.so"] {
        if !plugins.join(f).is_file() {
            return Err(format!(
                "`cmake --install` did not install {}",
                plugins.join(f).display()
            ));
        }
    }
    eprintln!(
        "xtask: meshlab-plugin: private MeshLab prefix {} ({linked} Debian plugins + ours)",
        p.display()
    );
    Ok(ours)
}

fn symlink(from: &Path, to: &Path) -> Result<(), String> {
    std::os::unix::fs::symlink(from, to)
        .map_err(|e| format!("symlinking {} -> {}: {e}", to.display(), from.display()))
}

fn which(program: &str) -> Result<PathBuf, String> {
    let out = Command::new("sh")
        .args(["-c", &format!("command -v {program}")])
        .output()
        .map_err(|e| e.to_string())?;
    let s = String::from_utf8_lossy(&out.stdout).trim().to_owned();
    if out.status.success() && !s.is_empty() {
        std::fs::canonicalize(&s).map_err(|e| format!("{s}: {e}"))
    } else {
        Err(format!("`{program}` is not on the PATH"))
    }
}

/// Runs a command, capturing its output, echoing the command line.
fn capture(cmd: &mut Command) -> Result<Output, String> {
    eprintln!("xtask: $ {}", describe(cmd));
    cmd.output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(cmd)))
}

fn run_harness(harness: &Path, plugin: &Path) -> Result<usize, String> {
    let out = capture(Command::new("xvfb-run").arg("-a").arg(harness).arg(plugin))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    for line in stdout.lines().filter(|l| !l.starts_with("ok ")) {
        eprintln!("  {line}");
    }
    let last = stdout.lines().last().unwrap_or("");
    let summary = last.split_once(" passed, ").and_then(|(p, f)| {
        Some((
            p.parse::<usize>().ok()?,
            f.strip_suffix(" failed")?.parse::<usize>().ok()?,
        ))
    });
    match summary {
        Some((passed, 0)) if out.status.success() && passed > 0 => Ok(passed),
        _ => Err(format!(
            "the plugin harness failed ({}); its output:\n{stdout}{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::pick_2025;

    #[test]
    fn the_2025_source_is_pinned_or_a_later_revision() {
        let both = "Package: meshlab\nVersion: 2020.09+dfsg1-2\n\nPackage: meshlab\nVersion: 2025.07~dfsg-4\n";
        assert_eq!(pick_2025(both).as_deref(), Some("meshlab=2025.07~dfsg-4"));
        let moved = "Version: 2020.09+dfsg1-2\nVersion: 2025.07~dfsg-10\nVersion: 2025.07~dfsg-5\n";
        assert_eq!(pick_2025(moved).as_deref(), Some("meshlab=2025.07~dfsg-10"));
        assert_eq!(
            pick_2025("Version: 2020.09+dfsg1-2\nVersion: 2026.01-1\n"),
            None
        );
    }
}
