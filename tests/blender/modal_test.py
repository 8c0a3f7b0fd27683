"""The Cut by Stroke tool driven by simulated mouse and keyboard events in a real Blender window.

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --enable-event-simulate \\
        --window-geometry 0 0 1280 800 --python-exit-code 1 SCENE.blend \\
        --python tests/blender/modal_test.py -- --zip target/addon/katachi-0.1.0.zip --out DIR

(``cargo xtask blender-test`` runs this with Debian's Blender 3.4; the ``bpy`` module has no
windows, so it cannot.) Blender's ``--enable-event-simulate`` ignores the real input and
lets ``Window.event_simulate`` feed events; each step below is a timer, so Blender handles
the events of one step (and redraws) before the next one runs.

The cases: the toolbar tool (a left-button drag, then release) cuts the grid in Edit mode,
the stroke is drawn over the viewport while dragging (seen in a screenshot), the cut edges
are selected, and the redo panel's way of running it again (the last operator's settings
changed, then ``ed.undo_redo``) cuts the recorded stroke again; the result matches the
katachi library called on the mesh from before with the stroke and view the operator
recorded. Esc cancels with the mesh untouched. The menu entry waits for the press, and
Enter cuts before the button is released. The last line printed is ``N passed, M
failed``; any failure exits with status 1.
"""

import argparse
import math
import os
import sys
import traceback

import bmesh
import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from addon_install import install  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--zip", required=True)
parser.add_argument("--out", required=True, help="a scratch directory (screenshots)")
parser.add_argument("-k", dest="only", default="", help="run only cases whose name has this")
ARGS = parser.parse_args(argv)

ADDON = None
RESULTS = []  # (name, error or None)
LAST = {}  # the library's answer for the last cut checked
STROKE_COLOUR = (1.0, 0.55, 0.1)


def view3d():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return window, area, region


def override():
    window, area, region = view3d()
    return bpy.context.temp_override(window=window, area=area, region=region)


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def grid():
    return bpy.data.objects["Grid"]


def edit_mesh():
    return bmesh.from_edit_mesh(grid().data)


def state():
    bm = edit_mesh()
    return (
        len(bm.verts),
        len(bm.faces),
        sorted(tuple(sorted(v.index for v in e.verts)) for e in bm.edges if e.select),
    )


def window_point(u, v):
    """The window coordinates of the point at (u, v) of the viewport region (0..1, y up)."""
    _, _, region = view3d()
    return int(region.x + u * region.width), int(region.y + v * region.height)


def stroke_path(n=24, v0=0.35, v1=0.62):
    """A stroke across the grid, left to right with a gentle wave, in window coordinates."""
    return [window_point(0.3 + 0.4 * i / (n - 1),
                         v0 + (v1 - v0) * i / (n - 1) + 0.03 * math.sin(6.0 * i / (n - 1)))
            for i in range(n)]


def simulate(kind, value="NOTHING", at=None, **keys):
    window, _, _ = view3d()
    x, y = at if at is not None else (0, 0)
    window.event_simulate(type=kind, value=value, x=x, y=y, **keys)


# ---------------------------------------------------------------------------- steps

# Each step is (name, function); a function may return a list of sub-steps run one per
# timer tick (events are handled between ticks).


def step_setup():
    global ADDON
    ADDON = install(ARGS.zip)
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=10, y_subdivisions=10, size=6.0)
    g = bpy.context.object
    g.name = "Grid"
    with override():
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="DESELECT")
        bpy.ops.view3d.view_axis(type="TOP")
        bpy.ops.view3d.view_selected()
    bpy.ops.ed.undo_push(message="setup")


def case_tool_drag():
    """The toolbar tool: press, drag, release; then the redo panel's way of running it again
    with other settings."""
    before = state()
    snapshot_mesh()
    with override():
        bpy.ops.wm.tool_set_by_id(name="katachi.cut_by_stroke_tool")
    path = stroke_path()
    ticks = [lambda: simulate("MOUSEMOVE", at=path[0]),
             lambda: simulate("LEFTMOUSE", "PRESS", at=path[0])]
    for p in path[1:]:
        ticks.append(lambda p=p: simulate("MOUSEMOVE", at=p))
    ticks.append(lambda: screenshot_check("drawing.png", path))
    ticks.append(lambda: simulate("LEFTMOUSE", "RELEASE", at=path[-1]))
    ticks.append(lambda: check_cut(before, "the tool"))
    ticks.append(redo_all_triangles)
    ticks.append(library_step)
    return ticks


