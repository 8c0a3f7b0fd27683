"""katachi's Blender operators against Blender's own tools and against the floor, side by side
in one Blender process, in interleaved rounds (``cargo xtask blender-bench`` runs this in
Debian's Blender 3.4 and in bpy 5.0 and prints the table):

    blender -b --factory-startup --python-exit-code 1 --python benches/blender/bench.py -- \\
        --zip target/addon/katachi-0.1.0.zip [--rounds 5] [--only subdivide|cut|cut1m]
    target/bpy-venv/bin/python benches/blender/bench.py --zip … (same options)

What is timed, each as a user's click runs it (``EXEC_DEFAULT`` with an undo step):

- **subdivide**: a torus of 384 × 256 = 98,304 quads with a UV map, two materials, creases
  (infinitely sharp and semi-sharp rings); katachi's Subdivide at 2 levels against Blender's
  Subdivision Surface modifier at 2 levels with its defaults (creases on, UVs: keep
  boundaries — katachi's default too —, limit surface on) added and applied;
- **cut**: ico spheres of 327,680 and 1,310,720 triangles with a UV map, seen by a camera;
  a 50-point stroke across the visible side; katachi's Cut by Stroke (the tool's scriptable
  form: the stroke and the view given) and Cut by Annotation (the same stroke drawn with
  Blender's Annotate tool, cut through the camera) against ``mesh.bisect`` through the
  whole mesh (Edit mode entered beforehand, not timed);
- **the floor** of each: the least any add-on must do for the same result: read the input's
  arrays with ``foreach_get`` (positions, faces, edges with their creases, UVs, materials,
  smooth flags) and build the result mesh (the operator's own result, read back once) from
  arrays with ``foreach_set``, then put it in the object's place. It runs as an operator
  with an undo step too, so every variant pays the same undo push.

Every variant gets a fresh object holding a copy of the same mesh (made outside the clock);
a round runs each variant once, in an order that rotates from round to round. Each line
printed as ``BENCH`` and tab-separated fields is one measurement; the closing ``BENCH-DONE`` line says the
run is complete. ``uptime``'s load is printed at the start and the end.
"""

import argparse
import array
import math
import os
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "blender"))
from addon_install import install  # noqa: E402

NEW_API = bpy.app.version >= (4, 0, 0)
VERSION = bpy.app.version_string


def parse_args():
    argv = sys.argv
    argv = argv[argv.index("--") + 1:] if "--" in argv else argv[1:]
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--zip", required=True, help="the add-on zip made by cargo xtask addon")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--only", default="", help="run only the cases whose name has this")
    return p.parse_args(argv)


def load():
    try:
        with open("/proc/loadavg") as f:
            return f.read().split()[0]
    except OSError:
        return "?"


def zeros(typecode, n):
    a = array.array(typecode)
    a.frombytes(bytes(n * a.itemsize))
    return a


def emit(case, variant, round_, seconds, **extra):
    """One measurement: ``BENCH`` and tab-separated fields (Blender version, case, variant,
    round, seconds, then ``key=value`` notes), for ``cargo xtask blender-bench``."""
    notes = " ".join(f"{k}={v}" for k, v in extra.items())
    print(f"BENCH\t{VERSION}\t{case}\t{variant}\t{round_}\t{seconds:.6f}\t{notes}", flush=True)


# ------------------------------------------------------------------------- mesh arrays


