//! `cargo xtask meshlab-plugin [--test]`: builds the MeshLab filter plugin (`meshlab_plugin/`)
//! and, with `--test`, tests it in MeshLab 2020.09 (Debian's `meshlab` package).
//!
//! Build:
//! 1. makes sure apt has a `deb-src` entry (adds `/etc/apt/sources.list.d/katachi-deb-src.sources`
//!    or `.list`, made from the system's own Debian/Ubuntu entries, when there is none; root);
//! 2. `apt-get source meshlab` into `<target>/meshlab/src` (kept and reused; `<target>` is
//!    `$CARGO_TARGET_DIR` or `<root>/target`, never part of the repository);
//! 3. `cargo build --release -p katachi` (the library the plugin links and the CLI the tests
//!    compare with);
//! 4. configures and builds `meshlab_plugin/` with CMake in `<target>/meshlab/build`.
//!
//! Test (`--test`, and `cargo xtask test`):
//! 1. a private MeshLab prefix `<target>/meshlab/prefix`: `bin/meshlabserver` copied (MeshLab
//!    looks for plugins beside its executable, in `../lib/<multiarch>/meshlab/plugins`),
//!    `libmeshlab-common.so` and Debian's plugins symlinked, ours installed by `cmake --install`
//!    (with `libkatachi.so` in `plugins/katachi/`). The system's MeshLab is not modified;
//! 2. `tests/meshlab/plugin_harness.cpp` (built with the plugin) loads the plugin as MeshLab
//!    does and checks layers, faux edges and errors in memory, including that a failed filter
//!    leaves the layer unchanged (meshlabserver cannot show that: it exits on the first
//!    failing filter without saving);
//! 3. `xvfb-run -a meshlabserver -i IN -o OUT.off -s SCRIPT.mlx` on shared models and on a
//!    triangulated plate with a through hole, compared with `katachi subdivide` with the same
//!    options (see [`compare`] for what "the same" means);
//! 4. bad input (a face with a repeated vertex, a NaN coordinate, 9 levels) through
//!    meshlabserver: it exits with an error, not a signal, prints katachi's message and
//!    writes no output;
//! 5. the cut by polyline through meshlabserver, with the view as MeshLab's camera XML and
//!    the stroke in the script, on a grid (orthographic, opened) and on `fandisk.off`
//!    (perspective, visible-only and through-all, new layer and in place): compared with
//!    `katachi cut` given the same mesh, stroke (flipped to katachi's top-left pixels) and the
//!    view-projection matrix the filter logs ([`compare_indexed`]: vertex for vertex, triangle
//!    for triangle); and bad cuts (a self-crossing stroke, no view) refused like 4.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Output};

use crate::ctest::target_dir;
use crate::util::{describe, have, is_root, root, run as run_cmd, run_in};

const USAGE: &str = "usage: cargo xtask meshlab-plugin [--test]";

/// Tools needed, with the Debian package that provides each.
const BUILD_TOOLS: [(&str, &str); 5] = [
    ("apt-get", "apt"),
    ("dpkg-source", "dpkg-dev"),
    ("cmake", "cmake"),
    ("make", "make"),
    ("g++", "g++"),
];
const TEST_TOOLS: [(&str, &str); 2] = [("meshlabserver", "meshlab"), ("xvfb-run", "xvfb")];

/// The filters' names, as scripts and menus show them.
const FILTER: &str = "katachi: Solid-aware subdivision";
const CUT_FILTER: &str = "katachi: Cut by polyline";

pub fn run(args: &[&str]) -> Result<(), String> {
    match args {
        [] => build().map(|_| ()),
        ["--test"] => test(),
        ["-h"] | ["--help"] => {
            eprintln!("{USAGE}");
            Ok(())
        }
        _ => Err(USAGE.into()),
    }
}

/// Where things go: all under `<target>/meshlab`.
struct Dirs {
    base: PathBuf,
    /// MeshLab's unpacked source (`meshlab-2020.09+dfsg1`).
    source: PathBuf,
    build: PathBuf,
    prefix: PathBuf,
    release: PathBuf,
}

/// Builds the plugin; returns the directories for the tests.
fn build() -> Result<Dirs, String> {
    check_tools(&BUILD_TOOLS)?;
    let base = target_dir().join("meshlab");
    let source = meshlab_source(&base.join("src"))?;
    run_cmd(Command::new(crate::util::cargo()).args(["build", "--release", "-p", "katachi"]))?;
    let release = target_dir().join("release");
    let lib = release.join("libkatachi.so");
    if !lib.is_file() {
        return Err(format!(
            "{} is missing after the release build",
            lib.display()
        ));
    }
    let dirs = Dirs {
        build: base.join("build"),
        prefix: base.join("prefix"),
        base,
        source,
        release,
    };
    let plugin_dir = dirs.prefix.join(plugin_subdir()?);
    let mut configure = Command::new("cmake");
    configure
        .arg("-S")
        .arg(root().join("meshlab_plugin"))
        .arg("-B")
        .arg(&dirs.build)
        .arg("-DCMAKE_BUILD_TYPE=Release")
        .arg(format!("-DMESHLAB_SOURCE_DIR={}", dirs.source.display()))
        .arg(format!(
            "-DMESHLAB_COMMON_LIBRARY={}",
            system_meshlab_lib_dir()?
                .join("libmeshlab-common.so")
                .display()
        ))
        .arg(format!("-DMESHLAB_PLUGIN_DIR={}", plugin_dir.display()))
        .arg(format!(
            "-DKATACHI_INCLUDE_DIR={}",
            root().join("include").display()
        ))
        .arg(format!("-DKATACHI_LIBRARY={}", lib.display()))
        .arg("-DKATACHI_BUILD_TESTS=ON");
    run_cmd(&mut configure)?;
    run_cmd(
        Command::new("cmake")
            .arg("--build")
            .arg(&dirs.build)
            .args(["-j", "2"]),
    )?;
    let so = dirs.build.join("libfilter_katachi.so");
    if !so.is_file() {
        return Err(format!("{} is missing after the build", so.display()));
    }
    eprintln!("xtask: meshlab-plugin: built {}", so.display());
    Ok(dirs)
}

