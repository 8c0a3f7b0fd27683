//! `cargo xtask install [--prefix P] [--libdir DIR] [--includedir DIR]`: installs katachi as
//! a C library, the way `make install` of a C project would; and `cargo xtask install-test`,
//! which proves the installed library works for a C and a C++ program built with pkg-config.
//!
//! # What lands where
//!
//! With version `MAJOR.MINOR.PATCH` (from `Cargo.toml`) and the defaults `--prefix /usr/local`,
//! `--libdir lib`, `--includedir include` (relative ones are taken under the prefix):
//!
//! ```text
//! P/lib/libkatachi.so.MAJOR.MINOR.PATCH   the shared library (SONAME libkatachi.so.<S>, below)
//! P/lib/libkatachi.so.<S>                 symlink → libkatachi.so.MAJOR.MINOR.PATCH (what the loader finds)
//! P/lib/libkatachi.so                     symlink → libkatachi.so.<S> (what `-lkatachi` finds)
//! P/lib/libkatachi.a                      the static library
//! P/lib/pkgconfig/katachi.pc              Cflags -I${includedir}/katachi, Libs -L${libdir} -lkatachi,
//!                                         Libs.private: rustc's native-static-libs
//! P/include/katachi/katachi.h             the header (so `#include <katachi.h>` with the Cflags)
//! ```
//!
//! `DESTDIR`, as packagers expect: when set, every file goes under `$DESTDIR/P/…` while the
//! `.pc` file and the library still say `P`.
//!
//! # The soname rule
//!
//! The soname changes exactly when Cargo's semver rules call a release incompatible:
//! `<S>` is `MAJOR` from 1.0 on, `0.MINOR` for `0.MINOR.x` (MINOR ≥ 1), and `0.0.PATCH` for
//! `0.0.x`. So 0.1.0 installs `libkatachi.so.0.1.0` with SONAME `libkatachi.so.0.1`, and 0.1.3
//! replaces it in place, while 0.2.0 installs beside it. The project bumps the version that way
//! whenever `KATACHI_ABI_VERSION` grows. Only `MAJOR.MINOR.PATCH` count: pre-release and build
//! tags are not part of file names.
//!
//! # How the soname gets there, and why not a `build.rs`
//!
//! The library is built with `cargo rustc -p katachi --lib --release -- -C
//! link-arg=-Wl,-soname,libkatachi.so.<S> --print native-static-libs`: one build gives the
//! SONAME'd `libkatachi.so`, `libkatachi.a` and the system libraries a static link needs (for
//! `Libs.private`). The SONAME is then read back with `readelf -d` and must be the rule's.
//! A `build.rs` emitting the soname for every build would also put it on
//! `target/{debug,release}/libkatachi.so`, and every program linked to those (the C tests of
//! `cargo xtask ctest`, the MeshLab plugin, which copies the file as `libkatachi.so`) would then
//! ask the loader for `libkatachi.so.<S>`, a file that exists only in an installed prefix.
//! The install build has a target directory of its own, `<target dir>/install-build`: the
//! extra rustc arguments are part of cargo's fingerprint, so sharing `target/release` would
//! recompile katachi whenever an install and a plain `cargo build --release` alternate, and
//! would leave a SONAME'd `target/release/libkatachi.so` for the next program linked to it.
//! The first install builds the dependencies once more (about a minute on 2 cores).
//!
//! Linux only (ELF shared libraries); cargo-c does the same job on every platform, but
//! katachi's needs are these few files, so a task of our own is simpler than a new tool.
//!
//! # install-test
//!
//! `cargo xtask install-test [--no-valgrind]` installs three times under
//! `<target dir>/install-test` (fresh each time): into `prefix/`, into `destdir/` as
//! `DESTDIR` with the prefix `/opt/katachi-test` and the multiarch libdir
//! `lib/x86_64-linux-gnu`, and again over `prefix/` (files and symlinks are replaced, not
//! refused). The checks are not here: `tests/c/installed/run_tests.py` checks both installs'
//! files, symlinks, SONAME and .pc file and pkg-config's answers, and builds and runs (under
//! valgrind) the example and the C++ programs of `tests/c/installed` against the prefix, with
//! nothing but pkg-config's flags, reading their output meshes through the installed
//! library. It ends with `N passed, M failed`. Missing tools are named with their Debian
//! packages.

