"""The Cut by Stroke tool as a user feels it: from the release of the mouse button to the
redrawn result, in a real Blender 3.4 window under Xvfb fed simulated events
(``cargo xtask blender-bench`` runs this after ``bench.py``):

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --enable-event-simulate \\
        --window-geometry 0 0 1280 800 --python-exit-code 1 SCENE.blend \\
        --python benches/blender/modal_bench.py -- --zip Z --out DIR [--rounds 5]

The mesh is the ico sphere of 327,680 triangles of ``bench.py`` (with a UV map), in Object
mode, filling the 3D Viewport. Each round, in rotating order:

- **katachi modal**: the tool is invoked (the menu entry), a 50-point stroke is dragged across
  the sphere (button press and moves in one timer tick), and the release is sent in the
  next; the clock starts when the release is sent and stops at the first redraw of the
  viewport that shows the new mesh (a draw handler notes it);
- **floor**: the floor of ``bench.py`` (read the input's arrays, build the same result from
  arrays, swap it in), run as an operator from a timer tick, timed the same way: from the
  call to the first redraw showing the new mesh.

Drawing is Xvfb's software OpenGL, so the redraw costs more than on a desktop's GPU; both
variants pay it. Lines ``BENCH`` + tab-separated fields are the measurements (host
``3.4.x window``), ``BENCH-DONE`` closes a complete run.
"""

import argparse
import math
import os
import sys
import time
import traceback

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "blender"))
sys.path.insert(0, HERE)
from addon_install import install  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--zip", required=True)
parser.add_argument("--out", required=True, help="a scratch directory")
parser.add_argument("--rounds", type=int, default=5)
ARGS = parser.parse_args(argv)

# bench.py's helpers (its main() runs only when it is the script Blender was given).
import bench  # noqa: E402

CASE = "modal cut 330k"
STATE = {"base": None, "pointer": None, "t0": None, "drawn": None}


def view3d():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return window, area, region


def override():
    window, area, region = view3d()
    return bpy.context.temp_override(window=window, area=area, region=region)


def on_draw():
    """Notes the first redraw that shows the new mesh."""
    obj = bpy.context.view_layer.objects.active
    if STATE["t0"] is None or STATE["drawn"] is not None or obj is None:
        return
    if obj.data.as_pointer() != STATE["pointer"]:
        STATE["drawn"] = time.perf_counter()


def window_point(u, v):
    _, _, region = view3d()
    return int(region.x + u * region.width), int(region.y + v * region.height)


def stroke_path(n=50):
    return [window_point(0.25 + 0.5 * i / (n - 1), 0.5 + 0.03 * math.sin(6.0 * i / (n - 1)))
            for i in range(n)]


def simulate(kind, value="NOTHING", at=(0, 0)):
    window, _, _ = view3d()
    window.event_simulate(type=kind, value=value, x=at[0], y=at[1])


def fresh():
    obj = bench.fresh_object(STATE["base"], "Ball")
    STATE["pointer"] = obj.data.as_pointer()
    STATE["t0"] = STATE["drawn"] = None
    return obj


def setup():
    install(ARGS.zip)
    bpy.utils.register_class(bench.BENCH_OT_floor)
    bpy.context.preferences.edit.undo_steps = 2
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    STATE["base"] = bench.ico_sphere(8)
    fresh()
    with override():
        bpy.ops.view3d.view_axis(type="FRONT")
        bpy.ops.view3d.view_selected()
    bpy.types.SpaceView3D.draw_handler_add(on_draw, (), "WINDOW", "POST_PIXEL")


def modal_ticks(round_):
    path = stroke_path()

    def start():
        fresh()
        with override():
            result = bpy.ops.katachi.cut_by_stroke("INVOKE_DEFAULT", True)
        if result != {"RUNNING_MODAL"}:
            raise RuntimeError(f"invoking the tool returned {result}")

    def drag():
        simulate("MOUSEMOVE", at=path[0])
        simulate("LEFTMOUSE", "PRESS", at=path[0])
        for p in path[1:]:
            simulate("MOUSEMOVE", at=p)

    def release():
        STATE["t0"] = time.perf_counter()
        simulate("LEFTMOUSE", "RELEASE", at=path[-1])

    return [start, drag, release, lambda: done("katachi modal", round_)]


def floor_ticks(round_):
    def build_result():
        # The floor's result: the tool's own, from the stroke and view it recorded.
        op = bpy.context.window_manager.operators[-1]
        if op.bl_idname != "KATACHI_OT_cut_by_stroke":
            raise RuntimeError(f"the last operator is {op.bl_idname}")
        obj = bpy.context.view_layer.objects.active
        bench.BENCH_OT_floor.result = bench.Arrays(obj.data, selection=True)

    def call():
        STATE["t0"] = time.perf_counter()
        with override():
            result = bpy.ops.katachi_bench.floor("EXEC_DEFAULT", True)
        if result != {"FINISHED"}:
            raise RuntimeError(f"the floor returned {result}")

    ticks = [fresh, call, lambda: done("floor", round_)]
    return ([build_result] if bench.BENCH_OT_floor.result is None else []) + ticks


def done(variant, round_):
    """Waits (re-running this tick) until the new mesh was drawn, then notes the time."""
    if STATE["drawn"] is None:
        if time.perf_counter() - STATE["t0"] > 120.0:
            raise RuntimeError(f"{variant}: no redraw with the new mesh within 120 s")
        return "again"
    bench.emit(CASE, variant, round_, STATE["drawn"] - STATE["t0"], load=bench.load())
    return None


def steps():
    setup()
    yield
    # The floor needs the tool's result: the first round runs the tool first.
    for r in range(ARGS.rounds):
        order = [modal_ticks, floor_ticks] if r % 2 == 0 else [floor_ticks, modal_ticks]
        for make in order:
            for tick in make(r):
                while tick() == "again":
                    yield
                yield


STEPS = steps()


def tick():
    try:
        next(STEPS)
    except StopIteration:
        print(f"BENCH-DONE load {bench.load()}", flush=True)
        os._exit(0)
    except Exception:
        traceback.print_exc()
        os._exit(1)
    return 0.05


os.makedirs(ARGS.out, exist_ok=True)
print(f"katachi modal bench: Blender {bpy.app.version_string} (window), load {bench.load()}",
      flush=True)
bench.VERSION = bpy.app.version_string + " window"
bpy.app.timers.register(tick, first_interval=1.0)