def redo_all_triangles():
    """The redo panel: the last operator's settings changed, then undo and run it again
    (``ed.undo_redo``, what the panel does); the recorded stroke is cut again, now with
    every face as katachi's triangles."""
    op = bpy.context.window_manager.operators[-1]
    check(op.bl_idname == "KATACHI_OT_cut_by_stroke", f"the last operator is {op.bl_idname}")
    op.properties.keep_polygons = False
    with override():
        result = bpy.ops.ed.undo_redo()
    check(result == {"FINISHED"}, f"undo_redo returned {result}")
    bm = edit_mesh()
    check(all(len(f.verts) == 3 for f in bm.faces), "the redo kept quads")
    op = bpy.context.window_manager.operators[-1]
    check(len(op.properties.stroke) >= 10, "the redo lost the stroke")
    LAST["triangles"] = len(bm.faces)


def library_step():
    """The library, on the mesh as it was before the cut, with the stroke and view the
    operator kept: the same vertices (and, after the redo with every face a triangle, the
    same faces)."""
    info = library_cut(LAST["recorded"])
    n_verts, n_faces, _ = state()
    check(n_verts == info.vertex_count,
          f"{n_verts} vertices, the library {info.vertex_count} for the recorded stroke")
    if "triangles" in LAST:
        check(n_faces == info.face_count,
              f"the redo made {n_faces} triangles, the library {info.face_count}")


def snapshot_mesh():
    """A copy of the edit mesh as it is now, for the library to cut later."""
    obj = grid()
    obj.update_from_editmode()
    LAST.clear()
    mesh = obj.data.copy()  # (undo would take a copy kept until later away: keep arrays)
    try:
        LAST["input"] = ADDON.convert.InputMesh(mesh)
    finally:
        bpy.data.meshes.remove(mesh)


def screenshot_check(name, path):
    """The stroke is drawn over the viewport while the button is held: the screenshot has
    the stroke's colour along it."""
    out = os.path.join(ARGS.out, name)
    with override():
        bpy.ops.screen.screenshot(filepath=out)
    image = bpy.data.images.load(out)
    try:
        w, h = image.size
        px = image.pixels[:]
        hits = 0
        for x, y in path[2:-2]:
            found = False
            for dx in range(-3, 4):
                for dy in range(-3, 4):
                    i = 4 * ((y + dy) * w + (x + dx))
                    r, g, b = px[i], px[i + 1], px[i + 2]
                    if abs(r - STROKE_COLOUR[0]) < 0.2 and abs(g - STROKE_COLOUR[1]) < 0.2 and b < 0.35:
                        found = True
            hits += found
        check(hits >= len(path[2:-2]) * 0.8,
              f"the stroke's colour is at {hits} of {len(path) - 4} stroke points in {out}")
    finally:
        bpy.data.images.remove(image)


def check_cut(before, how):
    after = state()
    check(after[1] > before[1], f"{how}: {before[1]} -> {after[1]} faces: nothing was cut")
    check(after[2], f"{how}: no edge is selected after the cut")
    op = bpy.context.window_manager.operators[-1]
    check(op.bl_idname == "KATACHI_OT_cut_by_stroke", f"the last operator is {op.bl_idname}")
    props = op.properties
    recorded = {
        "pixels": [c for p in props.stroke for c in p.co],
        "matrix": list(props.view_matrix),
        "size": tuple(props.view_size),
        "mode": props.mode,
    }
    check(len(recorded["pixels"]) >= 20, f"{how}: the operator kept {len(recorded['pixels']) // 2} stroke points")
    LAST["recorded"] = recorded


def library_cut(recorded):
    obj = grid()
    ffi, convert = ADDON.ffi, ADDON.convert
    lib = ffi.load()
    m = recorded["matrix"]
    from mathutils import Matrix

    vp_world = Matrix([m[4 * r:4 * r + 4] for r in range(4)]) @ obj.matrix_world
    vp = [vp_world[r][c] for c in range(4) for r in range(4)]
    size = recorded["size"]
    options = lib.katachi_cut_options_default()
    options.mode = getattr(ffi, f"KATACHI_CUT_MODE_{recorded['mode']}")
    with convert.to_katachi(lib, LAST["input"]) as km:
        with ffi.cut_by_stroke(lib, km, recorded["pixels"], vp, [0, 0, size[0], size[1]], options) as c:
            return c.info()


