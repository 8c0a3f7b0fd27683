"""Blender meshes to katachi meshes and back, by copying whole arrays.

Nothing geometric happens here, and nothing is done element by element in Python: the
input's arrays are read with ``foreach_get`` into ``array.array`` buffers (which ctypes
reads in place; Debian's Blender has no numpy), katachi computes the result and gives it
as the arrays Blender stores (float positions, polygons by their first corner, the edge
list with each corner's edge, creases in Blender's scale, materials and smooth flags
carried to the new faces, UVs per corner), and those are written with ``foreach_set``.

Each version's fastest path is used, the one that copies a whole array at once: Blender
3.4's element properties (``MeshVertex.co``, ``MeshLoop.vertex_index``…) with unsigned
(``I``) buffers, and from 4.0 the attributes (``position``, ``.corner_vert``,
``.edge_verts``, ``crease_edge``…) with signed (``i``) buffers, where the element
properties copy element by element, ten to a hundred times slower. Booleans go through
lists (3.4) or ``bytearray`` (4.0+), for the same reason.

Versions: Blender 3.4 keeps edge creases in ``MeshEdge.crease`` and vertex creases in
``Mesh.vertex_creases``; 4.0 and later in the ``crease_edge`` and ``crease_vert`` float
attributes, and smooth shading as the ``sharp_face`` attribute (4.1). From 4.0
``MeshPolygon.loop_total`` is read-only (face sizes follow from ``loop_start``).
"""

import array
import ctypes
import math
from ctypes import POINTER, byref, c_double, c_float, c_uint32

import bpy

from . import ffi

#: Blender 4.0 moved creases (and the mesh's own arrays) to attributes and made
#: ``loop_total`` read-only.
ATTRIBUTE_CREASES = NEW_API = bpy.app.version >= (4, 0, 0)
#: Element indices: 4.0+'s attributes copy whole signed arrays, 3.4's element properties
#: whole unsigned ones (katachi reads both as ``uint32_t``: indices are never negative).
INDEX = "i" if NEW_API else "I"


class ConversionError(Exception):
    """A Blender mesh that cannot be handed to katachi (or a result Blender refused)."""


def crease_to_sharpness(crease):
    """Blender's edge or vertex crease (0..1) as an OpenSubdiv sharpness (0..10).

    The mapping Blender's Subdivision Surface modifier uses with OpenSubdiv: the square of
    the crease times 10, so crease 1 is infinitely sharp (10) and 0.5 is 2.5. (katachi
    applies it itself to whole arrays: ``KATACHI_SHARPNESS_SCALE_CREASE``.)"""
    c = min(max(crease, 0.0), 1.0)
    return c * c * 10.0


def sharpness_to_crease(sharpness):
    """The inverse of :func:`crease_to_sharpness`, for creases left on the result."""
    return math.sqrt(min(max(sharpness, 0.0), 10.0) / 10.0)


def _zeros(typecode, n):
    a = array.array(typecode)
    a.frombytes(bytes(n * a.itemsize))
    return a


def _bools(n):
    """``n`` booleans for ``foreach_get``/``foreach_set`` (a list: Blender 3.4 accepts no
    buffer for boolean properties; these are per face, so the cost is small)."""
    return [False] * n


def _attribute(mesh, name, domain, data_type, typecode, n):
    """The values of attribute ``name`` (``array(typecode)``, or ``bytearray`` for booleans),
    None when the mesh has no such attribute."""
    attr = mesh.attributes.get(name)
    if attr is None or attr.domain != domain or attr.data_type != data_type:
        return None
    values = bytearray(n) if data_type == "BOOLEAN" else _zeros(typecode, n)
    attr.data.foreach_get("value", values)
    return values


def _float_attribute(mesh, name, domain, n):
    return _attribute(mesh, name, domain, "FLOAT", "f", n)


