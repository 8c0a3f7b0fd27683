"""The Cut by Stroke tests, run by run_tests.py inside Blender 3.4 and 5.0 after cases.py.

The strokes are annotations drawn with Blender's own Annotate operator
(``bpy.ops.gpencil.annotate``, given the mouse path), as a user draws them, and the cut is
``bpy.ops.katachi.cut_by_annotation`` (the tool's scriptable form) or
``bpy.ops.katachi.cut_by_stroke`` run with a stroke. The oracles are independent of the
add-on's conversion:

- the katachi library called directly through ctypes on the same mesh, with the stroke's
  pixels computed by Blender's own projection helpers (``view3d_utils`` for the 3D
  Viewport, ``world_to_camera_view`` for a camera): same face, vertex and path counts, the
  same cut edges selected;
- geometry that katachi cannot get wrong without the test noticing: with snapping off on a
  flat grid, UVs that are a linear function of position stay that function, each face's
  material and smooth flag is its grid cell's, creased and seam edges are the halves of
  the input's;
- the mesh before the call, for undo and for every error.
"""

import math

import bpy
from bpy_extras import object_utils, view3d_utils
from mathutils import Vector, geometry

import cases
from cases import CTX, check, near, select_only, snapshot

NEW_ANNOTATIONS = hasattr(bpy.types.Scene, "annotation") or hasattr(bpy.data, "annotations")

#: Snapping off: no vertex moves, so geometry can be checked exactly.
NO_SNAP = {"snap_vertex": 0.0, "snap_segment": 0.0}


# ------------------------------------------------------------------------------- helpers


def view3d():
    """(window, area, region, region_3d) of the startup screen's 3D Viewport."""
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return win, area, region, area.spaces.active.region_3d


def clear_annotations():
    scene = bpy.context.scene
    if NEW_ANNOTATIONS and hasattr(bpy.data, "annotations"):
        for a in list(bpy.data.annotations):
            bpy.data.annotations.remove(a)
    else:
        scene.grease_pencil = None
        for g in list(bpy.data.grease_pencils):
            bpy.data.grease_pencils.remove(g)


def annotate(mouse):
    """Draws one annotation stroke through the region points ``mouse`` (y up) with the
    Annotate tool (placement: 3D Cursor), as a user drags it."""
    win, area, region, _ = view3d()
    elements = []
    for i, (x, y) in enumerate(mouse):
        e = {
            "name": "", "location": (0.0, 0.0, 0.0), "mouse": (x, y), "mouse_event": (x, y),
            "pressure": 1.0, "size": 1.0, "time": 0.01 * i, "is_start": i == 0,
            "x_tilt": 0.0, "y_tilt": 0.0,
        }
        if bpy.app.version < (4, 0, 0):
            e["pen_flip"] = False
        elements.append(e)
    with bpy.context.temp_override(window=win, area=area, region=region):
        result = bpy.ops.gpencil.annotate(mode="DRAW", stroke=elements, wait_for_input=False)
    check(result == {"FINISHED"}, f"the Annotate operator returned {result}")


def annotation_points():
    """The world points of the last annotation stroke, read back from the scene."""
    scene = bpy.context.scene
    data = scene.annotation if hasattr(scene, "annotation") else scene.grease_pencil
    layers = data.layers
    layer = getattr(layers, "active", None) or layers[layers.active_index]
    stroke = layer.active_frame.strokes[-1]
    return [Vector(p.co) for p in stroke.points]


def annotate_world(points):
    """An annotation stroke over the 3D Viewport through the world ``points``."""
    _, _, region, rv3d = view3d()
    annotate([tuple(view3d_utils.location_3d_to_region_2d(region, rv3d, p)) for p in points])


def camera_ray_point(cam, u, v):
    """The world point on the camera's frame (its view_frame, at unit distance) at ``u``
    from the left and ``v`` from the top (0..1)."""
    scene = bpy.context.scene
    tr, br, bl, tl = [cam.matrix_world @ c for c in cam.data.view_frame(scene=scene)]
    top = tl.lerp(tr, u)
    bottom = bl.lerp(br, u)
    return top.lerp(bottom, v)


def annotate_through_camera(cam, uv):
    """An annotation stroke that the camera sees at the frame points ``uv`` (0..1 from the
    top-left): each point is where the camera ray meets the plane through the 3D cursor that
    the Annotate tool draws on, handed to the tool at its position in the 3D Viewport."""
    _, _, region, rv3d = view3d()
    cursor = bpy.context.scene.cursor.location
    normal = rv3d.view_rotation @ Vector((0.0, 0.0, -1.0))
    origin = cam.matrix_world.translation
    mouse = []
    for u, v in uv:
        target = camera_ray_point(cam, u, v)
        hit = geometry.intersect_line_plane(origin, target, cursor, normal)
        check(hit is not None, "a camera ray misses the annotation plane")
        mouse.append(tuple(view3d_utils.location_3d_to_region_2d(region, rv3d, hit)))
    annotate(mouse)


def add_camera(location=(0.0, -6.0, 0.0), rotation=(math.pi / 2, 0.0, 0.0), name="Cam"):
    data = bpy.data.cameras.new(name)
    cam = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(cam)
    cam.location = location
    cam.rotation_euler = rotation
    scene = bpy.context.scene
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = 800, 600
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    bpy.context.view_layer.update()
    return cam


#: Half the grids' side: big enough that a grid cell is about 30 pixels wide in the startup
#: file's 3D Viewport (smaller cells snap to any stroke everywhere).
HALF = 3.0