fn check_tools(tools: &[(&str, &str)]) -> Result<(), String> {
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
fn system_meshlab_lib_dir() -> Result<PathBuf, String> {
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
// MeshLab's source

/// The unpacked source under `dir`, fetched with `apt-get source meshlab` when not there yet.
fn meshlab_source(dir: &Path) -> Result<PathBuf, String> {
    if let Some(found) = find_source(dir) {
        eprintln!(
            "xtask: meshlab-plugin: reusing MeshLab's source in {}",
            found.display()
        );
        return Ok(found);
    }
    ensure_deb_src()?;
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    // The source of the installed MeshLab, not the newest one apt knows: a deb-src entry for
    // another suite (such as unstable, for MeshLab 2025.07's headers) must not change which
    // headers the 2020.09 plugin is built against.
    let installed = Command::new("dpkg-query")
        .args(["-W", "-f=${Version}", "meshlab"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|v| !v.is_empty());
    let spec = match &installed {
        Some(version) => format!("meshlab={version}"),
        None => "meshlab".to_string(),
    };
    let mut cmd = Command::new("apt-get");
    cmd.args(["source", "-q", &spec]);
    run_in(dir, &mut cmd)?;
    find_source(dir).ok_or_else(|| {
        format!(
            "`apt-get source meshlab` left no meshlab-*/src/common in {}",
            dir.display()
        )
    })
}

/// `dir/meshlab-*` holding MeshLab's `src/common` (the 2020.09 or the 2022+ layout).
fn find_source(dir: &Path) -> Option<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("meshlab-"))
                && (p.join("src/common/interfaces.h").is_file()
                    || p.join("src/common/plugins/interfaces/filter_plugin.h")
                        .is_file())
        })
        .collect();
    found.sort();
    found.pop()
}

const APT_DIR: &str = "/etc/apt";
const OUR_SOURCES: &str = "katachi-deb-src";

