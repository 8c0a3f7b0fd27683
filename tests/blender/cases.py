"""The katachi add-on's test cases, run by run_tests.py inside Blender 3.4 and 5.0.

Each case builds its meshes with Blender's own tools (primitives, the Boolean modifier),
runs ``bpy.ops.katachi.subdivide`` as the menu would, and checks the result against an
independent oracle: the ``katachi`` command-line tool run on the same mesh (exported here
as OBJ with OpenSubdiv ``t crease``/``t corner`` tags), Blender's own Subdivision Surface
modifier, or the input kept from before the call.
"""

import ctypes
import math
import os
import subprocess

import bpy

CTX = {}

#: Blender stores positions as f32; katachi computes in f64 (positions here are below 10).
TOL = 1e-6

NEW_API = bpy.app.version >= (4, 0, 0)


def setup(addon, zip_path, cli, work):
    CTX.update(addon=addon, zip=zip_path, cli=cli, work=work)


# ------------------------------------------------------------------------------- helpers


def fresh_scene():
    obj = bpy.context.view_layer.objects.active
    if obj is not None and obj.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    for collection in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras):
        for m in list(collection):
            collection.remove(m)


def check(cond, msg):
    if not cond:
        raise AssertionError(msg)


def select_only(*objs):
    for o in bpy.context.scene.objects:
        o.select_set(False)
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[0] if objs else None


def add_cube(name, size=2.0, location=(0.0, 0.0, 0.0)):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location)
    o = bpy.context.object
    o.name = name
    o.data.name = name
    return o


def object_from(name, verts, faces):
    me = bpy.data.meshes.new(name)
    me.from_pydata(verts, [], faces)
    me.update()
    o = bpy.data.objects.new(name, me)
    bpy.context.scene.collection.objects.link(o)
    return o


def edge_index(me, a, b):
    for e in me.edges:
        if set(e.vertices) == {a, b}:
            return e.index
    raise AssertionError(f"no edge {a}-{b} in {me.name}")


def set_edge_creases(me, creases):
    """creases: {(a, b): crease in 0..1}."""
    if NEW_API:
        attr = me.attributes.get("crease_edge") or me.attributes.new("crease_edge", "FLOAT", "EDGE")
        for (a, b), c in creases.items():
            attr.data[edge_index(me, a, b)].value = c
    else:
        for (a, b), c in creases.items():
            me.edges[edge_index(me, a, b)].crease = c


def edge_creases(me):
    """{(a, b) sorted: crease} for every edge with crease > 0."""
    if NEW_API:
        attr = me.attributes.get("crease_edge")
        values = [d.value for d in attr.data] if attr else [0.0] * len(me.edges)
    else:
        values = [e.crease for e in me.edges]
    return {tuple(sorted(e.vertices)): c for e, c in zip(me.edges, values) if c > 0}


def set_vertex_creases(me, creases):
    if NEW_API:
        attr = me.attributes.get("crease_vert") or me.attributes.new("crease_vert", "FLOAT", "POINT")
        for v, c in creases.items():
            attr.data[v].value = c
    else:
        import bmesh

        bm = bmesh.new()
        bm.from_mesh(me)
        layer = bm.verts.layers.crease.verify()
        bm.verts.ensure_lookup_table()
        for v, c in creases.items():
            bm.verts[v][layer] = c
        bm.to_mesh(me)
        bm.free()


def vertex_creases(me):
    if NEW_API:
        attr = me.attributes.get("crease_vert")
        return [d.value for d in attr.data] if attr else []
    layers = me.vertex_creases
    return [d.value for d in layers[0].data] if len(layers) else []


def sharpness(crease):
    """Blender's crease → OpenSubdiv sharpness, as Blender's Subdivision Surface modifier
    maps it (crease² × 10)."""
    return crease * crease * 10.0


def snapshot(obj):
    """Everything the operator could change about an object, to compare before/after."""
    me = obj.data
    return {
        "data": (me.name, me.as_pointer()),
        "co": [tuple(v.co) for v in me.vertices],
        "faces": [tuple(p.vertices) for p in me.polygons],
        "edges": [tuple(e.vertices) for e in me.edges],
        "creases": edge_creases(me),
        "vcreases": vertex_creases(me),
        "uv": {l.name: [tuple(d.uv) for d in l.data] for l in me.uv_layers},
        "materials": [p.material_index for p in me.polygons],
        "smooth": [p.use_smooth for p in me.polygons],
    }


