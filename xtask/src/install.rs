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
//! `cargo xtask install-test [--no-valgrind]` installs into `<target dir>/install-test/prefix`
//! (fresh each time) and checks the installed files, symlinks, SONAME and pkg-config's answers;
//! then, with `PKG_CONFIG_PATH=<prefix>/lib/pkgconfig` and nothing but pkg-config's flags (plus
//! an rpath into the prefix), it builds and runs under valgrind:
//!
//! - `examples/c/subdivide.c` with `gcc`, linked to the installed `libkatachi.so` (checked with
//!   `readelf -d` and `ldd`: it needs `libkatachi.so.<S>` and the loader finds it in the prefix),
//!   on the bundled all-quad `examples/models/fandisk_quads.off`: the OFF file it writes must
//!   hold 4^levels × 764 quads, the counts it prints must be the file's, and its failures
//!   (missing input, bad levels) must exit non-zero with katachi's message;
//! - `tests/c/installed/*.cpp` with `g++ -std=c++17`, which must end with `N passed, 0 failed`;
//! - `examples/c/subdivide.c` again, linked to `libkatachi.a` with `pkg-config --static --libs`
//!   (its `-lkatachi` named `-l:libkatachi.a`, as both libraries share the directory): no
//!   `NEEDED` on katachi, and the same results.
//!
//! Then it installs again with `DESTDIR` and a multiarch `--libdir`, and once more over the
//! first prefix, and checks the results. Missing tools are named with their Debian packages.

use std::ffi::OsStr;
use std::io::{BufRead, BufReader};
use std::os::unix::fs::{symlink, PermissionsExt};
use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};

use crate::ctest::target_dir;
use crate::util::{self, describe, have, root};

const INSTALL_USAGE: &str =
    "usage: cargo xtask install [--prefix P] [--libdir DIR] [--includedir DIR]   (honours DESTDIR)";
const TEST_USAGE: &str = "usage: cargo xtask install-test [--no-valgrind]";

/// The all-quad model the installed programs subdivide, and its face count.
const MODEL: &str = "examples/models/fandisk_quads.off";
const MODEL_QUADS: usize = 764;

/// The tools install-test needs, with the Debian package that provides each.
const TEST_TOOLS: [(&str, &str); 6] = [
    ("gcc", "gcc"),
    ("g++", "g++"),
    ("pkg-config", "pkg-config"),
    ("valgrind", "valgrind"),
    ("readelf", "binutils"),
    ("ldd", "libc-bin"),
];

const VALGRIND_FLAGS: [&str; 4] = [
    "--error-exitcode=1",
    "--leak-check=full",
    "--errors-for-leak-kinds=definite,possible",
    "--quiet",
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
    let soname = dynamic_entries(&built.shared)?.soname;
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

/// What an install wrote (staged paths, that is under DESTDIR when set).
struct Installed {
    real: PathBuf,
    soname_link: PathBuf,
    dev_link: PathBuf,
    static_lib: PathBuf,
    header: PathBuf,
    pc: PathBuf,
}

fn install_files(built: &Built, layout: &Layout) -> Result<Installed, String> {
    let p = &built.package;
    let lib = layout.staged(&layout.libdir);
    let inc = layout.staged(&layout.includedir).join("katachi");
    let pcdir = layout.staged(&layout.pkgconfig_dir());
    for d in [&lib, &inc, &pcdir] {
        std::fs::create_dir_all(d).map_err(|e| format!("creating {}: {e}", d.display()))?;
    }
    let installed = Installed {
        real: lib.join(p.real_name()),
        soname_link: lib.join(p.soname()),
        dev_link: lib.join("libkatachi.so"),
        static_lib: lib.join("libkatachi.a"),
        header: inc.join("katachi.h"),
        pc: pcdir.join("katachi.pc"),
    };
    copy_file(&built.shared, &installed.real, 0o755)?;
    link(&p.real_name(), &installed.soname_link)?;
    link(&p.soname(), &installed.dev_link)?;
    copy_file(&built.static_lib, &installed.static_lib, 0o644)?;
    copy_file(&built.header, &installed.header, 0o644)?;
    write_file(&installed.pc, &pc_file(built, layout), 0o644)?;
    Ok(installed)
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
    let installed = install_files(&built, &layout)?;
    eprintln!(
        "xtask: installed katachi {} (SONAME {}); build against it with\n  \
         PKG_CONFIG_PATH={} cc prog.c $(pkg-config --cflags --libs katachi)",
        built.package.version,
        built.package.soname(),
        installed
            .pc
            .parent()
            .expect("the .pc file is in a directory")
            .display()
    );
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// install-test

/// A failed check, with what was expected.
fn ensure(ok: bool, what: impl FnOnce() -> String) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(what())
    }
}