/// Makes sure apt knows a source-package (`deb-src`) entry; idempotent. When there is none,
/// writes one beside the system's entries, made from its Debian/Ubuntu archive entries
/// (deb822 `.sources` stanzas with `Types: deb-src`, or `deb-src` lines in a `.list`), and
/// runs `apt-get update`.
fn ensure_deb_src() -> Result<(), String> {
    let apt = Path::new(APT_DIR);
    let mut files = vec![apt.join("sources.list")];
    if let Ok(entries) = std::fs::read_dir(apt.join("sources.list.d")) {
        let mut more: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        more.sort();
        files.extend(more);
    }
    let mut stanzas = Vec::new();
    let mut lines = Vec::new();
    for f in &files {
        let Ok(text) = std::fs::read_to_string(f) else {
            continue;
        };
        let name = f.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.ends_with(".sources") {
            if has_deb_src_deb822(&text) {
                return Ok(());
            }
            // Only the distribution's own archive: third-party repositories often have no
            // source packages and would make `apt-get update` fail.
            if name == "debian.sources" || name == "ubuntu.sources" {
                stanzas.extend(deb_src_stanzas(&text));
            }
        } else if name == "sources.list" || name.ends_with(".list") {
            if has_deb_src_list(&text) {
                return Ok(());
            }
            if name == "sources.list" {
                lines.extend(deb_src_lines(&text));
            }
        }
    }
    let (path, body) = if !stanzas.is_empty() {
        (
            apt.join("sources.list.d")
                .join(format!("{OUR_SOURCES}.sources")),
            stanzas.join("\n"),
        )
    } else if !lines.is_empty() {
        (
            apt.join("sources.list.d")
                .join(format!("{OUR_SOURCES}.list")),
            lines.join("\n") + "\n",
        )
    } else {
        return Err(
            "apt has no deb-src entry and no Debian/Ubuntu archive entry (debian.sources, \
             ubuntu.sources or sources.list) to make one from; add a deb-src entry by hand"
                .into(),
        );
    };
    if !is_root() {
        return Err(format!(
            "apt has no deb-src entry, needed by `apt-get source meshlab`; run as root once \
             (`sudo cargo xtask meshlab-plugin`) or write {} with:\n{body}",
            path.display()
        ));
    }
    let header =
        "# Written by `cargo xtask meshlab-plugin` (katachi) for `apt-get source meshlab`.\n";
    std::fs::write(&path, format!("{header}{body}"))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    eprintln!(
        "xtask: meshlab-plugin: added the deb-src entry {}",
        path.display()
    );
    run_cmd(
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

// ---------------------------------------------------------------------------------------
// Tests

/// Builds, installs into the private prefix, and runs every MeshLab test.
pub fn test() -> Result<(), String> {
    check_tools(&TEST_TOOLS)?;
    let dirs = build()?;
    let meshlabserver = make_prefix(&dirs)?;
    let work = dirs.base.join("test");
    if work.exists() {
        std::fs::remove_dir_all(&work).map_err(|e| format!("{}: {e}", work.display()))?;
    }
    std::fs::create_dir_all(&work).map_err(|e| format!("{}: {e}", work.display()))?;

    let plugin = dirs
        .prefix
        .join(plugin_subdir()?)
        .join("libfilter_katachi.so");
    let harness_checks = run_harness(&dirs.build.join("plugin_harness"), &plugin)?;

    let katachi = dirs.release.join("katachi");
    let models = root().join("..").join("shared").join("data").join("models");
    let model = |name: &str| -> Result<PathBuf, String> {
        let p = models.join(name);
        if p.is_file() {
            Ok(p)
        } else {
            Err(format!("shared model {} is missing", p.display()))
        }
    };
    // MeshLab 2020.09's OBJ reader aborts on spot_quadrangulated.obj (an assertion in
    // vcg's import_obj.h), so both sides read the same mesh converted to OFF by katachi.
    let spot = work.join("spot_quadrangulated.off");
    run_cmd(
        Command::new(&katachi)
            .arg("convert")
            .arg(model("spot_quadrangulated.obj")?)
            .arg(&spot),
    )?;
    let plate = work.join("plate_with_hole.off");
    std::fs::write(&plate, plate_with_hole_off())
        .map_err(|e| format!("{}: {e}", plate.display()))?;

    let d = Opts::default();
    let cases = [
        (
            "fandisk_feature30",
            model("fandisk.off")?,
            Opts {
                feature_angle: 30.0,
                ..d
            },
        ),
        (
            "fandisk_quads_l2_inplace",
            model("fandisk_quads.off")?,
            Opts {
                levels: 2,
                new_layer: false,
                ..d
            },
        ),
        ("spot_quads", spot, d),
        (
            "hole_capsule_l2_corner",
            model("hole_capsule.off")?,
            Opts {
                levels: 2,
                edge_and_corner: true,
                ..d
            },
        ),
        (
            "plate_recover_smooth_l2",
            plate.clone(),
            Opts {
                levels: 2,
                recover: true,
                ..d
            },
        ),
        (
            "plate_recover_sharp",
            plate.clone(),
            Opts {
                recover: true,
                sharp_holes: true,
                new_layer: false,
                ..d
            },
        ),
        ("plate_triangles", plate.clone(), d),
    ];
    let mut checks = 0usize;
    for (name, input, opts) in &cases {
        checks += run_case(&meshlabserver, &katachi, &work, name, input, opts)?;
    }

    let tet = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n";
    let bad = [
        (
            "repeated_vertex",
            format!("{tet}0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 0 2\n"),
            d,
            "katachi_mesh_create: face 3",
        ),
        (
            "nan_coordinate",
            format!("{tet}0 0 nan\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"),
            Opts {
                new_layer: false,
                ..d
            },
            "katachi_mesh_create: vertex 3",
        ),
        (
            "nine_levels",
            format!("{tet}0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"),
            Opts { levels: 9, ..d },
            "katachi_subdivide: option levels",
        ),
    ];
    for (name, text, opts, message) in &bad {
        checks += run_bad_case(
            &meshlabserver,
            &work,
            name,
            text,
            &opts.mlx(),
            FILTER,
            message,
        )?;
    }

    // The cut by polyline.
    let grid = work.join("grid_10.off");
    std::fs::write(&grid, grid_off(10)).map_err(|e| format!("{}: {e}", grid.display()))?;
    // MeshLab reads floats: the CLI gets the same numbers (fandisk's rounded to f32).
    let fandisk = work.join("fandisk_f32.off");
    let fandisk_mesh = read_off(&model("fandisk.off")?)?;
    std::fs::write(&fandisk, off_f32(&fandisk_mesh))
        .map_err(|e| format!("{}: {e}", fandisk.display()))?;
    let top = Camera::looking_at([5.0, 5.0, 10.0], [5.0, 5.0, 0.0], [0.0, 1.0, 0.0], true);
    let (lo, hi) = bounding_box(&fandisk_mesh.positions);
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    let eye = [
        centre[0] + 1.2 * size,
        centre[1] + 0.9 * size,
        centre[2] + 1.6 * size,
    ];
    let oblique = Camera::looking_at(eye, centre, [0.0, 0.0, 1.0], false);
    let grid_stroke = wavy_stroke(20.0, 580.0, 300.0, 9, 40.0);
    let fandisk_stroke = wavy_stroke(40.0, 760.0, 310.0, 25, 30.0);
    let cut_cases = [
        CutCase {
            name: "cut_grid_ortho_open",
            input: grid.clone(),
            camera: top.clone(),
            stroke: grid_stroke.clone(),
            through_all: false,
            open: true,
            new_layer: true,
        },
        CutCase {
            name: "cut_fandisk_visible",
            input: fandisk.clone(),
            camera: oblique.clone(),
            stroke: fandisk_stroke.clone(),
            through_all: false,
            open: false,
            new_layer: true,
        },
        CutCase {
            name: "cut_fandisk_through_all_inplace",
            input: fandisk.clone(),
            camera: oblique.clone(),
            stroke: fandisk_stroke.clone(),
            through_all: true,
            open: false,
            new_layer: false,
        },
    ];
    for case in &cut_cases {
        checks += run_cut_case(&meshlabserver, &katachi, &work, case)?;
    }
    let crossing = vec![
        [100.0, 100.0],
        [500.0, 500.0],
        [500.0, 100.0],
        [100.0, 500.0],
    ];
    let grid_text = grid_off(10);
    let bad_cuts = [
        (
            "cut_self_crossing",
            CutCase {
                name: "cut_self_crossing",
                input: grid.clone(),
                camera: top.clone(),
                stroke: crossing,
                through_all: false,
                open: false,
                new_layer: true,
            }
            .mlx(),
            "katachi_cut_by_stroke: the stroke crosses itself",
        ),
        (
            "cut_no_view",
            CutCase {
                name: "cut_no_view",
                input: grid.clone(),
                camera: top.clone(),
                stroke: grid_stroke.clone(),
                through_all: false,
                open: false,
                new_layer: false,
            }
            .mlx()
            .replace(&xml_escape(&top.vcg_camera_xml()), ""),
            "katachi: the view has no viewport",
        ),
    ];
    for (name, script, message) in &bad_cuts {
        checks += run_bad_case(
            &meshlabserver,
            &work,
            name,
            &grid_text,
            script,
            CUT_FILTER,
            message,
        )?;
    }
    eprintln!(
        "xtask: meshlab-plugin: all passed: harness {harness_checks} checks, meshlabserver {} \
         subdivisions and {} cuts compared with the CLI, {} error cases ({checks} checks)",
        cases.len(),
        cut_cases.len(),
        bad.len() + bad_cuts.len()
    );
    Ok(())
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
    run_cmd(Command::new("cmake").arg("--install").arg(&dirs.build))?;
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

/// The filter's options, as the .mlx script and the CLI take them.
#[derive(Clone, Copy)]
struct Opts {
    levels: u32,
    sharp_holes: bool,
    recover: bool,
    feature_angle: f32,
    edge_and_corner: bool,
    new_layer: bool,
}

impl Default for Opts {
    fn default() -> Self {
        Opts {
            levels: 1,
            sharp_holes: false,
            recover: false,
            feature_angle: 0.0,
            edge_and_corner: false,
            new_layer: true,
        }
    }
}

impl Opts {
    /// A filter script. meshlabserver 2020.09 asserts when a script omits a parameter, so
    /// every parameter is given.
    fn mlx(&self) -> String {
        let en = |name: &str, v: bool, a: &str, b: &str| {
            format!(
                "  <Param type=\"RichEnum\" name=\"{name}\" value=\"{}\" enum_val0=\"{a}\" enum_val1=\"{b}\" enum_cardinality=\"2\"/>\n",
                u8::from(v)
            )
        };
        let bl = |name: &str, v: bool| {
            format!("  <Param type=\"RichBool\" name=\"{name}\" value=\"{v}\"/>\n")
        };
        format!(
            "<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name=\"{FILTER}\">\n  \
             <Param type=\"RichInt\" name=\"levels\" value=\"{}\"/>\n{}{}  \
             <Param type=\"RichFloat\" name=\"featureAngle\" value=\"{}\"/>\n{}{} </filter>\n</FilterScript>\n",
            self.levels,
            en("holeMethod", self.sharp_holes, "Smooth", "Sharp"),
            bl("recoverFacesWithHoles", self.recover),
            self.feature_angle,
            en("boundary", self.edge_and_corner, "Edge only", "Edge and corner"),
            bl("newLayer", self.new_layer),
        )
    }

    /// The same options for `katachi subdivide`.
    fn cli_args(&self) -> Vec<String> {
        let mut a = vec!["--levels".to_owned(), self.levels.to_string()];
        if self.sharp_holes {
            a.extend(["--holes".into(), "sharp".into()]);
        }
        if self.recover {
            a.push("--solid".into());
        }
        if self.feature_angle != 0.0 {
            a.extend(["--feature-angle".into(), self.feature_angle.to_string()]);
        }
        if self.edge_and_corner {
            a.extend(["--boundary".into(), "edge-and-corner".into()]);
        }
        a
    }
}

fn meshlabserver_cmd(server: &Path, input: &Path, output: &Path, script: &Path) -> Command {
    let mut c = Command::new("xvfb-run");
    c.arg("-a")
        .arg(server)
        .arg("-i")
        .arg(input)
        .arg("-o")
        .arg(output)
        .arg("-s")
        .arg(script);
    c
}

/// Writes the filter script `script` to `<work>/<name>.mlx` and runs meshlabserver with it
/// on `input`, writing `<work>/<name>_meshlab.off`; returns that path, meshlabserver's exit
/// status and its output (stdout, then stderr).
fn run_script(
    server: &Path,
    work: &Path,
    name: &str,
    input: &Path,
    script: &str,
) -> Result<(PathBuf, ExitStatus, String), String> {
    let mlx = work.join(format!("{name}.mlx"));
    std::fs::write(&mlx, script).map_err(|e| format!("{}: {e}", mlx.display()))?;
    let output = work.join(format!("{name}_meshlab.off"));
    let out = capture(&mut meshlabserver_cmd(server, input, &output, &mlx))?;
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    Ok((output, out.status, log))
}

/// [`run_script`] for a filter that must succeed: an error when meshlabserver fails or
/// writes no mesh. Returns the mesh's path and meshlabserver's output.
fn run_script_ok(
    server: &Path,
    work: &Path,
    name: &str,
    input: &Path,
    script: &str,
) -> Result<(PathBuf, String), String> {
    let (ml_out, status, log) = run_script(server, work, name, input, script)?;
    if !status.success() || !ml_out.is_file() {
        return Err(format!(
            "{name}: meshlabserver failed ({status}) or wrote no {}; its output:\n{log}",
            ml_out.display()
        ));
    }
    Ok((ml_out, log))
}

/// One comparison: meshlabserver with the plugin vs. `katachi subdivide`. Returns checks made.
fn run_case(
    server: &Path,
    katachi: &Path,
    work: &Path,
    name: &str,
    input: &Path,
    opts: &Opts,
) -> Result<usize, String> {
    let (ml_out, log) = run_script_ok(server, work, name, input, &opts.mlx())?;
    let cli_out = work.join(format!("{name}_cli.off"));
    // The filter ran (and not some other one): it logs its summary line.
    let ran = format!("katachi: {} levels:", opts.levels);
    if !log.contains(&ran) {
        return Err(format!("{name}: meshlabserver's log lacks `{ran}`:\n{log}"));
    }
    run_cmd(
        Command::new(katachi)
            .arg("subdivide")
            .arg(input)
            .arg(&cli_out)
            .args(opts.cli_args()),
    )?;
    let ml = read_off(&ml_out)?;
    let cli = read_off(&cli_out)?;
    let report = compare(&ml, &cli)
        .map_err(|e| format!("{name}: MeshLab's result differs from the CLI's: {e}"))?;
    eprintln!("xtask: meshlab-plugin: {name}: {report}");
    Ok(5)
}

/// A failing filter through meshlabserver: an error exit (not a signal), katachi's message
/// in the output, and no output file. Returns checks made.
fn run_bad_case(
    server: &Path,
    work: &Path,
    name: &str,
    text: &str,
    script_text: &str,
    filter: &str,
    message: &str,
) -> Result<usize, String> {
    use std::os::unix::process::ExitStatusExt;
    let input = work.join(format!("{name}.off"));
    std::fs::write(&input, text).map_err(|e| format!("{}: {e}", input.display()))?;
    let (output, status, log) = run_script(server, work, name, &input, script_text)?;
    // xvfb-run passes the server's exit code on; a crash would be 128 + signal or a signal.
    let code = status.code();
    let crashed = status.signal().is_some()
        || code.is_some_and(|c| (129..=159).contains(&c))
        || log.contains("Segmentation fault")
        || log.contains("Aborted");
    let mut problems = Vec::new();
    if status.success() {
        problems.push("meshlabserver exited 0".to_owned());
    }
    if crashed {
        problems.push(format!("meshlabserver crashed ({status})"));
    }
    if !log.contains(message) {
        problems.push(format!("the output lacks katachi's message `{message}`"));
    }
    if !log.contains(&format!("Problem with filter: {filter}")) {
        problems.push("the output lacks meshlabserver's `Problem with filter` line".into());
    }
    if output.exists() {
        problems.push(format!("{} was written", output.display()));
    }
    if problems.is_empty() {
        eprintln!(
            "xtask: meshlab-plugin: {name}: meshlabserver refused it ({status}) with katachi's message"
        );
        Ok(5)
    } else {
        Err(format!(
            "{name}: {}; its output:\n{log}",
            problems.join("; ")
        ))
    }
}

/// A square plate 4 x 4 x 1 with a 2 x 2 square hole through it, every face triangulated
/// (what a boolean leaves): 16 vertices, 32 triangles, closed, genus 1.
fn plate_with_hole_off() -> String {
    let outer = [(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)];
    let inner = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    // Vertex ids: bottom outer 0-3, bottom inner 4-7, top outer 8-11, top inner 12-15.
    let mut v = Vec::new();
    for z in [0.0, 1.0] {
        for (x, y) in outer.iter().chain(inner.iter()) {
            v.push(format!("{x} {y} {z}"));
        }
    }
    let (bo, bi, to, ti) = (0, 4, 8, 12);
    let mut quads = Vec::new();
    for k in 0..4 {
        let n = (k + 1) % 4;
        quads.push([to + k, to + n, ti + n, ti + k]); // top, facing +z
        quads.push([bo + k, bi + k, bi + n, bo + n]); // bottom, facing -z
        quads.push([bo + k, bo + n, to + n, to + k]); // outer wall, facing out
        quads.push([bi + k, ti + k, ti + n, bi + n]); // hole wall, facing the axis
    }
    let mut s = format!("OFF\n{} {} 0\n", v.len(), 2 * quads.len());
    for l in &v {
        s.push_str(l);
        s.push('\n');
    }
    for [a, b, c, d] in quads {
        let _ = writeln!(s, "3 {a} {b} {c}\n3 {a} {c} {d}");
    }
    s
}

/// A camera in MeshLab's terms (vcg::Shot), written as the `<VCGCamera …/>` element that
/// MeshLab's Windows ▸ Copy shot and its project files hold.
#[derive(Debug, Clone, PartialEq)]
struct Camera {
    /// The viewpoint.
    eye: [f64; 3],
    /// The rotation's rows: the camera's x (right), y (up) and z (backwards) axes.
    rows: [[f64; 3]; 3],
    orthographic: bool,
    viewport: [u32; 2],
    pixel_mm: f64,
    focal_mm: f64,
}

impl Camera {
    /// A camera at `eye` looking at `target` with `up` up: orthographic 600 × 600 pixels
    /// covering 12 units, or perspective 800 × 600 pixels with a 40° vertical field of view
    /// (MeshLab's pixel size).
    fn looking_at(eye: [f64; 3], target: [f64; 3], up: [f64; 3], orthographic: bool) -> Camera {
        let z = normalize(sub(eye, target));
        let x = normalize(cross(up, z));
        let y = cross(z, x);
        let (viewport, pixel_mm, focal_mm) = if orthographic {
            ([600, 600], 12.0 / 600.0, 1.0)
        } else {
            let pixel_mm = 0.036_916_077;
            let focal = 600.0 * pixel_mm / (2.0 * 20f64.to_radians().tan());
            ([800, 600], pixel_mm, focal)
        };
        Camera {
            eye,
            rows: [x, y, z],
            orthographic,
            viewport,
            pixel_mm,
            focal_mm,
        }
    }

    /// The `<VCGCamera …/>` element (vcg's text form: the translation vector is minus the
    /// viewpoint, the rotation matrix row after row).
    fn vcg_camera_xml(&self) -> String {
        let [x, y, z] = self.rows;
        let [w, h] = self.viewport;
        format!(
            "<VCGCamera TranslationVector=\"{} {} {} 1\" RotationMatrix=\"{} {} {} 0 {} {} {} 0 {} {} {} 0 0 0 0 1\" \
             CameraType=\"{}\" BinaryData=\"0\" FocalMm=\"{}\" LensDistortion=\"0 0\" PixelSizeMm=\"{} {}\" \
             ViewportPx=\"{w} {h}\" CenterPx=\"{} {}\"/>",
            -self.eye[0],
            -self.eye[1],
            -self.eye[2],
            x[0],
            x[1],
            x[2],
            y[0],
            y[1],
            y[2],
            z[0],
            z[1],
            z[2],
            u8::from(self.orthographic),
            self.focal_mm,
            self.pixel_mm,
            self.pixel_mm,
            f64::from(w) / 2.0,
            f64::from(h) / 2.0,
        )
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / n, a[1] / n, a[2] / n]
}

/// Text for an XML attribute value.
fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A polyline from x0 to x1 around height y (vcg pixels, y up) through `n` points, waving
/// by up to `amplitude` pixels; x grows, so it never crosses itself.
fn wavy_stroke(x0: f64, x1: f64, y: f64, n: usize, amplitude: f64) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            let x = x0 + (x1 - x0) * t;
            // Rounded to 1/4 pixel: the same numbers in the script and in the CLI's file.
            let wave = (amplitude * (0.9 * i as f64).sin() * 4.0).round() / 4.0;
            [(x * 4.0).round() / 4.0, y + wave]
        })
        .collect()
}