def check_unchanged(obj, before, what):
    after = snapshot(obj)
    for key in before:
        check(after[key] == before[key], f"{what}: {obj.name}'s {key} changed")


def subdivide(**options):
    """Runs the operator; every result must be a mesh Blender finds valid as it is (the
    add-on builds it from katachi's arrays without asking Blender to repair anything)."""
    result = bpy.ops.katachi.subdivide(**options)
    check(result == {"FINISHED"}, f"katachi.subdivide returned {result}")
    edit = bpy.context.mode == "EDIT_MESH"
    for o in bpy.context.selected_objects:
        if o.type == "MESH" and not edit:
            copy = o.data.copy()
            try:
                check(not copy.validate(verbose=True), f"{o.name}: Blender had to repair the result")
            finally:
                bpy.data.meshes.remove(copy)


def expect_error(fragments, **options):
    """Runs the operator expecting an ERROR report containing every fragment."""
    try:
        result = bpy.ops.katachi.subdivide(**options)
    except RuntimeError as e:
        msg = str(e)
        for f in fragments:
            check(f in msg, f"the error {msg!r} does not mention {f!r}")
        return msg
    raise AssertionError(f"katachi.subdivide succeeded ({result}) where an error was expected")


def export_obj(obj, path):
    """The object's mesh as OBJ with its creases as OpenSubdiv tags (0-based), positions
    written exactly (Python's repr of the f32 values)."""
    me = obj.data
    used = set()
    for p in me.polygons:
        used.update(p.edge_keys)
    with open(path, "w") as f:
        for v in me.vertices:
            f.write("v %r %r %r\n" % tuple(v.co))
        for p in me.polygons:
            f.write("f " + " ".join(str(i + 1) for i in p.vertices) + "\n")
        for (a, b), c in sorted(edge_creases(me).items()):
            if (a, b) in used:
                f.write(f"t crease 2/1/0 {a} {b} {sharpness(c)!r}\n")
        for v, c in enumerate(vertex_creases(me)):
            if c > 0:
                f.write(f"t corner 1/1/0 {v} {sharpness(c)!r}\n")


def read_obj(path):
    positions, faces = [], 0
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                positions.append(tuple(float(t) for t in line.split()[1:4]))
            elif line.startswith("f "):
                faces += 1
    return positions, faces


def cli_subdivide(input_path, *options):
    out = input_path[:-4] + "_cli.obj"
    cmd = [CTX["cli"], "subdivide", input_path, out, *options]
    run = subprocess.run(cmd, capture_output=True, text=True)
    check(run.returncode == 0, f"{' '.join(cmd)} failed: {run.stderr}")
    return read_obj(out)


def export_for_cli(obj, tag):
    path = os.path.join(CTX["work"], f"{tag}_{bpy.app.version_string.split()[0]}.obj")
    export_obj(obj, path)
    return path


def compare_with_cli(obj, input_path, *options):
    """The object's (subdivided) mesh equals the CLI's output for the input: same face count,
    same vertices in the same order to TOL. Returns the largest difference."""
    positions, faces = cli_subdivide(input_path, *options)
    me = obj.data
    check(len(me.polygons) == faces, f"{obj.name}: {len(me.polygons)} faces, the CLI {faces}")
    check(
        len(me.vertices) == len(positions),
        f"{obj.name}: {len(me.vertices)} vertices, the CLI {len(positions)}",
    )
    worst = 0.0
    for v, p in zip(me.vertices, positions):
        d = max(abs(a - b) for a, b in zip(v.co, p))
        worst = max(worst, d)
    check(worst <= TOL, f"{obj.name}: positions differ from the CLI's by {worst:.3g} > {TOL}")
    return worst


def boolean_plate(name):
    """A 4 × 4 × 0.5 plate with a round hole cut by Blender's own Boolean modifier."""
    plate = add_cube(name)
    plate.scale = (2.0, 2.0, 0.25)
    bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    bpy.ops.mesh.primitive_cylinder_add(vertices=16, radius=0.75, depth=2.0)
    cutter = bpy.context.object
    mod = plate.modifiers.new("hole", "BOOLEAN")
    mod.operation = "DIFFERENCE"
    mod.object = cutter
    select_only(plate)
    bpy.ops.object.modifier_apply(modifier=mod.name)
    bpy.data.objects.remove(cutter)
    check(len(plate.modifiers) == 0, "the Boolean modifier was not applied")
    return plate