class Arrays:
    """A mesh's arrays as Blender stores them, read with ``foreach_get`` and built back into a
    new mesh with ``foreach_set``, each through the fastest path the version offers (a plain
    copy of the whole array): Blender 3.4's ``MeshVertex``/``MeshEdge``/``MeshLoop``/
    ``MeshPolygon`` properties with unsigned (``I``) buffers; from 4.0 the attributes
    (``position``, ``.edge_verts``, ``.corner_vert``, ``.corner_edge``, …) with signed
    (``i``) buffers, where the element properties copy element by element, 10 to 100 times
    slower. Booleans go through lists (3.4) or ``bytearray`` (4.0+)."""

    def __init__(self, me, selection=False):
        nv, ne, nl, nf = len(me.vertices), len(me.edges), len(me.loops), len(me.polygons)
        self.counts = (nv, ne, nl, nf)
        self.co = zeros("f", 3 * nv)
        self.starts = zeros("I", nf)
        me.polygons.foreach_get("loop_start", self.starts)
        self.sizes = None
        self.uvs = []
        self.material_slots = list(me.materials)
        self.vert_select = self.edge_select = None
        if NEW_API:
            a = me.attributes
            a["position"].data.foreach_get("vector", self.co)
            self.edges = zeros("i", 2 * ne)
            a[".edge_verts"].data.foreach_get("value", self.edges)
            self.loop_verts = zeros("i", nl)
            a[".corner_vert"].data.foreach_get("value", self.loop_verts)
            self.loop_edges = zeros("i", nl)
            a[".corner_edge"].data.foreach_get("value", self.loop_edges)
            self.materials = self._attribute(a, "material_index", "i", nf)
            self.sharp_face = self._attribute(a, "sharp_face", "bool", nf)
            self.creases = self._attribute(a, "crease_edge", "f", ne)
            for layer in me.uv_layers:
                uv = zeros("f", 2 * nl)
                a[layer.name].data.foreach_get("vector", uv)
                self.uvs.append((layer.name, uv))
            if selection:
                self.vert_select = self._attribute(a, ".select_vert", "bool", nv)
                self.edge_select = self._attribute(a, ".select_edge", "bool", ne)
        else:
            me.vertices.foreach_get("co", self.co)
            self.sizes = zeros("I", nf)
            me.polygons.foreach_get("loop_total", self.sizes)
            self.edges = zeros("I", 2 * ne)
            me.edges.foreach_get("vertices", self.edges)
            self.loop_verts = zeros("I", nl)
            me.loops.foreach_get("vertex_index", self.loop_verts)
            self.loop_edges = zeros("I", nl)
            me.loops.foreach_get("edge_index", self.loop_edges)
            self.materials = zeros("I", nf)
            me.polygons.foreach_get("material_index", self.materials)
            self.smooth = [False] * nf
            me.polygons.foreach_get("use_smooth", self.smooth)
            self.creases = zeros("f", ne)
            me.edges.foreach_get("crease", self.creases)
            for layer in me.uv_layers:
                uv = zeros("f", 2 * nl)
                layer.data.foreach_get("uv", uv)
                self.uvs.append((layer.name, uv))
            if selection:
                self.vert_select = [False] * nv
                me.vertices.foreach_get("select", self.vert_select)
                self.edge_select = [False] * ne
                me.edges.foreach_get("select", self.edge_select)

    @staticmethod
    def _attribute(attributes, name, kind, n):
        attr = attributes.get(name)
        if attr is None:
            return None
        values = bytearray(n) if kind == "bool" else zeros(kind, n)
        attr.data.foreach_get("value", values)
        return values

    def build(self, name):
        nv, ne, nl, nf = self.counts
        me = bpy.data.meshes.new(name)
        me.vertices.add(nv)
        me.edges.add(ne)
        me.loops.add(nl)
        me.polygons.add(nf)
        me.polygons.foreach_set("loop_start", self.starts)
        for m in self.material_slots:
            me.materials.append(m)
        if NEW_API:
            a = me.attributes
            a["position"].data.foreach_set("vector", self.co)
            a[".edge_verts"].data.foreach_set("value", self.edges)
            a[".corner_vert"].data.foreach_set("value", self.loop_verts)
            a[".corner_edge"].data.foreach_set("value", self.loop_edges)
            for attr, kind, domain, values in (
                ("material_index", "INT", "FACE", self.materials),
                ("sharp_face", "BOOLEAN", "FACE", self.sharp_face),
                ("crease_edge", "FLOAT", "EDGE", self.creases),
            ):
                if values is not None:
                    (a.get(attr) or a.new(attr, kind, domain)).data.foreach_set("value", values)
            for uv_name, uv in self.uvs:
                me.uv_layers.new(name=uv_name, do_init=False)
                a[uv_name].data.foreach_set("vector", uv)
            if self.vert_select is not None:
                a[".select_vert"].data.foreach_set("value", self.vert_select)
                a[".select_edge"].data.foreach_set("value", self.edge_select)
        else:
            me.vertices.foreach_set("co", self.co)
            me.edges.foreach_set("vertices", self.edges)
            me.loops.foreach_set("vertex_index", self.loop_verts)
            me.loops.foreach_set("edge_index", self.loop_edges)
            me.polygons.foreach_set("loop_total", self.sizes)
            me.polygons.foreach_set("material_index", self.materials)
            me.polygons.foreach_set("use_smooth", self.smooth)
            me.edges.foreach_set("crease", self.creases)
            for uv_name, uv in self.uvs:
                me.uv_layers.new(name=uv_name, do_init=False).data.foreach_set("uv", uv)
            if self.vert_select is not None:
                me.vertices.foreach_set("select", self.vert_select)
                me.edges.foreach_set("select", self.edge_select)
        me.update()
        return me

    def summary(self):
        nv, ne, nl, nf = self.counts
        return {"vertices": nv, "edges": ne, "faces": nf, "corners": nl}


