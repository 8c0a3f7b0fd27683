//! `cargo xtask ctest [--no-valgrind] [NAME…]`: the C and C++ link tests.
//!
//! Builds the cdylib (`cargo build -p katachi --lib`), compiles every `tests/c/*.c` with
//! `gcc -std=c99 -Wall -Wextra -Werror -pedantic` and every `tests/c/*.cpp` with
//! `g++ -std=c++17 -Wall -Wextra -Werror` against `include/katachi.h`, links each to
//! `libkatachi.so` and libm (with an rpath, so no `LD_LIBRARY_PATH` is needed; `mesh_api` is also
//! linked to `libkatachi.a` as `mesh_api_static`), and runs each under
//! `valgrind --error-exitcode=1 --leak-check=full --errors-for-leak-kinds=definite,possible`.
//! Fails if a tool is missing (naming the Debian package), a program does not compile, exits
//! non-zero, or does not end with its `N passed, 0 failed` line.
//!
//! The library is looked for in `$CARGO_TARGET_DIR/debug` (default `<root>/target/debug`); the
//! programs go to `<that target dir>/ctest/`. `NAME…` runs only the programs with those stems
//! (`mesh_api`, `cpp_api`…); `--no-valgrind` runs them directly (quicker, for debugging).

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::util::{describe, have, parse_summary, root, run as run_cmd};

const USAGE: &str = "usage: cargo xtask ctest [--no-valgrind] [NAME…]";

/// The tools the C tests need, with the Debian package that provides each.
const TOOLS: [(&str, &str); 3] = [("gcc", "gcc"), ("g++", "g++"), ("valgrind", "valgrind")];

pub(crate) const C_FLAGS: [&str; 5] = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"];
const CXX_FLAGS: [&str; 5] = ["-std=c++17", "-Wall", "-Wextra", "-Werror", "-pthread"];
const VALGRIND_FLAGS: [&str; 4] = [
    "--error-exitcode=1",
    "--leak-check=full",
    "--errors-for-leak-kinds=definite,possible",
    "--quiet",
];

/// One test program: its source, what compiles it, and how it links katachi.
pub(crate) struct Program {
    pub name: String,
    pub source: PathBuf,
    pub cpp: bool,
    /// Link `libkatachi.a` instead of `libkatachi.so`.
    pub static_lib: bool,
}

/// The program also linked to the static library, to prove `libkatachi.a` links with only
/// the usual system libraries.
const STATIC_TOO: &str = "mesh_api";
/// What a Rust static library needs from the system (`rustc --print native-static-libs`).
const STATIC_SYSTEM_LIBS: [&str; 4] = ["-lgcc_s", "-lpthread", "-lm", "-ldl"];

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut valgrind = true;
    let mut only: Vec<&str> = Vec::new();
    for &a in args {
        match a {
            "--no-valgrind" => valgrind = false,
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return Ok(());
            }
            s if s.starts_with('-') => return Err(format!("unknown option `{s}`\n{USAGE}")),
            s => only.push(s),
        }
    }

    check_tools(valgrind)?;
    let programs = find_programs(&only)?;

    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| OsString::from("cargo"));
    run_cmd(Command::new(cargo).args(["build", "-p", "katachi", "--lib"]))?;
    let lib_dir = target_dir().join("debug");
    for lib in ["libkatachi.so", "libkatachi.a"] {
        let lib = lib_dir.join(lib);
        if !lib.is_file() {
            return Err(format!(
                "{} is missing after `cargo build -p katachi --lib`",
                lib.display()
            ));
        }
    }
    let out_dir = target_dir().join("ctest");
    std::fs::create_dir_all(&out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;

    let mut failures = Vec::new();
    let mut checks = 0u64;
    for p in &programs {
        let exe = out_dir.join(&p.name);
        compile(p, &exe, &lib_dir)?;
        match run_program(p, &exe, valgrind) {
            Ok(n) => checks += n,
            Err(e) => {
                eprintln!("xtask: ctest: {e}");
                failures.push(p.name.clone());
            }
        }
    }
    let how = if valgrind {
        "under valgrind"
    } else {
        "without valgrind"
    };
    if failures.is_empty() {
        eprintln!(
            "xtask: ctest: all {} programs ({checks} checks) passed {how}",
            programs.len()
        );
        Ok(())
    } else {
        Err(format!(
            "ctest: {} of {} programs failed {how}: {}",
            failures.len(),
            programs.len(),
            failures.join(", ")
        ))
    }
}

/// `$CARGO_TARGET_DIR` (relative to the workspace root when relative), else `<root>/target`.
pub fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(d) if !d.is_empty() => root().join(d),
        _ => root().join("target"),
    }
}