/// The dynamic section's SONAME, NEEDED and RUNPATH/RPATH entries (`readelf -d`).
#[derive(Default)]
struct Dynamic {
    soname: Option<String>,
    needed: Vec<String>,
    runpath: Vec<String>,
}

fn dynamic_entries(file: &Path) -> Result<Dynamic, String> {
    let text = output(Command::new("readelf").arg("-d").arg(file))?;
    let mut d = Dynamic::default();
    for line in text.lines() {
        let bracketed = || {
            let start = line.find('[')? + 1;
            let end = line.rfind(']')?;
            Some(line[start..end].to_owned())
        };
        if line.contains("(SONAME)") {
            d.soname = bracketed();
        } else if line.contains("(NEEDED)") {
            d.needed.extend(bracketed());
        } else if line.contains("(RUNPATH)") || line.contains("(RPATH)") {
            d.runpath.extend(
                bracketed()
                    .iter()
                    .flat_map(|p| p.split(':').map(str::to_owned)),
            );
        }
    }
    Ok(d)
}

/// Runs a command to completion; its stdout, or an error with its stderr.
fn output(cmd: &mut Command) -> Result<String, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("cannot start `{}`: {e}", describe(cmd)))?;
    if !out.status.success() {
        return Err(format!(
            "`{}` failed ({}):\n{}",
            describe(cmd),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// An OFF file's vertex count and faces (each a list of vertex indices).
struct Off {
    vertex_count: usize,
    faces: Vec<Vec<usize>>,
}

/// Reads an OFF file strictly enough to check a mesh katachi wrote (or the input model).
fn read_off(path: &Path) -> Result<Off, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let bad = |m: String| format!("{}: {m}", path.display());
    let mut lines = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty());
    let first = lines.next().ok_or_else(|| bad("empty file".into()))?;
    let rest = first
        .strip_prefix("OFF")
        .ok_or_else(|| bad(format!("starts with {first:?}, not OFF")))?;
    let counts_line = if rest.trim().is_empty() {
        lines.next().ok_or_else(|| bad("no counts line".into()))?
    } else {
        rest
    };
    let counts: Vec<usize> = counts_line
        .split_whitespace()
        .map(|t| {
            t.parse()
                .map_err(|_| bad(format!("bad counts {counts_line:?}")))
        })
        .collect::<Result<_, _>>()?;
    let (vertex_count, face_count) = match counts[..] {
        [v, f, ..] => (v, f),
        _ => return Err(bad(format!("bad counts {counts_line:?}"))),
    };
    for i in 0..vertex_count {
        let l = lines
            .next()
            .ok_or_else(|| bad(format!("ends at vertex {i}")))?;
        let ok = l
            .split_whitespace()
            .take(3)
            .filter(|t| t.parse::<f64>().map(f64::is_finite).unwrap_or(false))
            .count()
            == 3;
        ensure(ok, || {
            bad(format!("vertex {i}: {l:?} is not 3 finite numbers"))
        })?;
    }
    let mut faces = Vec::with_capacity(face_count);
    for i in 0..face_count {
        let l = lines
            .next()
            .ok_or_else(|| bad(format!("ends at face {i}")))?;
        let tokens: Vec<usize> = l
            .split_whitespace()
            .map(|t| t.parse().map_err(|_| bad(format!("face {i}: {l:?}"))))
            .collect::<Result<_, _>>()?;
        let n = *tokens
            .first()
            .ok_or_else(|| bad(format!("face {i} is empty")))?;
        let face = tokens
            .get(1..=n)
            .ok_or_else(|| bad(format!("face {i}: {l:?} has fewer than {n} indices")))?;
        ensure(face.iter().all(|&v| v < vertex_count), || {
            bad(format!("face {i}: {l:?} names a vertex ≥ {vertex_count}"))
        })?;
        faces.push(face.to_vec());
    }
    ensure(lines.next().is_none(), || {
        bad("more lines than the counts say".into())
    })?;
    Ok(Off {
        vertex_count,
        faces,
    })
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

/// The test's environment: the prefix and a pkg-config pointed at it.
struct Env {
    prefix: PathBuf,
    libdir: PathBuf,
    pkgconfig_path: PathBuf,
    out: PathBuf,
    valgrind: bool,
}

impl Env {
    /// `pkg-config ARGS katachi`, split into words.
    fn pkg_config(&self, args: &[&str]) -> Result<Vec<String>, String> {
        let mut cmd = Command::new("pkg-config");
        cmd.args(args)
            .arg("katachi")
            .env("PKG_CONFIG_PATH", &self.pkgconfig_path);
        let text = output(&mut cmd)?;
        Ok(text.split_whitespace().map(str::to_owned).collect())
    }

    /// A program run, under valgrind unless disabled; (exit success, stdout, stderr).
    fn run_program(&self, exe: &Path, args: &[&OsStr]) -> Result<(bool, String, String), String> {
        let mut cmd = if self.valgrind {
            let mut c = Command::new("valgrind");
            c.args(VALGRIND_FLAGS)
                .arg(format!(
                    "--suppressions={}",
                    root().join("tests/c/valgrind.supp").display()
                ))
                .arg(exe);
            c
        } else {
            Command::new(exe)
        };
        cmd.args(args).current_dir(&self.out);
        eprintln!("xtask: $ {}", describe(&cmd));
        let out = cmd
            .output()
            .map_err(|e| format!("cannot start `{}`: {e}", describe(&cmd)))?;
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        print!("{stdout}");
        eprint!("{stderr}");
        Ok((out.status.success(), stdout, stderr))
    }

    /// Compiles one program with the warnings-as-errors flags of its language (`gcc`: C99,
    /// `g++`: C++17): `before` goes before the source (pkg-config's Cflags), `libs` after it.
    fn compile(
        &self,
        compiler: &str,
        source: &Path,
        exe: &Path,
        before: &[String],
        libs: &[String],
    ) -> Result<(), String> {
        let flags = if compiler == "g++" {
            CXX_FLAGS
        } else {
            C_FLAGS
        };
        let mut cmd = Command::new(compiler);
        cmd.args(flags)
            .arg("-g")
            .args(before)
            .arg(source)
            .arg("-o")
            .arg(exe)
            .args(libs)
            .env("PKG_CONFIG_PATH", &self.pkgconfig_path);
        util::run(&mut cmd).map_err(|e| format!("compiling {}: {e}", source.display()))
    }
}

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

    let built = build()?;
    let layout = Layout::new(
        &base.join("prefix"),
        Path::new("lib"),
        Path::new("include"),
        None,
    )?;
    let installed = install_files(&built, &layout)?;
    let env = Env {
        prefix: layout.prefix.clone(),
        libdir: layout.libdir.clone(),
        pkgconfig_path: layout.pkgconfig_dir(),
        out,
        valgrind,
    };
    let mut checks = 0;
    checks += check_layout(&built, &installed)?;
    checks += check_pkg_config(&built, &env)?;
    checks += test_shared_example(&built, &env)?;
    checks += test_cpp(&built, &env)?;
    checks += test_static_example(&env)?;
    checks += test_reinstalls(&built, &base, &layout)?;
    eprintln!(
        "xtask: install-test: all {checks} checks passed ({})",
        if valgrind {
            "under valgrind"
        } else {
            "without valgrind"
        }
    );
    Ok(())
}

/// The files, their modes and the symlinks of one install; returns the number of checks.
fn check_layout(built: &Built, i: &Installed) -> Result<usize, String> {
    let p = &built.package;
    let mut n = 0;
    for (path, mode) in [
        (&i.real, 0o755),
        (&i.static_lib, 0o644),
        (&i.header, 0o644),
        (&i.pc, 0o644),
    ] {
        let meta = path
            .symlink_metadata()
            .map_err(|e| format!("{} was not installed: {e}", path.display()))?;
        ensure(meta.is_file(), || {
            format!("{} is not a regular file", path.display())
        })?;
        ensure(meta.permissions().mode() & 0o777 == mode, || {
            format!(
                "{} has mode {:o}, expected {mode:o}",
                path.display(),
                meta.permissions().mode() & 0o777
            )
        })?;
        n += 2;
    }
    for (link, target) in [(&i.soname_link, p.real_name()), (&i.dev_link, p.soname())] {
        let got = std::fs::read_link(link)
            .map_err(|e| format!("{} is not a symlink: {e}", link.display()))?;
        ensure(got == Path::new(&target), || {
            format!(
                "{} points to {}, expected {target}",
                link.display(),
                got.display()
            )
        })?;
        n += 1;
    }
    ensure(
        i.dev_link.canonicalize().ok() == i.real.canonicalize().ok(),
        || {
            format!(
                "{} does not lead to {}",
                i.dev_link.display(),
                i.real.display()
            )
        },
    )?;
    let same = |a: &Path, b: &Path| {
        std::fs::read(a).ok().is_some() && std::fs::read(a).ok() == std::fs::read(b).ok()
    };
    ensure(same(&i.header, &built.header), || {
        format!("{} differs from include/katachi.h", i.header.display())
    })?;
    ensure(same(&i.real, &built.shared), || {
        format!("{} differs from the built library", i.real.display())
    })?;
    let soname = dynamic_entries(&i.real)?.soname;
    ensure(soname.as_deref() == Some(p.soname().as_str()), || {
        format!(
            "readelf -d {}: SONAME {soname:?}, expected {}",
            i.real.display(),
            p.soname()
        )
    })?;
    n += 4;
    eprintln!(
        "xtask: install-test: layout ok: {} with SONAME {}",
        i.real.display(),
        p.soname()
    );
    Ok(n)
}

/// pkg-config's answers for the prefix.
fn check_pkg_config(built: &Built, env: &Env) -> Result<usize, String> {
    let version = env.pkg_config(&["--modversion"])?;
    ensure(version == [built.package.version.clone()], || {
        format!(
            "pkg-config --modversion katachi: {version:?}, expected {}",
            built.package.version
        )
    })?;
    let cflags = env.pkg_config(&["--cflags"])?;
    let want = [format!(
        "-I{}",
        env.prefix.join("include/katachi").display()
    )];
    ensure(cflags == want, || {
        format!("pkg-config --cflags katachi: {cflags:?}, expected {want:?}")
    })?;
    let libs = env.pkg_config(&["--libs"])?;
    let want = [
        format!("-L{}", env.libdir.display()),
        "-lkatachi".to_owned(),
    ];
    ensure(libs == want, || {
        format!("pkg-config --libs katachi: {libs:?}, expected {want:?}")
    })?;
    let static_libs = env.pkg_config(&["--static", "--libs"])?;
    ensure(
        static_libs.starts_with(&want)
            && built
                .native_static_libs
                .iter()
                .all(|l| static_libs.contains(l)),
        || {
            format!(
                "pkg-config --static --libs katachi: {static_libs:?}, expected {want:?} then {:?}",
                built.native_static_libs
            )
        },
    )?;
    eprintln!(
        "xtask: install-test: pkg-config ok: {}",
        static_libs.join(" ")
    );
    Ok(4)
}

/// Parses the example's "LABEL: V vertices, F faces" line.
fn printed_counts(stdout: &str, label: &str) -> Option<(usize, usize)> {
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix(label)?.strip_prefix(": "))?;
    let (v, f) = line.split_once(" vertices, ")?;
    Some((v.parse().ok()?, f.strip_suffix(" faces")?.parse().ok()?))
}