def near(a, b, tol=TOL):
    return abs(a - b) <= tol


# ------------------------------------------------------------------------------- cases


def test_installed_from_zip():
    addon = CTX["addon"]
    path = os.path.realpath(addon.__file__)
    # The target dir may lie inside the checkout (CI): compare with the add-on's sources.
    source = os.path.realpath(os.path.join(os.path.dirname(__file__), "..", "..", "blender_addon"))
    check(
        not path.startswith(source + os.sep),
        f"the add-on was loaded from the source tree ({path}), not from the installed zip",
    )
    lib_path = os.path.join(os.path.dirname(path), "libkatachi.so")
    check(os.path.isfile(lib_path), f"libkatachi.so is not beside the installed add-on: {lib_path}")
    ffi = addon.ffi
    lib = ffi.load()
    check(lib.katachi_abi_version() == ffi.KATACHI_ABI_VERSION, "ABI version mismatch")
    check(lib.version.count(".") == 2, f"odd library version {lib.version!r}")
    check(hasattr(bpy.types, "KATACHI_MT_object"), "the Object ▸ katachi menu is not registered")
    op = bpy.ops.katachi.subdivide.get_rna_type()
    check(op.name == "Subdivide (solid-aware)", f"operator label {op.name!r}")
    props = set(op.properties.keys())
    for p in ("levels", "holes", "recover_holes", "boundary", "crease_method", "uv_smooth"):
        check(p in props, f"operator property {p} is missing")
    # The operator is listed in the Object menu's katachi submenu and in Edit mode's Mesh menu.
    import inspect

    ui = inspect.getsource(addon.ui)
    check("VIEW3D_MT_object" in ui and "VIEW3D_MT_edit_mesh" in ui, "menu entries missing")


def test_creased_cube():
    cube = add_cube("Creased")
    me = cube.data
    top = [v.index for v in me.vertices if v.co.z > 0]
    ring = [(a, b) for a in top for b in top if a < b and edge_index_or_none(me, a, b) is not None]
    check(len(ring) == 4, f"the top of the cube has {len(ring)} edges")
    creases = {e: 1.0 for e in ring}
    bottom = [v.index for v in me.vertices if v.co.z < 0]
    semi = next((a, b) for a in bottom for b in bottom if a < b and edge_index_or_none(me, a, b) is not None)
    creases[semi] = 0.5
    set_edge_creases(me, creases)
    path = export_for_cli(cube, "creased_cube")
    select_only(cube)
    subdivide(levels=2)
    me = cube.data
    check(len(me.polygons) == 96, f"{len(me.polygons)} faces after 2 levels, not 96")
    compare_with_cli(cube, path, "--levels", "2")
    # Crease 1 is infinitely sharp: the top rim stays in the plane z = 1 …
    rim = [v for v in me.vertices if near(v.co.z, 1.0)]
    check(len(rim) >= 16 + 9, f"only {len(rim)} vertices stay on the creased top (z = 1)")
    # … and stays creased on the result (16 edges of crease 1 around the top).
    left = edge_creases(me)
    full = [c for c in left.values() if near(c, 1.0, 1e-6)]
    check(len(full) == 16, f"{len(full)} edges of crease 1 on the result, expected 16")
    # The semi-sharp edge (sharpness 2.5) has 0.5 left after 2 levels: crease sqrt(0.05).
    semi_left = [c for c in left.values() if not near(c, 1.0, 1e-6)]
    check(len(semi_left) == 4, f"{len(semi_left)} semi-sharp edges left, expected 4")
    for c in semi_left:
        check(near(c, math.sqrt(0.05), 1e-6), f"semi-sharp crease left {c}, expected sqrt(0.05)")


def edge_index_or_none(me, a, b):
    for e in me.edges:
        if set(e.vertices) == {a, b}:
            return e.index
    return None


def test_creases_change_the_result():
    plain = add_cube("Plain")
    creased = add_cube("Creased", location=(4, 0, 0))
    set_edge_creases(creased.data, {tuple(creased.data.edges[0].vertices): 1.0})
    select_only(plain, creased)
    subdivide(levels=1)
    a = [tuple(v.co) for v in plain.data.vertices]
    b = [tuple(v.co) for v in creased.data.vertices]
    check(len(a) == len(b), "cube results differ in size")
    check(max(max(abs(x - y) for x, y in zip(p, q)) for p, q in zip(a, b)) > 1e-3,
          "an edge crease of 1 did not change the subdivided cube")


