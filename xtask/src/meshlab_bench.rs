//! `cargo xtask meshlab-bench [--rounds N]`: katachi's MeshLab 2020.09 filters against
//! MeshLab's own, as MeshLab times a filter (the time of its `applyFilter`, which MeshLab's
//! log reports), in one process with interleaved rounds, printed as a table of times and
//! per-round ratios.
//!
//! Builds the plugin with its test programs (`cargo xtask meshlab-plugin`'s build, which
//! includes `benches/meshlab/meshlab_bench.cpp`), then runs the bench under `xvfb-run` (Qt
//! needs a display) with the plugin from the build directory and MeshLab's own plugins from
//! the installed MeshLab. See the bench's source for the meshes and what is timed.

use std::process::Command;

use crate::bench_table::{self, Goal};
use crate::meshlab::{build, check_tools, system_meshlab_lib_dir, Versions, TEST_TOOLS};
use crate::util::{describe, root};

const USAGE: &str = "usage: cargo xtask meshlab-bench [--rounds N]";

/// The goals (issue 35 §1): the subdivision at most half MeshLab's Catmull-Clark, the
/// cut at most twice the time MeshLab takes to duplicate the layer.
const GOALS: [Goal; 2] = [
    Goal {
        case: "subdivide",
        host: "",
        against: "host",
        limit: 0.5,
    },
    Goal {
        case: "cut",
        host: "",
        against: "host",
        limit: 2.0,
    },
];

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut rounds = 5u32;
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
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    check_tools(&TEST_TOOLS[..2])?;
    let dirs = build(Versions {
        v2020: true,
        v2025: false,
    })?;
    let bench = dirs.build2020.join("meshlab_bench");
    let plugin = dirs.build2020.join("libfilter_katachi.so");
    let meshlab_plugins = system_meshlab_lib_dir()?.join("plugins");
    eprintln!(
        "xtask: meshlab-bench: load before {}",
        crate::blender_bench::load()
    );
    let mut cmd = Command::new("xvfb-run");
    cmd.arg("-a")
        .arg(&bench)
        .arg(&plugin)
        .arg(&meshlab_plugins)
        .arg(rounds.to_string())
        .current_dir(root());
    eprintln!("xtask: $ {}", describe(&cmd));
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(&cmd)))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    for line in stdout.lines().filter(|l| !l.starts_with("BENCH\t")) {
        println!("{line}");
    }
    eprint!("{}", String::from_utf8_lossy(&out.stderr));
    if !out.status.success() || !stdout.lines().any(|l| l.starts_with("BENCH-DONE")) {
        return Err(format!(
            "`{}` failed ({}) before its BENCH-DONE line",
            describe(&cmd),
            out.status
        ));
    }
    let samples = bench_table::parse(&stdout, "MeshLab ")?;
    eprintln!(
        "xtask: meshlab-bench: load after {}",
        crate::blender_bench::load()
    );
    println!("\n{}", bench_table::table(&samples, &GOALS));
    Ok(())
}
