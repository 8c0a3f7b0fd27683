"""The MeshLab plugin in MeshLab 2020.09 (Debian 12's), through meshlabserver.

    python3 run_meshlabserver.py --meshlabserver PREFIX/bin/meshlabserver --katachi CLI \
        --lib libkatachi.so --models DIR --work DIR [-k NAME]

Run by `cargo xtask meshlab-plugin --test`, with meshlabserver from a private prefix where
the plugin is installed (MeshLab 2020.09 loads plugins only from beside its executable).
Each case writes a filter script (.mlx), runs `xvfb-run -a meshlabserver -i IN -o OUT.off
-s SCRIPT`, reads OUT.off with katachi's reader and compares it with the katachi CLI given
the same options (cases.py). A bad input must make meshlabserver exit with an error (not a
signal), print katachi's message and write nothing: meshlabserver stops at a failing filter
without saving, so that the layer is left unchanged is checked in memory by the harness
(plugin_harness.cpp) instead. Ends with `N passed, M failed`.

License: MIT OR Apache-2.0.
"""

import argparse
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(os.path.dirname(HERE), "python")]

import cases  # noqa: E402
from katachi_mesh import Katachi  # noqa: E402


def meshlabserver(args, name, input_path, script):
    """Runs the script `script` on `input_path`; returns (output path, exit code, log)."""
    mlx = os.path.join(args.work, f"{name}.mlx")
    with open(mlx, "w") as f:
        f.write(script)
    out = os.path.join(args.work, f"{name}_meshlab.off")
    cmd = ["xvfb-run", "-a", args.meshlabserver, "-i", input_path, "-o", out, "-s", mlx]
    print(f"# $ {' '.join(cmd)}", flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True, errors="replace")
    return out, p.returncode, p.stdout + p.stderr


def ran_ok(run, name, out, code, log):
    ok = code == 0 and os.path.isfile(out)
    run.check(ok, f"{name}: meshlabserver applies the filter and writes the result"
              + ("" if ok else f" (exit {code}); its output:\n{log}"))
    return ok


def subdivision(run, args, kat, name, path, opts):
    out, code, log = meshlabserver(args, name, path, opts.mlx())
    if not ran_ok(run, name, out, code, log):
        return
    summary = f"katachi: {opts.levels} levels:"
    run.check(summary in log, f"{name}: the filter's log has `{summary}`")
    cli_out = os.path.join(args.work, f"{name}_cli.off")
    cases.run_cli(args.katachi, ["subdivide", path, cli_out] + opts.cli_args())
    try:
        run.check(True, f"{name}: {cases.compare(kat.read(out), kat.read(cli_out))}")
    except AssertionError as e:
        run.check(False, f"{name}: MeshLab's result differs from the CLI's: {e}")


def refused(run, name, input_path, script, filter_name, message):
    out, code, log = meshlabserver(args_global, name, input_path, script)
    # xvfb-run passes the server's exit code on; a crash is a negative code (a signal) or
    # 128 + signal.
    crashed = code < 0 or 129 <= code <= 159 or "Segmentation fault" in log or "Aborted" in log
    run.check(code != 0 and not crashed,
              f"{name}: meshlabserver exits with an error, not a crash (exit {code})")
    run.check(message in log, f"{name}: its output has katachi's message `{message}`"
              + ("" if message in log else f"; it is:\n{log}"))
    run.check(f"Problem with filter: {filter_name}" in log,
              f"{name}: meshlabserver reports the failing filter")
    run.check(not os.path.exists(out), f"{name}: no output is written")


def view_proj_from_log(log):
    """The view-projection matrix the filter logs (`katachi: view: … y down): m0 … m15`)."""
    line = next((l for l in log.splitlines() if "katachi: view:" in l), None)
    if line is None or "y down):" not in line:
        raise AssertionError(f"the log has no `katachi: view:` line:\n{log}")
    m = [float(t) for t in line.split("y down):", 1)[1].split()]
    if len(m) != 16:
        raise AssertionError(f"{len(m)} numbers in `{line}`, not 16")
    return m


def cut(run, args, kat, case):
    name = case.name
    out, code, log = meshlabserver(args, name, case.input, case.mlx())
    if not ran_ok(run, name, out, code, log):
        return
    w, h = case.camera.viewport
    run.check("katachi: cut by polyline (" in log and f"{w} x {h} pixels" in log,
              f"{name}: the log reports the cut in the {w} x {h} view")
    view_proj = view_proj_from_log(log)
    stroke = os.path.join(args.work, f"{name}_stroke.json")
    with open(stroke, "w") as f:
        f.write(case.stroke_json(view_proj))
    cli_out = os.path.join(args.work, f"{name}_cli.off")
    cases.run_cli(args.katachi, ["cut", case.input, cli_out, "--stroke", stroke]
                  + case.cli_args())
    ml, before = kat.read(out), kat.read(case.input)
    run.check(len(ml.faces) > len(before.faces),
              f"{name}: {len(before.faces)} -> {len(ml.faces)} triangles")
    try:
        run.check(True, f"{name}: {cases.compare_indexed(ml, kat.read(cli_out))}")
    except AssertionError as e:
        run.check(False, f"{name}: MeshLab's result differs from the CLI's: {e}")


args_global = None


def main():
    global args_global
    ap = argparse.ArgumentParser()
    for a in ("--meshlabserver", "--katachi", "--lib", "--models", "--work"):
        ap.add_argument(a, required=True)
    ap.add_argument("-k")
    args = args_global = ap.parse_args()
    run = cases.Run("meshlabserver 2020.09", args.k)
    kat = Katachi(args.lib)

    run.case("self_test", lambda: cases.self_test(run))
    for name, path, opts in cases.subdivision_cases(args.models, args.work, kat, "off"):
        run.case(name, lambda name=name, path=path, opts=opts:
                 subdivision(run, args, kat, name, path, opts))
    for name, (positions, faces), opts, message in cases.BAD_SUBDIVISIONS:
        def bad(name=name, positions=positions, faces=faces, opts=opts, message=message):
            path = os.path.join(args.work, f"{name}.off")
            with open(path, "w") as f:
                f.write(cases.off_text(positions, faces))
            refused(run, name, path, cases.Subdivision.of(opts).mlx(), cases.SUBDIVIDE,
                    message)
        run.case(name, bad)
    cut_cases, bad_cuts = cases.cut_cases(args.models, args.work, kat)
    for case in cut_cases:
        run.case(case.name, lambda case=case: cut(run, args, kat, case))
    for case, no_view, message in bad_cuts:
        def bad_cut(case=case, no_view=no_view, message=message):
            script = case.mlx()
            if no_view:  # an empty value: a 2020.09 script may omit only the first parameter
                script = script.replace(cases.xml_escape(case.camera.xml()), "")
            refused(run, case.name, case.input, script, cases.CUT, message)
        run.case(case.name, bad_cut)
    run.finish()


if __name__ == "__main__":
    main()
