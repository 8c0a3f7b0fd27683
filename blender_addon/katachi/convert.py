"""Blender meshes to katachi meshes and back.

Nothing geometric happens here: positions, faces, creases, UVs and face data are copied in
bulk (``foreach_get``/``foreach_set`` into ``array.array`` buffers, which ctypes reads in
place — Debian's Blender has no numpy) and everything computed comes from the katachi
library. Blender stores ``float`` (f32); katachi computes in ``double``.

Versions: Blender 3.4 keeps edge creases in ``MeshEdge.crease`` and vertex creases in
``Mesh.vertex_creases``; 4.0 and later in the ``crease_edge`` and ``crease_vert`` float
attributes. From 4.0 ``MeshPolygon.loop_total`` is read-only (face sizes follow from
``loop_start``).
"""

import array
import ctypes
import math
from ctypes import POINTER, byref, c_double, c_uint32

import bpy

from . import ffi

#: Blender 4.0 moved creases to attributes and made ``loop_total`` read-only.
ATTRIBUTE_CREASES = bpy.app.version >= (4, 0, 0)


class ConversionError(Exception):
    """A Blender mesh that cannot be handed to katachi (or a result Blender refused)."""


def crease_to_sharpness(crease):
    """Blender's edge or vertex crease (0..1) as an OpenSubdiv sharpness (0..10).

    The mapping Blender's Subdivision Surface modifier uses with OpenSubdiv: the square of
    the crease times 10, so crease 1 is infinitely sharp (10) and 0.5 is 2.5."""
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


# ---------------------------------------------------------------------------- reading


class InputMesh:
    """A Blender mesh's data, in katachi's corner order (polygon after polygon)."""

    def __init__(self, mesh):
        self.name = mesh.name
        nv, ne = len(mesh.vertices), len(mesh.edges)
        nf, nl = len(mesh.polygons), len(mesh.loops)
        self.vertex_count, self.face_count, self.corner_count = nv, nf, nl

        co = _zeros("f", 3 * nv)
        mesh.vertices.foreach_get("co", co)
        self.positions = array.array("d", co)

        starts = _zeros("I", nf)
        sizes = _zeros("I", nf)
        mesh.polygons.foreach_get("loop_start", starts)
        mesh.polygons.foreach_get("loop_total", sizes)
        self.loop_sizes = sizes
        loop_verts = _zeros("I", nl)
        mesh.loops.foreach_get("vertex_index", loop_verts)

        # katachi's corners run polygon after polygon; Blender's loops usually do too.
        expected = 0
        for s, n in zip(starts, sizes):
            if s != expected:
                break
            expected += n
        else:
            expected = -1
        if expected == -1 and sum(sizes) == nl:
            self.corner_loops = None  # corner k is loop k
            self.corners = loop_verts
        else:
            self.corner_loops = array.array("I")
            for s, n in zip(starts, sizes):
                self.corner_loops.extend(range(s, s + n))
            self.corners = array.array("I", (loop_verts[i] for i in self.corner_loops))

        # Edges: creases of edges that some face uses (loose edges are not subdivided).
        edge_verts = _zeros("I", 2 * ne)
        mesh.edges.foreach_get("vertices", edge_verts)
        used = bytearray(ne)
        loop_edges = _zeros("I", nl)
        mesh.loops.foreach_get("edge_index", loop_edges)
        for e in loop_edges:
            used[e] = 1
        self.loose_edge_count = ne - sum(used)
        creases = _edge_creases(mesh, ne)
        self.sharp_edges = array.array("I")
        self.sharp_values = array.array("d")
        if creases is not None:
            for e in range(ne):
                c = creases[e]
                if c > 0.0 and used[e]:
                    self.sharp_edges.append(edge_verts[2 * e])
                    self.sharp_edges.append(edge_verts[2 * e + 1])
                    self.sharp_values.append(crease_to_sharpness(c))

        vcreases = _vertex_creases(mesh, nv)
        if vcreases is not None and any(c > 0.0 for c in vcreases):
            self.vertex_sharpness = array.array("d", (crease_to_sharpness(c) for c in vcreases))
        else:
            self.vertex_sharpness = None

        # UV maps: one value per distinct (vertex, uv) pair, one index per corner.
        self.uv_layers = []
        for layer in mesh.uv_layers:
            uv = _zeros("f", 2 * nl)
            layer.data.foreach_get("uv", uv)
            self.uv_layers.append((layer.name, *self._weld(uv)))
        self.active_uv = mesh.uv_layers.active_index if mesh.uv_layers else -1
        self.active_render_uv = next(
            (i for i, l in enumerate(mesh.uv_layers) if l.active_render), -1
        )

    def _weld(self, uv):
        """Per-corner UVs as (values, indices): corners at the same vertex with the same UV
        share a value, so that katachi sees UV seams where Blender has them."""
        values = array.array("d")
        indices = _zeros("I", self.corner_count)
        seen = {}
        loops = self.corner_loops
        for k, v in enumerate(self.corners):
            i = k if loops is None else loops[k]
            key = (v, uv[2 * i], uv[2 * i + 1])
            idx = seen.get(key)
            if idx is None:
                idx = len(seen)
                seen[key] = idx
                values.append(key[1])
                values.append(key[2])
            indices[k] = idx
        return values, indices


