//! `cargo xtask windows` and `cargo xtask windows-test`: katachi for Windows, cross-built with
//! MinGW-w64 on Debian and tested under Wine.
//!
//! `windows [--release]` builds `katachi.dll` (with its import library `libkatachi.dll.a` and
//! the static `libkatachi.a`) and the command-line tool `katachi.exe` for
//! `x86_64-pc-windows-gnu`, and lays them out with the header as the folder a Windows user
//! unpacks: `<target>/windows/<profile>/katachi-<version>-windows-x64/` holding
//! `bin/katachi.dll`, `bin/katachi.exe`, `lib/libkatachi.dll.a`, `lib/libkatachi.a` and
//! `include/katachi.h` (the same header as on Linux). Nothing else is needed beside them: the
//! DLL and the EXE import only Windows' own DLLs (checked).
//!
//! `windows-test [--no-cli] [NAME…]` builds that folder (debug) and, under Wine 8 in a prefix
//! of its own (`<target>/wine`, `WINEDEBUG=-all`, no display needed):
//! 0. runs clippy (`-D warnings`) on the library and the CLI for Windows;
//! 1. checks that `katachi.dll` exports every function `katachi.h` declares and no other
//!    `katachi_` name, and that the DLL and the EXE import only Windows' own DLLs;
//! 2. compiles every C/C++ link test (`tests/c/*.c`, `*.cpp`, as `cargo xtask ctest` does)
//!    with MinGW-w64 gcc/g++ (`-Werror`), links it to the import library (`mesh_api` also to
//!    the static library), and runs it; each must end with `N passed, 0 failed`;
//! 3. the installed files: builds `tests/c/installed/installed_api.cpp` with nothing but the
//!    package's `include/` and `lib/`, runs it with the package's `bin/` on Wine's PATH (not
//!    beside the program) on the bundled `fandisk_quads.off`, named with `\` separators;
//! 4. the CLI's tests (`cli/tests/*.rs`) cross-compiled and run under Wine
//!    (`CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER`), so the `katachi.exe` they spawn is the
//!    Windows one; its reader fuzzing runs 20 files per format there (`KATACHI_FUZZ_CASES`,
//!    default 200 here, sets it). `--no-cli` skips this part.
//!
//! `NAME…` runs only those C programs (and neither part 3 nor 4). Missing MinGW-w64, Wine or
//! the Rust target is an error naming what to install (`cargo xtask deps` installs all three),
//! never a silent pass.
//!
//! Wine 8.0 (Debian 12) lacks `bcryptprimitives.dll`, whose `ProcessPrng` Rust's standard
//! library calls on Windows 10 and later; the prefix gets a stand-in built from
//! `tests/windows/wine/bcryptprimitives.c` (see there). It is a test fixture, never shipped.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::ctest::{find_programs, target_dir, Program, C_FLAGS};
use crate::util::{describe, have, parse_summary, root, run as run_cmd};

/// The Rust target of the Windows build (MinGW-w64's ABI: links with Debian's mingw-w64 gcc).
pub const TARGET: &str = "x86_64-pc-windows-gnu";

const USAGE: &str = "usage: cargo xtask windows [--release]\n       \
                     cargo xtask windows-test [--no-cli] [NAME…]";

const CC: &str = "x86_64-w64-mingw32-gcc";
/// The POSIX-threads build of g++: `std::thread` (tests/c/cpp_api.cpp) needs it.
const CXX: &str = "x86_64-w64-mingw32-g++-posix";
const OBJDUMP: &str = "x86_64-w64-mingw32-objdump";
/// Wine's 64-bit loader (Debian package wine64); `wine` (package wine) starts it.
const WINE64: &str = "/usr/lib/wine/wine64";

/// What a program linking `libkatachi.a` needs from Windows (`rustc --print native-static-libs`).
const STATIC_SYSTEM_LIBS: [&str; 5] = [
    "-lkernel32",
    "-lntdll",
    "-luserenv",
    "-lws2_32",
    "-ldbghelp",
];
/// The C++ programs link libstdc++ and winpthread statically: a test program then needs only
/// katachi.dll and Windows' own DLLs, as a user's program would.
const CXX_FLAGS: [&str; 6] = [
    "-std=c++17",
    "-Wall",
    "-Wextra",
    "-Werror",
    "-pthread",
    "-static",
];