use std::io::{BufRead, BufReader};
use std::os::unix::fs::{symlink, PermissionsExt};
use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};

use crate::ctest::target_dir;
use crate::util::{self, describe, have, root};

const INSTALL_USAGE: &str =
    "usage: cargo xtask install [--prefix P] [--libdir DIR] [--includedir DIR]   (honours DESTDIR)";
const TEST_USAGE: &str = "usage: cargo xtask install-test [--no-valgrind]";

/// The tools install-test needs, with the Debian package that provides each.
const TEST_TOOLS: [(&str, &str); 7] = [
    ("python3", "python3"),
    ("gcc", "gcc"),
    ("g++", "g++"),
    ("pkg-config", "pkg-config"),
    ("valgrind", "valgrind"),
    ("readelf", "binutils"),
    ("ldd", "libc-bin"),
];

// ---------------------------------------------------------------------------------------------
// The version and the soname rule

/// katachi's version and description, from the root `Cargo.toml`.
struct Package {
    version: String,
    major: u64,
    minor: u64,
    patch: u64,
    description: String,
}

/// katachi's version (`MAJOR.MINOR.PATCH`), from the root `Cargo.toml`.
pub(crate) fn version() -> Result<String, String> {
    Package::read().map(|p| p.version)
}

impl Package {
    fn read() -> Result<Package, String> {
        let path = root().join("Cargo.toml");
        let text =
            std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let version = package_field(&text, "version")
            .ok_or_else(|| format!("{}: no version in [package]", path.display()))?;
        let description = package_field(&text, "description").unwrap_or_default();
        let core = version.split(['-', '+']).next().unwrap_or_default();
        let parts: Vec<Option<u64>> = core.split('.').map(|p| p.parse().ok()).collect();
        match parts[..] {
            [Some(major), Some(minor), Some(patch)] => Ok(Package {
                version,
                major,
                minor,
                patch,
                description,
            }),
            _ => Err(format!(
                "{}: version `{version}` is not MAJOR.MINOR.PATCH",
                path.display()
            )),
        }
    }

    /// `<S>` of the module docs' soname rule.
    fn soname_version(&self) -> String {
        soname_version(self.major, self.minor, self.patch)
    }

    fn soname(&self) -> String {
        format!("libkatachi.so.{}", self.soname_version())
    }

    fn real_name(&self) -> String {
        format!("libkatachi.so.{}.{}.{}", self.major, self.minor, self.patch)
    }
}

/// The soname rule: the leading version components up to and including the first non-zero
/// one (Cargo's semver compatibility), or all three for 0.0.x.
fn soname_version(major: u64, minor: u64, patch: u64) -> String {
    match (major, minor) {
        (0, 0) => format!("0.0.{patch}"),
        (0, _) => format!("0.{minor}"),
        _ => major.to_string(),
    }
}

/// `key = "value"` in the `[package]` table of a Cargo.toml (the simple form katachi's uses).
fn package_field(toml: &str, key: &str) -> Option<String> {
    let mut in_package = false;
    for line in toml.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            in_package = line == "[package]";
            continue;
        }
        if !in_package {
            continue;
        }
        if let Some((k, v)) = line.split_once('=') {
            if k.trim() == key {
                let v = v.trim();
                return v
                    .strip_prefix('"')
                    .and_then(|v| v.strip_suffix('"'))
                    .map(str::to_owned);
            }
        }
    }
    None
}

// ---------------------------------------------------------------------------------------------
// Building

/// The release build's artifacts.
struct Built {
    package: Package,
    shared: PathBuf,
    static_lib: PathBuf,
    header: PathBuf,
    /// What a program linking `libkatachi.a` also needs (rustc's native-static-libs).
    native_static_libs: Vec<String>,
}