/// One cut through meshlabserver, compared with `katachi cut`.
struct CutCase {
    name: &'static str,
    input: PathBuf,
    camera: Camera,
    /// Pixels of the camera's viewport, origin bottom-left, y up (the filter's convention).
    stroke: Vec<[f64; 2]>,
    through_all: bool,
    open: bool,
    new_layer: bool,
}

impl CutCase {
    /// The filter script. meshlabserver 2020.09 cannot read a shot (RichShotf) from a script
    /// (its reader asserts), so the script leaves out the first parameter, `shot`, and gives
    /// the view as MeshLab's camera XML in `viewXml`; every other parameter is given.
    fn mlx(&self) -> String {
        let stroke: Vec<String> = self
            .stroke
            .iter()
            .map(|[x, y]| format!("{x} {y}"))
            .collect();
        format!(
            "<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name=\"{CUT_FILTER}\">\n  \
             <Param type=\"RichString\" name=\"viewXml\" value=\"{}\"/>\n  \
             <Param type=\"RichString\" name=\"stroke\" value=\"{}\"/>\n  \
             <Param type=\"RichEnum\" name=\"mode\" value=\"{}\" enum_val0=\"Visible only\" enum_val1=\"Through all\" enum_cardinality=\"2\"/>\n  \
             <Param type=\"RichBool\" name=\"openCut\" value=\"{}\"/>\n  \
             <Param type=\"RichBool\" name=\"newLayer\" value=\"{}\"/>\n </filter>\n</FilterScript>\n",
            xml_escape(&self.camera.vcg_camera_xml()),
            stroke.join("; "),
            u8::from(self.through_all),
            self.open,
            self.new_layer,
        )
    }

