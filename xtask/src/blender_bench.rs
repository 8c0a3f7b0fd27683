//! `cargo xtask blender-bench [--rounds N] [--only 3.4|5.0] [-k CASE] [--modal-only|--no-modal]`:
//! katachi's Blender operators against Blender's own tools and against the floor (the least
//! any add-on must do for the same result), in Debian's Blender 3.4 and in bpy 5.0, printed
//! as one table of times and per-round ratios.
//!
//! Builds the add-on zip (`cargo xtask addon`), then runs `benches/blender/bench.py` (see its
//! docs for the meshes and what is timed) in each Blender, each in one process with
//! interleaved rounds, and in Blender 3.4 under Xvfb `benches/blender/modal_bench.py`: the
//! Cut by Stroke tool driven by simulated mouse events, timed from the release of the
//! button to the redrawn result. The load (`/proc/loadavg`) is printed before and after:
//! the machine is shared, so absolute times drift while ratios within one process hold.

use std::path::Path;
use std::process::Command;

use crate::bench_table::{self, Goal, Sample};
use crate::blender::{blender_window, fresh_home, isolate, venv_python};
use crate::util::{describe, have, root};

const USAGE: &str = "usage: cargo xtask blender-bench [--rounds N] [--only 3.4|5.0] [-k CASE] \
                     [--no-modal | --modal-only]";

/// The goals (issue 35 §1).
const GOALS: [Goal; 5] = [
    Goal {
        case: "subdivide",
        host: "",
        against: "floor",
        limit: 1.5,
    },
    Goal {
        case: "subdivide",
        host: "Blender 3.4",
        against: "host",
        limit: 0.5,
    },
    Goal {
        case: "cut",
        host: "",
        against: "floor",
        limit: 1.5,
    },
    Goal {
        case: "cut",
        host: "Blender 3.4",
        against: "host",
        limit: 0.4,
    },
    Goal {
        case: "cut",
        host: "Blender 5",
        against: "host",
        limit: 0.5,
    },
];

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut rounds = 5u32;
    let mut only: Option<&str> = None;
    let mut filter = "";
    let (mut modal, mut main) = (true, true);
    let mut it = args.iter().copied();
    while let Some(a) = it.next() {
        match a {
            "--rounds" => {
                rounds = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .filter(|&n| n > 0)
                    .ok_or(format!("--rounds takes a positive number\n{USAGE}"))?
            }
            "--only" => match it.next() {
                Some(v @ ("3.4" | "5.0")) => only = Some(v),
                _ => return Err(format!("--only takes 3.4 or 5.0\n{USAGE}")),
            },
            "-k" => filter = it.next().ok_or(USAGE)?,
            "--no-modal" => modal = false,
            "--modal-only" => main = false,
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    let run34 = only != Some("5.0");
    let run50 = only != Some("3.4") && main;
    modal &= run34;
    if run34 && !have("blender") {
        return Err(
            "`blender` is not on the PATH: install the Debian package `blender` (as root), \
                    or run `cargo xtask deps`"
                .into(),
        );
    }
    if modal && !(have("xvfb-run") && have("xauth")) {
        return Err(
            "the modal tool's bench needs `xvfb-run` and `xauth` (Debian packages \
                    `xvfb`, `xauth`; `cargo xtask deps`), or pass --no-modal"
                .into(),
        );
    }
    let python = if run50 { Some(venv_python()?) } else { None };
    let zip = crate::addon::build()?;
    let script = root().join("benches/blender/bench.py");
    let mut rest: Vec<String> = vec![
        "--zip".into(),
        zip.display().to_string(),
        "--rounds".into(),
        rounds.to_string(),
    ];
    if !filter.is_empty() {
        rest.extend(["--only".into(), filter.into()]);
    }
    eprintln!("xtask: blender-bench: load before {}", load());
    let mut samples: Vec<Sample> = Vec::new();
    if run34 && main {
        let home = fresh_home("bench-3.4")?;
        let mut c = Command::new("blender");
        c.args([
            "-b",
            "--factory-startup",
            "--python-exit-code",
            "1",
            "--python",
        ])
        .arg(&script)
        .arg("--")
        .args(&rest);
        isolate(&mut c, &home);
        samples.extend(run_bench(&mut c)?);
    }
    if let Some(python) = &python {
        let home = fresh_home("bench-5.0")?;
        let mut c = Command::new(python);
        c.arg(&script).args(&rest);
        isolate(&mut c, &home);
        samples.extend(run_bench(&mut c)?);
    }
    if modal && (filter.is_empty() || "modal cut".contains(filter)) {
        let home = fresh_home("bench-3.4-window")?;
        let mut c = blender_window(
            &home,
            "benches/blender/modal_bench.py",
            &zip,
            &home.join("work"),
        )?;
        c.args(["--rounds", &rounds.to_string()]);
        samples.extend(run_bench(&mut c)?);
    }
    eprintln!("xtask: blender-bench: load after {}", load());
    println!("\n{}", bench_table::table(&samples, &GOALS));
    Ok(())
}

/// Runs a bench script (echoing its output) and returns its measurements; fails unless it
/// exits 0 with its closing `BENCH-DONE` line.
fn run_bench(cmd: &mut Command) -> Result<Vec<Sample>, String> {
    cmd.current_dir(root());
    eprintln!("xtask: $ {}", describe(cmd));
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(cmd)))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    for line in stdout.lines() {
        if !line.starts_with("BENCH\t") {
            println!("{line}");
        }
    }
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    if !out.status.success() || !stdout.lines().any(|l| l.starts_with("BENCH-DONE")) {
        return Err(format!(
            "`{}` failed ({}) before its BENCH-DONE line",
            describe(cmd),
            out.status
        ));
    }
    bench_table::parse(&stdout, "Blender ")
}

/// The 1-minute load average.
pub fn load() -> String {
    std::fs::read_to_string(Path::new("/proc/loadavg"))
        .ok()
        .and_then(|s| s.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "?".into())
}