def test_vertex_crease_pins_a_corner():
    cube = add_cube("Corner")
    me = cube.data
    corner = next(v.index for v in me.vertices if v.co.x > 0 and v.co.y > 0 and v.co.z > 0)
    set_vertex_creases(me, {corner: 1.0})
    check(len(vertex_creases(me)) == len(me.vertices), "the vertex crease was not stored")
    path = export_for_cli(cube, "vertex_crease")
    select_only(cube)
    subdivide(levels=2)
    pinned = [v for v in cube.data.vertices if all(near(c, 1.0) for c in v.co)]
    check(len(pinned) == 1, "the corner with vertex crease 1 did not stay at (1, 1, 1)")
    compare_with_cli(cube, path, "--levels", "2")


def test_boolean_plate_recovered():
    plate = boolean_plate("Plate")
    n_in = len(plate.data.polygons)
    path = export_for_cli(plate, "plate")
    results = {}
    for holes in ("SMOOTH", "SHARP"):
        fresh = plate.copy()
        fresh.data = plate.data.copy()
        bpy.context.scene.collection.objects.link(fresh)
        select_only(fresh)
        subdivide(levels=2, holes=holes, recover_holes=True)
        check(len(fresh.data.polygons) > 4 * n_in // 2, f"{holes}: too few faces")
        compare_with_cli(fresh, path, "--levels", "2", "--solid", "--holes", holes.lower())
        results[holes] = fresh
    # Method [b] keeps the face around the hole planar: its hole rim stays at the top
    # (z = 0.25) and round (radius 0.75 at the 16 cut vertices); method [a] rounds it off.
    top_b = [v for v in results["SHARP"].data.vertices if near(v.co.z, 0.25)]
    top_a = [v for v in results["SMOOTH"].data.vertices if near(v.co.z, 0.25)]
    check(len(top_b) > len(top_a), f"[b] kept {len(top_b)} vertices on the top plane, [a] {len(top_a)}")
    def rim(obj):
        return [v for v in obj.data.vertices
                if near(v.co.z, 0.25) and 0.70 < math.hypot(v.co.x, v.co.y) < 0.76]

    # Level 2 puts 4 rim vertices on each of the 16 hole edges; the sharp rim is a B-spline
    # of the 16-gon, so at radius about 0.732.
    rim_a, rim_b = rim(results["SMOOTH"]), rim(results["SHARP"])
    check(len(rim_b) == 64, f"[b] kept {len(rim_b)} hole-rim vertices on the top plane, not 64")
    check(len(rim_a) == 0, f"[a] left {len(rim_a)} hole-rim vertices on the top plane, not 0")
    # Without recovery the Boolean's n-gons are subdivided as they are: another result.
    plain = plate.copy()
    plain.data = plate.data.copy()
    bpy.context.scene.collection.objects.link(plain)
    select_only(plain)
    subdivide(levels=2, holes="SHARP", recover_holes=False)
    compare_with_cli(plain, path, "--levels", "2", "--holes", "sharp")
    check(
        len(plain.data.vertices) != len(results["SHARP"].data.vertices)
        or any(not near(a.co.z, b.co.z) for a, b in zip(plain.data.vertices, results["SHARP"].data.vertices)),
        "recovering faces with holes made no difference on a Boolean's output",
    )
    # The original (not selected) plate was left alone.
    check(len(plate.data.polygons) == n_in, "the unselected plate changed")


def cube_side(p):
    """(axis, sign) of the cube face a face of a (subdivided) cube centred at 0 lies over."""
    c = p.center
    axis = max(range(3), key=lambda i: abs(c[i]))
    return axis, 1 if c[axis] > 0 else -1


def expected_material(p):
    return 1 if cube_side(p) == (0, 1) else 0


def expected_smooth(p):
    return cube_side(p) != (2, 1)


def test_uvs_materials_and_smooth_flags():
    """Against Blender's own Subdivision Surface modifier on the same mesh: positions and, at
    each position, the UVs of both maps (Keep Boundaries, Blender's default); materials and
    smooth flags follow the faces they come from."""
    cube = add_cube("Textured")
    me = cube.data
    check(len(me.uv_layers) == 1, "the cube primitive has no UV map")
    second = me.uv_layers.new(name="Second")
    for d, src in zip(second.data, me.uv_layers[0].data):
        d.uv = (src.uv[0] * 0.5 + 0.25, src.uv[1] * 0.5 + 0.1)
    red, blue = bpy.data.materials.new("Red"), bpy.data.materials.new("Blue")
    me.materials.append(red)
    me.materials.append(blue)
    for p in me.polygons:
        p.material_index = expected_material(p)
        p.use_smooth = expected_smooth(p)
    reference = cube.copy()
    reference.data = me.copy()
    bpy.context.scene.collection.objects.link(reference)
    mod = reference.modifiers.new("subsurf", "SUBSURF")
    mod.levels = 2
    mod.uv_smooth = "PRESERVE_BOUNDARIES"
    mod.boundary_smooth = "ALL"
    mod.use_limit_surface = False
    deps = bpy.context.evaluated_depsgraph_get()
    ref = reference.evaluated_get(deps).to_mesh()

    select_only(cube)
    subdivide(levels=2, uv_smooth="PRESERVE_BOUNDARIES")
    me = cube.data
    check([l.name for l in me.uv_layers] == ["UVMap", "Second"], "UV maps not carried by name")
    check([m.name for m in me.materials] == ["Red", "Blue"], "materials not carried")
    check(len(me.polygons) == len(ref.polygons) == 96, "face counts differ from the modifier's")

    def corners(mesh):
        out = {}
        for p in mesh.polygons:
            for li in p.loop_indices:
                v = mesh.loops[li].vertex_index
                key = tuple(round(c, 5) for c in mesh.vertices[v].co)
                uvs = tuple(tuple(round(x, 5) for x in l.data[li].uv) for l in mesh.uv_layers)
                out.setdefault(key, set()).add(uvs)
        return out

    ours, theirs = corners(me), corners(ref)
    check(set(ours) == set(theirs), "vertex positions differ from Blender's Subdivision Surface")
    bad = [k for k in ours if ours[k] != theirs[k]]
    check(not bad, f"UVs differ from Blender's Subdivision Surface at {len(bad)} vertices, e.g. {bad[:1]}")
    # Each face of the rounded cube lies over the cube face it comes from: the axis of its
    # centre's largest coordinate names that face.
    for p in me.polygons:
        check(p.material_index == expected_material(p), f"face {p.index}: material")
        check(p.use_smooth == expected_smooth(p), f"face {p.index}: smooth flag")
    reference.evaluated_get(deps).to_mesh_clear()


def test_uv_modes_reach_katachi():
    a = add_cube("UvAll")
    b = add_cube("UvNone", location=(4, 0, 0))
    select_only(a)
    subdivide(levels=1, uv_smooth="SMOOTH_ALL")
    select_only(b)
    subdivide(levels=1, uv_smooth="NONE")
    ua = [tuple(d.uv) for d in a.data.uv_layers[0].data]
    ub = [tuple(d.uv) for d in b.data.uv_layers[0].data]
    check(len(ua) == len(ub), "UV counts differ")
    check(any(abs(x - y) > 1e-4 for p, q in zip(ua, ub) for x, y in zip(p, q)),
          "UV Smooth 'All' and 'None' gave the same UVs")


def set_planar_uvs(me):
    """One UV per vertex and no seams: every loop's UV is (x, y) of its vertex."""
    layer = me.uv_layers[0] if me.uv_layers else me.uv_layers.new(name="UVMap")
    for loop, d in zip(me.loops, layer.data):
        co = me.vertices[loop.vertex_index].co
        d.uv = (co.x, co.y)


def uv_position_gap(me):
    """The largest |UV − (x, y)| over all loops of the first UV map."""
    layer = me.uv_layers[0]
    worst = 0.0
    for loop, d in zip(me.loops, layer.data):
        co = me.vertices[loop.vertex_index].co
        worst = max(worst, abs(d.uv[0] - co.x), abs(d.uv[1] - co.y))
    return worst


def test_smooth_uvs_on_faces_kept_with_their_holes():
    """Method [b] keeps the recovered top and bottom faces of a Boolean plate whole, holes
    and all; smooth UVs over them used to fail (the add-on fell back to linear UVs). With
    UV = (x, y) of each vertex and no seams, smooth face-varying interpolation is the vertex
    interpolation applied to (x, y), so each refined loop's UV is (x, y) of its refined vertex;
    linear UVs (UV Smooth 'None') are not, which shows the check can fail."""
    addon = CTX["addon"]
    ffi, convert = addon.ffi, addon.convert
    lib = ffi.load()
    plate = boolean_plate("UvPlate")
    set_planar_uvs(plate.data)
    check(uv_position_gap(plate.data) < 1e-7, "the input UVs are not (x, y)")
    path = export_for_cli(plate, "uv_plate")

    # The case is the one that failed: faces with holes survive level 0 (katachi's own count).
    options = lib.katachi_subdivide_options_default()
    options.levels = 2
    options.holes = ffi.KATACHI_HOLE_METHOD_SHARP
    options.recover_faces_with_holes = 1
    with convert.to_katachi(lib, convert.InputMesh(plate.data)) as mesh:
        with ffi.subdivide(lib, mesh, options) as sub:
            handle = ctypes.POINTER(ffi.KatachiMesh)()
            lib.call("katachi_subdivision_mesh", sub.handle, ctypes.byref(handle))
            with ffi.Mesh(lib, handle) as refined:
                kept = refined.inspect().faces_with_holes_count
    check(kept > 0, "no face kept its hole: the case does not test faces kept whole")

    gaps = {}
    for mode in ("SMOOTH_ALL", "PRESERVE_CORNERS", "PRESERVE_BOUNDARIES", "NONE"):
        o = plate.copy()
        o.data = plate.data.copy()
        o.name = o.data.name = f"UvPlate_{mode}"
        bpy.context.scene.collection.objects.link(o)
        select_only(o)
        subdivide(levels=2, holes="SHARP", recover_holes=True, uv_smooth=mode)
        compare_with_cli(o, path, "--levels", "2", "--solid", "--holes", "sharp")
        check(len(o.data.uv_layers) == 1, f"{mode}: {len(o.data.uv_layers)} UV maps")
        gaps[mode] = uv_position_gap(o.data)
    # 'All' is katachi's FaceVarying::Smooth; without seams the other smooth modes have no
    # UV boundary to treat apart, so they agree with it.
    for mode in ("SMOOTH_ALL", "PRESERVE_CORNERS", "PRESERVE_BOUNDARIES"):
        check(gaps[mode] <= 1e-5,
              f"UV Smooth {mode}: refined UVs differ from (x, y) by {gaps[mode]:.3g} "
              f"(linear UVs differ by {gaps['NONE']:.3g})")
    check(gaps["NONE"] > 1e-3,
          f"linear UVs match (x, y) to {gaps['NONE']:.3g}: the check above cannot fail")


def fin(name):
    """A non-manifold mesh: three quads on one edge."""
    verts = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (1, -1, 0), (0, -1, 0), (1, 0, 1), (0, 0, 1)]
    return object_from(name, verts, [(0, 1, 2, 3), (1, 0, 5, 4), (0, 1, 6, 7)])