fn check_tools(valgrind: bool) -> Result<(), String> {
    let missing: Vec<(&str, &str)> = TOOLS
        .iter()
        .copied()
        .filter(|(tool, _)| (valgrind || *tool != "valgrind") && !have(tool))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let tools: Vec<&str> = missing.iter().map(|(t, _)| *t).collect();
    let packages: Vec<&str> = missing.iter().map(|(_, p)| *p).collect();
    Err(format!(
        "the C/C++ link tests need {} on the PATH, and {} missing.\n  \
         Install the Debian package(s): `apt-get install {}` (as root), or run `cargo xtask deps`.",
        TOOLS.map(|(t, _)| t).join(", "),
        if tools.len() == 1 {
            format!("`{}` is", tools[0])
        } else {
            format!("`{}` are", tools.join("`, `"))
        },
        packages.join(" ")
    ))
}

/// The programs in `tests/c`, sorted, filtered by `only` (stems) when it is not empty.
pub(crate) fn find_programs(only: &[&str]) -> Result<Vec<Program>, String> {
    let dir = root().join("tests").join("c");
    let entries = std::fs::read_dir(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut programs = Vec::new();
    for entry in entries {
        let path = entry.map_err(|e| format!("{}: {e}", dir.display()))?.path();
        let cpp = match path.extension().and_then(|e| e.to_str()) {
            Some("c") => false,
            Some("cpp") => true,
            _ => continue,
        };
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .ok_or_else(|| format!("{}: not a UTF-8 file name", path.display()))?
            .to_owned();
        if name == STATIC_TOO {
            programs.push(Program {
                name: format!("{name}_static"),
                source: path.clone(),
                cpp,
                static_lib: true,
            });
        }
        programs.push(Program {
            name,
            source: path,
            cpp,
            static_lib: false,
        });
    }
    programs.sort_by(|a, b| a.name.cmp(&b.name));
    if programs.is_empty() {
        return Err(format!("no .c or .cpp programs in {}", dir.display()));
    }
    if !only.is_empty() {
        for want in only {
            if !programs.iter().any(|p| p.name == *want) {
                let names: Vec<&str> = programs.iter().map(|p| p.name.as_str()).collect();
                return Err(format!(
                    "no test program `{want}` in tests/c (there are: {})",
                    names.join(", ")
                ));
            }
        }
        programs.retain(|p| only.contains(&p.name.as_str()));
    }
    Ok(programs)
}

fn compile(p: &Program, exe: &Path, lib_dir: &Path) -> Result<(), String> {
    let (compiler, flags) = if p.cpp {
        ("g++", CXX_FLAGS)
    } else {
        ("gcc", C_FLAGS)
    };
    let mut cmd = Command::new(compiler);
    cmd.args(flags)
        .arg("-g")
        .arg("-I")
        .arg(root().join("include"))
        .arg(&p.source)
        .arg("-o")
        .arg(exe);
    if p.static_lib {
        cmd.arg(lib_dir.join("libkatachi.a"))
            .args(STATIC_SYSTEM_LIBS);
    } else {
        cmd.arg("-L")
            .arg(lib_dir)
            .arg("-lkatachi")
            .arg(format!("-Wl,-rpath,{}", lib_dir.display()))
            // The tests' own math (sqrt, hypot, cos): libm is not implied in C.
            .arg("-lm");
    }
    run_cmd(&mut cmd).map_err(|e| format!("compiling {}: {e}", p.source.display()))
}

/// Runs one program; returns its number of passed checks.
fn run_program(p: &Program, exe: &Path, valgrind: bool) -> Result<u64, String> {
    let mut cmd = if valgrind {
        let mut c = Command::new("valgrind");
        let supp = root().join("tests/c/valgrind.supp");
        c.args(VALGRIND_FLAGS)
            .arg(format!("--suppressions={}", supp.display()))
            .arg(exe);
        c
    } else {
        Command::new(exe)
    };
    cmd.current_dir(root());
    eprintln!("xtask: $ {}", describe(&cmd));
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(&cmd)))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    print!("{stdout}");
    eprint!("{stderr}");
    if !out.status.success() {
        let why = if valgrind && stderr.contains("==") {
            " (see valgrind's report above)"
        } else {
            ""
        };
        return Err(format!("{} failed: {}{why}", p.name, out.status));
    }
    // The closing line proves the program ran to its end.
    let last = stdout.lines().last().unwrap_or("");
    match parse_summary(last) {
        Some((passed, 0)) if passed > 0 => Ok(passed),
        _ => Err(format!(
            "{} exited 0 but did not end with `N passed, 0 failed` (last line: {last:?})",
            p.name
        )),
    }
}