fn build() -> Result<Built, String> {
    if !cfg!(target_os = "linux") {
        return Err("cargo xtask install supports Linux (ELF shared libraries) only".into());
    }
    if !have("readelf") {
        return Err(
            "`readelf` is missing: install the Debian package binutils (`apt-get install binutils`)"
                .into(),
        );
    }
    let package = Package::read()?;
    let header = root().join("include").join("katachi.h");
    check_header_version(&header, &package)?;

    let target = install_target_dir();
    let mut cmd = Command::new(util::cargo());
    cmd.env("CARGO_TARGET_DIR", &target)
        .args(["rustc", "-p", "katachi", "--lib", "--release", "--"])
        .arg(format!("-Clink-arg=-Wl,-soname,{}", package.soname()))
        .args(["--print", "native-static-libs"])
        .current_dir(root())
        .stderr(Stdio::piped());
    eprintln!(
        "xtask: $ CARGO_TARGET_DIR={} {}",
        target.display(),
        describe(&cmd)
    );
    let mut child = cmd
        .spawn()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(&cmd)))?;
    // Pass cargo's and rustc's messages through, keeping rustc's note on native libraries.
    let mut native = None;
    for line in BufReader::new(child.stderr.take().expect("stderr is piped")).lines() {
        let line = line.map_err(|e| format!("reading cargo's output: {e}"))?;
        eprintln!("{line}");
        if let Some((_, libs)) = line.split_once("native-static-libs:") {
            native = Some(libs.split_whitespace().map(str::to_owned).collect());
        }
    }
    let status = child
        .wait()
        .map_err(|e| format!("waiting for cargo: {e}"))?;
    if !status.success() {
        return Err(format!("`{}` failed ({status})", describe(&cmd)));
    }
    let native_static_libs = native.ok_or(
        "rustc printed no `native-static-libs:` note (needed for the .pc file's Libs.private)",
    )?;

    let out = target.join("release");
    let built = Built {
        shared: out.join("libkatachi.so"),
        static_lib: out.join("libkatachi.a"),
        header,
        native_static_libs,
        package,
    };
    for f in [&built.shared, &built.static_lib] {
        if !f.is_file() {
            return Err(format!("{} is missing after the build", f.display()));
        }
    }
    let soname = soname_of(&built.shared)?;
    if soname.as_deref() != Some(built.package.soname().as_str()) {
        return Err(format!(
            "{} has SONAME {soname:?}, expected {}",
            built.shared.display(),
            built.package.soname()
        ));
    }
    Ok(built)
}

/// Where the install build happens (see the module docs for why not `target/release`).
fn install_target_dir() -> PathBuf {
    target_dir().join("install-build")
}