def _float_attribute(mesh, name, domain, n):
    attr = mesh.attributes.get(name)
    if attr is None or attr.domain != domain or attr.data_type != "FLOAT":
        return None
    values = _zeros("f", n)
    attr.data.foreach_get("value", values)
    return values


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


# ---------------------------------------------------------------------------- katachi


def _u32(a):
    return ffi.ptr(a, c_uint32)


def _f64(a):
    return ffi.ptr(a, c_double)


def create_mesh(lib, data):
    """A new :class:`ffi.Mesh` of ``data``'s simple faces: ``positions``, ``vertex_count``,
    ``loop_sizes``, ``face_count``, ``corners`` and ``corner_count`` (an :class:`InputMesh`
    or a ``cutting.CutSource``)."""
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


def to_katachi(lib, data):
    """A new :class:`ffi.Mesh` holding ``data`` with its edge and vertex sharpness."""
    mesh = create_mesh(lib, data)
    try:
        if len(data.sharp_values):
            lib.call(
                "katachi_mesh_set_edge_sharpnesses",
                mesh.handle,
                _u32(data.sharp_edges),
                _f64(data.sharp_values),
                len(data.sharp_values),
            )
        if data.vertex_sharpness is not None:
            lib.call(
                "katachi_mesh_set_all_vertex_sharpness",
                mesh.handle,
                _f64(data.vertex_sharpness),
                len(data.vertex_sharpness),
            )
    except BaseException:
        mesh.close()
        raise
    return mesh


class Result:
    """A subdivided mesh in Blender's terms (simple polygons), ready to become a mesh."""

    positions = None  # array('d'), 3 per vertex
    loop_sizes = None  # array('I'), one per face
    corners = None  # array('I')
    face_origin = None  # array('I'), input face of each face
    uv_layers = ()  # [(name, array('d') 2 per corner)]
    sharp_edges = None  # array('I') pairs
    sharp_values = None  # array('d')
    vertex_sharpness = None  # array('d') or None
    fallback = ()  # [(input face, reason)]

    def __init__(self):
        self.warnings = []  # what the user should know, for self.report({'WARNING'})


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