    /// The stroke file `katachi cut` reads: the stroke flipped to katachi's pixels (origin
    /// top-left, y down) and the view-projection matrix the filter logged.
    fn stroke_json(&self, view_proj: &[f64]) -> String {
        let h = f64::from(self.camera.viewport[1]);
        let points: Vec<String> = self
            .stroke
            .iter()
            .map(|[x, y]| format!("[{x:?}, {:?}]", h - y))
            .collect();
        let matrix: Vec<String> = view_proj.iter().map(|x| format!("{x:?}")).collect();
        format!(
            "{{\"stroke\": [{}], \"view_proj\": [{}], \"viewport\": [0, 0, {}, {}], \"mode\": \"{}\", \"open\": {}}}\n",
            points.join(", "),
            matrix.join(", "),
            self.camera.viewport[0],
            self.camera.viewport[1],
            if self.through_all {
                "through-all"
            } else {
                "visible-only"
            },
            self.open
        )
    }
}

/// The view-projection matrix the filter logs (`katachi: view: … y down): m0 … m15`).
fn logged_view_proj(log: &str) -> Result<Vec<f64>, String> {
    let line = log
        .lines()
        .find(|l| l.contains("katachi: view:"))
        .ok_or("the log has no `katachi: view:` line")?;
    let (_, numbers) = line
        .split_once("y down):")
        .ok_or_else(|| format!("cannot read the matrix in `{line}`"))?;
    let m: Vec<f64> = numbers
        .split_whitespace()
        .map(|t| {
            t.parse()
                .map_err(|_| format!("`{t}` in `{line}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    if m.len() == 16 {
        Ok(m)
    } else {
        Err(format!("{} numbers in `{line}`, not 16", m.len()))
    }
}

/// One cut: meshlabserver with the plugin vs. `katachi cut`. Returns checks made.
fn run_cut_case(
    server: &Path,
    katachi: &Path,
    work: &Path,
    case: &CutCase,
) -> Result<usize, String> {
    let name = case.name;
    let (ml_out, log) = run_script_ok(server, work, name, &case.input, &case.mlx())?;
    let cli_out = work.join(format!("{name}_cli.off"));
    if !log.contains("katachi: cut by polyline (") {
        return Err(format!(
            "{name}: meshlabserver's log lacks the cut's report:\n{log}"
        ));
    }
    let [w, h] = case.camera.viewport;
    if !log.contains(&format!("{w} x {h} pixels")) {
        return Err(format!(
            "{name}: the log does not show the {w} x {h} viewport:\n{log}"
        ));
    }
    let view_proj = logged_view_proj(&log).map_err(|e| format!("{name}: {e}:\n{log}"))?;
    let json = work.join(format!("{name}_stroke.json"));
    std::fs::write(&json, case.stroke_json(&view_proj))
        .map_err(|e| format!("{}: {e}", json.display()))?;
    let mut cli = Command::new(katachi);
    cli.arg("cut")
        .arg(&case.input)
        .arg(&cli_out)
        .arg("--stroke")
        .arg(&json)
        .args([
            "--mode",
            if case.through_all {
                "through-all"
            } else {
                "visible-only"
            },
        ]);
    if case.open {
        cli.arg("--open");
    }
    run_cmd(&mut cli)?;
    let input = read_off(&case.input)?;
    let ml = read_off(&ml_out)?;
    let cli = read_off(&cli_out)?;
    if ml.faces.len() <= input.faces.len() {
        return Err(format!(
            "{name}: MeshLab's result has {} faces, the input {}: nothing was cut",
            ml.faces.len(),
            input.faces.len()
        ));
    }
    let report = compare_indexed(&ml, &cli)
        .map_err(|e| format!("{name}: MeshLab's result differs from the CLI's: {e}"))?;
    eprintln!(
        "xtask: meshlab-plugin: {name}: {} -> {} triangles; {report}",
        input.faces.len(),
        ml.faces.len()
    );
    Ok(5)
}

/// Checks that MeshLab's cut `ml` is the CLI's `cli` element for element: the filter writes
/// katachi's vertices and triangles in katachi's order, so vertex i is within `REL_TOL` × the
/// CLI bounding-box diagonal of CLI vertex i (MeshLab stores floats) and triangle i has the
/// same corners in the same order. (Opening a cut makes coincident vertices, which a match by
/// position alone, as [`compare`] does, cannot tell apart.)
fn compare_indexed(ml: &Off, cli: &Off) -> Result<String, String> {
    if ml.positions.len() != cli.positions.len() || ml.faces.len() != cli.faces.len() {
        return Err(format!(
            "MeshLab has {} vertices and {} faces, the CLI {} and {}",
            ml.positions.len(),
            ml.faces.len(),
            cli.positions.len(),
            cli.faces.len()
        ));
    }
    let (lo, hi) = bounding_box(&cli.positions);
    let diag = (0..3)
        .map(|k| (hi[k] - lo[k]).powi(2))
        .sum::<f64>()
        .sqrt()
        .max(f64::MIN_POSITIVE);
    let mut worst = 0.0f64;
    for (i, (p, q)) in ml.positions.iter().zip(&cli.positions).enumerate() {
        let d = (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f64::max);
        if d.is_nan() || d > REL_TOL * diag {
            return Err(format!(
                "vertex {i} is at {p:?} in MeshLab's result, {q:?} in the CLI's"
            ));
        }
        worst = worst.max(d);
    }
    if let Some(f) = (0..ml.faces.len()).find(|&f| ml.faces[f] != cli.faces[f]) {
        return Err(format!(
            "face {f} is {:?} in MeshLab's result, {:?} in the CLI's",
            ml.faces[f], cli.faces[f]
        ));
    }
    Ok(format!(
        "{} vertices (max deviation {:.2e} of the diagonal) and {} triangles, the same as the CLI's",
        ml.positions.len(),
        worst / diag,
        ml.faces.len()
    ))
}

fn bounding_box(positions: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    positions.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        },
    )
}

/// An n × n grid of unit squares in the plane z = 0, each square two triangles facing +z.
fn grid_off(n: usize) -> String {
    let mut s = format!("OFF\n{} {} 0\n", (n + 1) * (n + 1), 2 * n * n);
    for j in 0..=n {
        for i in 0..=n {
            let _ = writeln!(s, "{i} {j} 0");
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, d) = (a + 1, a + n + 2, a + n + 1);
            let _ = writeln!(s, "3 {a} {b} {c}\n3 {a} {c} {d}");
        }
    }
    s
}

