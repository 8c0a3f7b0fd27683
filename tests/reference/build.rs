//! Builds the C++ shim over OpenSubdiv, OpenMesh, CGAL and Boost.Graph and generates its Rust
//! bindings, and the bindings of Gmsh's C API.
//!
//! Needs the Debian packages libosd-dev, libopenmesh-dev, libcgal-dev (with libgmp-dev and
//! libmpfr-dev), libboost-graph-dev, libgmsh-dev, libclang-dev and a C++ compiler (g++),
//! which `cargo xtask deps` installs. When one is missing the build stops with a message naming
//! the package instead of a compiler or linker error.
//!
//! Extra search directories (for a non-Debian layout) can be given in the colon-separated
//! environment variables `KATACHI_REFERENCE_INCLUDE_DIRS` and `KATACHI_REFERENCE_LIB_DIRS`;
//! bindgen honours `LIBCLANG_PATH`.

use std::env;
use std::path::{Path, PathBuf};

const SHIM_SOURCES: &[&str] = &[
    "shim/osd.cpp",
    "shim/openmesh.cpp",
    "shim/result.cpp",
    "shim/boost_flow.cpp",
];
/// Compiled apart, with the flag CGAL requires of GCC (-frounding-math, for its interval filters),
/// so that the OpenSubdiv and OpenMesh code the benchmarks time is compiled as before.
const CGAL_SOURCES: &[&str] = &["shim/cgal_cut.cpp"];
const SHIM_HEADERS: &[&str] = &["shim/katachi_reference.h", "shim/shim_internal.hpp"];

/// (header or library file, Debian package, what it is)
const HEADERS: &[(&str, &str, &str)] = &[
    (
        "opensubdiv/far/topologyRefinerFactory.h",
        "libosd-dev",
        "OpenSubdiv 3.5 headers",
    ),
    (
        "OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh",
        "libopenmesh-dev",
        "OpenMesh 9 headers",
    ),
    (
        "CGAL/Constrained_Delaunay_triangulation_2.h",
        "libcgal-dev",
        "CGAL 5 headers",
    ),
    ("mpfr.h", "libmpfr-dev", "MPFR headers (for CGAL)"),
    ("gmshc.h", "libgmsh-dev", "Gmsh 4.8's C API header"),
    (
        "boost/graph/boykov_kolmogorov_max_flow.hpp",
        "libboost-graph-dev",
        "Boost.Graph headers (the max-flow reference)",
    ),
];
const LIBRARIES: &[(&str, &str, &str)] = &[
    ("osdCPU", "libosd-dev", "OpenSubdiv's CPU library"),
    ("OpenMeshCore", "libopenmesh-dev", "OpenMesh's core library"),
    ("gmp", "libgmp-dev", "GMP (CGAL's exact numbers)"),
    ("mpfr", "libmpfr-dev", "MPFR (CGAL's exact numbers)"),
    (
        "gmsh",
        "libgmsh-dev",
        "Gmsh 4.8 (the peer for curved meshing)",
    ),
];