def _edge_creases(mesh, ne):
    if ATTRIBUTE_CREASES:
        return _float_attribute(mesh, "crease_edge", "EDGE", ne)
    values = _zeros("f", ne)
    mesh.edges.foreach_get("crease", values)
    return values


def _vertex_creases(mesh, nv):
    if ATTRIBUTE_CREASES:
        return _float_attribute(mesh, "crease_vert", "POINT", nv)
    layers = getattr(mesh, "vertex_creases", None)
    if not layers or len(layers) == 0:
        return None
    values = _zeros("f", nv)
    layers[0].data.foreach_get("value", values)
    return values


def _any_nonzero(values):
    """Whether an ``array``/``bytearray`` holds anything but zeros (a C-speed scan)."""
    return values is not None and values.count(0) != len(values)


# ---------------------------------------------------------------------------- reading


class InputMesh:
    """A Blender mesh's arrays, read whole (see the module's docs for the paths)."""

    def __init__(self, mesh):
        self.name = mesh.name
        nv, ne = len(mesh.vertices), len(mesh.edges)
        nf, nl = len(mesh.polygons), len(mesh.loops)
        self.vertex_count, self.edge_count = nv, ne
        self.face_count, self.corner_count = nf, nl
        self.positions = _zeros("f", 3 * nv)
        self.face_starts = _zeros("I", nf)
        mesh.polygons.foreach_get("loop_start", self.face_starts)
        self.face_sizes = None  # 4.0+: faces are stored one after the other
        self.corners = _zeros(INDEX, nl)
        self.edges = _zeros(INDEX, 2 * ne)
        self.corner_edges = _zeros(INDEX, nl)
        self.uv_layers = []  # [(name, array('f'), 2 per corner)]
        if NEW_API:
            a = mesh.attributes
            # An empty domain has no attribute at all.
            for name, prop, buf in (
                ("position", "vector", self.positions),
                (".corner_vert", "value", self.corners),
                (".corner_edge", "value", self.corner_edges),
                (".edge_verts", "value", self.edges),
            ):
                if len(buf):
                    a[name].data.foreach_get(prop, buf)
            self.materials = _attribute(mesh, "material_index", "FACE", "INT", "i", nf)
            self.sharp_face = _attribute(mesh, "sharp_face", "FACE", "BOOLEAN", None, nf)
            self.smooth = None
            for layer in mesh.uv_layers:
                uv = _zeros("f", 2 * nl)
                a[layer.name].data.foreach_get("vector", uv)
                self.uv_layers.append((layer.name, uv))
        else:
            mesh.vertices.foreach_get("co", self.positions)
            self.face_sizes = _zeros("I", nf)
            mesh.polygons.foreach_get("loop_total", self.face_sizes)
            mesh.loops.foreach_get("vertex_index", self.corners)
            mesh.loops.foreach_get("edge_index", self.corner_edges)
            mesh.edges.foreach_get("vertices", self.edges)
            self.materials = _zeros("I", nf)
            mesh.polygons.foreach_get("material_index", self.materials)
            self.smooth = _bools(nf)
            mesh.polygons.foreach_get("use_smooth", self.smooth)
            self.sharp_face = None
            for layer in mesh.uv_layers:
                uv = _zeros("f", 2 * nl)
                layer.data.foreach_get("uv", uv)
                self.uv_layers.append((layer.name, uv))
        self.edge_creases = _edge_creases(mesh, ne)
        vcreases = _vertex_creases(mesh, nv)
        self.vertex_creases = vcreases if _any_nonzero(vcreases) else None
        self.active_uv = mesh.uv_layers.active_index if mesh.uv_layers else -1
        self.active_render_uv = next(
            (i for i, l in enumerate(mesh.uv_layers) if l.active_render), -1
        )
        #: Edges in no face (katachi drops them); known once :func:`to_katachi` ran.
        self.loose_edge_count = 0


# ---------------------------------------------------------------------------- katachi