/// Runs a built `subdivide` on the model with `levels` and checks what it wrote.
fn check_example_run(
    env: &Env,
    exe: &Path,
    levels: Option<u32>,
    tag: &str,
) -> Result<usize, String> {
    let model = root().join(MODEL);
    let input = read_off(&model)?;
    ensure(
        input.faces.len() == MODEL_QUADS && input.faces.iter().all(|f| f.len() == 4),
        || format!("{MODEL} is no longer {MODEL_QUADS} quads"),
    )?;
    let result = env.out.join(format!("{tag}.off"));
    let levels_arg = levels.map(|l| l.to_string());
    let mut args: Vec<&OsStr> = vec![model.as_os_str(), result.as_os_str()];
    if let Some(l) = &levels_arg {
        args.push(OsStr::new(l));
    }
    let (ok, stdout, stderr) = env.run_program(exe, &args)?;
    ensure(ok, || format!("{tag}: {} failed:\n{stderr}", exe.display()))?;
    let levels = levels.unwrap_or(1);
    let off = read_off(&result)?;
    let want = MODEL_QUADS * 4usize.pow(levels);
    ensure(
        off.faces.len() == want && off.faces.iter().all(|f| f.len() == 4),
        || {
            format!(
            "{tag}: {} holds {} faces ({} quads), expected {want} quads (4^{levels} × {MODEL_QUADS})",
            result.display(),
            off.faces.len(),
            off.faces.iter().filter(|f| f.len() == 4).count()
        )
        },
    )?;
    let label = format!("after {levels} level{}", if levels == 1 { "" } else { "s" });
    let printed = printed_counts(&stdout, &label);
    ensure(printed == Some((off.vertex_count, off.faces.len())), || {
        format!("{tag}: printed counts {printed:?} for `{label}`, but the file has {} vertices and {} faces", off.vertex_count, off.faces.len())
    })?;
    let printed_in = printed_counts(&stdout, "input");
    ensure(
        printed_in == Some((input.vertex_count, MODEL_QUADS)),
        || {
            format!(
                "{tag}: printed input counts {printed_in:?}, expected ({}, {MODEL_QUADS})",
                input.vertex_count
            )
        },
    )?;
    eprintln!(
        "xtask: install-test: {tag}: {} quads after {levels} level(s)",
        off.faces.len()
    );
    Ok(3)
}