def test_three_objects_at_once():
    cube = add_cube("A")
    set_edge_creases(cube.data, {tuple(cube.data.edges[0].vertices): 0.7})
    plate = boolean_plate("B")
    plate.location = (6, 0, 0)
    bpy.ops.mesh.primitive_cylinder_add(vertices=12, location=(0, 6, 0))
    cyl = bpy.context.object
    cyl.name = "C"
    paths = {o.name: export_for_cli(o, f"three_{o.name}") for o in (cube, plate, cyl)}
    select_only(cube, plate, cyl)
    subdivide(levels=2, recover_holes=True, holes="SHARP", crease_method="CHAIKIN")
    for o in (cube, plate, cyl):
        compare_with_cli(o, paths[o.name], "--levels", "2", "--solid", "--holes", "sharp",
                         "--crease-method", "chaikin")


def test_options_reach_katachi():
    """Boundary rule on an open grid, compared with the CLI for both values."""
    for boundary, flag in (("EDGE_ONLY", "edge-only"), ("EDGE_AND_CORNER", "edge-and-corner")):
        fresh_scene()
        bpy.ops.mesh.primitive_grid_add(x_subdivisions=3, y_subdivisions=3, size=2)
        grid = bpy.context.object
        path = export_for_cli(grid, f"grid_{flag}")
        select_only(grid)
        subdivide(levels=2, boundary=boundary)
        compare_with_cli(grid, path, "--levels", "2", "--boundary", flag)
        corner_kept = any(near(v.co.x, 1.0) and near(v.co.y, 1.0) for v in grid.data.vertices)
        check(corner_kept == (boundary == "EDGE_AND_CORNER"),
              f"{boundary}: the grid's corner {'moved' if corner_kept is False else 'stayed'}")