def read_creases(me):
    """A mesh's edge creases (``array('f')``), None when it has none (4.0+)."""
    ne = len(me.edges)
    if NEW_API:
        attr = me.attributes.get("crease_edge")
        if attr is None:
            return None
        values = zeros("f", ne)
        attr.data.foreach_get("value", values)
        return values
    values = zeros("f", ne)
    me.edges.foreach_get("crease", values)
    return values


def write_creases(me, values):
    if NEW_API:
        attr = me.attributes.get("crease_edge") or me.attributes.new("crease_edge", "FLOAT", "EDGE")
        attr.data.foreach_set("value", values)
    else:
        me.edges.foreach_set("crease", values)


def read_input(me):
    """What any add-on must read of its input: positions, faces, edges and their creases, UVs,
    materials and smooth flags."""
    return Arrays(me)


# ------------------------------------------------------------------------- the floor


class BENCH_OT_floor(bpy.types.Operator):
    """The floor: read the input's arrays, build the given result from arrays, swap it in"""

    bl_idname = "katachi_bench.floor"
    bl_label = "katachi bench: floor"
    bl_options = {"REGISTER", "UNDO"}

    result = None  # the Arrays to build (set before the call)

    def execute(self, context):
        obj = context.active_object
        old = obj.data
        read_input(old)
        new = BENCH_OT_floor.result.build(old.name + "_floor")
        obj.data = new
        if old.users == 0:
            bpy.data.meshes.remove(old)
        return {"FINISHED"}


# ------------------------------------------------------------------------- scene helpers


def clear_scene():
    if bpy.context.object is not None and bpy.context.object.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for o in list(bpy.data.objects):
        if o.type == "MESH":
            bpy.data.objects.remove(o)
    for m in list(bpy.data.meshes):
        if m.users == 0 and not m.use_fake_user:
            bpy.data.meshes.remove(m)


def fresh_object(base, name):
    """A new selected, active object holding a copy of ``base`` (a mesh kept with a fake
    user), in Object mode."""
    clear_scene()
    me = base.copy()
    me.use_fake_user = False
    obj = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(obj)
    for o in bpy.context.scene.objects:
        o.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    return obj


def timed(fn):
    t = time.perf_counter()
    result = fn()
    return time.perf_counter() - t, result


def run_rounds(case, variants, base, rounds, info):
    """Each round runs every variant once on a fresh copy of ``base``; the order rotates."""
    names = list(variants)
    for r in range(rounds):
        k = r % len(names)
        for name in names[k:] + names[:k]:
            setup, run, check = variants[name]
            obj = fresh_object(base, f"{case}_{name}")
            ctx = setup(obj) if setup else None
            seconds, result = timed(lambda: run(obj, ctx))
            if result != {"FINISHED"}:
                raise RuntimeError(f"{case}/{name} returned {result}")
            if check:
                check(obj)
            emit(case, name, r, seconds, load=load(), **info)
    clear_scene()


# ------------------------------------------------------------------------- subdivide