/// DLLs every Windows 10 and 11 has: all katachi.dll and katachi.exe may import.
/// (`bcryptprimitives.dll` is one; Wine 8.0 lacks it, see the module docs.)
const SYSTEM_DLLS: [&str; 10] = [
    "kernel32.dll",
    "ntdll.dll",
    "msvcrt.dll",
    "userenv.dll",
    "ws2_32.dll",
    "bcryptprimitives.dll",
    "advapi32.dll",
    "api-ms-win-core-synch-l1-2-0.dll",
    "dbghelp.dll",
    "shell32.dll",
];

/// The Windows package: where its files are.
pub struct Package {
    pub dir: PathBuf,
    pub version: String,
}

impl Package {
    fn bin(&self) -> PathBuf {
        self.dir.join("bin")
    }
    fn lib(&self) -> PathBuf {
        self.dir.join("lib")
    }
    fn include(&self) -> PathBuf {
        self.dir.join("include")
    }
}

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut release = false;
    for &a in args {
        match a {
            "--release" => release = true,
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    check_build_tools()?;
    let package = build(release)?;
    eprintln!("xtask: windows: {}", package.dir.display());
    Ok(())
}

pub fn test(args: &[&str]) -> Result<(), String> {
    let mut cli = true;
    let mut only = Vec::new();
    for &a in args {
        match a {
            "--no-cli" => cli = false,
            "-h" | "--help" => {
                eprintln!("{USAGE}");
                return Ok(());
            }
            s if s.starts_with('-') => return Err(format!("unknown option `{s}`\n{USAGE}")),
            s => only.push(s),
        }
    }
    check_build_tools()?;
    check_wine()?;
    let programs = find_programs(&only)?;
    // What only Windows compiles (`cfg(windows)`, no `cfg(unix)`) gets clippy's checks too.
    run_cmd(Command::new(crate::util::cargo()).args([
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
    ]))?;
    let package = build(false)?;
    let wine = Wine::prepare()?;
    let result = test_in(&package, &wine, &programs, only.is_empty(), cli);
    wine.stop();
    result
}

fn test_in(
    package: &Package,
    wine: &Wine,
    programs: &[Program],
    all: bool,
    cli: bool,
) -> Result<(), String> {
    check_exports(package)?;
    for file in [
        package.bin().join("katachi.dll"),
        package.bin().join("katachi.exe"),
    ] {
        check_imports(&file)?;
    }

    let out_dir = target_dir().join("windows").join("ctest");
    std::fs::create_dir_all(&out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;
    // Beside the programs: Windows' loader looks in the program's folder first.
    copy(
        &package.bin().join("katachi.dll"),
        &out_dir.join("katachi.dll"),
    )?;
    let mut failures = Vec::new();
    let mut checks = 0u64;
    for p in programs {
        let exe = out_dir.join(format!("{}.exe", p.name));
        compile(p, &exe, package)?;
        // The import library really was linked (katachi.dll loaded at start), or not at all.
        let loads_dll = objdump(&exe)?
            .lines()
            .any(|l| l.trim().eq_ignore_ascii_case("DLL Name: katachi.dll"));
        if loads_dll == p.static_lib {
            return Err(format!(
                "{}: linked to {}, but it {} katachi.dll",
                exe.display(),
                if p.static_lib {
                    "libkatachi.a"
                } else {
                    "the import library"
                },
                if loads_dll {
                    "imports"
                } else {
                    "does not import"
                }
            ));
        }
        match wine.run_program(&p.name, Command::new(&exe), &[]) {
            Ok(n) => checks += n,
            Err(e) => {
                eprintln!("xtask: windows-test: {e}");
                failures.push(p.name.clone());
            }
        }
    }
    if !failures.is_empty() {
        return Err(format!(
            "windows-test: {} of {} C/C++ programs failed under Wine: {}",
            failures.len(),
            programs.len(),
            failures.join(", ")
        ));
    }
    eprintln!(
        "xtask: windows-test: all {} C/C++ programs ({checks} checks) passed under Wine",
        programs.len()
    );
    if all {
        installed_files(package, wine)?;
        if cli {
            cli_tests(wine)?;
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------
// Tools

fn check_build_tools() -> Result<(), String> {
    let missing: Vec<&str> = [CC, CXX, OBJDUMP]
        .into_iter()
        .filter(|t| !have(t))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "the Windows build needs MinGW-w64 ({} missing): install the Debian packages \
             gcc-mingw-w64-x86-64 g++-mingw-w64-x86-64 with `cargo xtask deps`",
            missing.join(", ")
        ));
    }
    crate::util::require_rust_target(TARGET)
}

fn check_wine() -> Result<(), String> {
    if have("wine") && Path::new(WINE64).is_file() {
        return Ok(());
    }
    Err(format!(
        "the Windows tests run under Wine, and {} missing: install the Debian packages \
         wine wine64 with `cargo xtask deps`",
        if have("wine") {
            format!("{WINE64} (package wine64) is")
        } else {
            "`wine` is".to_string()
        }
    ))
}

// ---------------------------------------------------------------------------------------
// The build

/// Cross-builds the DLL, the static library and the CLI, and lays out the package.
fn build(release: bool) -> Result<Package, String> {
    let profile = if release { "release" } else { "debug" };
    // Two builds: `--lib` applies to every package named in one command, so together they
    // would build the CLI crate's library only and never katachi.exe.
    let builds: [&[&str]; 2] = [
        &["-p", "katachi", "--lib"],
        &["-p", "katachi-cli", "--bin", "katachi"],
    ];
    for what in builds {
        let mut cmd = Command::new(crate::util::cargo());
        cmd.args(["build", "--target", TARGET]).args(what);
        if release {
            cmd.arg("--release");
        }
        run_cmd(&mut cmd)?;
    }
    let built = target_dir().join(TARGET).join(profile);
    let version = crate::install::version()?;
    let dir = target_dir()
        .join("windows")
        .join(profile)
        .join(format!("katachi-{version}-windows-x64"));
    let package = Package { dir, version };
    let _ = std::fs::remove_dir_all(&package.dir);
    for (from, to) in [
        (built.join("katachi.dll"), package.bin().join("katachi.dll")),
        (built.join("katachi.exe"), package.bin().join("katachi.exe")),
        (
            built.join("libkatachi.dll.a"),
            package.lib().join("libkatachi.dll.a"),
        ),
        (
            built.join("libkatachi.a"),
            package.lib().join("libkatachi.a"),
        ),
        (
            root().join("include/katachi.h"),
            package.include().join("katachi.h"),
        ),
    ] {
        copy(&from, &to)?;
    }
    Ok(package)
}

fn copy(from: &Path, to: &Path) -> Result<(), String> {
    if let Some(dir) = to.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::copy(from, to)
        .map(|_| ())
        .map_err(|e| format!("copying {} to {}: {e}", from.display(), to.display()))
}

/// `objdump -p` of a Windows file.
fn objdump(file: &Path) -> Result<String, String> {
    let out = Command::new(OBJDUMP)
        .arg("-p")
        .arg(file)
        .output()
        .map_err(|e| format!("cannot run {OBJDUMP}: {e}"))?;
    if !out.status.success() {
        return Err(format!("{OBJDUMP} -p {} failed", file.display()));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The functions `katachi.h` declares (`… katachi_name(` at column 0, outside comments).
fn declared_functions(header: &str) -> Vec<String> {
    let mut names: Vec<String> = header
        .lines()
        .filter(|l| !l.starts_with([' ', '\t', '#', '/', '*']))
        .filter_map(|l| {
            let before = &l[..l.find('(')?];
            let name = &before[before.rfind(['*', ' '])? + 1..];
            name.starts_with("katachi_").then(|| name.to_string())
        })
        .collect();
    names.sort();
    names.dedup();
    names
}

/// The `katachi_` names in a DLL's export table (`objdump -p`).
fn exported_functions(objdump: &str) -> Vec<String> {
    let mut names: Vec<String> = objdump
        .lines()
        .skip_while(|l| !l.contains("[Ordinal/Name Pointer] Table"))
        .filter_map(|l| {
            let name = l.trim().rsplit(' ').next()?;
            name.starts_with("katachi_").then(|| name.to_string())
        })
        .collect();
    names.sort();
    names.dedup();
    names
}

/// katachi.dll exports exactly the header's functions.
fn check_exports(package: &Package) -> Result<(), String> {
    let header = std::fs::read_to_string(package.include().join("katachi.h"))
        .map_err(|e| format!("the package's katachi.h: {e}"))?;
    let declared = declared_functions(&header);
    if declared.is_empty() {
        return Err("no katachi_ function found in katachi.h".into());
    }
    let dll = package.bin().join("katachi.dll");
    let exported = exported_functions(&objdump(&dll)?);
    let missing: Vec<&String> = declared.iter().filter(|d| !exported.contains(d)).collect();
    let extra: Vec<&String> = exported.iter().filter(|e| !declared.contains(e)).collect();
    if !missing.is_empty() || !extra.is_empty() {
        return Err(format!(
            "{}: exports do not match katachi.h: declared, not exported: {missing:?}; \
             exported, not declared: {extra:?}",
            dll.display()
        ));
    }
    eprintln!(
        "xtask: windows-test: katachi.dll exports the {} functions katachi.h declares",
        declared.len()
    );
    Ok(())
}

/// A Windows file imports only DLLs every Windows has (no MinGW runtime DLL to ship).
fn check_imports(file: &Path) -> Result<(), String> {
    let text = objdump(file)?;
    let foreign: Vec<String> = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("DLL Name: "))
        .map(str::to_ascii_lowercase)
        .filter(|d| !SYSTEM_DLLS.contains(&d.as_str()))
        .collect();
    if foreign.is_empty() {
        return Ok(());
    }
    Err(format!(
        "{} imports DLLs that are not Windows' own (a user would lack them): {}",
        file.display(),
        foreign.join(", ")
    ))
}

fn compile(p: &Program, exe: &Path, package: &Package) -> Result<(), String> {
    let mut cmd = if p.cpp {
        let mut c = Command::new(CXX);
        c.args(CXX_FLAGS);
        c
    } else {
        let mut c = Command::new(CC);
        c.args(C_FLAGS);
        c
    };
    cmd.arg("-g")
        .arg("-I")
        .arg(package.include())
        .arg(&p.source)
        .arg("-o")
        .arg(exe);
    if p.static_lib {
        cmd.arg(package.lib().join("libkatachi.a"))
            .args(STATIC_SYSTEM_LIBS);
    } else {
        cmd.arg("-L").arg(package.lib()).arg(import_library(p.cpp));
    }
    run_cmd(&mut cmd).map_err(|e| format!("compiling {} for Windows: {e}", p.source.display()))
}

/// How a program links katachi.dll: `-lkatachi` finds the import library `libkatachi.dll.a`
/// before `libkatachi.a`, except under `-static` (the C++ programs'), which needs it by name.
fn import_library(cpp: bool) -> &'static str {
    if cpp {
        "-l:libkatachi.dll.a"
    } else {
        "-lkatachi"
    }
}

// ---------------------------------------------------------------------------------------
// Wine

/// Wine in a prefix of the project's own.
struct Wine {
    prefix: PathBuf,
}

impl Wine {
    /// Makes the prefix when it is missing and puts the `bcryptprimitives.dll` stand-in in.
    fn prepare() -> Result<Wine, String> {
        let wine = Wine {
            prefix: target_dir().join("wine"),
        };
        if !wine.prefix.join("system.reg").is_file() {
            eprintln!(
                "xtask: windows-test: making the Wine prefix {}",
                wine.prefix.display()
            );
            run_cmd(wine.command("wine").args(["wineboot", "--init"]))?;
            run_cmd(wine.command("wineserver").arg("--wait"))?;
        }
        let system32 = wine.prefix.join("drive_c/windows/system32");
        if !system32.is_dir() {
            return Err(format!(
                "{} is missing after `wineboot --init`: remove {} and retry",
                system32.display(),
                wine.prefix.display()
            ));
        }
        run_cmd(
            Command::new(CC)
                .args(["-O2", "-Wall", "-Wextra", "-Werror", "-shared", "-o"])
                .arg(system32.join("bcryptprimitives.dll"))
                .arg(root().join("tests/windows/wine/bcryptprimitives.c"))
                .arg("-ladvapi32"),
        )?;
        Ok(wine)
    }

    /// `program` (wine, wineserver) in this prefix.
    fn command(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        self.env(&mut c);
        c
    }

    /// This prefix, quiet, without a display (console programs need none).
    fn env(&self, c: &mut Command) {
        c.env("WINEPREFIX", &self.prefix)
            .env("WINEARCH", "win64")
            .env("WINEDEBUG", "-all")
            // No Mono/Gecko install dialogs when the prefix is made.
            .env("WINEDLLOVERRIDES", "mscoree,mshtml=")
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY");
    }

    /// Runs a Windows test program under Wine, with `env` added; returns its number of
    /// passed checks.
    fn run_program(
        &self,
        name: &str,
        program: Command,
        env: &[(&str, String)],
    ) -> Result<u64, String> {
        let mut cmd = self.command("wine");
        cmd.arg(program.get_program()).args(program.get_args());
        for (k, v) in env {
            cmd.env(k, v);
        }
        cmd.current_dir(root());
        eprintln!("xtask: $ {}", describe(&cmd));
        let out = cmd
            .output()
            .map_err(|e| format!("cannot start `{}`: {e}", describe(&cmd)))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        print!("{stdout}");
        eprint!("{}", String::from_utf8_lossy(&out.stderr));
        if !out.status.success() {
            return Err(format!("{name} failed under Wine: {}", out.status));
        }
        let last = stdout.lines().last().unwrap_or("").trim_end_matches('\r');
        match parse_summary(last) {
            Some((passed, 0)) if passed > 0 => Ok(passed),
            _ => Err(format!(
                "{name} exited 0 under Wine but did not end with `N passed, 0 failed` \
                 (last line: {last:?})"
            )),
        }
    }

    /// Stops this prefix's wineserver (it lingers a few seconds after the last program).
    fn stop(&self) {
        let _ = self.command("wineserver").arg("-k").status();
    }
}

/// `Z:\…`: a Linux path as Wine's programs see it (drive Z: is `/`).
fn windows_path(path: &Path) -> String {
    format!("Z:{}", path.display()).replace('/', "\\")
}

// ---------------------------------------------------------------------------------------
// The installed files and the CLI

/// A C++ program built against nothing but the package's `include/` and `lib/`, run with the
/// package's `bin/` on Wine's PATH.
fn installed_files(package: &Package, wine: &Wine) -> Result<(), String> {
    let dir = target_dir().join("windows").join("installed");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let exe = dir.join("installed_api.exe");
    run_cmd(
        Command::new(CXX)
            .args(CXX_FLAGS)
            .arg(format!(
                "-DKATACHI_EXPECTED_VERSION=\"{}\"",
                package.version
            ))
            .arg("-I")
            .arg(package.include())
            .arg(root().join("tests/c/installed/installed_api.cpp"))
            .arg("-o")
            .arg(&exe)
            .arg("-L")
            .arg(package.lib())
            .arg(import_library(true)),
    )?;
    let mut program = Command::new(&exe);
    // `\` separators all the way, as a Windows user types a path.
    program.arg(windows_path(
        &root().join("examples/models/fandisk_quads.off"),
    ));
    let n = wine.run_program(
        "installed_api",
        program,
        &[("WINEPATH", windows_path(&package.bin()))],
    )?;
    eprintln!(
        "xtask: windows-test: a C++ program built against the package's files alone passed ({n} checks)"
    );
    Ok(())
}

/// The CLI's tests, cross-compiled, run under Wine.
fn cli_tests(wine: &Wine) -> Result<(), String> {
    let mut cmd = Command::new(crate::util::cargo());
    cmd.args(["test", "--target", TARGET, "-p", "katachi-cli"]);
    wine.env(&mut cmd);
    let runner = format!(
        "CARGO_TARGET_{}_RUNNER",
        TARGET.to_uppercase().replace('-', "_")
    );
    cmd.env(runner, "wine");
    if std::env::var_os("KATACHI_FUZZ_CASES").is_none() {
        cmd.env("KATACHI_FUZZ_CASES", "200");
    }
    // The summary of `cargo xtask test` counts the Linux runs only.
    cmd.env_remove("KATACHI_TEST_RECORD");
    run_cmd(&mut cmd).map_err(|e| format!("the CLI's tests under Wine: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn functions_of_the_header_and_the_export_table() {
        let header = "/* katachi_nothing( */\n#define katachi_macro(x)\n\
                      const char *katachi_version_string(\nvoid);\n\
                      KatachiStatus katachi_mesh_read(const char *path);\n\
                      uint32_t katachi_abi_version(void);\n  void katachi_not(\n";
        assert_eq!(
            declared_functions(header),
            [
                "katachi_abi_version",
                "katachi_mesh_read",
                "katachi_version_string"
            ]
        );
        let dump = "DLL Name: KERNEL32.dll\n[Ordinal/Name Pointer] Table\n\
                    \t[   0] katachi_abi_version\n\t[   1] rust_eh_personality\n\
                    \t[   2] katachi_version_string\n";
        assert_eq!(
            exported_functions(dump),
            ["katachi_abi_version", "katachi_version_string"]
        );
        assert_eq!(
            windows_path(Path::new("/work/a b/x.off")),
            "Z:\\work\\a b\\x.off"
        );
    }
}
