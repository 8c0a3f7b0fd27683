"""The installed C library, checked as a C or C++ programmer meets it.

    python3 run_tests.py --prefix P --destdir D --destdir-prefix /opt/katachi-test \
        --destdir-libdir lib/x86_64-linux-gnu --built-library LIB --version V \
        --native-static-libs "-lgcc_s ..." --work DIR [--no-valgrind]

Run by `cargo xtask install-test`, which builds katachi, installs it into the prefix P, into
the staging directory D (DESTDIR, a multiarch libdir) and once more over P, and then runs
this program. It checks:

- the files of both installs: modes, the symlinks libkatachi.so -> .so.<S> -> .so.X.Y.Z, the
  SONAME (`readelf -d`), the header and library identical to the built ones; the staged
  install's paths and its .pc file naming the prefix without the staging directory;
- pkg-config's answers for P (version, Cflags, Libs, Libs.private);
- `examples/c/subdivide.c` built with gcc and nothing but pkg-config's flags (plus an rpath
  into P): it needs libkatachi.so.<S> and the loader finds it in P; run (under valgrind) on
  `examples/models/fandisk_quads.off`, the file it writes holds 4^levels x 764 quads and the
  counts it prints are the file's; its failures (a missing input, 9 levels, a bad output
  extension) exit non-zero with katachi's message and write nothing;
- `tests/c/installed/*.cpp` built with g++, each ending with `N passed, 0 failed`;
- the example linked to libkatachi.a with `pkg-config --static --libs`: no NEEDED on katachi,
  the same results.

Every mesh is read with katachi's own reader, through the C ABI of the installed library
(`tests/python/katachi_mesh.py`). Ends with `N passed, M failed`.

License: MIT OR Apache-2.0.
"""

import argparse
import os
import re
import shlex
import stat
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))

from katachi_mesh import Katachi  # noqa: E402

MODEL = os.path.join(ROOT, "examples", "models", "fandisk_quads.off")
MODEL_QUADS = 764
EXAMPLE = os.path.join(ROOT, "examples", "c", "subdivide.c")
C_FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]
CXX_FLAGS = ["-std=c++17", "-Wall", "-Wextra", "-Werror", "-pthread"]
VALGRIND = ["valgrind", "--error-exitcode=1", "--leak-check=full",
            "--errors-for-leak-kinds=definite,possible", "--quiet",
            f"--suppressions={os.path.join(ROOT, 'tests', 'c', 'valgrind.supp')}"]

passed = failed = 0


def check(ok, what):
    global passed, failed
    print(f"{'ok  ' if ok else 'FAIL'} installed library: {what}", flush=True)
    if ok:
        passed += 1
    else:
        failed += 1
    return ok


def output(cmd, env=None):
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout}{p.stderr}")
    return p.stdout


def readelf(path):
    """(SONAME or None, [NEEDED…]) from `readelf -d`."""
    text = output(["readelf", "-d", path])
    soname = re.search(r"\(SONAME\)\s+Library soname: \[(.*)\]", text)
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[(.*)\]", text)
    return (soname.group(1) if soname else None), needed


class Names:
    def __init__(self, version):
        m = re.match(r"(\d+)\.(\d+)\.(\d+)", version)
        major, minor, patch = (int(x) for x in m.groups())
        # The soname rule (xtask/src/install.rs): up to the first non-zero component.
        s = (f"0.0.{patch}" if (major, minor) == (0, 0) else
             f"0.{minor}" if major == 0 else str(major))
        self.version = version
        self.soname = f"libkatachi.so.{s}"
        self.real = f"libkatachi.so.{major}.{minor}.{patch}"


def check_layout(label, libdir, includedir, names, args):
    """The files, modes and symlinks of one install."""
    files = {
        os.path.join(libdir, names.real): 0o755,
        os.path.join(libdir, "libkatachi.a"): 0o644,
        os.path.join(includedir, "katachi", "katachi.h"): 0o644,
        os.path.join(libdir, "pkgconfig", "katachi.pc"): 0o644,
    }
    for path, mode in files.items():
        st = os.lstat(path) if os.path.lexists(path) else None
        check(st is not None and stat.S_ISREG(st.st_mode) and stat.S_IMODE(st.st_mode) == mode,
              f"{label}: {path} is a regular file with mode {mode:o}")
    for link, target in ((names.soname, names.real), ("libkatachi.so", names.soname)):
        path = os.path.join(libdir, link)
        got = os.readlink(path) if os.path.islink(path) else None
        check(got == target, f"{label}: {path} -> {target} (is {got})")
    same = lambda a, b: open(a, "rb").read() == open(b, "rb").read()
    check(same(os.path.join(includedir, "katachi", "katachi.h"),
               os.path.join(ROOT, "include", "katachi.h")),
          f"{label}: the header is include/katachi.h")
    real = os.path.join(libdir, names.real)
    check(same(real, args.built_library), f"{label}: the library is the one built")
    soname, _ = readelf(real)
    check(soname == names.soname, f"{label}: SONAME {soname}, expected {names.soname}")


