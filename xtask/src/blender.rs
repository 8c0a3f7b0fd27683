//! `cargo xtask blender-test [--only 3.4|5.0] [--no-window] [-k NAME]`: the Blender add-on's
//! tests in Debian's Blender 3.4 and in Blender 5.0 (the `bpy` module from PyPI).
//!
//! Builds the add-on zip (`cargo xtask addon`) and the `katachi` CLI (release), then runs
//! `tests/blender/run_tests.py` (the cases of `cases.py`, then the stroke cut's of
//! `cut_cases.py`), which installs the zip the way a user does (Blender 3.4: Install
//! add-on; 5.0: Install extension from disk) and compares the operators' results with the
//! CLI's, the katachi library's, Blender's own Subdivision Surface modifier, or the
//! untouched input:
//!
//! - 3.4: `blender -b --factory-startup --python-exit-code 1 --python run_tests.py -- …`
//!   (the Debian package `blender`);
//! - 5.0: `<target>/bpy-venv/bin/python run_tests.py …`, with `bpy==5.0.1` installed by pip
//!   into a venv this task creates once (`python3.11 -m venv`, the Debian package
//!   `python3-venv`; about 360 MB downloaded the first time) and reuses afterwards.
//!
//! Then, in Blender 3.4 only, the Cut by Stroke tool's modal operator is driven by simulated
//! mouse and keyboard events in a real window (`tests/blender/modal_test.py`): `xvfb-run -a
//! blender --factory-startup --enable-event-simulate SCENE.blend --python modal_test.py`
//! under Xvfb (the Debian packages `xvfb` and `xauth`), on a scene saved first so that no
//! splash screen takes the events. `--no-window` skips this run. The `bpy` module has no
//! windows (no `Window.event_simulate`, no event loop), so 5.0 cannot run it.
//!
//! Each run gets its own Blender user directories under `<target>/blender-test/<label>/`
//! (emptied first), so nothing is installed into the user's own Blender. A run passes when
//! it exits 0 and its last line is `N passed, 0 failed` with N > 0 (N = 0 is allowed for
//! the window run when `-k` selects none of its cases).
//!
//! `cargo xtask blender-screenshot` renders the operator's redo panel under Xvfb
//! (`xvfb-run`, the Debian packages `xvfb` and `xauth`) into `docs/images/blender_subdivide.png`.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::ctest::target_dir;
use crate::util::{describe, have, parse_summary, root, run as run_cmd};

const USAGE: &str = "usage: cargo xtask blender-test [--only 3.4|5.0] [--no-window] [-k NAME]";