def test_shared_mesh_and_non_mesh_in_selection():
    cube = add_cube("Shared")
    twin = cube.copy()  # a linked duplicate: same mesh
    bpy.context.scene.collection.objects.link(twin)
    empty = bpy.data.objects.new("Helper", None)
    bpy.context.scene.collection.objects.link(empty)
    select_only(cube, twin, empty)
    subdivide(levels=1)
    check(cube.data == twin.data, "the linked duplicates no longer share their mesh")
    check(len(cube.data.polygons) == 24, f"{len(cube.data.polygons)} faces, expected 24")
    check(cube.data.name == "Shared", f"the mesh was renamed to {cube.data.name}")
    check(bpy.data.meshes.get("Shared") is cube.data and len(bpy.data.meshes) == 1,
          "the old mesh was not replaced")


def test_edit_mode():
    cube = add_cube("Edited")
    path = export_for_cli(cube, "edit_mode")
    select_only(cube)
    bpy.ops.object.mode_set(mode="EDIT")
    subdivide(levels=1)
    check(cube.mode == "EDIT", "the operator left Edit mode")
    bpy.ops.object.mode_set(mode="OBJECT")
    compare_with_cli(cube, path, "--levels", "1")


def test_progress_per_level():
    """katachi_subdivide_with_progress reports each level; the operator's progress bar
    advances with them."""
    addon = CTX["addon"]
    ffi, convert = addon.ffi, addon.convert
    lib = ffi.load()
    cube = add_cube("Progress")
    data = convert.InputMesh(cube.data)
    options = lib.katachi_subdivide_options_default()
    options.levels = 3
    calls = []
    with convert.to_katachi(lib, data) as mesh:
        with ffi.subdivide(lib, mesh, options, lambda done, total: calls.append((done, total))) as sub:
            check(sub.info().face_count == 6 * 4 ** 3, "3 levels did not give 384 faces")
        check(calls == [(1, 3), (2, 3), (3, 3)], f"progress calls {calls}")
        with ffi.subdivide(lib, mesh, options) as sub:  # no callback (NULL)
            check(sub.info().levels == 3, "subdividing without a callback failed")

        # An exception in the callback comes out of ffi.subdivide once katachi returns.
        def stop(done, total):
            raise KeyError(f"stop at {done}")

        try:
            ffi.subdivide(lib, mesh, options, stop)
        except KeyError as e:
            check("stop at 1" in str(e), f"the callback's exception {e!r} is not the first one")
        else:
            raise AssertionError("an exception in the progress callback was lost")

    # The operator hands convert.subdivide a progress function that wm.progress_update
    # follows; between reading the mesh (0.1) and the result (0.6) it moves once per level.
    seen = []
    real = convert.subdivide

    def spy(lib, data, options, uv_mode, progress=None):
        check(progress is not None, "the operator gave no progress function")

        def record(fraction):
            seen.append(fraction)
            progress(fraction)

        return real(lib, data, options, uv_mode, record)

    convert.subdivide = spy
    try:
        select_only(cube)
        subdivide(levels=4)
    finally:
        convert.subdivide = real
    per_level = [f for f in seen if 0.1 < f < 0.6 + 1e-9]
    expected = [0.1 + 0.5 * k / 4 for k in range(1, 5)]
    check(len(per_level) >= 4 and all(near(a, b, 1e-9) for a, b in zip(per_level, expected)),
          f"progress fractions {seen}, expected {expected} between 0.1 and 0.6")
    check(seen == sorted(seen), f"progress went backwards: {seen}")
    check(len(cube.data.polygons) == 6 * 4 ** 4, "the operator did not subdivide 4 levels")