def _u32(a):
    return ffi.ptr(a, c_uint32)


def _f64(a):
    return ffi.ptr(a, c_double)


def _f32(a):
    return ffi.ptr(a, c_float)


def _void(a):
    return ctypes.cast(ffi.ptr(a, ctypes.c_uint8), ctypes.c_void_p)


def create_mesh(lib, data):
    """A new :class:`ffi.Mesh` of ``data``'s simple faces: ``positions`` (doubles),
    ``vertex_count``, ``loop_sizes``, ``face_count``, ``corners`` and ``corner_count`` (a
    ``cutting.CutSource``)."""
    handle = POINTER(ffi.KatachiMesh)()
    face_loops = array.array("I", [1]) * data.face_count
    lib.call(
        "katachi_mesh_create",
        _f64(data.positions),
        data.vertex_count,
        _u32(data.loop_sizes),
        data.face_count,
        _u32(face_loops),
        data.face_count,
        _u32(data.corners),
        data.corner_count,
        byref(handle),
    )
    return ffi.Mesh(lib, handle)


def _copy_positions(lib, mesh, counts):
    positions = _zeros("d", 3 * counts.vertex_count)
    lib.call("katachi_mesh_copy_positions", mesh.handle, _f64(positions), len(positions))
    return positions


def _copy_faces(lib, mesh, counts):
    loop_sizes = _zeros("I", counts.loop_count)
    face_loops = _zeros("I", counts.face_count)
    corners = _zeros("I", counts.corner_count)
    lib.call(
        "katachi_mesh_copy_faces",
        mesh.handle,
        _u32(loop_sizes),
        len(loop_sizes),
        _u32(face_loops),
        len(face_loops),
        _u32(corners),
        len(corners),
    )
    return loop_sizes, face_loops, corners


def to_katachi(lib, data):
    """A new :class:`ffi.Mesh` holding ``data`` (an :class:`InputMesh`) with its edge and
    vertex creases; sets ``data.loose_edge_count``."""
    handle = POINTER(ffi.KatachiMesh)()
    lib.call(
        "katachi_mesh_create_polygons_f32",
        _f32(data.positions),
        data.vertex_count,
        _u32(data.face_starts),
        _u32(data.face_sizes) if data.face_sizes is not None else None,
        data.face_count,
        _u32(data.corners),
        data.corner_count,
        byref(handle),
    )
    mesh = ffi.Mesh(lib, handle)
    try:
        loose = c_uint32(0)
        creases = data.edge_creases if _any_nonzero(data.edge_creases) else None
        lib.call(
            "katachi_mesh_set_edge_sharpness_f32",
            mesh.handle,
            _u32(data.edges),
            _f32(creases) if creases is not None else None,
            data.edge_count,
            _u32(data.corner_edges),
            data.corner_count,
            ffi.KATACHI_SHARPNESS_SCALE_CREASE,
            byref(loose),
        )
        data.loose_edge_count = loose.value
        if data.vertex_creases is not None:
            lib.call(
                "katachi_mesh_set_vertex_sharpness_f32",
                mesh.handle,
                _f32(data.vertex_creases),
                data.vertex_count,
                ffi.KATACHI_SHARPNESS_SCALE_CREASE,
            )
    except BaseException:
        mesh.close()
        raise
    return mesh


class Result:
    """A subdivided mesh as the arrays Blender stores (see :func:`subdivide`)."""

    positions = None  # array('f'), 3 per vertex
    face_starts = None  # array('I'), first corner of each face
    face_sizes = None  # array('I'), corners of each face (for Blender 3.4's loop_total)
    corners = None  # array(INDEX), one vertex per corner
    edges = None  # array(INDEX), 2 per edge
    corner_edges = None  # array(INDEX), one edge per corner
    edge_creases = None  # array('f') per edge, or None when no crease is left
    vertex_creases = None  # array('f') per vertex, or None
    materials = None  # array per face, or None (all 0)
    smooth = None  # 3.4: list per face, or None (all flat)
    sharp_face = None  # 4.0+: bytearray per face, or None (all smooth)
    uv_layers = ()  # [(name, array('f') 2 per corner)]
    fallback = ()  # [(input face, reason)]

    def __init__(self):
        self.warnings = []  # what the user should know, for self.report({'WARNING'})