/// `mesh` as OFF text with every coordinate rounded to f32 and written exactly, so that
/// MeshLab (which stores floats) and the CLI (doubles) read the same numbers.
fn off_f32(mesh: &Off) -> String {
    let mut s = format!("OFF\n{} {} 0\n", mesh.positions.len(), mesh.faces.len());
    for p in &mesh.positions {
        let [x, y, z] = p.map(|c| f64::from(c as f32));
        let _ = writeln!(s, "{x:?} {y:?} {z:?}");
    }
    for f in &mesh.faces {
        let corners: Vec<String> = f.iter().map(usize::to_string).collect();
        let _ = writeln!(s, "{} {}", f.len(), corners.join(" "));
    }
    s
}

/// A polygon mesh read from an OFF file.
#[derive(Debug, Clone, PartialEq)]
struct Off {
    positions: Vec<[f64; 3]>,
    faces: Vec<Vec<usize>>,
}

fn read_off(path: &Path) -> Result<Off, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_off(&text).map_err(|e| format!("{}: {e}", path.display()))
}

fn parse_off(text: &str) -> Result<Off, String> {
    let mut lines = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty());
    let head = lines.next().ok_or("empty file")?;
    let counts_line = match head.strip_prefix("OFF") {
        Some("") => lines.next().ok_or("no counts line")?,
        Some(rest) => rest.trim(),
        None => return Err(format!("not an OFF file (first line `{head}`)")),
    };
    let counts: Vec<usize> = counts_line
        .split_whitespace()
        .take(2)
        .map(|t| t.parse().map_err(|_| format!("bad count `{t}`")))
        .collect::<Result<_, _>>()?;
    let [nv, nf] = counts[..] else {
        return Err(format!("bad counts line `{counts_line}`"));
    };
    let mut positions = Vec::with_capacity(nv);
    for i in 0..nv {
        let l = lines.next().ok_or(format!("vertex {i} missing"))?;
        let p: Vec<f64> = l
            .split_whitespace()
            .take(3)
            .map(|t| {
                t.parse()
                    .map_err(|_| format!("vertex {i}: bad number `{t}`"))
            })
            .collect::<Result<_, _>>()?;
        let [x, y, z] = p[..] else {
            return Err(format!("vertex {i}: fewer than 3 coordinates"));
        };
        positions.push([x, y, z]);
    }
    let mut faces = Vec::with_capacity(nf);
    for f in 0..nf {
        let l = lines.next().ok_or(format!("face {f} missing"))?;
        let mut it = l.split_whitespace();
        let n: usize = it
            .next()
            .and_then(|t| t.parse().ok())
            .ok_or(format!("face {f}: no corner count"))?;
        let face: Vec<usize> = it
            .take(n)
            .map(|t| t.parse().map_err(|_| format!("face {f}: bad index `{t}`")))
            .collect::<Result<_, _>>()?;
        if face.len() != n || face.iter().any(|&v| v >= nv) {
            return Err(format!("face {f}: bad corners `{l}`"));
        }
        faces.push(face);
    }
    Ok(Off { positions, faces })
}