fn example_source() -> PathBuf {
    root().join("examples/c/subdivide.c")
}

const C_FLAGS: [&str; 5] = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"];
const CXX_FLAGS: [&str; 5] = ["-std=c++17", "-Wall", "-Wextra", "-Werror", "-pthread"];

fn rpath(env: &Env) -> String {
    format!("-Wl,-rpath,{}", env.libdir.display())
}

/// A program linked to the shared library needs `libkatachi.so.<S>` and finds it in the prefix.
fn check_resolves_to_prefix(built: &Built, env: &Env, exe: &Path) -> Result<usize, String> {
    let soname = built.package.soname();
    let d = dynamic_entries(exe)?;
    ensure(d.needed.contains(&soname), || {
        format!(
            "readelf -d {}: NEEDED {:?} lacks {soname}",
            exe.display(),
            d.needed
        )
    })?;
    let ldd = output(Command::new("ldd").arg(exe))?;
    let expected = env.libdir.join(&soname);
    let found = ldd.lines().find_map(|l| {
        let (name, rest) = l.trim().split_once(" => ")?;
        (name == soname).then(|| rest.split(" (").next().unwrap_or(rest).trim().to_owned())
    });
    ensure(
        found.as_deref().map(Path::new) == Some(expected.as_path()),
        || {
            format!(
            "ldd {}: {soname} resolves to {found:?}, expected {} (the prefix, not target/):\n{ldd}",
            exe.display(),
            expected.display()
        )
        },
    )?;
    Ok(2)
}