def _carry(lib, sub, values, typecode, size, n):
    """Per-input-face ``values`` (``size`` bytes each) carried to the ``n`` result faces."""
    out = _zeros(typecode, n) if typecode else bytearray(n)
    lib.call(
        "katachi_subdivision_carry_face_data", sub.handle, _void(values), len(values), size,
        _void(out), n,
    )
    return out


def subdivide(lib, data, options, uv_mode, progress=None):
    """Subdivides ``data`` (an :class:`InputMesh`) with ``options`` (a
    ``KatachiSubdivideOptions``); UV maps follow with ``uv_mode`` (a ``KatachiFaceVarying``).
    Faces with holes in the result come back cut into simple polygons (Blender stores
    none). ``progress(fraction)`` is called between stages and after each subdivision
    level (from 0.1 to 0.6 as the levels are refined). Raises :class:`ffi.KatachiError`."""
    step = progress or (lambda f: None)
    out = Result()

    def level_done(done, total):
        step(0.1 + 0.5 * done / max(total, 1))

    options.split_faces_with_holes = 1
    with to_katachi(lib, data) as mesh:
        step(0.1)
        subdivision = ffi.subdivide(lib, mesh, options, level_done)
    with subdivision as sub:
        step(0.6)
        info = sub.info()
        out.fallback = _fallbacks(lib, sub, info)
        h = sub.handle
        nv, nf, nc, ne = info.vertex_count, info.face_count, info.corner_count, info.edge_count
        out.positions = _zeros("f", 3 * nv)
        lib.call("katachi_subdivision_copy_positions_f32", h, _f32(out.positions), 3 * nv)
        out.face_starts = _zeros("I", nf)
        out.corners = _zeros(INDEX, nc)
        if not NEW_API:
            out.face_sizes = _zeros("I", nf)
        lib.call(
            "katachi_subdivision_copy_polygons", h, _u32(out.face_starts), nf,
            _u32(out.face_sizes) if out.face_sizes is not None else None, nf,
            _u32(out.corners), nc,
        )
        out.edges = _zeros(INDEX, 2 * ne)
        out.corner_edges = _zeros(INDEX, nc)
        lib.call(
            "katachi_subdivision_copy_edges", h, _u32(out.edges), 2 * ne,
            _u32(out.corner_edges), nc,
        )
        if info.sharp_edge_count:
            out.edge_creases = _zeros("f", ne)
            lib.call(
                "katachi_subdivision_copy_edge_sharpness_f32", h, _f32(out.edge_creases), ne,
                ffi.KATACHI_SHARPNESS_SCALE_CREASE,
            )
        if info.sharp_vertex_count:
            out.vertex_creases = _zeros("f", nv)
            lib.call(
                "katachi_subdivision_copy_vertex_sharpness_f32", h, _f32(out.vertex_creases),
                nv, ffi.KATACHI_SHARPNESS_SCALE_CREASE,
            )
        if _any_nonzero(data.materials):
            out.materials = _carry(lib, sub, data.materials, INDEX, 4, nf)
        if data.smooth is not None and any(data.smooth):
            flags = _carry(lib, sub, bytearray(data.smooth), None, 1, nf)
            out.smooth = [True] * nf if all(data.smooth) else list(flags)
        if data.sharp_face is not None:
            out.sharp_face = _carry(lib, sub, data.sharp_face, None, 1, nf)
        step(0.7)
        layers = []
        for name, uv in data.uv_layers:
            refined = _zeros("f", 2 * nc)
            lib.call(
                "katachi_subdivision_refine_corner_data_f32", h, _f32(uv), len(uv), 2, uv_mode,
                _f32(refined), len(refined),
            )
            layers.append((name, refined))
        out.uv_layers = layers
    step(0.9)
    return out