def test_bad_options_are_invalid_arguments():
    """Bad options are KATACHI_STATUS_INVALID_ARGUMENT (an empty mesh stays BAD_INPUT); the
    operator's Levels cannot leave katachi's range 1..8."""
    addon = CTX["addon"]
    ffi, convert = addon.ffi, addon.convert
    lib = ffi.load()
    cube = add_cube("Options")
    with convert.to_katachi(lib, convert.InputMesh(cube.data)) as mesh:
        for field, value in (("levels", 0), ("levels", 9), ("holes", 7), ("boundary", 9)):
            options = lib.katachi_subdivide_options_default()
            setattr(options, field, value)
            try:
                ffi.subdivide(lib, mesh, options).close()
            except ffi.KatachiError as e:
                check(e.status == ffi.KATACHI_STATUS_INVALID_ARGUMENT,
                      f"{field} = {value}: status {e.status} ({e}), not INVALID_ARGUMENT")
                check(e.function == "katachi_subdivide_with_progress", f"raised by {e.function}")
                check(str(e), f"{field} = {value}: no message")
            else:
                raise AssertionError(f"{field} = {value} was accepted")
    levels = bpy.ops.katachi.subdivide.get_rna_type().properties["levels"]
    check((levels.hard_min, levels.hard_max) == (1, 8),
          f"Levels ranges {levels.hard_min}..{levels.hard_max}, katachi takes 1..8")
    # An empty mesh is bad input, not a bad argument; the operator reports it by name.
    o = object_from("EmptyForStatus", [], [])
    try:
        with convert.to_katachi(lib, convert.InputMesh(o.data)) as mesh:
            ffi.subdivide(lib, mesh, lib.katachi_subdivide_options_default()).close()
    except ffi.KatachiError as e:
        check(e.status == ffi.KATACHI_STATUS_BAD_INPUT,
              f"an empty mesh: status {e.status} ({e}), not BAD_INPUT")
    else:
        raise AssertionError("an empty mesh was subdivided")
    select_only(o)
    expect_error(["katachi", "EmptyForStatus", "empty"])


