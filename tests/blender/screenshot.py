"""Renders the katachi operator's redo panel in Blender's UI and saves a screenshot.

    xvfb-run -a blender --factory-startup --python tests/blender/screenshot.py -- \\
        --zip target/addon/katachi-0.1.0.zip --out docs/images/blender_subdivide.png

(``cargo xtask blender-screenshot`` runs this.) The add-on is installed from its zip, the
default cube gets creased edges, the operator runs in the 3D viewport as if chosen from
Object ▸ katachi, and once its "Subdivide (solid-aware)" panel is drawn the window is
saved and Blender quits. Any failure quits with exit status 1.
"""

import argparse
import os
import sys
import traceback

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from addon_install import install  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--zip", required=True)
parser.add_argument("--out", required=True)
ARGS = parser.parse_args(argv)


def view3d():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return window, area, region


def fail():
    traceback.print_exc()
    sys.stdout.flush()
    os._exit(1)


def run_operator():
    try:
        cube = bpy.data.objects["Cube"]
        me = cube.data
        for e in me.edges:
            if all(me.vertices[v].co.z > 0 for v in e.vertices):
                e.crease = 1.0
        for o in bpy.context.scene.objects:
            o.select_set(o == cube)
        bpy.context.view_layer.objects.active = cube
        window, area, region = view3d()
        with bpy.context.temp_override(window=window, area=area, region=region):
            bpy.ops.view3d.view_selected()
            bpy.ops.view3d.zoom(delta=-3)
            # undo=True: called as the menu would, so the operator is registered for redo.
            result = bpy.ops.katachi.subdivide(
                "INVOKE_DEFAULT", True, levels=2, recover_holes=True
            )
        if result != {"FINISHED"}:
            raise RuntimeError(f"katachi.subdivide returned {result}")
        if len(cube.data.polygons) != 96:
            raise RuntimeError("the cube was not subdivided")
    except Exception:
        fail()
    return None


def open_panel():
    """Clicks the collapsed "Subdivide (solid-aware)" panel in the viewport's corner open
    (Blender runs with --enable-event-simulate, so the click is a simulated event)."""
    try:
        window, area, _ = view3d()
        hud = next((r for r in area.regions if r.type == "HUD"), None)
        if hud is None or hud.width <= 1:
            raise RuntimeError("the operator's redo panel (HUD region) is not shown")
        x, y = hud.x + 40, hud.y + hud.height // 2
        window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        window.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
        window.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
        window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=700, y=500)
    except Exception:
        fail()
    return None


def save():
    try:
        window, area, region = view3d()
        with bpy.context.temp_override(window=window, area=area, region=region):
            bpy.ops.screen.screenshot(filepath=ARGS.out)
        if not os.path.isfile(ARGS.out):
            raise RuntimeError(f"no screenshot at {ARGS.out}")
        print(f"screenshot: wrote {ARGS.out}")
    except Exception:
        fail()
    bpy.ops.wm.quit_blender()
    return None


install(ARGS.zip)
bpy.app.timers.register(run_operator, first_interval=1.0)
bpy.app.timers.register(open_panel, first_interval=2.0)
bpy.app.timers.register(save, first_interval=3.5)