def grid(name="Grid", n=10, size=2 * HALF):
    """An n × n grid of quads (n + 1 vertices a side) in the plane z = 0, centred at 0."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n, y_subdivisions=n, size=size)
    o = bpy.context.object
    o.name = o.data.name = name
    return o


def sphere(name="Ball"):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0)
    o = bpy.context.object
    o.name = o.data.name = name
    return o


def wavy_line(a, b, n=40, amp=0.15):
    """World points from ``a`` to ``b`` (in units of :data:`HALF`, on z = 0) with a gentle
    wave, so that the stroke does not run along grid lines."""
    a = Vector(a) * HALF
    b = Vector(b) * HALF
    amp *= HALF
    out = []
    for i in range(n):
        t = i / (n - 1)
        p = Vector(a).lerp(Vector(b), t)
        d = (Vector(b) - Vector(a)).normalized()
        side = Vector((-d.y, d.x, 0.0))
        out.append(p + side * amp * math.sin(2.0 * math.pi * t + 0.3))
    return out


#: Every setting, passed on every call: Blender remembers an operator's last settings and
#: would otherwise carry one test's into the next.
DEFAULTS = {
    "mode": "VISIBLE_ONLY", "open": False, "keep_polygons": True,
    "snap_vertex": 0.3, "snap_segment": 0.3, "corner_angle": math.radians(60.0),
}
ANNOTATION_DEFAULTS = {"view": "VIEW", "camera": "", "stroke_index": -1}


def _operator(op, options):
    if op == "annotation":
        return bpy.ops.katachi.cut_by_annotation, {**DEFAULTS, **ANNOTATION_DEFAULTS, **options}
    return bpy.ops.katachi.cut_by_stroke, {**DEFAULTS, **options}


def cut(op="annotation", expect="FINISHED", **options):
    """Runs a cut operator as a user's click does (with an undo step); every result must be
    a mesh Blender finds valid as it is (the add-on builds it from katachi's arrays without
    asking Blender to repair anything)."""
    fn, options = _operator(op, options)
    result = fn("EXEC_DEFAULT", True, **options)
    check(result == {expect}, f"katachi.cut_by_{op} returned {result}, not {expect}")
    if result == {"FINISHED"} and bpy.context.mode != "EDIT_MESH":
        for o in bpy.context.selected_objects:
            if o.type == "MESH":
                copy = o.data.copy()
                try:
                    check(not copy.validate(verbose=True), f"{o.name}: Blender had to repair the cut")
                finally:
                    bpy.data.meshes.remove(copy)


def expect_cut_error(fragments, op="annotation", **options):
    fn, options = _operator(op, options)
    try:
        result = fn(**options)
    except RuntimeError as e:
        msg = str(e)
        for f in fragments:
            check(f.lower() in msg.lower(), f"the error {msg!r} does not mention {f!r}")
        return msg
    raise AssertionError(f"katachi.cut_by_{op} succeeded ({result}) where an error was expected")


def stroke_items(pixels):
    """A stroke (katachi pixels, flat) as the operator's ``stroke`` collection."""
    return [{"name": "", "co": (pixels[2 * i], pixels[2 * i + 1])} for i in range(len(pixels) // 2)]


# ---- the oracle: the library itself


def region_pixels(points):
    """Annotation points in katachi pixels over the 3D Viewport, by Blender's projection."""
    _, _, region, rv3d = view3d()
    out = []
    for p in points:
        q = view3d_utils.location_3d_to_region_2d(region, rv3d, p)
        out += [q.x, region.height - q.y]
    return out, (region.width, region.height)


def camera_pixels(cam, points):
    """Annotation points in katachi pixels seen by ``cam``, by world_to_camera_view."""
    r = bpy.context.scene.render
    w, h = r.resolution_x, r.resolution_y
    out = []
    for p in points:
        q = object_utils.world_to_camera_view(bpy.context.scene, cam, p)
        out += [q.x * w, (1.0 - q.y) * h]
    return out, (w, h)


def view_matrix_3d(obj):
    _, _, _, rv3d = view3d()
    return rv3d.perspective_matrix @ obj.matrix_world


def view_matrix_camera(cam, obj):
    r = bpy.context.scene.render
    deps = bpy.context.evaluated_depsgraph_get()
    proj = cam.calc_matrix_camera(deps, x=r.resolution_x, y=r.resolution_y)
    return proj @ cam.matrix_world.inverted() @ obj.matrix_world


def library_cut(obj, pixels, size, matrix, mode="VISIBLE_ONLY", open_=False, snap=None):
    """katachi's own answer for the object's mesh: (info, paths, face_origin)."""
    addon = CTX["addon"]
    ffi, convert = addon.ffi, addon.convert
    lib = ffi.load()
    options = lib.katachi_cut_options_default()
    options.mode = getattr(ffi, f"KATACHI_CUT_MODE_{mode}")
    options.open = 1 if open_ else 0
    if snap is not None:
        options.snap_vertex_ratio = options.snap_segment_ratio = snap
    vp = [matrix[r][c] for c in range(4) for r in range(4)]
    with convert.to_katachi(lib, convert.InputMesh(obj.data)) as mesh:
        with ffi.cut_by_stroke(lib, mesh, pixels, vp, [0.0, 0.0, size[0], size[1]], options) as c:
            info = c.info()
            offsets = ctypes_u32(info.path_count + 1)
            verts = ctypes_u32(max(info.path_vertex_count, 1))
            lib.call("katachi_cut_copy_paths", c.handle, offsets, info.path_count + 1,
                     verts, info.path_vertex_count)
            closed = ctypes_u32(max(info.path_count, 1))
            pieces = ctypes_u32(max(info.path_count, 1))
            lib.call("katachi_cut_copy_path_pieces", c.handle, pieces, closed, info.path_count)
            paths = [(list(verts[offsets[i]:offsets[i + 1]]), bool(closed[i]))
                     for i in range(info.path_count)]
            origin = ctypes_u32(max(info.face_count, 1))
            lib.call("katachi_cut_copy_face_origin", c.handle, origin, info.face_count)
            return info, paths, list(origin[:info.face_count])


def cli_cut(obj, tag, pixels, size, matrix, mode="VISIBLE_ONLY", open_=False):
    """The ``katachi cut`` command-line tool's report (its JSON) for the object's mesh,
    exported as OBJ, and a stroke file with the same pixels and view."""
    import json
    import os
    import subprocess

    mesh_path = cases.export_for_cli(obj, tag)
    base = mesh_path[:-4]
    with open(base + "_stroke.json", "w") as f:
        json.dump({
            "stroke": [[pixels[2 * i], pixels[2 * i + 1]] for i in range(len(pixels) // 2)],
            "view_proj": [matrix[r][c] for c in range(4) for r in range(4)],
            "viewport": [0.0, 0.0, size[0], size[1]],
            "mode": mode.lower().replace("_", "-"),
            "open": open_,
        }, f)
    cmd = [CTX["cli"], "cut", mesh_path, base + "_cut.obj", "--stroke", base + "_stroke.json",
           "--report", base + "_cut.json"]
    run = subprocess.run(cmd, capture_output=True, text=True)
    check(run.returncode == 0, f"{' '.join(cmd)} failed: {run.stderr}")
    check(os.path.isfile(base + "_cut.obj"), "the CLI wrote no mesh")
    with open(base + "_cut.json") as f:
        return json.load(f)


def cli_paths(report):
    return [(p["vertices"], p["closed"]) for p in report["paths"]]


def ctypes_u32(n):
    import ctypes

    return (ctypes.c_uint32 * n)()


def path_edge_set(paths):
    edges = set()
    for verts, closed in paths:
        n = len(verts)
        for i in range(n - 1 + (1 if closed and n > 2 else 0)):
            a, b = verts[i], verts[(i + 1) % n]
            edges.add((min(a, b), max(a, b)))
    return edges


def selected_edges(me):
    return {tuple(sorted(e.vertices)) for e in me.edges if e.select}


def components(me):
    parent = list(range(len(me.vertices)))

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for p in me.polygons:
        vs = list(p.vertices)
        for v in vs[1:]:
            ra, rb = find(vs[0]), find(v)
            if ra != rb:
                parent[ra] = rb
    return len({find(v) for p in me.polygons for v in p.vertices})


def reports_of(fn):
    """Runs ``fn`` and returns what it printed, the operator's INFO and WARNING reports among
    it (Blender prints an operator's reports to the process's standard output in
    background mode, from C, so they are caught at the file descriptor)."""
    import ctypes
    import os
    import sys
    import tempfile

    libc = ctypes.CDLL(None)
    sys.stdout.flush()
    libc.fflush(None)
    saved = os.dup(1)
    with tempfile.TemporaryFile(mode="w+b") as tmp:
        os.dup2(tmp.fileno(), 1)
        try:
            fn()
        finally:
            sys.stdout.flush()
            libc.fflush(None)
            os.dup2(saved, 1)
            os.close(saved)
        tmp.seek(0)
        text = tmp.read().decode("utf-8", "replace")
    sys.stdout.write(text)
    return text


# ------------------------------------------------------------------------------- cases


def test_cut_registered():
    addon = CTX["addon"]
    for idname, label in (("cut_by_stroke", "Cut by Stroke"), ("cut_by_annotation", "Cut by Annotation")):
        op = getattr(bpy.ops.katachi, idname).get_rna_type()
        check(op.name == label, f"operator label {op.name!r}")
        props = set(op.properties.keys())
        for p in ("mode", "open", "keep_polygons", "snap_vertex", "snap_segment", "corner_angle"):
            check(p in props, f"{idname}: property {p} is missing")
    props = set(bpy.ops.katachi.cut_by_annotation.get_rna_type().properties.keys())
    for p in ("view", "camera", "stroke_index"):
        check(p in props, f"cut_by_annotation: property {p} is missing")
    # Menus: both in Edit mode's Mesh ▸ katachi; the annotation form in Object ▸ katachi.
    import inspect

    ui = inspect.getsource(addon.ui)
    check("KATACHI_OT_cut_by_stroke.bl_idname" in ui, "Cut by Stroke is not in a menu")
    # The toolbar tool, after the Knife in Edit mode's toolbar.
    from bl_ui.space_toolsystem_common import ToolSelectPanelHelper

    cls = ToolSelectPanelHelper._tool_class_from_space_type("VIEW_3D")

    def flat(items):
        for t in items:
            if t is None or callable(t):
                continue
            if hasattr(t, "idname"):
                yield t.idname
            elif isinstance(t, tuple):
                yield from flat(t)

    ids = list(flat(cls._tools["EDIT_MESH"]))
    check("katachi.cut_by_stroke_tool" in ids, f"the tool is not in the Edit mode toolbar: {ids}")
    check(ids.index("katachi.cut_by_stroke_tool") > ids.index("builtin.knife"),
          f"the tool does not follow the Knife: {ids}")


def test_cut_grid_matches_the_library():
    """A wavy stroke across a 10 × 10 grid, through the 3D Viewport: the counts, the path and
    the selected edges are the library's for the same pixels."""
    g = grid()
    clear_annotations()
    annotate_world(wavy_line((-1.3, 0.2, 0.0), (1.3, -0.3, 0.0)))
    pixels, size = region_pixels(annotation_points())
    info, paths, _ = library_cut(g, pixels, size, view_matrix_3d(g))
    check(info.path_count == 1 and info.new_face_count > 0, f"the library cut nothing: {info.path_count} paths, {info.new_face_count} new faces")
    report = cli_cut(g, "grid", pixels, size, view_matrix_3d(g))
    select_only(g)
    text = reports_of(lambda: cut(keep_polygons=False))
    me = g.data
    # The command-line tool on the same mesh (as OBJ) and stroke file agrees.
    check((report["face_count"], report["vertex_count"]) == (len(me.polygons), len(me.vertices)),
          f"the CLI made {report['face_count']} faces, {report['vertex_count']} vertices; "
          f"the operator {len(me.polygons)}, {len(me.vertices)}")
    check(path_edge_set(cli_paths(report)) == selected_edges(me), "the CLI's cut path is not the selection")
    dropped = report["dropped"]
    for stage, words in (("first_normalization", "by the first normalization"),
                         ("second_normalization", "by the second normalization"),
                         ("off_mesh", "off the mesh"), ("preprocessing", "in preprocessing")):
        if dropped[stage]:
            check(f"{len(dropped[stage])} {words}" in text,
                  f"the report {text!r} does not say {len(dropped[stage])} points were dropped {words}")
    if report["moved"]:
        check(f"{len(report['moved'])} vertices moved onto the stroke" in text,
              f"the report does not count the CLI's {len(report['moved'])} moved vertices")
    check(len(me.polygons) == info.face_count,
          f"{len(me.polygons)} faces, the library {info.face_count}")
    check(len(me.vertices) == info.vertex_count,
          f"{len(me.vertices)} vertices, the library {info.vertex_count}")
    check(all(len(p.vertices) == 3 for p in me.polygons), "Keep Uncut Faces off left a quad")
    want = path_edge_set(paths)
    got = selected_edges(me)
    check(got == want, f"selected edges differ from the cut path: {len(got)} vs {len(want)}")
    check(not any(p.select for p in me.polygons), "faces are selected after the cut")
    # The report says what happened: faces, moved vertices and the largest move, stages.
    for fragment in ("100 -> ", f"{info.new_face_count} new faces", "stroke points dropped",
                     f"{info.moved_vertex_count} vertices moved" if info.moved_vertex_count else "no vertex moved"):
        check(fragment in text, f"the report {text!r} lacks {fragment!r}")
    if info.dropped_first_normalization_count:
        check(f"{info.dropped_first_normalization_count} by the first normalization" in text,
              "the report does not count the points the first normalization dropped")
    # Every cut vertex lies on the stroke as the 3D Viewport shows it (the pixel convention).
    _, _, region, rv3d = view3d()
    stroke_2d = [Vector((pixels[2 * i], pixels[2 * i + 1])) for i in range(len(pixels) // 2)]
    tol = 0.31 * info.mean_edge_length_px + 1e-3
    for a, b in got:
        for v in (a, b):
            q = view3d_utils.location_3d_to_region_2d(region, rv3d, g.matrix_world @ me.vertices[v].co)
            q = Vector((q.x, region.height - q.y))
            d = min(distance_to_segment(q, stroke_2d[i], stroke_2d[i + 1]) for i in range(len(stroke_2d) - 1))
            check(d <= tol, f"cut vertex {v} is {d:.2f} px from the stroke (L = {info.mean_edge_length_px:.1f} px)")


def distance_to_segment(p, a, b):
    ab = b - a
    t = 0.0 if ab.length_squared == 0 else max(0.0, min(1.0, (p - a).dot(ab) / ab.length_squared))
    return (a + ab * t - p).length


def test_cut_keeps_uncut_faces():
    """With Keep Uncut Faces (the default) the quads the cut does not touch stay quads, and
    the cut faces are the library's triangles: quads × 2 + triangles = its count. The
    second stroke's path runs along the quads' diagonals (snapping pulls the grid's vertices
    onto it), so those quads must not come back whole."""
    for a, b, amp in (((-1.3, -0.6, 0.0), (1.2, 0.3, 0.0), 0.3),
                      ((-1.3, -0.4, 0.0), (1.3, 0.5, 0.0), 0.15)):
        cases.fresh_scene()
        g = grid()
        clear_annotations()
        annotate_world(wavy_line(a, b, amp=amp))
        pixels, size = region_pixels(annotation_points())
        info, paths, origin = library_cut(g, pixels, size, view_matrix_3d(g))
        select_only(g)
        cut()
        me = g.data
        quads = sum(1 for p in me.polygons if len(p.vertices) == 4)
        tris = sum(1 for p in me.polygons if len(p.vertices) == 3)
        check(quads + tris == len(me.polygons), "faces other than quads and triangles")
        check(2 * quads + tris == info.face_count,
              f"{quads} quads + {tris} triangles do not make the library's {info.face_count} triangles")
        check(70 < quads < 100, f"{quads} quads kept of 100")
        check(len(me.vertices) == info.vertex_count, "vertex counts differ")
        edges = {tuple(sorted(e.vertices)) for e in me.edges}
        path = path_edge_set(paths)
        check(path <= edges, f"{len(path - edges)} cut edges vanished inside kept faces")
        check(selected_edges(me) == path, "selected edges differ from the cut path")


def test_cut_uvs_materials_smooth_on_flat_grid():
    """Snapping off, so nothing moves: UV = (x, y) stays true at every corner (a linear
    function, interpolated linearly), each face's material and smooth flag is the grid
    cell's it lies in (stripes by column), and the vertex crease stays on its vertex."""
    g = grid(n=8)
    me = g.data
    cases.set_planar_uvs(me)
    second = me.uv_layers.new(name="Second")
    for loop, d in zip(me.loops, second.data):
        co = me.vertices[loop.vertex_index].co
        d.uv = (0.5 * co.x + 0.25 * co.y + 0.1, -co.y)
    red, blue = bpy.data.materials.new("Red"), bpy.data.materials.new("Blue")
    me.materials.append(red)
    me.materials.append(blue)
    cell = 2 * HALF / 8

    def column(x):
        return int(math.floor((x + HALF) / cell))

    for p in me.polygons:
        p.material_index = column(p.center.x) % 2
        p.use_smooth = p.center.y > 0
    corner = next(v.index for v in me.vertices if near(v.co.x, HALF) and near(v.co.y, HALF))
    cases.set_vertex_creases(me, {corner: 0.8})
    clear_annotations()
    annotate_world(wavy_line((-1.2, -0.9, 0.0), (1.2, 0.8, 0.0)))
    for keep in (False, True):
        o = g.copy()
        o.data = me.copy()
        o.name = o.data.name = f"Flat_{keep}"
        bpy.context.scene.collection.objects.link(o)
        select_only(o)
        cut(keep_polygons=keep, **NO_SNAP)
        m = o.data
        check(len(m.polygons) > len(me.polygons), f"keep={keep}: nothing was cut")
        check([l.name for l in m.uv_layers] == ["UVMap", "Second"], "UV maps not carried by name")
        check([x.name for x in m.materials] == ["Red", "Blue"], "materials not carried")
        worst = 0.0
        for loop, a, b in zip(m.loops, m.uv_layers[0].data, m.uv_layers[1].data):
            co = m.vertices[loop.vertex_index].co
            check(near(co.z, 0.0, 1e-6), "a vertex left the grid's plane with snapping off")
            worst = max(worst, abs(a.uv[0] - co.x), abs(a.uv[1] - co.y),
                        abs(b.uv[0] - (0.5 * co.x + 0.25 * co.y + 0.1)), abs(b.uv[1] + co.y))
        check(worst < 1e-5, f"keep={keep}: UVs differ from their linear function by {worst:.3g}")
        for p in m.polygons:
            c = p.center
            check(p.material_index == column(c.x) % 2,
                  f"keep={keep}: face {p.index} at x = {c.x:.3f}: material {p.material_index}")
            check(p.use_smooth == (c.y > 0), f"keep={keep}: face {p.index}: smooth flag")
        vc = cases.vertex_creases(m)
        check(near(vc[corner], 0.8, 1e-6) and sum(1 for c in vc if c > 0) == 1,
              f"keep={keep}: the vertex crease did not stay on vertex {corner}")


def test_cut_edge_data_follows_the_halves():
    """Creases and seams of the grid's horizontal lines and sharp marks of its vertical ones
    stay on both halves of every split edge; the cut's own edges and diagonals get none; a
    loose edge is kept."""
    g = grid(n=8)
    me = g.data
    line = 2 * HALF / 8

    def on_line(c):
        return near((c + HALF) / line, round((c + HALF) / line), 1e-4)

    horizontal = {e.index for e in me.edges
                  if near(me.vertices[e.vertices[0]].co.y, me.vertices[e.vertices[1]].co.y)}
    cases.set_edge_creases(me, {tuple(me.edges[i].vertices): 0.7 for i in horizontal})
    for e in me.edges:
        e.use_seam = e.index in horizontal
        e.use_edge_sharp = e.index not in horizontal
    # A loose edge off the grid.
    n = len(me.vertices)
    me.vertices.add(2)
    me.vertices[n].co = (3.0, 3.0, 0.0)
    me.vertices[n + 1].co = (3.5, 3.0, 0.0)
    me.edges.add(1)
    me.edges[-1].vertices = (n, n + 1)
    me.update()
    clear_annotations()
    annotate_world(wavy_line((-0.9, -1.3, 0.0), (0.8, 1.3, 0.0), amp=0.2))
    select_only(g)
    cut(keep_polygons=False, **NO_SNAP)
    m = g.data
    creases = cases.edge_creases(m)
    split = 0
    for e in m.edges:
        a, b = (m.vertices[v].co for v in e.vertices)
        key = tuple(sorted(e.vertices))
        if set(e.vertices) == {n, n + 1}:
            check(not e.use_seam and key not in creases, "the loose edge gained data")
            continue
        is_h = near(a.y, b.y, 1e-6) and on_line(a.y)
        is_v = near(a.x, b.x, 1e-6) and on_line(a.x)
        if is_h:
            check(e.use_seam and near(creases.get(key, 0.0), 0.7, 1e-6),
                  f"horizontal edge {key} lost its seam or crease")
            split += not (on_line(a.x) and on_line(b.x))
        else:
            check(not e.use_seam and key not in creases, f"edge {key} gained a seam or crease")
        check(e.use_edge_sharp == is_v, f"edge {key}: sharp is {e.use_edge_sharp}, vertical {is_v}")
    check(split >= 4, f"only {split} halves of split horizontal edges were seen")
    loose = [e for e in m.edges if set(e.vertices) == {n, n + 1}]
    check(len(loose) == 1, "the loose edge was not kept")
    check(tuple(m.vertices[n].co) == (3.0, 3.0, 0.0), "the loose edge's vertex moved")


def test_cut_vertex_groups_and_shape_keys():
    """Snapping off: a vertex group whose weight is a linear function of x and a shape key
    that lifts each vertex by a linear function of (x, y) stay those functions on every
    vertex, new ones included, in Object mode and in Edit mode; the key's settings follow."""

    def weight(co):
        return (co.x + HALF) / (2 * HALF)

    def lift(co):
        return 0.1 * co.x + 0.2 * co.y + 0.5

    for mode in ("OBJECT", "EDIT"):
        cases.fresh_scene()
        g = grid(n=8)
        group = g.vertex_groups.new(name="Ramp")
        for v in g.data.vertices:
            group.add([v.index], weight(v.co), "REPLACE")
        basis = g.shape_key_add(name="Basis")
        up = g.shape_key_add(name="Up")
        for d in up.data:
            d.co.z = lift(d.co)
        up.value = 0.25
        up.slider_max = 2.0
        up.vertex_group = "Ramp"
        up.relative_key = basis
        clear_annotations()
        annotate_world(wavy_line((-1.2, -0.9, 0.0), (1.2, 0.8, 0.0)))
        select_only(g)
        n_before = len(g.data.vertices)
        if mode == "EDIT":
            bpy.ops.object.mode_set(mode="EDIT")
        cut(**NO_SNAP)
        if mode == "EDIT":
            bpy.ops.object.mode_set(mode="OBJECT")
        me = g.data
        check(len(me.vertices) > n_before, f"{mode}: nothing was cut")
        keys = me.shape_keys.key_blocks
        check([k.name for k in keys] == ["Basis", "Up"], f"{mode}: shape keys {[k.name for k in keys]}")
        up = keys["Up"]
        check(near(up.value, 0.25) and near(up.slider_max, 2.0) and up.vertex_group == "Ramp"
              and up.relative_key.name == "Basis", f"{mode}: the key's settings were not kept")
        worst_w = worst_k = 0.0
        ramp = g.vertex_groups["Ramp"].index
        for v in me.vertices:
            w = next((x.weight for x in v.groups if x.group == ramp), 0.0)
            worst_w = max(worst_w, abs(w - weight(v.co)))
            k = up.data[v.index].co
            b = keys["Basis"].data[v.index].co
            worst_k = max(worst_k, abs(k.z - lift(v.co)), abs(k.x - v.co.x), abs(k.y - v.co.y),
                          (b - v.co).length)
        check(worst_w < 1e-5, f"{mode}: weights differ from their linear function by {worst_w:.3g}")
        check(worst_k < 1e-5, f"{mode}: shape keys differ from their linear function by {worst_k:.3g}")


def test_cut_sphere_through_camera_visible_vs_through_all():
    """A stroke across a UV sphere seen by a camera: Visible Only cuts the near side (one
    path), Through All both sides (two paths), each as the library says for the camera's
    pixels, and the named camera gives the scene camera's result."""
    cam = add_camera()
    clear_annotations()
    annotate_through_camera(cam, [(0.15 + 0.7 * i / 29, 0.47 + 0.04 * math.sin(i / 5.0)) for i in range(30)])
    points = annotation_points()
    results = {}
    for mode in ("VISIBLE_ONLY", "THROUGH_ALL"):
        s = sphere(f"Ball_{mode}")
        pixels, size = camera_pixels(cam, points)
        info, paths, _ = library_cut(s, pixels, size, view_matrix_camera(cam, s), mode=mode)
        report = cli_cut(s, f"sphere_{mode}", pixels, size, view_matrix_camera(cam, s), mode=mode)
        select_only(s)
        cut(view="CAMERA", mode=mode, keep_polygons=False)
        me = s.data
        check(report["face_count"] == len(me.polygons) and len(report["paths"]) == info.path_count,
              f"{mode}: the CLI made {report['face_count']} faces and {len(report['paths'])} paths")
        check(len(me.polygons) == info.face_count, f"{mode}: {len(me.polygons)} faces, the library {info.face_count}")
        check(len(me.vertices) == info.vertex_count, f"{mode}: vertex counts differ")
        check(selected_edges(me) == path_edge_set(paths), f"{mode}: selected edges differ")
        ys = [me.vertices[v].co.y for e in selected_edges(me) for v in e]
        results[mode] = (info, ys)
        bpy.data.objects.remove(s)
    vis, thr = results["VISIBLE_ONLY"], results["THROUGH_ALL"]
    check(vis[0].path_count == 1, f"Visible Only: {vis[0].path_count} paths, not 1")
    check(thr[0].path_count == 2, f"Through All: {thr[0].path_count} paths, not 2")
    # The camera looks along +y from y = -6: the near side has y < 0.
    check(max(vis[1]) < 0.1, f"Visible Only cut the far side (y up to {max(vis[1]):.2f})")
    check(max(thr[1]) > 0.5 and min(thr[1]) < -0.5, "Through All did not cut both sides")
    # A camera named explicitly, while the scene camera points elsewhere.
    other = add_camera(location=(6.0, 0.0, 0.0), rotation=(math.pi / 2, 0.0, math.pi / 2), name="Side")
    bpy.context.scene.camera = other
    s = sphere("Ball_named")
    select_only(s)
    cut(view="CAMERA", camera=cam.name, mode="VISIBLE_ONLY", keep_polygons=False)
    check(len(s.data.polygons) == vis[0].face_count, "the named camera gave another cut")


def test_cut_open_separates_the_grid():
    """Open, boundary to boundary: the grid falls in two pieces; both sides of the cut are
    selected; the vertices are the library's."""
    g = grid()
    clear_annotations()
    annotate_world(wavy_line((-1.4, 0.1, 0.0), (1.4, -0.2, 0.0)))
    pixels, size = region_pixels(annotation_points())
    info, paths, _ = library_cut(g, pixels, size, view_matrix_3d(g), open_=True)
    report = cli_cut(g, "open", pixels, size, view_matrix_3d(g), open_=True)
    select_only(g)
    cut(open=True)
    me = g.data
    check(report["vertex_count"] == len(me.vertices), f"the CLI made {report['vertex_count']} vertices")
    check(len(me.vertices) == info.vertex_count, f"{len(me.vertices)} vertices, the library {info.vertex_count}")
    check(components(me) == 2, f"{components(me)} pieces after an open cut across the grid")
    # Both sides of the cut are selected: twice the path's edges, all on the new boundary,
    # touching every vertex of the path (an opened path's own ids hold one side of each
    # vertex; the other side's copies come after them).
    sel = selected_edges(me)
    path = path_edge_set(paths)
    check(len(sel) == 2 * len(path),
          f"{len(sel)} edges selected for a path of {len(path)} edges (both sides expected)")
    uses = {}
    for p in me.polygons:
        for key in p.edge_keys:
            uses[key] = uses.get(key, 0) + 1
    check(all(uses.get(e) == 1 for e in sel), "a selected edge is not on the opened boundary")
    touched = {v for e in sel for v in e}
    check({v for e in path for v in e} <= touched, "a path vertex has no selected edge")


def test_cut_edit_mode_and_undo():
    """In Edit mode: the edit mesh is cut, Edit mode stays, the cut edges are the selection,
    and one undo gives the mesh back exactly."""
    g = grid()
    clear_annotations()
    annotate_world(wavy_line((-1.3, -0.5, 0.0), (1.2, 0.6, 0.0)))
    pixels, size = region_pixels(annotation_points())
    info, paths, _ = library_cut(g, pixels, size, view_matrix_3d(g))
    before = snapshot(g)
    select_only(g)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.ed.undo_push(message="before the cut")
    cut(keep_polygons=False)
    check(g.mode == "EDIT", "the cut left Edit mode")
    import bmesh

    bm = bmesh.from_edit_mesh(g.data)
    check(len(bm.faces) == info.face_count, f"{len(bm.faces)} faces in the edit mesh, the library {info.face_count}")
    got = {tuple(sorted(v.index for v in e.verts)) for e in bm.edges if e.select}
    check(got == path_edge_set(paths), "the edit mesh's selection is not the cut")
    check(not any(f.select for f in bm.faces), "faces are selected after the cut")
    bpy.ops.ed.undo()
    bpy.ops.object.mode_set(mode="OBJECT")
    g = bpy.data.objects["Grid"]  # undo may have reloaded the objects
    after = snapshot(g)
    for key in ("co", "faces", "uv", "materials"):
        check(after[key] == before[key], f"undo did not restore the mesh's {key}")


def test_cut_hidden_faces_stay_hidden():
    """Faces hidden in Edit mode stay hidden, their pieces too; shown faces have no hidden
    corner; nothing hidden is selected."""
    g = grid(n=8)
    clear_annotations()
    annotate_world(wavy_line((-1.2, -0.9, 0.0), (1.2, 0.8, 0.0)))
    select_only(g)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bpy.ops.object.mode_set(mode="OBJECT")
    for p in g.data.polygons:
        p.select = p.center.x < 0
    bpy.context.tool_settings.mesh_select_mode = (False, False, True)  # hide faces, not vertices
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.hide(unselected=False)
    cut(**NO_SNAP)
    bpy.ops.object.mode_set(mode="OBJECT")
    me = g.data
    check(len(me.polygons) > 64, "nothing was cut")
    for p in me.polygons:
        check(p.hide == (p.center.x < 0), f"face {p.index} at x = {p.center.x:.3f}: hide {p.hide}")
        if not p.hide:
            check(not any(me.vertices[v].hide for v in p.vertices), f"shown face {p.index} has a hidden corner")
    check(not any(e.select and e.hide for e in me.edges), "a hidden edge is selected")
    check(any(e.select for e in me.edges), "no shown cut edge is selected")
    bpy.context.tool_settings.mesh_select_mode = (True, False, False)


def test_cut_object_mode_undo():
    g = grid()
    clear_annotations()
    annotate_world(wavy_line((-1.3, 0.5, 0.0), (1.2, -0.6, 0.0)))
    select_only(g)
    bpy.ops.ed.undo_push(message="before the cut")
    before = snapshot(g)
    cut()
    check(len(g.data.polygons) > 100, "nothing was cut")
    bpy.ops.ed.undo()
    g = bpy.data.objects["Grid"]
    after = snapshot(g)
    for key in ("co", "faces", "edges", "uv", "materials"):
        check(after[key] == before[key], f"undo did not restore the mesh's {key}")


def test_cut_by_stroke_scripted_equals_annotation():
    """The modal tool's operator run from a script with a stroke (katachi pixels) and the
    view it was drawn over gives the annotation form's result."""
    a = grid("A")
    b = grid("B")
    clear_annotations()
    annotate_world(wavy_line((-1.3, -0.2, 0.0), (1.3, 0.3, 0.0)))
    pixels, size = region_pixels(annotation_points())
    select_only(a)
    cut(keep_polygons=False)
    _, _, _, rv3d = view3d()
    m = rv3d.perspective_matrix
    select_only(b)
    cut("stroke", stroke=stroke_items(pixels),
        view_matrix=[m[r][c] for r in range(4) for c in range(4)], view_size=size,
        keep_polygons=False)
    check(len(a.data.polygons) == len(b.data.polygons), "the two forms cut differently")
    check([tuple(p.vertices) for p in a.data.polygons] == [tuple(p.vertices) for p in b.data.polygons],
          "the two forms gave different faces")


def test_cut_nothing_crossed_changes_nothing():
    g = grid()
    clear_annotations()
    annotate_world([Vector((1.5 * HALF + 0.1 * i, 1.5 * HALF, 0.0)) for i in range(10)])  # beside it
    before = snapshot(g)
    select_only(g)
    cut(expect="CANCELLED")
    check_same(g, before, "a stroke beside the mesh")


# ---- bad input: katachi's message, and nothing changed


def full_snapshot(obj):
    s = snapshot(obj)
    me = obj.data
    s["seams"] = [e.use_seam for e in me.edges]
    s["select"] = [v.select for v in me.vertices]
    return s


def check_same(obj, before, what):
    after = full_snapshot(obj)
    for key in before:
        check(after[key] == before[key], f"{what}: {obj.name}'s {key} changed")


def test_cut_error_one_point_stroke():
    g = grid()
    cases.set_planar_uvs(g.data)
    clear_annotations()
    _, _, region, rv3d = view3d()
    p = view3d_utils.location_3d_to_region_2d(region, rv3d, Vector((0.3, 0.3, 0.0)))
    annotate([tuple(p)])
    check(len(annotation_points()) == 1, f"the annotation has {len(annotation_points())} points")
    before = full_snapshot(g)
    select_only(g)
    expect_cut_error(["katachi", "Grid", "stroke"])
    check_same(g, before, "a one-point stroke")
    # The scripted form says the same.
    expect_cut_error(["katachi", "stroke"], op="stroke", stroke=stroke_items([10.0, 10.0]))
    check_same(g, before, "a one-point stroke (scripted)")


def test_cut_error_self_intersecting_stroke():
    g = grid()
    cases.set_planar_uvs(g.data)
    g.data.materials.append(bpy.data.materials.new("M"))
    clear_annotations()
    figure8 = [HALF * Vector((0.9 * math.sin(2 * math.pi * t / 40), 0.5 * math.sin(4 * math.pi * t / 40), 0.0))
               for t in range(41)]
    annotate_world(figure8)
    before = full_snapshot(g)
    select_only(g)
    msg = expect_cut_error(["katachi", "Grid"])
    check("intersect" in msg.lower() or "cross" in msg.lower(), f"{msg!r} does not say the stroke crosses itself")
    check_same(g, before, "a self-intersecting stroke")
    check(len(bpy.data.meshes) == 1, f"{len(bpy.data.meshes)} meshes after a failed cut: results leaked")


def test_cut_error_non_mesh_object():
    empty = bpy.data.objects.new("JustAnEmpty", None)
    bpy.context.scene.collection.objects.link(empty)
    g = grid()
    clear_annotations()
    annotate_world(wavy_line((-1.3, 0.0, 0.0), (1.3, 0.1, 0.0)))
    before = full_snapshot(g)
    select_only(empty)
    expect_cut_error(["katachi", "no mesh", "JustAnEmpty"])
    check_same(g, before, "a non-mesh object")


def test_cut_error_non_manifold():
    """A non-manifold edge under the stroke: katachi refuses, naming it."""
    fin = cases.fin("Fin")
    fin.scale = (2.0, 2.0, 2.0)
    bpy.context.view_layer.update()
    clear_annotations()
    annotate_world([Vector((0.2 + 1.6 * t / 19, -1.5 + 3.5 * t / 19, 0.05)) for t in range(20)])
    before = full_snapshot(fin)
    select_only(fin)
    msg = expect_cut_error(["katachi", "Fin"], mode="THROUGH_ALL")
    check("manifold" in msg.lower(), f"{msg!r} does not say non-manifold")
    check_same(fin, before, "a non-manifold mesh")


def test_cut_error_no_annotation_and_bad_camera():
    g = grid()
    clear_annotations()
    before = full_snapshot(g)
    select_only(g)
    expect_cut_error(["katachi", "annotation"])
    annotate_world(wavy_line((-1.3, 0.0, 0.0), (1.3, 0.1, 0.0)))
    expect_cut_error(["katachi", "camera"], view="CAMERA")  # the scene has no camera
    expect_cut_error(["katachi", "Grid", "not a camera"], view="CAMERA", camera="Grid")
    cam = add_camera(location=(0.0, 0.0, -5.0), rotation=(0.0, 0.0, 0.0))  # looking down, away
    expect_cut_error(["katachi", "behind"], view="CAMERA", camera=cam.name)
    check_same(g, before, "no annotation, no camera")


TESTS = [(name, fn) for name, fn in list(globals().items()) if name.startswith("test_cut")]