def subdivide(lib, data, options, uv_mode, progress=None):
    """Subdivides ``data`` (an :class:`InputMesh`) with ``options`` (a
    ``KatachiSubdivideOptions``); UV maps follow with ``uv_mode`` (a ``KatachiFaceVarying``).
    ``progress(fraction)`` is called between stages and after each subdivision level (from
    0.1 to 0.6 as the levels are refined). Raises :class:`ffi.KatachiError`."""
    step = progress or (lambda f: None)
    out = Result()

    def level_done(done, total):
        step(0.1 + 0.5 * done / max(total, 1))

    with to_katachi(lib, data) as mesh:
        step(0.1)
        subdivision = ffi.subdivide(lib, mesh, options, level_done)
    with subdivision as sub:
        step(0.6)
        info = sub.info()
        origin = _zeros("I", info.face_count)
        lib.call("katachi_subdivision_copy_face_origin", sub.handle, _u32(origin), len(origin))
        out.fallback = _fallbacks(lib, sub, info)

        refined_uvs = []
        for name, values, indices in data.uv_layers:
            uv = _zeros("d", 2 * info.corner_count)
            lib.call(
                "katachi_subdivision_refine_face_varying",
                sub.handle,
                _f64(values),
                len(values),
                2,
                _u32(indices),
                len(indices),
                uv_mode,
                _f64(uv),
                len(uv),
            )
            refined_uvs.append((name, uv))
        step(0.75)

        rhandle = POINTER(ffi.KatachiMesh)()
        lib.call("katachi_subdivision_mesh", sub.handle, byref(rhandle))
    with ffi.Mesh(lib, rhandle) as refined:
        counts = refined.counts()
        if counts.loop_count > counts.face_count:
            # Faces with holes (method [b], or a recovered face method [a] could not bridge):
            # Blender stores none, so katachi cuts them along bridge edges.
            final, corner_of = _split(lib, refined, counts, origin)
        else:
            final, corner_of = refined, None
            out.face_origin = origin
        try:
            fcounts = final.counts()
            out.positions = _copy_positions(lib, final, fcounts)
            out.loop_sizes, _, out.corners = _copy_faces(lib, final, fcounts)
            if corner_of is not None:
                out.face_origin = final.face_origin
                refined_uvs = [
                    (name, array.array("d", _gather2(uv, corner_of))) for name, uv in refined_uvs
                ]
            out.uv_layers = refined_uvs
            out.sharp_edges = _zeros("I", 2 * fcounts.sharp_edge_count)
            out.sharp_values = _zeros("d", fcounts.sharp_edge_count)
            lib.call(
                "katachi_mesh_copy_sharp_edges",
                final.handle,
                _u32(out.sharp_edges),
                _f64(out.sharp_values),
                fcounts.sharp_edge_count,
            )
            if fcounts.sharp_vertex_count:
                out.vertex_sharpness = _zeros("d", fcounts.vertex_count)
                lib.call(
                    "katachi_mesh_copy_vertex_sharpness",
                    final.handle,
                    _f64(out.vertex_sharpness),
                    len(out.vertex_sharpness),
                )
        finally:
            if final is not refined:
                final.close()
    step(0.9)
    return out


def _gather2(uv, corner_of):
    for k in corner_of:
        yield uv[2 * k]
        yield uv[2 * k + 1]


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


def _split(lib, refined, counts, origin):
    """Cuts the faces with holes of ``refined``; returns the new mesh (with ``face_origin``
    composed down to the input faces) and, per new corner, the refined corner it copies."""
    split_origin = _zeros("I", counts.corner_count)  # more than enough: ≤ one face per corner
    handle = POINTER(ffi.KatachiMesh)()
    lib.call(
        "katachi_mesh_split_faces_with_holes",
        refined.handle,
        byref(handle),
        _u32(split_origin),
        len(split_origin),
    )
    final = ffi.Mesh(lib, handle)
    try:
        fcounts = final.counts()
        r_sizes, r_face_loops, r_corners = _copy_faces(lib, refined, counts)
        # First corner of each refined face, and whether it has holes.
        first = _zeros("I", counts.face_count + 1)
        loop = 0
        for f, nloops in enumerate(r_face_loops):
            n = 0
            for _ in range(nloops):
                n += r_sizes[loop]
                loop += 1
            first[f + 1] = first[f] + n
        f_sizes, _, f_corners = _copy_faces(lib, final, fcounts)
        corner_of = _zeros("I", fcounts.corner_count)
        face_origin = _zeros("I", fcounts.face_count)
        maps = {}
        k = 0
        for f in range(fcounts.face_count):
            r = split_origin[f]
            face_origin[f] = origin[r]
            n = f_sizes[f]
            a, b = first[r], first[r + 1]
            if r_face_loops[r] == 1:
                # A simple face is copied as it was, corner for corner.
                for j in range(n):
                    corner_of[k + j] = a + j
            else:
                where = maps.get(r)
                if where is None:
                    where = {r_corners[c]: c for c in range(a, b)}
                    maps[r] = where
                for j in range(n):
                    corner_of[k + j] = where[f_corners[k + j]]
            k += n
        final.face_origin = face_origin
    except BaseException:
        final.close()
        raise
    return final, corner_of