/// The header's `KATACHI_VERSION_*` macros must be Cargo.toml's version (else it is stale).
fn check_header_version(header: &Path, package: &Package) -> Result<(), String> {
    let text = std::fs::read_to_string(header).map_err(|e| format!("{}: {e}", header.display()))?;
    for (name, want) in [
        ("MAJOR", package.major),
        ("MINOR", package.minor),
        ("PATCH", package.patch),
    ] {
        let define = format!("#define KATACHI_VERSION_{name} ");
        let got = text
            .lines()
            .find_map(|l| l.strip_prefix(&define))
            .and_then(|v| v.trim().parse::<u64>().ok());
        if got != Some(want) {
            return Err(format!(
                "{}: KATACHI_VERSION_{name} is {got:?}, but Cargo.toml's version is {} \
                 (run `cargo xtask header`)",
                header.display(),
                package.version
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Installing

/// Where the files go. All paths absolute, as the `.pc` file names them (without DESTDIR).
struct Layout {
    prefix: PathBuf,
    libdir: PathBuf,
    includedir: PathBuf,
    destdir: Option<PathBuf>,
}

impl Layout {
    fn new(
        prefix: &Path,
        libdir: &Path,
        includedir: &Path,
        destdir: Option<PathBuf>,
    ) -> Result<Layout, String> {
        let prefix = if prefix.is_absolute() {
            prefix.to_path_buf()
        } else {
            std::env::current_dir()
                .map_err(|e| format!("current directory: {e}"))?
                .join(prefix)
        };
        let prefix = normalize(&prefix);
        let under = |d: &Path| normalize(&prefix.join(d));
        Ok(Layout {
            libdir: under(libdir),
            includedir: under(includedir),
            prefix,
            destdir,
        })
    }

    /// Where a file of the layout is written: under DESTDIR when it is set.
    fn staged(&self, path: &Path) -> PathBuf {
        match &self.destdir {
            Some(d) => d.join(path.strip_prefix("/").unwrap_or(path)),
            None => path.to_path_buf(),
        }
    }

    fn pkgconfig_dir(&self) -> PathBuf {
        self.libdir.join("pkgconfig")
    }
}

/// Removes `.` and `..` components without touching the file system (the prefix need not exist).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            c => out.push(c),
        }
    }
    out
}

/// Installs the files of `layout`; returns the (staged) path of the .pc file.
fn install_files(built: &Built, layout: &Layout) -> Result<PathBuf, String> {
    let p = &built.package;
    let lib = layout.staged(&layout.libdir);
    let inc = layout.staged(&layout.includedir).join("katachi");
    let pcdir = layout.staged(&layout.pkgconfig_dir());
    for d in [&lib, &inc, &pcdir] {
        std::fs::create_dir_all(d).map_err(|e| format!("creating {}: {e}", d.display()))?;
    }
    let pc = pcdir.join("katachi.pc");
    copy_file(&built.shared, &lib.join(p.real_name()), 0o755)?;
    link(&p.real_name(), &lib.join(p.soname()))?;
    link(&p.soname(), &lib.join("libkatachi.so"))?;
    copy_file(&built.static_lib, &lib.join("libkatachi.a"), 0o644)?;
    copy_file(&built.header, &inc.join("katachi.h"), 0o644)?;
    write_file(&pc, &pc_file(built, layout), 0o644)?;
    Ok(pc)
}

/// The pkg-config file. Directories inside the prefix are written relative to `${prefix}`, so
/// a relocated prefix needs only its first line changed (`pkg-config --define-prefix` works).
fn pc_file(built: &Built, layout: &Layout) -> String {
    let relative = |dir: &Path, var: &str| match dir.strip_prefix(&layout.prefix) {
        Ok(rel) if rel.as_os_str().is_empty() => format!("${{{var}}}"),
        Ok(rel) => format!("${{{var}}}/{}", rel.display()),
        Err(_) => dir.display().to_string(),
    };
    let p = &built.package;
    format!(
        "# katachi {version}, installed by `cargo xtask install`.\n\
         prefix={prefix}\n\
         exec_prefix=${{prefix}}\n\
         libdir={libdir}\n\
         includedir={includedir}\n\
         \n\
         Name: katachi\n\
         Description: {description}\n\
         Version: {version}\n\
         Libs: -L${{libdir}} -lkatachi\n\
         Libs.private: {private}\n\
         Cflags: -I${{includedir}}/katachi\n",
        version = p.version,
        prefix = layout.prefix.display(),
        libdir = relative(&layout.libdir, "exec_prefix"),
        includedir = relative(&layout.includedir, "prefix"),
        description = p.description,
        private = built.native_static_libs.join(" "),
    )
}

/// Writes through a temporary file and a rename, so a program running the old library keeps
/// its mapping and nobody sees a half-written file.
fn copy_file(from: &Path, to: &Path, mode: u32) -> Result<(), String> {
    let bytes = std::fs::read(from).map_err(|e| format!("reading {}: {e}", from.display()))?;
    write_bytes(to, &bytes, mode)
}

fn write_file(to: &Path, text: &str, mode: u32) -> Result<(), String> {
    write_bytes(to, text.as_bytes(), mode)
}

fn write_bytes(to: &Path, bytes: &[u8], mode: u32) -> Result<(), String> {
    let tmp = to.with_extension("xtask-tmp");
    let err = |e: std::io::Error| format!("writing {}: {e}", to.display());
    std::fs::write(&tmp, bytes).map_err(err)?;
    std::fs::set_permissions(&tmp, std::fs::Permissions::from_mode(mode)).map_err(err)?;
    std::fs::rename(&tmp, to).map_err(err)?;
    eprintln!("xtask: installed {}", to.display());
    Ok(())
}

/// A relative symlink `at` → `target`, replacing whatever was there.
fn link(target: &str, at: &Path) -> Result<(), String> {
    if at.symlink_metadata().is_ok() {
        std::fs::remove_file(at).map_err(|e| format!("removing {}: {e}", at.display()))?;
    }
    symlink(target, at).map_err(|e| format!("linking {} → {target}: {e}", at.display()))?;
    eprintln!("xtask: installed {} -> {target}", at.display());
    Ok(())
}

pub fn run(args: &[&str]) -> Result<(), String> {
    let mut prefix = PathBuf::from("/usr/local");
    let mut libdir = PathBuf::from("lib");
    let mut includedir = PathBuf::from("include");
    let mut i = 0;
    while i < args.len() {
        let (key, inline) = match args[i].split_once('=') {
            Some((k, v)) => (k, Some(v)),
            None => (args[i], None),
        };
        if matches!(key, "-h" | "--help") {
            eprintln!("{INSTALL_USAGE}");
            return Ok(());
        }
        let slot = match key {
            "--prefix" => &mut prefix,
            "--libdir" => &mut libdir,
            "--includedir" => &mut includedir,
            _ => return Err(format!("unknown argument `{}`\n{INSTALL_USAGE}", args[i])),
        };
        let value = match inline {
            Some(v) => v,
            None => {
                i += 1;
                *args
                    .get(i)
                    .ok_or_else(|| format!("{key} needs a value\n{INSTALL_USAGE}"))?
            }
        };
        if value.is_empty() {
            return Err(format!("{key} needs a value\n{INSTALL_USAGE}"));
        }
        *slot = PathBuf::from(value);
        i += 1;
    }
    let destdir = std::env::var_os("DESTDIR")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from);
    if destdir.is_some() && !prefix.is_absolute() {
        return Err("with DESTDIR set, --prefix must be an absolute path".into());
    }
    let layout = Layout::new(&prefix, &libdir, &includedir, destdir)?;
    let built = build()?;
    let pc = install_files(&built, &layout)?;
    eprintln!(
        "xtask: installed katachi {} (SONAME {}); build against it with\n  \
         PKG_CONFIG_PATH={} cc prog.c $(pkg-config --cflags --libs katachi)",
        built.package.version,
        built.package.soname(),
        pc.parent()
            .expect("the .pc file is in a directory")
            .display()
    );
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// install-test

/// The SONAME of a shared library (`readelf -d`).
fn soname_of(file: &Path) -> Result<Option<String>, String> {
    let cmd = &mut Command::new("readelf");
    cmd.arg("-d").arg(file);
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(cmd)))?;
    if !out.status.success() {
        return Err(format!("`{}` failed ({})", describe(cmd), out.status));
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| l.contains("(SONAME)"))
        .find_map(|l| Some(l[l.find('[')? + 1..l.rfind(']')?].to_owned())))
}