/// (a) The example against the installed shared library, and its failures.
fn test_shared_example(built: &Built, env: &Env) -> Result<usize, String> {
    let exe = env.out.join("subdivide");
    let cflags = env.pkg_config(&["--cflags"])?;
    let mut libs = env.pkg_config(&["--libs"])?;
    libs.push(rpath(env));
    env.compile("gcc", &example_source(), &exe, &cflags, &libs)?;
    let mut n = check_resolves_to_prefix(built, env, &exe)?;
    n += check_example_run(env, &exe, Some(2), "shared-2-levels")?;
    n += check_example_run(env, &exe, None, "shared-default-levels")?;

    // Failures: a non-zero exit, katachi's message, and no output file.
    let model = root().join(MODEL);
    let missing = env.out.join("no-such-model.off");
    let result = env.out.join("must-not-exist.off");
    let cases: [(&str, Vec<&OsStr>, &str); 3] = [
        (
            "a missing input",
            vec![missing.as_os_str(), result.as_os_str()],
            "no-such-model.off",
        ),
        (
            "9 levels",
            vec![model.as_os_str(), result.as_os_str(), OsStr::new("9")],
            "levels",
        ),
        (
            "a bad output extension",
            vec![model.as_os_str(), OsStr::new("out.xyz"), OsStr::new("1")],
            "out.xyz",
        ),
    ];
    for (what, args, needle) in cases {
        let (ok, _, stderr) = env.run_program(&exe, &args)?;
        ensure(!ok, || format!("subdivide with {what} succeeded"))?;
        ensure(
            stderr.contains("subdivide: ") && stderr.contains(needle),
            || {
                format!("subdivide with {what}: stderr {stderr:?} lacks katachi's message naming {needle:?}")
            },
        )?;
        ensure(!result.exists(), || {
            format!("subdivide with {what} wrote {}", result.display())
        })?;
        n += 3;
    }
    Ok(n)
}