/// The bpy release the 5.0 tests use (Python 3.11 only).
const BPY: &str = "bpy==5.0.1";
const BPY_VERSION: &str = "5.0.1";

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut only: Option<&str> = None;
    let mut filter: Option<&str> = None;
    let mut window = true;
    let mut it = args.iter().copied();
    while let Some(a) = it.next() {
        match a {
            "--only" => match it.next() {
                Some(v @ ("3.4" | "5.0")) => only = Some(v),
                _ => return Err(format!("--only takes 3.4 or 5.0\n{USAGE}")),
            },
            "--no-window" => window = false,
            "-k" => filter = Some(it.next().ok_or(USAGE)?),
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    let run34 = only != Some("5.0");
    let run50 = only != Some("3.4");
    let run_window = run34 && window;

    // Fail on a missing Blender before building anything.
    if run34 && !have("blender") {
        return Err(
            "`blender` is not on the PATH: the add-on tests need Blender 3.4. \
             Install the Debian package `blender` (as root), or run `cargo xtask deps`."
                .into(),
        );
    }
    if run_window {
        for (tool, pkg) in [("xvfb-run", "xvfb"), ("xauth", "xauth")] {
            if !have(tool) {
                return Err(format!(
                    "`{tool}` is not on the PATH: the Cut by Stroke tool's window test needs it. \
                     Install the Debian package `{pkg}` (as root), run `cargo xtask deps`, or \
                     pass --no-window"
                ));
            }
        }
    }
    let python = if run50 { Some(venv_python()?) } else { None };

    let zip = crate::addon::build()?;
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    run_cmd(Command::new(cargo).args([
        "build",
        "--release",
        "-p",
        "katachi-cli",
        "--bin",
        "katachi",
    ]))?;
    let cli = target_dir().join("release").join("katachi");

    let mut summary = Vec::new();
    if run34 {
        let n = run_tests("3.4", &zip, &cli, filter, |script, rest| {
            let mut c = Command::new("blender");
            c.args([
                "-b",
                "--factory-startup",
                "--python-exit-code",
                "1",
                "--python",
            ])
            .arg(script)
            .arg("--")
            .args(rest);
            c
        })?;
        summary.push(format!("Blender 3.4: {n} passed"));
    }
    if run_window {
        let n = run_window_tests(&zip, filter)?;
        summary.push(format!("Blender 3.4 window (simulated events): {n} passed"));
    }
    if let Some(python) = python {
        let n = run_tests("5.0", &zip, &cli, filter, |script, rest| {
            let mut c = Command::new(&python);
            c.arg(script).args(rest);
            c
        })?;
        summary.push(format!("Blender {BPY_VERSION} (bpy): {n} passed"));
    }
    eprintln!("xtask: blender-test: {}", summary.join("; "));
    Ok(())
}

/// Runs `run_tests.py` through `command(script, args)`; returns the number of passed tests.
fn run_tests(
    label: &str,
    zip: &Path,
    cli: &Path,
    filter: Option<&str>,
    command: impl Fn(&Path, &[std::ffi::OsString]) -> Command,
) -> Result<u64, String> {
    let home = fresh_home(label)?;
    let work = home.join("work");
    std::fs::create_dir_all(&work).map_err(|e| format!("{}: {e}", work.display()))?;
    let mut rest: Vec<std::ffi::OsString> = vec![
        "--zip".into(),
        zip.into(),
        "--cli".into(),
        cli.into(),
        "--work".into(),
        work.into(),
    ];
    if let Some(k) = filter {
        rest.push("-k".into());
        rest.push(k.into());
    }
    let script = root().join("tests/blender/run_tests.py");
    let mut cmd = command(&script, &rest);
    cmd.current_dir(root());
    isolate(&mut cmd, &home);
    summarize(label, &mut cmd, false)
}

/// Runs `cmd`, echoing its output, and reads its closing `N passed, M failed` line; returns
/// N. `none_ok`: N = 0 passes (a `-k` filter that selects no case).
fn summarize(label: &str, cmd: &mut Command, none_ok: bool) -> Result<u64, String> {
    eprintln!("xtask: $ {}", describe(cmd));
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(cmd)))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    print!("{stdout}");
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    // Blender may print after the script's closing line ("Blender quit", a traceback).
    let counts = stdout.lines().rev().find_map(parse_summary);
    let last = stdout
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("");
    match (out.status.success(), counts) {
        (true, Some((passed, 0))) if passed > 0 || none_ok => Ok(passed),
        (_, Some((passed, failed))) => Err(format!(
            "Blender {label}: {passed} passed, {failed} failed (see FAIL above)"
        )),
        (ok, None) => Err(format!(
            "Blender {label} {} without the closing `N passed, M failed` line (last line: {last:?})",
            if ok { "exited 0" } else { "failed" }
        )),
    }
}

/// The Cut by Stroke tool's modal operator in Blender 3.4's real window under Xvfb, fed
/// simulated events (`tests/blender/modal_test.py`); returns the number of passed cases.
fn run_window_tests(zip: &Path, filter: Option<&str>) -> Result<u64, String> {
    let home = fresh_home("3.4-window")?;
    let mut cmd = blender_window(
        &home,
        "tests/blender/modal_test.py",
        zip,
        &home.join("work"),
    )?;
    if let Some(k) = filter {
        cmd.args(["-k", k]);
    }
    cmd.current_dir(root());
    summarize("3.4 (window)", &mut cmd, filter.is_some())
}

/// `<target>/blender-test/<label>/`, emptied (made anew).
pub(crate) fn fresh_home(label: &str) -> Result<PathBuf, String> {
    let home = target_dir().join("blender-test").join(label);
    if home.exists() {
        std::fs::remove_dir_all(&home).map_err(|e| format!("{}: {e}", home.display()))?;
    }
    std::fs::create_dir_all(&home).map_err(|e| format!("{}: {e}", home.display()))?;
    Ok(home)
}

/// Blender 3.4 in a 1280 × 800 window under Xvfb, accepting simulated events, running
/// `script` (relative to the repository) with `-- --zip ZIP --out OUT`, its user
/// directories in `home`. Blender shows its splash screen (which would take the events)
/// unless it opens a file, so the factory startup scene is saved into `home` first.
pub(crate) fn blender_window(
    home: &Path,
    script: &str,
    zip: &Path,
    out: &Path,
) -> Result<Command, String> {
    let scene = home.join("scene.blend");
    save_startup_scene(&scene, home)?;
    let mut cmd = Command::new("xvfb-run");
    cmd.args([
        "-a",
        "-s",
        "-screen 0 1280x800x24",
        "blender",
        "--factory-startup",
        "--window-geometry",
        "0",
        "0",
        "1280",
        "800",
        "--python-exit-code",
        "1",
        "--enable-event-simulate",
    ])
    .arg(&scene)
    .arg("--python")
    .arg(root().join(script))
    .arg("--")
    .arg("--zip")
    .arg(zip)
    .arg("--out")
    .arg(out);
    isolate(&mut cmd, home);
    Ok(cmd)
}

