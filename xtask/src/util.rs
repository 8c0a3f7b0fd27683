//! Small helpers shared by the tasks.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The workspace root (the directory holding the top Cargo.toml).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace root")
        .to_path_buf()
}

/// Runs a command in the workspace root, echoing it; fails with the command line on a non-zero exit.
pub fn run(cmd: &mut Command) -> Result<(), String> {
    cmd.current_dir(root());
    eprintln!("xtask: $ {}", describe(cmd));
    wait(cmd)
}

/// [`run`] in another directory.
pub fn run_in(dir: &Path, cmd: &mut Command) -> Result<(), String> {
    cmd.current_dir(dir);
    eprintln!("xtask: (in {}) $ {}", dir.display(), describe(cmd));
    wait(cmd)
}

fn wait(cmd: &mut Command) -> Result<(), String> {
    let status = cmd
        .status()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(cmd)))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`{}` failed ({status})", describe(cmd)))
    }
}

/// The command line as a string, for messages.
pub fn describe(cmd: &Command) -> String {
    let mut s = cmd.get_program().to_string_lossy().into_owned();
    for a in cmd.get_args() {
        s.push(' ');
        s.push_str(&a.to_string_lossy());
    }
    s
}

/// Whether a program is on the PATH.
pub fn have(program: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {program} >/dev/null 2>&1")])
        .status()
        .map(|s| s.success())
        .unwrap_or(false)
}

/// The cargo that runs xtask (`$CARGO`), so the same toolchain builds everything.
pub fn cargo() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())
}

/// Fails, saying how to get it, when rustup has not installed the standard library of the
/// Rust `target` for the toolchain that runs.
pub fn require_rust_target(target: &str) -> Result<(), String> {
    let sysroot = Command::new("rustc")
        .args(["--print", "sysroot"])
        .output()
        .map_err(|e| format!("cannot run `rustc --print sysroot`: {e}"))?;
    let sysroot = PathBuf::from(String::from_utf8_lossy(&sysroot.stdout).trim());
    if sysroot.join("lib/rustlib").join(target).is_dir() {
        return Ok(());
    }
    Err(format!(
        "the Rust target {target} is not installed for {}: run `cargo xtask deps` \
         (it runs `rustup target add {target}`)",
        sysroot.display()
    ))
}

/// Whether this process runs as root.
pub fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
        .unwrap_or(false)
}

/// A test program's last line, `"12 passed, 0 failed"` → `(12, 0)`.
pub fn parse_summary(line: &str) -> Option<(u64, u64)> {
    let (p, f) = line.trim().split_once(", ")?;
    let passed = p.strip_suffix(" passed")?.parse().ok()?;
    let failed = f.strip_suffix(" failed")?.parse().ok()?;
    Some((passed, failed))
}

#[cfg(test)]
mod tests {
    use super::parse_summary;

    #[test]
    fn summary_lines() {
        assert_eq!(parse_summary("191 passed, 0 failed"), Some((191, 0)));
        assert_eq!(parse_summary("3 passed, 2 failed\n"), Some((3, 2)));
        assert_eq!(parse_summary("ok   something"), None);
        assert_eq!(parse_summary("Blender quit"), None);
    }
}