/// (b) The C++ programs of tests/c/installed.
fn test_cpp(built: &Built, env: &Env) -> Result<usize, String> {
    let dir = root().join("tests/c/installed");
    let mut sources: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "cpp"))
        .collect();
    sources.sort();
    ensure(!sources.is_empty(), || {
        format!("no .cpp programs in {}", dir.display())
    })?;
    let cflags = env.pkg_config(&["--cflags"])?;
    let mut libs = env.pkg_config(&["--libs"])?;
    libs.push(rpath(env));
    let version = format!(
        "-DKATACHI_EXPECTED_VERSION=\"{}\"",
        env.pkg_config(&["--modversion"])?.join(" ")
    );
    let mut before = cflags;
    before.push(version);
    let mut n = 0;
    for source in sources {
        let stem = source
            .file_stem()
            .expect("a .cpp file has a stem")
            .to_string_lossy()
            .into_owned();
        let exe = env.out.join(&stem);
        env.compile("g++", &source, &exe, &before, &libs)?;
        n += check_resolves_to_prefix(built, env, &exe)?;
        let model = root().join(MODEL);
        let (ok, stdout, stderr) = env.run_program(&exe, &[model.as_os_str()])?;
        ensure(ok, || {
            format!(
                "{stem} failed{}",
                if stderr.contains("==") {
                    " (see valgrind's report above)"
                } else {
                    ""
                }
            )
        })?;
        let last = stdout.lines().last().unwrap_or("");
        let passed = last
            .strip_suffix(" passed, 0 failed")
            .and_then(|p| p.parse::<usize>().ok());
        match passed {
            Some(p) if p > 0 => n += p,
            _ => {
                return Err(format!(
                    "{stem} did not end with `N passed, 0 failed` (last line: {last:?})"
                ))
            }
        }
    }
    Ok(n)
}