/// Position tolerance, relative to the CLI result's bounding-box diagonal: MeshLab stores
/// floats and writes 7 significant digits.
const REL_TOL: f64 = 1e-5;

/// Checks that MeshLab's result `ml` (triangles) is the CLI's result `cli` (polygons):
///
/// 1. the same number of vertices, and a one-to-one map from MeshLab's vertices to the CLI's
///    with every coordinate within `REL_TOL` × the CLI bounding-box diagonal (each MeshLab
///    vertex must have exactly one CLI vertex that close);
/// 2. through that map, MeshLab's triangles are triangulations of the CLI's polygons: every
///    triangle lies in exactly one CLI polygon (its three corners are corners of that polygon,
///    in the polygon's cyclic order, so it has the polygon's orientation), an n-gon gets
///    exactly n − 2 triangles, and each side of the n-gon is a side of one of its triangles.
///
/// Vertex order and where a polygon's corner list starts may differ (MeshLab rebuilds
/// polygons from faux edges), so neither is compared. Returns a one-line summary.
fn compare(ml: &Off, cli: &Off) -> Result<String, String> {
    if ml.positions.len() != cli.positions.len() {
        return Err(format!(
            "{} vertices in MeshLab's result, {} in the CLI's",
            ml.positions.len(),
            cli.positions.len()
        ));
    }
    let (lo, hi) = cli.positions.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        },
    );
    let diag = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
    let tol = REL_TOL * diag.max(f64::MIN_POSITIVE);
    // Grid of the CLI's vertices, cells 2 tol wide: a match is in a neighbouring cell.
    let cell = |p: &[f64; 3]| -> [i64; 3] {
        [0, 1, 2].map(|k| ((p[k] - lo[k]) / (2.0 * tol)).floor() as i64)
    };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in cli.positions.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i);
    }
    let mut map = vec![usize::MAX; ml.positions.len()];
    let mut taken = vec![false; cli.positions.len()];
    let mut worst = 0.0f64;
    for (i, p) in ml.positions.iter().enumerate() {
        let c = cell(p);
        let mut found = Vec::new();
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        for &j in list {
                            let q = &cli.positions[j];
                            let d = (0..3).map(|k| (p[k] - q[k]).abs()).fold(0.0, f64::max);
                            if d <= tol {
                                found.push((j, d));
                            }
                        }
                    }
                }
            }
        }
        match found[..] {
            [(j, d)] if !taken[j] => {
                map[i] = j;
                taken[j] = true;
                worst = worst.max(d);
            }
            [(j, _)] => {
                return Err(format!(
                    "MeshLab vertices {i} and another both match CLI vertex {j} at {:?}",
                    cli.positions[j]
                ))
            }
            [] => {
                return Err(format!(
                    "MeshLab vertex {i} at {p:?} has no CLI vertex within {tol:.3e}"
                ))
            }
            _ => {
                return Err(format!(
                    "MeshLab vertex {i} at {p:?} has {} CLI vertices within {tol:.3e}",
                    found.len()
                ))
            }
        }
    }

    // CLI polygons around each vertex.
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); cli.positions.len()];
    for (f, face) in cli.faces.iter().enumerate() {
        for &v in face {
            around[v].push(f);
        }
    }
    let mut tri_count = vec![0usize; cli.faces.len()];
    let mut sides: HashMap<(usize, usize), usize> = HashMap::new(); // directed side -> uses
    for (t, tri) in ml.faces.iter().enumerate() {
        let [a, b, c] = tri[..] else {
            return Err(format!("MeshLab face {t} has {} corners, not 3", tri.len()));
        };
        let [a, b, c] = [map[a], map[b], map[c]];
        let homes: Vec<usize> = around[a]
            .iter()
            .copied()
            .filter(|&f| in_cyclic_order(&cli.faces[f], a, b, c))
            .collect();
        let [home] = homes[..] else {
            return Err(format!(
                "MeshLab triangle {t} (CLI vertices {a} {b} {c}) lies in {} CLI polygons, not 1",
                homes.len()
            ));
        };
        tri_count[home] += 1;
        for (x, y) in [(a, b), (b, c), (c, a)] {
            *sides.entry((x, y)).or_default() += 1;
        }
    }
    for (f, face) in cli.faces.iter().enumerate() {
        if tri_count[f] != face.len() - 2 {
            return Err(format!(
                "CLI polygon {f} ({} corners) is covered by {} MeshLab triangles, not {}",
                face.len(),
                tri_count[f],
                face.len() - 2
            ));
        }
        for k in 0..face.len() {
            let side = (face[k], face[(k + 1) % face.len()]);
            if sides.get(&side).copied() != Some(1) {
                return Err(format!(
                    "side {} -> {} of CLI polygon {f} is a side of {} MeshLab triangles, not 1",
                    side.0,
                    side.1,
                    sides.get(&side).copied().unwrap_or(0)
                ));
            }
        }
    }
    let quads = cli.faces.iter().filter(|f| f.len() == 4).count();
    Ok(format!(
        "{} vertices (max deviation {:.2e} = {:.2e} of the diagonal), {} polygons ({quads} quads) = {} MeshLab triangles: same as the CLI",
        ml.positions.len(),
        worst,
        worst / diag.max(f64::MIN_POSITIVE),
        cli.faces.len(),
        ml.faces.len()
    ))
}