/// Saves Blender's factory startup scene to `scene`, with the user directories in `home`.
fn save_startup_scene(scene: &Path, home: &Path) -> Result<(), String> {
    let mut save = Command::new("blender");
    save.args([
        "-b",
        "--factory-startup",
        "--python-exit-code",
        "1",
        "--python-expr",
    ])
    .arg(format!(
        "import bpy; bpy.ops.wm.save_as_mainfile(filepath={:?})",
        scene.display().to_string()
    ));
    isolate(&mut save, home);
    run_cmd(&mut save)
}

/// Points Blender's user directories (config, scripts, extensions) into `home`.
pub(crate) fn isolate(cmd: &mut Command, home: &Path) {
    cmd.env("BLENDER_USER_RESOURCES", home.join("user"))
        .env("BLENDER_USER_CONFIG", home.join("user/config"))
        .env("BLENDER_USER_SCRIPTS", home.join("user/scripts"))
        .env("BLENDER_USER_DATAFILES", home.join("user/datafiles"))
        .env("BLENDER_USER_EXTENSIONS", home.join("user/extensions"))
        .env("PYTHONDONTWRITEBYTECODE", "1");
}

/// The Python interpreter of `<target>/bpy-venv` with bpy 5.0.1, creating the venv and
/// installing bpy when they are missing.
pub(crate) fn venv_python() -> Result<PathBuf, String> {
    let venv = target_dir().join("bpy-venv");
    let python = venv.join("bin").join("python");
    if python.is_file() && has_bpy(&python) {
        return Ok(python);
    }
    if !python.is_file() {
        let base = ["/usr/bin/python3.11", "python3.11"]
            .into_iter()
            .find(|p| Path::new(p).is_file() || have(p))
            .ok_or(
                "bpy 5.0 needs Python 3.11 (`python3.11`), which is missing. Install the Debian \
                 packages `python3.11` and `python3-venv` (as root), or run `cargo xtask deps`.",
            )?;
        if venv.exists() {
            std::fs::remove_dir_all(&venv).map_err(|e| format!("{}: {e}", venv.display()))?;
        }
        run_cmd(Command::new(base).args(["-m", "venv"]).arg(&venv)).map_err(|e| {
            format!(
                "{e}\n  creating the bpy venv failed: install the Debian package `python3-venv` \
                 (as root), or run `cargo xtask deps`"
            )
        })?;
    }
    eprintln!(
        "xtask: blender-test: installing {BPY} into {} (once; about 360 MB)",
        venv.display()
    );
    run_cmd(Command::new(&python).args([
        "-m",
        "pip",
        "install",
        "--disable-pip-version-check",
        "-q",
        BPY,
    ]))
    .map_err(|e| format!("{e}\n  pip could not install {BPY} (PyPI unreachable?)"))?;
    if !has_bpy(&python) {
        return Err(format!(
            "{BPY} is still not importable from {}",
            python.display()
        ));
    }
    Ok(python)
}

fn has_bpy(python: &Path) -> bool {
    Command::new(python)
        .args([
            "-c",
            "import bpy, sys; sys.exit(bpy.app.version_string != sys.argv[1])",
        ])
        .arg(BPY_VERSION)
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// `cargo xtask blender-screenshot`: the operator's redo panel, rendered by Blender 3.4
/// under Xvfb, into `docs/images/blender_subdivide.png`.
pub fn screenshot(args: &[&str]) -> Result<(), String> {
    if let Some(a) = args.first() {
        return Err(format!(
            "unknown argument `{a}`\nusage: cargo xtask blender-screenshot"
        ));
    }
    for (tool, pkg) in [
        ("blender", "blender"),
        ("xvfb-run", "xvfb"),
        ("xauth", "xauth"),
    ] {
        if !have(tool) {
            return Err(format!(
                "`{tool}` is not on the PATH: install the Debian package `{pkg}` (as root), \
                 or run `cargo xtask deps`"
            ));
        }
    }
    let zip = crate::addon::build()?;
    let home = fresh_home("screenshot")?;
    let png = root().join("docs/images/blender_subdivide.png");
    let tmp = home.join("blender_subdivide.png");
    run_cmd(&mut blender_window(
        &home,
        "tests/blender/screenshot.py",
        &zip,
        &tmp,
    )?)?;
    if !tmp.is_file() {
        return Err(format!("Blender wrote no screenshot to {}", tmp.display()));
    }
    std::fs::create_dir_all(png.parent().expect("a parent"))
        .map_err(|e| format!("{}: {e}", png.display()))?;
    std::fs::copy(&tmp, &png).map_err(|e| format!("{}: {e}", png.display()))?;
    eprintln!("xtask: blender-screenshot: wrote {}", png.display());
    Ok(())
}