def case_escape_cancels():
    before = state()
    path = stroke_path(v0=0.7, v1=0.4)
    ticks = [lambda: simulate("MOUSEMOVE", at=path[0]),
             lambda: simulate("LEFTMOUSE", "PRESS", at=path[0])]
    for p in path[1:12]:
        ticks.append(lambda p=p: simulate("MOUSEMOVE", at=p))
    ticks.append(lambda: simulate("ESC", "PRESS", at=path[11]))
    ticks.append(lambda: simulate("ESC", "RELEASE", at=path[11]))
    ticks.append(lambda: simulate("LEFTMOUSE", "RELEASE", at=path[11]))
    ticks.append(lambda: check(state() == before, "Esc changed the mesh"))
    return ticks


def case_menu_then_enter():
    """Mesh ▸ katachi ▸ Cut by Stroke waits for the press; Enter cuts before the release."""
    before = state()
    snapshot_mesh()
    with override():
        bpy.ops.wm.tool_set_by_id(name="builtin.select_box")
    path = stroke_path(n=16, v0=0.6, v1=0.3)

    def invoke():
        with override():
            result = bpy.ops.katachi.cut_by_stroke("INVOKE_DEFAULT", True)
        check(result == {"RUNNING_MODAL"}, f"invoking from the menu returned {result}")

    ticks = [lambda: simulate("MOUSEMOVE", at=path[0]), invoke,
             lambda: check(state() == before, "the tool cut before any stroke"),
             lambda: simulate("LEFTMOUSE", "PRESS", at=path[0])]
    for p in path[1:]:
        ticks.append(lambda p=p: simulate("MOUSEMOVE", at=p))
    ticks.append(lambda: simulate("RET", "PRESS", at=path[-1]))
    ticks.append(lambda: simulate("RET", "RELEASE", at=path[-1]))
    ticks.append(lambda: simulate("LEFTMOUSE", "RELEASE", at=path[-1]))
    ticks.append(lambda: check_cut(before, "the menu entry and Enter"))
    ticks.append(library_step)
    return ticks


CASES = [(name, fn) for name, fn in (
    ("window_cut_tool_drag", case_tool_drag),
    ("window_cut_escape_cancels", case_escape_cancels),
    ("window_cut_menu_then_enter", case_menu_then_enter),
) if ARGS.only in name]


# ---------------------------------------------------------------------------- driver


def finish():
    passed = sum(1 for _, e in RESULTS if e is None)
    failed = [n for n, e in RESULTS if e is not None]
    print(f"Blender {bpy.app.version_string} (window): {passed} passed, {len(failed)} failed")
    print(f"{passed} passed, {len(failed)} failed", flush=True)
    os._exit(1 if failed or not (passed or not CASES) else 0)


def runner():
    """A generator of timer steps: setup, then each case's ticks; a failure ends its case."""
    try:
        step_setup()
    except Exception:
        traceback.print_exc()
        RESULTS.append(("setup", "failed"))
        return
    yield
    for name, case in CASES:
        error = None
        try:
            ticks = case() or []
            yield
            for tick in ticks:
                tick()
                yield
        except Exception:
            error = traceback.format_exc()
            print(f"FAIL {name}\n{error}", flush=True)
            # Leave any modal operator and button state behind.
            simulate("ESC", "PRESS")
            simulate("ESC", "RELEASE")
            simulate("LEFTMOUSE", "RELEASE")
            yield
        else:
            print(f"ok   {name}", flush=True)
        RESULTS.append((name, error))


STEPS = runner()


def tick():
    try:
        next(STEPS)
    except StopIteration:
        finish()
        return None
    except Exception:
        traceback.print_exc()
        RESULTS.append(("driver", "failed"))
        finish()
        return None
    return 0.15


os.makedirs(ARGS.out, exist_ok=True)
bpy.app.timers.register(tick, first_interval=1.0)