fn main() {
    for f in SHIM_SOURCES.iter().chain(CGAL_SOURCES).chain(SHIM_HEADERS) {
        println!("cargo:rerun-if-changed={f}");
    }
    for v in [
        "KATACHI_REFERENCE_INCLUDE_DIRS",
        "KATACHI_REFERENCE_LIB_DIRS",
        "LIBCLANG_PATH",
        "CPLUS_INCLUDE_PATH",
        "CPATH",
        "LIBRARY_PATH",
    ] {
        println!("cargo:rerun-if-env-changed={v}");
    }

    let include_dirs = search_dirs(
        "KATACHI_REFERENCE_INCLUDE_DIRS",
        &["CPLUS_INCLUDE_PATH", "CPATH"],
        &["/usr/local/include", "/usr/include"],
    );
    let mut lib_dirs = search_dirs(
        "KATACHI_REFERENCE_LIB_DIRS",
        &["LIBRARY_PATH"],
        &["/usr/local/lib", "/usr/lib", "/lib"],
    );
    lib_dirs.extend(multiarch_dirs());

    let mut missing = Vec::new();
    for (file, package, what) in HEADERS {
        if !include_dirs.iter().any(|d| d.join(file).is_file()) {
            missing.push(format!("{what} ({file}): Debian package {package}"));
        }
    }
    let mut extra_link_dirs = Vec::new();
    for (lib, package, what) in LIBRARIES {
        let names = [format!("lib{lib}.so"), format!("lib{lib}.a")];
        match lib_dirs
            .iter()
            .find(|d| names.iter().any(|n| d.join(n).exists()))
        {
            Some(d) => extra_link_dirs.push(d.clone()),
            None => missing.push(format!("{what} (lib{lib}.so): Debian package {package}")),
        }
    }
    if !missing.is_empty() {
        fail(&format!(
            "katachi-reference needs system packages that are missing:\n  - {}\n\
             Install them with `cargo xtask deps` (as root), or set \
             KATACHI_REFERENCE_INCLUDE_DIRS / KATACHI_REFERENCE_LIB_DIRS to where they are.",
            missing.join("\n  - ")
        ));
    }

    // The shim is always optimised: OpenMesh's subdivider is header-only template code, and the
    // crate exists to be compared against, including in benchmarks.
    let build = shim_build(&include_dirs, SHIM_SOURCES);
    if let Err(e) = build.try_compile("katachi_reference_shim") {
        fail(&format!(
            "compiling the C++ shim failed: {e}\n\
             It needs a C++17 compiler (Debian package g++) and the headers of OpenSubdiv >= 3.5 \
             (libosd-dev, for Far::PrimvarRefinerReal) and OpenMesh >= 9 (libopenmesh-dev); \
             `cargo xtask deps` installs them."
        ));
    }

    // The exact stroke cut: CGAL is header-only (5.x) and uses GMP and MPFR, linked below.
    // CGAL needs -frounding-math with GCC; kept out of the code the benchmarks time.
    let mut cgal = shim_build(&include_dirs, CGAL_SOURCES);
    cgal.flag_if_supported("-frounding-math");
    if let Err(e) = cgal.try_compile("katachi_reference_cgal") {
        fail(&format!(
            "compiling the CGAL part of the shim (shim/cgal_cut.cpp) failed: {e}\n\
             It needs a C++17 compiler (g++) and CGAL >= 5 (libcgal-dev, header-only) with \
             GMP and MPFR (libgmp-dev, libmpfr-dev); `cargo xtask deps` installs them."
        ));
    }

    for d in &extra_link_dirs {
        if !is_default_lib(d) {
            println!("cargo:rustc-link-search=native={}", d.display());
        }
    }
    for (lib, _, _) in LIBRARIES {
        println!("cargo:rustc-link-lib=dylib={lib}");
    }

    // Bindings of the shim's C header, generated with libclang.
    let builder = bindgen::Builder::default()
        .header("shim/katachi_reference.h")
        .allowlist_function("kr_.*")
        .allowlist_type("kr_.*")
        .allowlist_var("KR_.*")
        .layout_tests(false)
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    // bindgen panics when it cannot load libclang; catch that and say what to install, with
    // bindgen's own message but without a backtrace.
    let panic_message = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
    let sink = panic_message.clone();
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if let Ok(mut m) = sink.lock() {
            *m = info.to_string();
        }
    }));
    let generated =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || builder.generate()));
    std::panic::set_hook(default_hook);
    let bindings = match generated {
        Ok(Ok(b)) => b,
        Ok(Err(e)) => fail(&format!(
            "bindgen could not read shim/katachi_reference.h: {e}\n\
             It needs libclang (Debian packages libclang-dev and clang); `cargo xtask deps` installs them."
        )),
        Err(_) => fail(&format!(
            "bindgen could not load libclang: {}\n\
             Install the Debian packages libclang-dev and clang with `cargo xtask deps`, \
             or point LIBCLANG_PATH at the directory that holds libclang.so.",
            panic_message.lock().map(|m| m.clone()).unwrap_or_default()
        )),
    };
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    if let Err(e) = bindings.write_to_file(out.join("bindings.rs")) {
        fail(&format!("writing the generated bindings failed: {e}"));
    }

    // Gmsh's own C API (a C header, no shim needed), for curved meshing (seed 000).
    let gmsh_header = include_dirs
        .iter()
        .map(|d| d.join("gmshc.h"))
        .find(|p| p.is_file())
        .expect("checked above");
    let gmsh = bindgen::Builder::default()
        .header(gmsh_header.to_string_lossy())
        .allowlist_function("gmsh.*")
        .layout_tests(false)
        .generate();
    match gmsh {
        Ok(b) => {
            if let Err(e) = b.write_to_file(out.join("gmsh_bindings.rs")) {
                fail(&format!("writing the Gmsh bindings failed: {e}"));
            }
        }
        Err(e) => fail(&format!("bindgen could not read gmshc.h: {e}")),
    }
}

/// Stops the build with a message that cargo shows under the build script's stderr.
fn fail(message: &str) -> ! {
    eprintln!("\nerror: {message}\n");
    std::process::exit(1);
}

/// Directories from our own variable, then from the compiler's variables, then the defaults.
fn search_dirs(own: &str, compiler_vars: &[&str], defaults: &[&str]) -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    for var in std::iter::once(own).chain(compiler_vars.iter().copied()) {
        if let Some(v) = env::var_os(var) {
            dirs.extend(env::split_paths(&v).filter(|p| !p.as_os_str().is_empty()));
        }
    }
    dirs.extend(defaults.iter().map(PathBuf::from));
    dirs
}

/// Debian's multiarch library directories (/usr/lib/x86_64-linux-gnu, ...).
fn multiarch_dirs() -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    for root in ["/usr/lib", "/lib"] {
        if let Ok(entries) = std::fs::read_dir(root) {
            for e in entries.flatten() {
                let name = e.file_name();
                let name = name.to_string_lossy();
                if name.contains("-linux-") && e.path().is_dir() {
                    dirs.push(e.path());
                }
            }
        }
    }
    dirs.sort();
    dirs
}

fn is_default_include(d: &Path) -> bool {
    d == Path::new("/usr/include") || d == Path::new("/usr/local/include")
}

fn is_default_lib(d: &Path) -> bool {
    let s = d.to_string_lossy();
    s == "/usr/lib" || s == "/lib" || s == "/usr/local/lib" || {
        (s.starts_with("/usr/lib/") || s.starts_with("/lib/")) && s.contains("-linux-")
    }
}

/// A C++17 build of shim sources, optimised, with the found library include directories.
fn shim_build(include_dirs: &[PathBuf], sources: &[&str]) -> cc::Build {
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .std("c++17")
        .opt_level(2)
        .include("shim")
        .warnings(true)
        .extra_warnings(true)
        // OpenMesh 9's VectorT leaves its default-constructed storage uninitialised on purpose.
        .flag_if_supported("-Wno-maybe-uninitialized")
        .define("NDEBUG", None)
        .files(sources);
    for d in include_dirs {
        if !is_default_include(d) {
            build.include(d);
        }
    }
    build
}