# ---------------------------------------------------------------------------- writing


def to_blender(result, source, name):
    """A new Blender mesh from ``result``; face data, materials and UV map names come from
    ``source`` (the input Blender mesh, which is not changed)."""
    me = bpy.data.meshes.new(name)
    try:
        _fill(me, result, source)
    except BaseException:
        bpy.data.meshes.remove(me)
        raise
    return me


def _fill(me, result, source):
    nv = len(result.positions) // 3
    me.vertices.add(nv)
    me.vertices.foreach_set("co", array.array("f", result.positions))
    add_faces(me, result.loop_sizes, result.corners)

    # Face data follows the input face each face comes from.
    src_mat = _zeros("I", len(source.polygons))
    source.polygons.foreach_get("material_index", src_mat)
    me.polygons.foreach_set(
        "material_index", array.array("I", (src_mat[o] for o in result.face_origin))
    )
    src_smooth = _bools(len(source.polygons))
    source.polygons.foreach_get("use_smooth", src_smooth)
    me.polygons.foreach_set("use_smooth", [src_smooth[o] for o in result.face_origin])
    for mat in source.materials:
        me.materials.append(mat)

    me.update(calc_edges=True)
    repair_selection_attributes(me)

    for name, uv in result.uv_layers:
        add_uv_map(me, name, array.array("f", uv))
    for i, layer in enumerate(source.uv_layers):
        if i < len(me.uv_layers):
            if layer.active_render:
                me.uv_layers[i].active_render = True
    if source.uv_layers and 0 <= source.uv_layers.active_index < len(me.uv_layers):
        me.uv_layers.active_index = source.uv_layers.active_index

    _write_creases(me, result)
    finish(me, source, "subdivided")


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


def finish(me, source, what):
    """The new mesh ``me`` takes the auto smooth settings of ``source`` (Blender < 4.1) and
    is validated: :class:`ConversionError` (naming the ``what`` mesh) when Blender finds it
    invalid."""
    if hasattr(source, "use_auto_smooth"):  # Blender < 4.1
        me.use_auto_smooth = source.use_auto_smooth
        me.auto_smooth_angle = source.auto_smooth_angle

    if me.validate(verbose=False):
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


def _write_creases(me, result):
    """The sharpness left after refinement (semi-sharp creases not yet spent, infinitely
    sharp ones) goes back to Blender as creases."""
    n = len(result.sharp_values)
    if n:
        ne = len(me.edges)
        edge_verts = _zeros("I", 2 * ne)
        me.edges.foreach_get("vertices", edge_verts)
        sharp = {}
        for i in range(n):
            a, b = result.sharp_edges[2 * i], result.sharp_edges[2 * i + 1]
            sharp[(a, b) if a < b else (b, a)] = result.sharp_values[i]
        creases = _zeros("f", ne)
        for e in range(ne):
            a, b = edge_verts[2 * e], edge_verts[2 * e + 1]
            s = sharp.get((a, b) if a < b else (b, a))
            if s is not None:
                creases[e] = sharpness_to_crease(s)
        if ATTRIBUTE_CREASES:
            attr = me.attributes.new("crease_edge", "FLOAT", "EDGE")
            attr.data.foreach_set("value", creases)
        else:
            me.edges.foreach_set("crease", creases)
    if result.vertex_sharpness is not None:
        vc = array.array("f", (sharpness_to_crease(s) for s in result.vertex_sharpness))
        if ATTRIBUTE_CREASES:
            attr = me.attributes.new("crease_vert", "FLOAT", "POINT")
            attr.data.foreach_set("value", vc)
        else:
            write_with_bmesh(me, vc)


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