class Env:
    def __init__(self, args, names):
        self.prefix = args.prefix
        self.libdir = os.path.join(args.prefix, "lib")
        self.names = names
        self.work = args.work
        self.valgrind = not args.no_valgrind
        self.env = dict(os.environ, PKG_CONFIG_PATH=os.path.join(self.libdir, "pkgconfig"))
        self.kat = Katachi(os.path.join(self.libdir, names.soname))

    def pkg_config(self, *flags):
        return output(["pkg-config", *flags, "katachi"], self.env).split()

    def compile(self, compiler, source, exe, before, libs):
        flags = CXX_FLAGS if compiler == "g++" else C_FLAGS
        cmd = [compiler, *flags, "-g", *before, source, "-o", exe, *libs]
        print(f"# $ {shlex.join(cmd)}", flush=True)
        output(cmd, self.env)

    def run(self, exe, *args):
        cmd = (VALGRIND if self.valgrind else []) + [exe, *args]
        print(f"# $ {shlex.join(cmd)}", flush=True)
        p = subprocess.run(cmd, capture_output=True, text=True, cwd=self.work)
        sys.stdout.write(p.stdout)
        sys.stderr.write(p.stderr)
        return p.returncode == 0, p.stdout, p.stderr

    def rpath(self):
        return f"-Wl,-rpath,{self.libdir}"


def check_pkg_config(env, args):
    v = env.pkg_config("--modversion")
    check(v == [env.names.version], f"pkg-config --modversion: {v}")
    c = env.pkg_config("--cflags")
    check(c == [f"-I{os.path.join(env.prefix, 'include', 'katachi')}"], f"--cflags: {c}")
    want = [f"-L{env.libdir}", "-lkatachi"]
    libs = env.pkg_config("--libs")
    check(libs == want, f"--libs: {libs}")
    static = env.pkg_config("--static", "--libs")
    check(static[:2] == want and all(l in static for l in args.native_static_libs.split()),
          f"--static --libs: {static} (rustc's native-static-libs after -lkatachi)")


def check_resolves_to_prefix(env, exe):
    _, needed = readelf(exe)
    check(env.names.soname in needed, f"{os.path.basename(exe)} needs {env.names.soname}")
    ldd = output(["ldd", exe])
    found = None
    for line in ldd.splitlines():
        name, _, rest = line.strip().partition(" => ")
        if name == env.names.soname:
            found = rest.split(" (")[0].strip()
    expected = os.path.join(env.libdir, env.names.soname)
    check(found == expected, f"{os.path.basename(exe)}: the loader finds {found}, "
          f"expected {expected} (the prefix)")


def printed_counts(stdout, label):
    m = re.search(rf"^{re.escape(label)}: (\d+) vertices, (\d+) faces$", stdout, re.M)
    return (int(m.group(1)), int(m.group(2))) if m else None


def check_example_run(env, exe, levels, tag):
    model = env.kat.read(MODEL)
    result = os.path.join(env.work, f"{tag}.off")
    ok, stdout, stderr = env.run(exe, MODEL, result, *([str(levels)] if levels else []))
    if not check(ok, f"{tag}: the example runs" + ("" if ok else f":\n{stderr}")):
        return
    levels = levels or 1
    out = env.kat.read(result)
    want = MODEL_QUADS * 4 ** levels
    check(len(out.faces) == want and all(len(f) == 4 for f in out.faces),
          f"{tag}: it writes {len(out.faces)} faces, expected {want} quads "
          f"(4^{levels} x {MODEL_QUADS})")
    label = f"after {levels} level{'' if levels == 1 else 's'}"
    check(printed_counts(stdout, label) == (len(out.positions), len(out.faces)),
          f"{tag}: it prints the file's counts `{label}`")
    check(printed_counts(stdout, "input") == (len(model.positions), MODEL_QUADS),
          f"{tag}: it prints the input's counts")


