//! `cargo xtask <task>`: the project's automation. See `cargo xtask help`.

mod addon;
mod bench;
mod bench_table;
mod blender;
mod blender_bench;
mod ctest;
mod deps;
mod header;
mod install;
mod macos;
mod meshlab;
mod meshlab_bench;
mod test;
mod util;
mod windows;

use std::process::ExitCode;

const HELP: &str = "\
cargo xtask <task>

tasks:
  deps            install the Debian packages the tests need (root, Debian/Ubuntu; idempotent)
  test            run every test: fmt, clippy, cargo test, header check, C/C++ tests under valgrind
  bench           run the benchmarks (criterion)
  header          regenerate include/katachi.h with the pinned cbindgen
  header --check  fail if include/katachi.h is stale
  ctest           build and run the C/C++ link tests under valgrind
  install         install the C library: --prefix P [--libdir DIR] [--includedir DIR] (DESTDIR honoured)
  install-test    install into a temporary prefix; build C/C++ programs with pkg-config, run under valgrind
  addon           build the Blender add-on zip (target/addon/katachi-<version>.zip)
  blender-test    test the add-on headless in Blender 3.4 and bpy 5.0 [--only 3.4|5.0] [-k NAME]
  blender-bench   time the add-on's operators against Blender's own tools and the floor, in
                  Blender 3.4 and bpy 5.0 [--rounds N] [--only 3.4|5.0] [-k CASE] [--no-modal]
  blender-screenshot  render the add-on's redo panel under Xvfb into docs/images/
  meshlab-bench   time the MeshLab filters against MeshLab's own (2020.09) [--rounds N]
  windows [--release]  cross-build katachi.dll, its import library and katachi.exe for Windows
                  (target/windows/<profile>/katachi-<version>-windows-x64/)
  windows-test    build for Windows and run the C/C++ link tests, the installed-files check and
                  the CLI's tests under Wine [--no-cli] [NAME…]
  macos-check     the library and CLI type-check for macOS under clippy -D warnings (no SDK to link)
  meshlab-plugin  build the MeshLab plugin for 2020.09 and 2025.07 [--only 2020.09|2025.07];
                  --test: test it in meshlabserver 2020.09 and pymeshlab 2025.7 [-k NAME]
";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rest: Vec<&str> = args.iter().skip(1).map(String::as_str).collect();
    let result = match args.first().map(String::as_str) {
        Some("deps") => deps::run(&rest),
        Some("test") => test::run(&rest),
        Some("bench") => bench::run(&rest),
        Some("header") => header::run(&rest),
        Some("ctest") => ctest::run(&rest),
        Some("install") => install::run(&rest),
        Some("install-test") => install::test(&rest),
        Some("meshlab-plugin") => meshlab::run(&rest),
        Some("meshlab-bench") => meshlab_bench::run(&rest),
        Some("addon") => addon::run(&rest),
        Some("windows") => windows::run(&rest),
        Some("windows-test") => windows::test(&rest),
        Some("macos-check") => macos::check(&rest),
        Some("blender-test") => blender::run(&rest),
        Some("blender-bench") => blender_bench::run(&rest),
        Some("blender-screenshot") => blender::screenshot(&rest),
        Some("help") | Some("--help") | Some("-h") | None => {
            print!("{HELP}");
            Ok(())
        }
        Some(other) => Err(format!("unknown task `{other}`\n\n{HELP}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: error: {e}");
            ExitCode::FAILURE
        }
    }
}
