//! `cargo xtask macos-check`: the library and the CLI type-check for macOS
//! (`aarch64-apple-darwin`) under `cargo clippy -D warnings`.
//!
//! Linking for macOS needs Apple's SDK, which no registry reachable here provides, so nothing
//! is built or run for macOS; this check keeps the code free of what would stop a macOS build
//! (a Linux-only call outside its `cfg`, a Unix path) and of warnings only macOS would see.
//! It needs the Rust target's standard library only (`cargo xtask deps` adds it).

use std::process::Command;

use crate::util::{self, run as run_cmd};

/// The Rust target checked (Apple silicon; the Intel target differs only in the CPU).
pub const TARGET: &str = "aarch64-apple-darwin";

pub fn check(args: &[&str]) -> Result<(), String> {
    if let Some(a) = args.first() {
        return Err(format!(
            "unknown argument `{a}`\nusage: cargo xtask macos-check"
        ));
    }
    util::require_rust_target(TARGET)?;
    run_cmd(Command::new(util::cargo()).args([
        "clippy",
        "--target",
        TARGET,
        "-p",
        "katachi",
        "-p",
        "katachi-cli",
        "--",
        "-D",
        "warnings",
    ]))
}