/// (c) The example against libkatachi.a, with `pkg-config --static --libs`.
fn test_static_example(env: &Env) -> Result<usize, String> {
    let exe = env.out.join("subdivide_static");
    let cflags = env.pkg_config(&["--cflags"])?;
    // -lkatachi would pick libkatachi.so from the same directory; name the archive instead.
    let libs: Vec<String> = env
        .pkg_config(&["--static", "--libs"])?
        .into_iter()
        .map(|w| {
            if w == "-lkatachi" {
                "-l:libkatachi.a".to_owned()
            } else {
                w
            }
        })
        .collect();
    ensure(libs.iter().any(|w| w == "-l:libkatachi.a"), || {
        format!("pkg-config --static --libs katachi has no -lkatachi: {libs:?}")
    })?;
    env.compile("gcc", &example_source(), &exe, &cflags, &libs)?;
    let d = dynamic_entries(&exe)?;
    ensure(!d.needed.iter().any(|l| l.contains("katachi")), || {
        format!(
            "{} links statically but needs {:?}",
            exe.display(),
            d.needed
        )
    })?;
    Ok(2 + check_example_run(env, &exe, Some(1), "static-1-level")?)
}

/// DESTDIR with a multiarch libdir, and an install over an existing prefix.
fn test_reinstalls(built: &Built, base: &Path, first: &Layout) -> Result<usize, String> {
    let destdir = base.join("destdir");
    let layout = Layout::new(
        Path::new("/opt/katachi-test"),
        Path::new("lib/x86_64-linux-gnu"),
        Path::new("include"),
        Some(destdir.clone()),
    )?;
    let i = install_files(built, &layout)?;
    let mut n = check_layout(built, &i)?;
    let staged_lib = destdir.join("opt/katachi-test/lib/x86_64-linux-gnu");
    ensure(
        i.real.parent() == Some(staged_lib.as_path())
            && i.header == destdir.join("opt/katachi-test/include/katachi/katachi.h"),
        || {
            format!(
                "DESTDIR install put the library at {} and the header at {}",
                i.real.display(),
                i.header.display()
            )
        },
    )?;
    let pc = std::fs::read_to_string(&i.pc).map_err(|e| format!("{}: {e}", i.pc.display()))?;
    ensure(
        pc.lines().any(|l| l == "prefix=/opt/katachi-test")
            && pc
                .lines()
                .any(|l| l == "libdir=${exec_prefix}/lib/x86_64-linux-gnu")
            && !pc.contains(&destdir.display().to_string()),
        || {
            format!(
                "{} does not name /opt/katachi-test without DESTDIR:\n{pc}",
                i.pc.display()
            )
        },
    )?;
    n += 2;

    // Again over the first prefix: files and symlinks are replaced, not refused.
    let again = install_files(built, first)?;
    n += check_layout(built, &again)?;
    Ok(n)
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

    #[test]
    fn example_counts_line() {
        let out = "input: 766 vertices, 764 faces\nafter 2 levels: 12226 vertices, 12224 faces\n";
        assert_eq!(printed_counts(out, "input"), Some((766, 764)));
        assert_eq!(printed_counts(out, "after 2 levels"), Some((12226, 12224)));
        assert_eq!(printed_counts(out, "after 1 level"), None);
    }
}
