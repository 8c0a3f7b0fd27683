//! `cargo xtask bench`: runs the criterion benchmarks; extra arguments go to criterion
//! (e.g. `cargo xtask bench -- connectivity` to filter).

use std::process::Command;

use crate::util;

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut cmd = Command::new(util::cargo());
    cmd.args(["bench", "--workspace"]);
    if !args.is_empty() {
        cmd.arg("--");
        cmd.args(args.iter().filter(|a| **a != "--"));
    }
    util::run(&mut cmd)
}