/// Whether a, b, c are corners of `face` that come in this cyclic order.
fn in_cyclic_order(face: &[usize], a: usize, b: usize, c: usize) -> bool {
    let pos = |v: usize| face.iter().position(|&x| x == v);
    let (Some(i), Some(j), Some(k)) = (pos(a), pos(b), pos(c)) else {
        return false;
    };
    let n = face.len();
    let (dj, dk) = ((j + n - i) % n, (k + n - i) % n);
    0 < dj && dj < dk
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad_mesh() -> Off {
        // Two quads sharing the edge 1-4.
        Off {
            positions: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, 0.0],
                [2.0, 1.0, 0.0],
            ],
            faces: vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]],
        }
    }

    /// The same mesh with vertices reordered and each quad split into two triangles.
    fn as_meshlab(cli: &Off) -> Off {
        let perm = [5, 3, 1, 0, 2, 4]; // new index of old vertex i
        let mut positions = vec![[0.0; 3]; 6];
        for (i, p) in cli.positions.iter().enumerate() {
            positions[perm[i]] = *p;
        }
        let faces = vec![
            vec![perm[1], perm[4], perm[3]],
            vec![perm[1], perm[3], perm[0]],
            vec![perm[1], perm[2], perm[5]],
            vec![perm[1], perm[5], perm[4]],
        ];
        Off { positions, faces }
    }

    #[test]
    fn same_mesh_modulo_order_and_triangulation() {
        let cli = quad_mesh();
        let ml = as_meshlab(&cli);
        assert!(compare(&ml, &cli).is_ok(), "{:?}", compare(&ml, &cli));
        // Within tolerance: a 1e-6 relative error passes.
        let mut near = ml.clone();
        near.positions[0][0] += 1e-6;
        assert!(compare(&near, &cli).is_ok());
    }

    #[test]
    fn differences_are_caught() {
        let cli = quad_mesh();
        let ml = as_meshlab(&cli);
        let mut moved = ml.clone();
        moved.positions[2][1] += 1e-3;
        assert!(compare(&moved, &cli).unwrap_err().contains("no CLI vertex"));
        let mut flipped = ml.clone();
        flipped.faces[0].reverse();
        assert!(compare(&flipped, &cli)
            .unwrap_err()
            .contains("lies in 0 CLI polygons"));
        let mut missing = ml.clone();
        missing.faces.pop();
        assert!(compare(&missing, &cli)
            .unwrap_err()
            .contains("covered by 1"));
        let mut doubled = ml.clone();
        doubled.faces[1] = doubled.faces[0].clone();
        assert!(compare(&doubled, &cli).is_err());
        let mut fewer = ml.clone();
        fewer.positions.pop();
        assert!(compare(&fewer, &cli).unwrap_err().contains("vertices"));
    }

    #[test]
    fn off_parsing() {
        let off = parse_off("OFF\n# c\n3 1 0\n0 0 0\n1 0 0 \n0 1 0\n3 0 1 2 255 0 0\n").unwrap();
        assert_eq!(off.faces, vec![vec![0, 1, 2]]);
        assert_eq!(off.positions[1], [1.0, 0.0, 0.0]);
        assert!(parse_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n").is_err());
        assert!(parse_off("PLY\n").is_err());
    }

    #[test]
    fn plate_is_closed_and_consistent() {
        let plate = parse_off(&plate_with_hole_off()).unwrap();
        assert_eq!((plate.positions.len(), plate.faces.len()), (16, 32));
        // Every directed side once, and its reverse once: closed and consistently oriented.
        let mut sides = HashMap::new();
        for f in &plate.faces {
            for k in 0..3 {
                *sides.entry((f[k], f[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        assert!(sides
            .iter()
            .all(|(&(a, b), &n)| n == 1 && sides.get(&(b, a)) == Some(&1)));
        // Euler characteristic 0: a torus.
        assert_eq!(16 - sides.len() as i64 / 2 + 32, 0);
    }

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

    fn cut_case() -> CutCase {
        CutCase {
            name: "t",
            input: PathBuf::from("in.off"),
            camera: Camera::looking_at([5.0, 5.0, 10.0], [5.0, 5.0, 0.0], [0.0, 1.0, 0.0], true),
            stroke: vec![[10.0, 20.0], [30.5, 40.25]],
            through_all: true,
            open: false,
            new_layer: true,
        }
    }

    #[test]
    fn cut_mlx_gives_every_parameter_but_the_shot() {
        let s = cut_case().mlx();
        for p in ["viewXml", "stroke", "mode", "openCut", "newLayer"] {
            assert!(s.contains(&format!("name=\"{p}\"")), "{p} missing");
        }
        assert!(!s.contains("name=\"shot\""));
        assert!(s.contains("value=\"10 20; 30.5 40.25\""));
        assert!(s.contains("name=\"mode\" value=\"1\""));
        // The camera XML is escaped inside the attribute.
        assert!(s.contains("value=\"&lt;VCGCamera TranslationVector=&quot;-5 -5 -10 1&quot;"));
        assert!(!s.contains("<VCGCamera"));
    }

    #[test]
    fn cut_stroke_file_flips_y() {
        let case = cut_case();
        let m: Vec<f64> = (0..16).map(f64::from).collect();
        let json = case.stroke_json(&m);
        assert!(
            json.starts_with("{\"stroke\": [[10.0, 580.0], [30.5, 559.75]]"),
            "{json}"
        );
        assert!(json.contains("\"viewport\": [0, 0, 600, 600]"));
        assert!(json.contains("\"mode\": \"through-all\""));
    }

    #[test]
    fn camera_axes_are_orthonormal() {
        let c = Camera::looking_at([1.0, -4.0, 3.0], [0.5, 0.2, 0.1], [0.0, 0.0, 1.0], false);
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for i in 0..3 {
            for j in 0..3 {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((dot(c.rows[i], c.rows[j]) - expected).abs() < 1e-12);
            }
        }
        // z points from the target back to the eye (vcg looks down -z).
        assert!(dot(c.rows[2], sub(c.eye, [0.5, 0.2, 0.1])) > 0.0);
    }

    #[test]
    fn logged_matrix_is_read() {
        let log = "LOG: 2 katachi: view: perspective, 800 x 600 pixels; view-projection \
                   (column-major, katachi's pixels top-left, y down): 1 0 0 0 0 2 0 0 0 0 -1.5 -1 \
                   -4.25 -6 3.5e-13 12\nLOG: 2 other";
        let m = logged_view_proj(log).unwrap();
        assert_eq!(m.len(), 16);
        assert_eq!(m[14], 3.5e-13);
        assert!(logged_view_proj("nothing").is_err());
    }

    #[test]
    fn indexed_comparison() {
        let grid = parse_off(&grid_off(2)).unwrap();
        assert_eq!((grid.positions.len(), grid.faces.len()), (9, 8));
        assert!(compare_indexed(&grid, &grid).is_ok());
        let mut moved = grid.clone();
        moved.positions[4][2] += 1e-3;
        assert!(compare_indexed(&moved, &grid)
            .unwrap_err()
            .contains("vertex 4"));
        let mut turned = grid.clone();
        turned.faces[3].rotate_left(1);
        assert!(compare_indexed(&turned, &grid)
            .unwrap_err()
            .contains("face 3"));
        let f32_text = off_f32(&Off {
            positions: vec![[0.1, 1.0 / 3.0, 2.0]],
            faces: vec![],
        });
        let back = parse_off(&f32_text).unwrap();
        assert_eq!(back.positions[0][0], f64::from(0.1f32));
        assert_eq!(back.positions[0][1], f64::from((1.0f64 / 3.0) as f32));
    }

    #[test]
    fn mlx_has_every_parameter() {
        let s = Opts::default().mlx();
        for p in [
            "levels",
            "holeMethod",
            "recoverFacesWithHoles",
            "featureAngle",
            "boundary",
            "newLayer",
        ] {
            assert!(s.contains(&format!("name=\"{p}\"")), "{p} missing");
        }
    }
}