fn check_test_tools(valgrind: bool) -> Result<(), String> {
    let missing: Vec<(&str, &str)> = TEST_TOOLS
        .iter()
        .copied()
        .filter(|(t, _)| (valgrind || *t != "valgrind") && !have(t))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let tools: Vec<&str> = missing.iter().map(|m| m.0).collect();
    let mut packages: Vec<&str> = missing.iter().map(|m| m.1).collect();
    packages.dedup();
    Err(format!(
        "install-test needs {} on the PATH, and {} missing.\n  \
         Install the Debian package(s): `apt-get install {}` (as root), or run `cargo xtask deps`.",
        TEST_TOOLS.map(|t| t.0).join(", "),
        tools.join(", "),
        packages.join(" ")
    ))
}

/// The staged install's prefix and libdir (a multiarch one, as Debian's packages use).
const STAGED_PREFIX: &str = "/opt/katachi-test";
const STAGED_LIBDIR: &str = "lib/x86_64-linux-gnu";

pub fn test(args: &[&str]) -> Result<(), String> {
    let mut valgrind = true;
    for &a in args {
        match a {
            "--no-valgrind" => valgrind = false,
            "-h" | "--help" => {
                eprintln!("{TEST_USAGE}");
                return Ok(());
            }
            _ => return Err(format!("unknown argument `{a}`\n{TEST_USAGE}")),
        }
    }
    check_test_tools(valgrind)?;
    let base = target_dir().join("install-test");
    if base.exists() {
        std::fs::remove_dir_all(&base).map_err(|e| format!("removing {}: {e}", base.display()))?;
    }
    let out = base.join("out");
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;

    // Three installs: into a prefix, staged under DESTDIR with a multiarch libdir, and again
    // over the first prefix (its files and symlinks are replaced, not refused).
    let built = build()?;
    let prefix = base.join("prefix");
    let first = Layout::new(&prefix, Path::new("lib"), Path::new("include"), None)?;
    install_files(&built, &first)?;
    let destdir = base.join("destdir");
    let staged = Layout::new(
        Path::new(STAGED_PREFIX),
        Path::new(STAGED_LIBDIR),
        Path::new("include"),
        Some(destdir.clone()),
    )?;
    install_files(&built, &staged)?;
    install_files(&built, &first)?;

    // The checks are tests/c/installed/run_tests.py's.
    let mut cmd = Command::new("python3");
    cmd.arg(root().join("tests/c/installed/run_tests.py"))
        .arg("--prefix")
        .arg(&prefix)
        .arg("--destdir")
        .arg(&destdir)
        .args(["--destdir-prefix", STAGED_PREFIX])
        .args(["--destdir-libdir", STAGED_LIBDIR])
        .arg("--built-library")
        .arg(&built.shared)
        .args(["--version", &built.package.version])
        .arg("--native-static-libs")
        .arg(built.native_static_libs.join(" "))
        .arg("--work")
        .arg(&out);
    if !valgrind {
        cmd.arg("--no-valgrind");
    }
    eprintln!("xtask: $ {}", describe(&cmd));
    let run = cmd
        .output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(&cmd)))?;
    let stdout = String::from_utf8_lossy(&run.stdout);
    print!("{stdout}");
    eprint!("{}", String::from_utf8_lossy(&run.stderr));
    match (
        run.status.success(),
        stdout.lines().rev().find_map(util::parse_summary),
    ) {
        (true, Some((passed, 0))) if passed > 0 => {
            eprintln!(
                "xtask: install-test: {passed} checks passed ({})",
                if valgrind {
                    "under valgrind"
                } else {
                    "without valgrind"
                }
            );
            Ok(())
        }
        (_, Some((passed, failed))) => Err(format!(
            "install-test: {passed} passed, {failed} failed (see FAIL above)"
        )),
        (_, None) => Err(format!(
            "install-test: run_tests.py ended ({}) without `N passed, M failed`",
            run.status
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soname_rule() {
        assert_eq!(soname_version(0, 1, 0), "0.1");
        assert_eq!(soname_version(0, 1, 7), "0.1");
        assert_eq!(soname_version(0, 12, 3), "0.12");
        assert_eq!(soname_version(0, 0, 4), "0.0.4");
        assert_eq!(soname_version(1, 0, 0), "1");
        assert_eq!(soname_version(2, 5, 1), "2");
    }

    #[test]
    fn cargo_toml_fields() {
        let toml = "[workspace]\nversion = \"9.9.9\"\n\n[package]\nname = \"katachi\"\nversion = \"0.3.1\"\ndescription = \"A kernel\"\n\n[dependencies]\nversion = \"1\"\n";
        assert_eq!(package_field(toml, "version").as_deref(), Some("0.3.1"));
        assert_eq!(
            package_field(toml, "description").as_deref(),
            Some("A kernel")
        );
        assert_eq!(package_field(toml, "license"), None);
    }

    #[test]
    fn layout_paths_and_pc_file() {
        let built = Built {
            package: Package {
                version: "0.1.0".into(),
                major: 0,
                minor: 1,
                patch: 0,
                description: "d".into(),
            },
            shared: PathBuf::new(),
            static_lib: PathBuf::new(),
            header: PathBuf::new(),
            native_static_libs: vec!["-lgcc_s".into(), "-lm".into()],
        };
        let l = Layout::new(
            Path::new("/usr/./local/"),
            Path::new("lib"),
            Path::new("/opt/inc"),
            Some("/tmp/stage".into()),
        )
        .unwrap();
        assert_eq!(l.libdir, Path::new("/usr/local/lib"));
        assert_eq!(l.staged(&l.libdir), Path::new("/tmp/stage/usr/local/lib"));
        let pc = pc_file(&built, &l);
        assert!(pc.contains("\nprefix=/usr/local\n"), "{pc}");
        assert!(pc.contains("\nlibdir=${exec_prefix}/lib\n"), "{pc}");
        assert!(pc.contains("\nincludedir=/opt/inc\n"), "{pc}");
        assert!(pc.contains("\nLibs.private: -lgcc_s -lm\n"), "{pc}");
        assert!(pc.contains("\nCflags: -I${includedir}/katachi\n"), "{pc}");
    }
}