def torus(major=384, minor=256, radius=1.0, tube=0.3):
    """The subdivision input: a torus of ``major × minor`` quads (Blender's Add Torus stops at
    256 × 256, so it is built here) with a UV map, two materials and creases (1.0 on eight
    rings around the tube, 0.5 on eight others); a mesh kept with a fake user."""
    co = array.array("f")
    for i in range(major):
        a = 2.0 * math.pi * i / major
        for j in range(minor):
            b = 2.0 * math.pi * j / minor
            w = radius + tube * math.cos(b)
            co.extend((w * math.cos(a), w * math.sin(a), tube * math.sin(b)))
    corners = array.array("I")
    uv = array.array("f")
    for i in range(major):
        for j in range(minor):
            i1, j1 = (i + 1) % major, (j + 1) % minor
            corners.extend((i * minor + j, i1 * minor + j, i1 * minor + j1, i * minor + j1))
            u0, u1, v0, v1 = i / major, (i + 1) / major, j / minor, (j + 1) / minor
            uv.extend((u0, v0, u1, v0, u1, v1, u0, v1))
    nf = major * minor
    me = bpy.data.meshes.new("Torus")
    me.vertices.add(len(co) // 3)
    me.vertices.foreach_set("co", co)
    me.loops.add(len(corners))
    me.loops.foreach_set("vertex_index", corners)
    me.polygons.add(nf)
    me.polygons.foreach_set("loop_start", array.array("I", range(0, 4 * nf, 4)))
    if not NEW_API:
        me.polygons.foreach_set("loop_total", array.array("I", [4]) * nf)
    me.update(calc_edges=True)
    me.uv_layers.new(name="UVMap", do_init=False).data.foreach_set("uv", uv)
    ne = len(me.edges)
    ev = zeros("I", 2 * ne)
    me.edges.foreach_get("vertices", ev)
    creases = zeros("f", ne)
    step = major // 8
    for e in range(ne):
        a, b = ev[2 * e] // minor, ev[2 * e + 1] // minor
        if a == b and a % step == 0:
            creases[e] = 1.0
        elif a == b and a % step == step // 2:
            creases[e] = 0.5
    write_creases(me, creases)
    for name in ("katachi bench A", "katachi bench B"):
        me.materials.append(bpy.data.materials.get(name) or bpy.data.materials.new(name))
    me.polygons.foreach_set("material_index", array.array("I", ((f // 64) % 2 for f in range(nf))))
    me.polygons.foreach_set("use_smooth", [True] * nf)
    me.validate()
    me.use_fake_user = True
    return me


def bench_subdivide(rounds):
    base = torus()
    info = {"input_faces": len(base.polygons), "levels": 2}

    def katachi(obj, _):
        return bpy.ops.katachi.subdivide(
            "EXEC_DEFAULT", True, levels=2, uv_smooth="PRESERVE_BOUNDARIES",
        )

    def modifier(obj, _):
        # Blender's defaults (creases on, UVs: keep boundaries, limit surface on), 2 levels.
        m = obj.modifiers.new("Subdivision", "SUBSURF")
        m.levels = m.render_levels = 2
        return bpy.ops.object.modifier_apply("EXEC_DEFAULT", True, modifier=m.name)

    # The floor's result: katachi's own, read back once.
    obj = fresh_object(base, "subdivide_reference")
    katachi(obj, None)
    BENCH_OT_floor.result = Arrays(obj.data)
    expected = BENCH_OT_floor.result.summary()
    info["output_faces"] = expected["faces"]

    def floor(obj, _):
        return bpy.ops.katachi_bench.floor("EXEC_DEFAULT", True)

    def same_faces(obj):
        if len(obj.data.polygons) != expected["faces"]:
            raise RuntimeError(f"{len(obj.data.polygons)} faces, expected {expected['faces']}")

    run_rounds("subdivide", {
        "katachi": (None, katachi, same_faces),
        "host": (None, modifier, same_faces),
        "floor": (None, floor, same_faces),
    }, base, rounds, info)
    base.use_fake_user = False
    bpy.data.meshes.remove(base)


# ------------------------------------------------------------------------- cut

RESOLUTION = (800, 600)


def camera():
    cam = bpy.data.objects.get("BenchCam")
    if cam is None:
        cam = bpy.data.objects.new("BenchCam", bpy.data.cameras.new("BenchCam"))
        bpy.context.scene.collection.objects.link(cam)
    cam.location = (0.0, -4.0, 0.0)
    cam.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene = bpy.context.scene
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = RESOLUTION
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    bpy.context.view_layer.update()
    return cam


def ico_sphere(subdivisions):
    """An ico sphere of radius 1 (20 × 4^(subdivisions − 1) triangles) with Blender's UV
    map; a mesh kept with a fake user."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions, radius=1.0)
    obj = bpy.context.object
    me = obj.data
    me.use_fake_user = True
    bpy.data.objects.remove(obj)
    return me


def stroke_pixels(n=50):
    """50 points across the visible side of the sphere, left to right with a gentle wave,
    in pixels from the top-left corner of the camera's frame."""
    w, h = RESOLUTION
    return [(w * (0.12 + 0.76 * i / (n - 1)), h * (0.47 + 0.05 * math.sin(6.0 * i / (n - 1))))
            for i in range(n)]


def view_matrix(cam):
    deps = bpy.context.evaluated_depsgraph_get()
    proj = cam.calc_matrix_camera(deps, x=RESOLUTION[0], y=RESOLUTION[1])
    m = proj @ cam.matrix_world.inverted()
    return [m[r][c] for r in range(4) for c in range(4)]  # row after row


def annotate_camera_stroke(cam, pixels):
    """The stroke drawn with Blender's Annotate tool where the camera sees ``pixels`` (the
    tests' helper: the Annotate tool draws on the 3D cursor's plane in the 3D Viewport)."""
    import cut_cases

    cut_cases.clear_annotations()
    w, h = RESOLUTION
    cut_cases.annotate_through_camera(cam, [(x / w, y / h) for x, y in pixels])


def bench_cut(rounds, subdivisions, case):
    cam = camera()
    base = ico_sphere(subdivisions)
    pixels = stroke_pixels()
    matrix = view_matrix(cam)
    annotate_camera_stroke(cam, pixels)
    info = {"input_faces": len(base.polygons), "stroke_points": len(pixels)}
    common = dict(mode="VISIBLE_ONLY", open=False, keep_polygons=True,
                  snap_vertex=0.3, snap_segment=0.3, corner_angle=math.radians(60.0))

    def by_stroke(obj, _):
        return bpy.ops.katachi.cut_by_stroke(
            "EXEC_DEFAULT", True,
            stroke=[{"name": "", "co": p} for p in pixels],
            view_matrix=matrix, view_size=RESOLUTION, **common,
        )

    def by_annotation(obj, _):
        return bpy.ops.katachi.cut_by_annotation(
            "EXEC_DEFAULT", True, view="CAMERA", camera=cam.name, stroke_index=-1, **common,
        )

    def edit_mode(obj):
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")

    def bisect(obj, _):
        return bpy.ops.mesh.bisect(
            "EXEC_DEFAULT", True, plane_co=(0.0, 0.0, 0.03), plane_no=(0.05, 0.0, 1.0),
            use_fill=False, clear_inner=False, clear_outer=False,
        )

    obj = fresh_object(base, "cut_reference")
    by_stroke(obj, None)
    BENCH_OT_floor.result = Arrays(obj.data, selection=True)
    expected = BENCH_OT_floor.result.summary()
    info["output_faces"] = expected["faces"]

    def floor(obj, _):
        return bpy.ops.katachi_bench.floor("EXEC_DEFAULT", True)

    def same_faces(obj):
        if len(obj.data.polygons) != expected["faces"]:
            raise RuntimeError(f"{len(obj.data.polygons)} faces, expected {expected['faces']}")

    def leave_edit(obj):
        bpy.ops.object.mode_set(mode="OBJECT")

    def cut_something(obj):
        if len(obj.data.polygons) <= info["input_faces"]:
            raise RuntimeError(f"{len(obj.data.polygons)} faces: nothing was cut")

    run_rounds(case, {
        "katachi": (None, by_stroke, same_faces),
        "katachi annotation": (None, by_annotation, cut_something),
        "host": (edit_mode, bisect, leave_edit),
        "floor": (None, floor, same_faces),
    }, base, rounds, info)
    base.use_fake_user = False
    bpy.data.meshes.remove(base)


# ------------------------------------------------------------------------- main


CASES = [
    ("subdivide", bench_subdivide),
    ("cut 330k", lambda r: bench_cut(r, 8, "cut 330k")),
    ("cut 1.3M", lambda r: bench_cut(r, 9, "cut 1.3M")),
]


def main():
    args = parse_args()
    print(f"katachi blender bench: Blender {VERSION}, load {load()}", flush=True)
    install(args.zip)
    bpy.utils.register_class(BENCH_OT_floor)
    # A few undo steps: each variant pushes one, and the meshes are large.
    bpy.context.preferences.edit.undo_steps = 2
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    for name, fn in CASES:
        if args.only and args.only not in name:
            continue
        print(f"case {name}", flush=True)
        fn(args.rounds)
    print(f"BENCH-DONE load {load()}", flush=True)


if __name__ == "__main__":
    main()