def _fallbacks(lib, sub, info):
    n = info.fallback_face_count
    if n == 0:
        return []
    faces = _zeros("I", n)
    lib.call("katachi_subdivision_copy_fallback_faces", sub.handle, _u32(faces), n)
    out = []
    for i in range(n):
        buf = ctypes.create_string_buffer(4096)
        lib.call("katachi_subdivision_fallback_reason", sub.handle, i, buf, len(buf))
        out.append((faces[i], buf.value.decode("utf-8", "replace")))
    return out


# ---------------------------------------------------------------------------- writing


def to_blender(result, source, name):
    """A new Blender mesh from ``result``; materials and UV map names come from ``source``
    (the input Blender mesh, which is not changed)."""
    me = bpy.data.meshes.new(name)
    try:
        _fill(me, result, source)
    except BaseException:
        bpy.data.meshes.remove(me)
        raise
    return me


def write_arrays(me, r, attributes):
    """Writes result `r`'s arrays into the empty mesh `me`: its elements, topology, UV maps
    and (Blender 4+: as `attributes`, (name, type, domain, values or None); before: materials
    and smooth flags through the element properties) per-face data. Shared by every operator
    that builds a mesh from katachi's arrays."""
    me.vertices.add(len(r.positions) // 3)
    me.edges.add(len(r.edges) // 2)
    me.loops.add(len(r.corners))
    me.polygons.add(len(r.face_starts))
    me.polygons.foreach_set("loop_start", r.face_starts)
    if NEW_API:
        a = me.attributes
        for name, prop, buf in (
            ("position", "vector", r.positions),
            (".edge_verts", "value", r.edges),
            (".corner_vert", "value", r.corners),
            (".corner_edge", "value", r.corner_edges),
        ):
            if len(buf):
                a[name].data.foreach_set(prop, buf)
        for attr, data_type, domain, values in attributes:
            if values is not None:
                (a.get(attr) or a.new(attr, data_type, domain)).data.foreach_set("value", values)
        for uv_name, uv in r.uv_layers:
            if me.uv_layers.new(name=uv_name, do_init=False) is None:
                raise ConversionError(f"Blender refused UV map {uv_name!r} (too many UV maps?)")
            a[uv_name].data.foreach_set("vector", uv)
    else:
        me.vertices.foreach_set("co", r.positions)
        me.edges.foreach_set("vertices", r.edges)
        me.loops.foreach_set("vertex_index", r.corners)
        me.loops.foreach_set("edge_index", r.corner_edges)
        me.polygons.foreach_set("loop_total", r.face_sizes)
        if r.materials is not None:
            me.polygons.foreach_set("material_index", r.materials)
        if r.smooth is not None:
            me.polygons.foreach_set("use_smooth", r.smooth)
        for uv_name, uv in r.uv_layers:
            add_uv_map(me, uv_name, uv)


def _fill(me, r, source):
    nv, nf = len(r.positions) // 3, len(r.face_starts)
    nc, ne = len(r.corners), len(r.edges) // 2
    write_arrays(
        me,
        r,
        (
            ("material_index", "INT", "FACE", r.materials),
            ("sharp_face", "BOOLEAN", "FACE", r.sharp_face),
            ("crease_edge", "FLOAT", "EDGE", r.edge_creases),
            ("crease_vert", "FLOAT", "POINT", r.vertex_creases),
        ),
    )
    if not NEW_API and r.edge_creases is not None:
        me.edges.foreach_set("crease", r.edge_creases)
    for mat in source.materials:
        me.materials.append(mat)
    me.update()
    if not NEW_API and r.vertex_creases is not None:
        write_with_bmesh(me, r.vertex_creases)
    for i, layer in enumerate(source.uv_layers):
        if i < len(me.uv_layers) and layer.active_render:
            me.uv_layers[i].active_render = True
    if source.uv_layers and 0 <= source.uv_layers.active_index < len(me.uv_layers):
        me.uv_layers.active_index = source.uv_layers.active_index
    if (len(me.vertices), len(me.edges), len(me.loops), len(me.polygons)) != (nv, ne, nc, nf):
        raise ConversionError(
            "Blender changed the subdivided mesh while building it; the object was left as "
            "it was (please report this as a katachi bug)"
        )
    finish(me, source, "subdivided", validate=False)


def add_faces(me, loop_sizes, loop_verts):
    """Adds faces to the empty ``me`` (whose vertices are in): ``loop_sizes`` corners each,
    at the vertices ``loop_verts`` (face after face)."""
    nf = len(loop_sizes)
    me.loops.add(len(loop_verts))
    me.loops.foreach_set("vertex_index", loop_verts)
    me.polygons.add(nf)
    starts = _zeros("I", nf)
    s = 0
    for f, n in enumerate(loop_sizes):
        starts[f] = s
        s += n
    me.polygons.foreach_set("loop_start", starts)
    if not ATTRIBUTE_CREASES:
        me.polygons.foreach_set("loop_total", loop_sizes)


def add_uv_map(me, name, uv):
    """A new UV map ``name`` on ``me`` holding ``uv`` (``array('f')``, 2 per loop)."""
    layer = me.uv_layers.new(name=name, do_init=False)
    if layer is None:
        raise ConversionError(f"Blender refused UV map {name!r} (too many UV maps?)")
    layer.data.foreach_set("uv", uv)


def finish(me, source, what, validate=True):
    """The new mesh ``me`` takes the auto smooth settings of ``source`` (Blender < 4.1) and,
    with ``validate``, is validated: :class:`ConversionError` (naming the ``what`` mesh)
    when Blender finds it invalid. (A mesh built from katachi's own arrays is valid by
    construction, and Blender's validation costs several times the building.)"""
    if hasattr(source, "use_auto_smooth"):  # Blender < 4.1
        me.use_auto_smooth = source.use_auto_smooth
        me.auto_smooth_angle = source.auto_smooth_angle

    if validate and me.validate(verbose=False):
        raise ConversionError(
            f"Blender found the {what} mesh invalid; the object was left as it was "
            "(please report this as a katachi bug)"
        )


def repair_selection_attributes(me):
    """Blender 5.0.1's ``Mesh.update(calc_edges=True)`` makes the edge selection
    (``.select_edge``) an INT32_2D attribute, and writing ``MeshEdge.select`` then crashes
    Blender. A selection attribute of the wrong type is removed (nothing selected), so
    Blender makes a proper one when the selection is next written."""
    for name in (".select_vert", ".select_edge", ".select_poly"):
        attr = me.attributes.get(name)
        if attr is not None and attr.data_type != "BOOLEAN":
            me.attributes.remove(attr)


def write_with_bmesh(me, creases, weights=None, groups=0):
    """Vertex creases (Blender 3.x, which has no Python call that adds their layer) and
    vertex group weights (``groups`` per vertex; a mesh without an object has no other way
    to get them)."""
    import bmesh

    bm = bmesh.new()
    try:
        bm.from_mesh(me)
        bm.verts.ensure_lookup_table()
        if creases is not None:
            layer = bm.verts.layers.crease.verify()
            for v, c in zip(bm.verts, creases):
                v[layer] = c
        if weights is not None:
            layer = bm.verts.layers.deform.verify()
            for i, v in enumerate(bm.verts):
                row = weights[i * groups:(i + 1) * groups]
                if any(row):
                    d = v[layer]
                    for g, w in enumerate(row):
                        if w > 0.0:
                            d[g] = w
        bm.to_mesh(me)
    finally:
        bm.free()
