//! `cargo xtask test`: every test, in order of cost, stopping at the first failure.

use std::process::Command;
use std::time::Instant;

use crate::util;

type Step = Box<dyn Fn() -> Result<(), String>>;

pub fn run(args: &[&str]) -> Result<(), String> {
    let skip_c = args.contains(&"--no-c");
    let start = Instant::now();
    let mut steps: Vec<(&str, Step)> = vec![
        ("system packages", Box::new(|| crate::deps::run(&[]))),
        (
            "format",
            Box::new(|| {
                util::run(Command::new(util::cargo()).args(["fmt", "--all", "--", "--check"]))
            }),
        ),
        (
            "clippy",
            Box::new(|| {
                util::run(Command::new(util::cargo()).args([
                    "clippy",
                    "--workspace",
                    "--all-targets",
                    "--",
                    "-D",
                    "warnings",
                ]))
            }),
        ),
        ("header", Box::new(crate::header::check)),
        (
            "docs",
            Box::new(|| {
                util::run(
                    Command::new(util::cargo())
                        .args(["doc", "--no-deps", "-p", "katachi"])
                        .env("RUSTDOCFLAGS", "-D warnings"),
                )
            }),
        ),
        (
            "cargo test",
            Box::new(|| util::run(Command::new(util::cargo()).args(["test", "--workspace"]))),
        ),
    ];
    if !skip_c {
        steps.push(("C/C++ link tests", Box::new(|| crate::ctest::run(&[]))));
        steps.push((
            "installed C library (pkg-config, C and C++, valgrind)",
            Box::new(|| crate::install::test(&[])),
        ));
        steps.push((
            "MeshLab plugin (2020.09 through meshlabserver under xvfb-run, 2025.07 in pymeshlab)",
            Box::new(crate::meshlab::test),
        ));
    }
    steps.push((
        "Blender add-on (Blender 3.4 and bpy 5.0, headless)",
        Box::new(|| crate::blender::run(&[])),
    ));
    let total = steps.len();
    for (i, (name, step)) in steps.iter().enumerate() {
        eprintln!("xtask test: [{}/{total}] {name}", i + 1);
        let t = Instant::now();
        step().map_err(|e| format!("step `{name}` failed: {e}"))?;
        eprintln!(
            "xtask test: [{}/{total}] {name} ok ({:.0?})",
            i + 1,
            t.elapsed()
        );
    }
    eprintln!(
        "xtask test: all {total} steps passed in {:.0?}",
        start.elapsed()
    );
    Ok(())
}