def test_shared_example(env):
    exe = os.path.join(env.work, "subdivide")
    env.compile("gcc", EXAMPLE, exe, env.pkg_config("--cflags"),
                env.pkg_config("--libs") + [env.rpath()])
    check_resolves_to_prefix(env, exe)
    check_example_run(env, exe, 2, "shared-2-levels")
    check_example_run(env, exe, None, "shared-default-levels")
    result = os.path.join(env.work, "must-not-exist.off")
    missing = os.path.join(env.work, "no-such-model.off")
    for what, argv, needle in (
            ("a missing input", [missing, result], "no-such-model.off"),
            ("9 levels", [MODEL, result, "9"], "levels"),
            ("a bad output extension", [MODEL, "out.xyz", "1"], "out.xyz")):
        ok, _, stderr = env.run(exe, *argv)
        check(not ok and "subdivide: " in stderr and needle in stderr
              and not os.path.exists(result),
              f"the example with {what} fails with katachi's message naming {needle!r} and "
              "writes nothing")


def test_cpp(env):
    d = os.path.join(ROOT, "tests", "c", "installed")
    sources = sorted(f for f in os.listdir(d) if f.endswith(".cpp"))
    check(bool(sources), f"C++ programs in {d}")
    before = env.pkg_config("--cflags") + [
        f'-DKATACHI_EXPECTED_VERSION="{env.names.version}"']
    for src in sources:
        stem = src[:-4]
        exe = os.path.join(env.work, stem)
        env.compile("g++", os.path.join(d, src), exe, before,
                    env.pkg_config("--libs") + [env.rpath()])
        check_resolves_to_prefix(env, exe)
        ok, stdout, _ = env.run(exe, MODEL)
        last = (stdout.strip().splitlines() or [""])[-1]
        m = re.fullmatch(r"(\d+) passed, 0 failed", last)
        check(ok and m is not None and int(m.group(1)) > 0,
              f"{stem}: exits 0 and ends with `N passed, 0 failed` ({last!r})")


def test_static_example(env):
    exe = os.path.join(env.work, "subdivide_static")
    # -lkatachi would pick libkatachi.so from the same directory; name the archive instead.
    libs = ["-l:libkatachi.a" if w == "-lkatachi" else w
            for w in env.pkg_config("--static", "--libs")]
    check("-l:libkatachi.a" in libs, f"pkg-config --static --libs names katachi: {libs}")
    env.compile("gcc", EXAMPLE, exe, env.pkg_config("--cflags"), libs)
    _, needed = readelf(exe)
    check(not any("katachi" in n for n in needed),
          f"the static example needs no katachi library ({needed})")
    check_example_run(env, exe, 1, "static-1-level")


def test_destdir(args, names):
    staged = os.path.join(args.destdir, args.destdir_prefix.lstrip("/"))
    libdir = os.path.join(staged, args.destdir_libdir)
    check_layout("DESTDIR", libdir, os.path.join(staged, "include"), names, args)
    pc = open(os.path.join(libdir, "pkgconfig", "katachi.pc")).read()
    check(f"prefix={args.destdir_prefix}" in pc.splitlines()
          and f"libdir=${{exec_prefix}}/{args.destdir_libdir}" in pc.splitlines()
          and args.destdir not in pc,
          f"DESTDIR: the .pc file names {args.destdir_prefix}, not the staging directory")


def main():
    ap = argparse.ArgumentParser()
    for a in ("--prefix", "--destdir", "--destdir-prefix", "--destdir-libdir",
              "--built-library", "--version", "--native-static-libs", "--work"):
        ap.add_argument(a, required=True)
    ap.add_argument("--no-valgrind", action="store_true")
    args = ap.parse_args()
    names = Names(args.version)
    steps = [
        ("layout", lambda: check_layout("prefix", os.path.join(args.prefix, "lib"),
                                        os.path.join(args.prefix, "include"), names, args)),
        ("DESTDIR", lambda: test_destdir(args, names)),
    ]
    for name, step in steps:
        try:
            step()
        except Exception as e:  # a broken step is a failed check; the others still run
            check(False, f"{name}: {e}")
    env = Env(args, names)
    for name, step in (("pkg-config", lambda: check_pkg_config(env, args)),
                       ("shared example", lambda: test_shared_example(env)),
                       ("C++ programs", lambda: test_cpp(env)),
                       ("static example", lambda: test_static_example(env))):
        try:
            step()
        except Exception as e:
            check(False, f"{name}: {e}")
    print(f"{passed} passed, {failed} failed", flush=True)
    sys.exit(0 if failed == 0 and passed > 0 else 1)


if __name__ == "__main__":
    main()
