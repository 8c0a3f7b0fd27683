"""Runs the katachi add-on's tests (``cases.py``, then the stroke cut's ``cut_cases.py``)
inside Blender, after installing the add-on's zip the way a user does.

    blender -b --factory-startup --python-exit-code 1 --python tests/blender/run_tests.py -- \\
        --zip target/addon/katachi-0.1.0.zip --cli target/release/katachi --work DIR
    python -c 'import bpy' && python tests/blender/run_tests.py --zip … --cli … --work DIR

Blender 3.4 installs it as a legacy add-on (Preferences ▸ Add-ons ▸ Install), Blender 4.2
and later as an extension (Preferences ▸ Get Extensions ▸ Install from Disk). The last line
printed is ``N passed, M failed``; any failure ends the run with an exception, which makes
``--python-exit-code 1`` (or the Python interpreter, for the bpy module) exit non-zero.
``cargo xtask blender-test`` runs this in both Blender versions.
"""

import argparse
import os
import sys
import time
import traceback

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import cases  # noqa: E402  (needs the path above)
import cut_cases  # noqa: E402
from addon_install import install  # noqa: E402


def parse_args():
    argv = sys.argv
    argv = argv[argv.index("--") + 1:] if "--" in argv else argv[1:]
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--zip", required=True, help="the add-on zip made by cargo xtask addon")
    p.add_argument("--cli", required=True, help="the katachi command-line tool")
    p.add_argument("--work", required=True, help="a scratch directory for meshes")
    p.add_argument("-k", dest="only", default="", help="run only tests whose name has this")
    return p.parse_args(argv)


def main():
    args = parse_args()
    os.makedirs(args.work, exist_ok=True)
    print(f"katachi blender tests: Blender {bpy.app.version_string}, zip {args.zip}")
    addon = install(args.zip)
    cases.setup(addon=addon, zip_path=args.zip, cli=args.cli, work=args.work)
    passed, failed = 0, []
    for name, fn in cases.TESTS + cut_cases.TESTS:
        if args.only and args.only not in name:
            continue
        t = time.time()
        try:
            cases.fresh_scene()
            fn()
        except Exception:
            failed.append(name)
            print(f"FAIL {name}\n{traceback.format_exc()}", flush=True)
        else:
            passed += 1
            print(f"ok   {name} ({time.time() - t:.1f} s)", flush=True)
    print(f"Blender {bpy.app.version_string}: {passed} passed, {len(failed)} failed")
    # The closing line xtask reads.
    print(f"{passed} passed, {len(failed)} failed", flush=True)
    if failed:
        raise RuntimeError(f"katachi blender tests failed: {', '.join(failed)}")


main()