# ---- bad cases: an error with katachi's message, and nothing changed ----


def test_error_non_mesh_only():
    empty = bpy.data.objects.new("JustAnEmpty", None)
    bpy.context.scene.collection.objects.link(empty)
    cube = add_cube("Bystander")
    before = snapshot(cube)
    select_only(empty)
    expect_error(["katachi", "no mesh object", "JustAnEmpty"])
    check_unchanged(cube, before, "non-mesh selection")


def test_error_empty_mesh():
    o = object_from("Nothing", [], [])
    before = snapshot(o)
    select_only(o)
    expect_error(["katachi", "Nothing", "empty"])
    check_unchanged(o, before, "empty mesh")


def test_error_nan_vertex():
    cube = add_cube("Broken")
    cube.data.vertices[3].co.x = float("nan")
    before = snapshot(cube)
    select_only(cube)
    msg = expect_error(["katachi", "Broken", "3"])
    check("nan" in msg.lower() or "finite" in msg.lower(), f"the message {msg!r} names no NaN")
    after = snapshot(cube)
    check(math.isnan(after["co"][3][0]), "the NaN vertex changed")
    before["co"] = after["co"] = None
    check_unchanged(cube, {k: v for k, v in before.items() if k != "co"}, "NaN vertex")


def test_error_repeated_vertex_in_face():
    o = object_from("Pinched", [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [(0, 1, 2, 1)])
    check(len(o.data.polygons) == 1, "Blender did not keep the pinched face")
    before = snapshot(o)
    select_only(o)
    expect_error(["katachi", "Pinched"])
    check_unchanged(o, before, "repeated vertex")


def test_error_leaves_every_selected_object_unchanged():
    good = add_cube("Good")
    set_edge_creases(good.data, {tuple(good.data.edges[0].vertices): 1.0})
    bad = object_from("Bad", [], [])
    snaps = {o.name: snapshot(o) for o in (good, bad)}
    select_only(good, bad)
    expect_error(["katachi", "Bad"], levels=2)
    for o in (good, bad):
        check_unchanged(o, snaps[o.name], "one bad object among several")
    check(len(bpy.data.meshes) == 2, f"{len(bpy.data.meshes)} meshes after a failed run: results leaked")


def test_error_non_manifold_with_recovery():
    """Recovering faces with holes needs a manifold mesh: katachi refuses, naming the edge."""
    o = fin("Fin")
    before = snapshot(o)
    select_only(o)
    expect_error(["katachi", "Fin", "non-manifold", "0-1"], recover_holes=True)
    check_unchanged(o, before, "non-manifold mesh")


def test_non_manifold_is_subdivided():
    """katachi subdivides non-manifold meshes (as OpenSubdiv does), so this is no error."""
    o = fin("Fin")
    path = export_for_cli(o, "fin")
    select_only(o)
    subdivide(levels=2)
    compare_with_cli(o, path, "--levels", "2")


TESTS = [(name, fn) for name, fn in list(globals().items()) if name.startswith("test_")]
