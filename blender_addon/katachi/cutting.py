"""Blender meshes through katachi's stroke cut (``katachi_cut_by_stroke``) and back.

Nothing geometric happens here, as in ``convert.py``: the cut, the snapping of vertices onto
the stroke and the interpolation of UVs are katachi's; this module copies data in bulk and
keeps Blender's per-element data with the element it belongs to.

How each kind of data follows the cut:

- Vertices: katachi keeps input vertex ``v`` as result vertex ``v`` (maybe moved onto the
  stroke), so vertex data stays where it was. New vertices follow; an opened cut's copies
  of path vertices take their original's data (``katachi_cut_copy_vertex_original``),
  other new vertices get no crease. Vertex group weights and shape keys (as offsets from
  the mesh's own positions, so a key follows a vertex snapping moves) go through
  ``katachi_cut_interpolate_vertex_data``: a new vertex gets the blend of the triangle it
  was made in.
- Faces: ``katachi_cut_copy_face_origin`` names the input face of every result triangle;
  materials, smooth flags and face selection follow it. katachi cuts triangles, so n-gons
  are triangulated; with ``keep_polygons`` a face the cut left whole (its triangles are
  still the triangulation of the face, with its own corners and no cut path across it) is
  given back as the polygon it was, with its own UVs.
- Corners: UV maps through ``katachi_cut_interpolate_corner_data`` (all maps in one call).
- Edges: katachi carries an edge attribute through the cut (an edge split in two gives both
  halves its value). The add-on lends that attribute: it tags each edge of the input with
  its Blender index + 1 (``katachi_mesh_set_edge_sharpnesses``) and reads the tags back from
  the result (``katachi_mesh_copy_sharp_edges``), so every result edge lying on an input
  edge knows it and takes its crease, bevel weight, seam, sharp and freestyle marks. Edges
  the cut made inside a face (and triangulation diagonals) get none. Loose edges, which
  katachi does not take, are put back as they were (their vertices keep their indices).
"""

import array
import math
from ctypes import POINTER, byref

import bpy

from . import ffi
from .convert import (
    ATTRIBUTE_CREASES,
    ConversionError,
    _bools,
    _copy_faces,
    _copy_positions,
    _f64,
    _float_attribute,
    _u32,
    _vertex_creases,
    _zeros,
    add_faces,
    add_uv_map,
    create_mesh,
    finish,
    repair_selection_attributes,
    write_with_bmesh,
)

#: Per-edge data carried by the edge tags: RNA properties of ``MeshEdge`` (both versions).
EDGE_FLAGS = ("use_seam", "use_edge_sharp")
#: Per-edge float data: Blender 3.x ``MeshEdge`` properties, 4.0+ attributes.
EDGE_FLOATS_3X = ("crease", "bevel_weight")
EDGE_FLOATS_4X = ("crease_edge", "bevel_weight_edge")
#: Freestyle edge marks: a ``MeshEdge`` property in 3.x, a boolean attribute in 4.0+.
FREESTYLE_4X = "freestyle_edge"


class CutSource:
    """A Blender mesh's data, read once, for :func:`cut` and :func:`to_blender`.
    ``vertex_groups``: the object's ``vertex_groups`` (Blender 3.0+ keeps their names in the
    mesh, so a new mesh needs them again)."""

    def __init__(self, mesh, vertex_groups=()):
        self.name = mesh.name
        self.group_names = [(g.name, g.lock_weight) for g in vertex_groups]
        nv, ne = len(mesh.vertices), len(mesh.edges)
        nf, nl = len(mesh.polygons), len(mesh.loops)
        self.vertex_count, self.edge_count = nv, ne
        self.face_count, self.corner_count = nf, nl

        co = _zeros("f", 3 * nv)
        mesh.vertices.foreach_get("co", co)
        self.positions = array.array("d", co)

        self.loop_starts = _zeros("I", nf)
        self.loop_sizes = _zeros("I", nf)
        mesh.polygons.foreach_get("loop_start", self.loop_starts)
        mesh.polygons.foreach_get("loop_total", self.loop_sizes)
        self.loop_verts = _zeros("I", nl)
        mesh.loops.foreach_get("vertex_index", self.loop_verts)
        # katachi's corners run polygon after polygon: corner_loops[k] is corner k's loop.
        self.corner_loops = array.array("I")
        for s, n in zip(self.loop_starts, self.loop_sizes):
            self.corner_loops.extend(range(s, s + n))
        self.corners = array.array("I", (self.loop_verts[i] for i in self.corner_loops))
        self.corner_start = _zeros("I", nf + 1)
        for f, n in enumerate(self.loop_sizes):
            self.corner_start[f + 1] = self.corner_start[f] + n

        self.edge_verts = _zeros("I", 2 * ne)
        mesh.edges.foreach_get("vertices", self.edge_verts)
        loop_edges = _zeros("I", nl)
        mesh.loops.foreach_get("edge_index", loop_edges)
        used = bytearray(ne)
        for e in loop_edges:
            used[e] = 1
        self.used_edges = array.array("I", (e for e in range(ne) if used[e]))
        self.loose_edges = array.array("I", (e for e in range(ne) if not used[e]))

        # Per-corner UVs in katachi's corner order, every map side by side (dim 2 × maps).
        self.uv_names = [layer.name for layer in mesh.uv_layers]
        self.uv_loops = []  # per map: array('f'), 2 per Blender loop
        for layer in mesh.uv_layers:
            uv = _zeros("f", 2 * nl)
            layer.data.foreach_get("uv", uv)
            self.uv_loops.append(uv)
        self.active_uv = mesh.uv_layers.active_index if mesh.uv_layers else -1
        self.active_render_uv = next(
            (i for i, l in enumerate(mesh.uv_layers) if l.active_render), -1
        )

        self.materials = _zeros("I", nf)
        mesh.polygons.foreach_get("material_index", self.materials)
        self.smooth = _bools(nf)
        mesh.polygons.foreach_get("use_smooth", self.smooth)
        self.face_hide = _bools(nf)
        mesh.polygons.foreach_get("hide", self.face_hide)
        self.vertex_hide = _bools(nv)
        mesh.vertices.foreach_get("hide", self.vertex_hide)
        self.edge_hide = _bools(ne)
        mesh.edges.foreach_get("hide", self.edge_hide)

        self.edge_data = _read_edge_data(mesh, ne)
        self.vertex_creases = _read_vertex_creases(mesh, nv)
        self.group_count, self.weights = _read_weights(mesh, nv)
        self.shape_keys, self.key_offsets = _read_shape_keys(mesh, self.positions)

    def corner_uvs(self):
        """All UV maps per katachi corner: ``2 × maps`` doubles per corner."""
        maps = len(self.uv_loops)
        out = _zeros("d", 2 * maps * self.corner_count)
        for m, uv in enumerate(self.uv_loops):
            for k, loop in enumerate(self.corner_loops):
                at = 2 * (maps * k + m)
                out[at] = uv[2 * loop]
                out[at + 1] = uv[2 * loop + 1]
        return out


def _read_edge_data(mesh, ne):
    """{name: (kind, values)} of the edge data worth carrying, only what is set anywhere."""
    data = {}
    for name in EDGE_FLAGS:
        values = _bools(ne)
        mesh.edges.foreach_get(name, values)
        if any(values):
            data[name] = ("flag", values)
    if ATTRIBUTE_CREASES:
        for name in EDGE_FLOATS_4X:
            values = _float_attribute(mesh, name, "EDGE", ne)
            if values is not None and any(values):
                data[name] = ("attribute", values)
        attr = mesh.attributes.get(FREESTYLE_4X)
        if attr is not None and attr.domain == "EDGE" and attr.data_type == "BOOLEAN":
            values = _bools(ne)
            attr.data.foreach_get("value", values)
            if any(values):
                data[FREESTYLE_4X] = ("bool attribute", values)
    else:
        for name in EDGE_FLOATS_3X:
            values = _zeros("f", ne)
            mesh.edges.foreach_get(name, values)
            if any(values):
                data[name] = ("float", values)
        values = _bools(ne)
        mesh.edges.foreach_get("use_freestyle_mark", values)
        if any(values):
            data["use_freestyle_mark"] = ("flag", values)
    return data


def _read_weights(mesh, nv):
    """Vertex group weights as ``(G, array('d') of nv × G)`` (G groups), or ``(0, None)``."""
    entries = []
    groups = 0
    for v in mesh.vertices:
        for g in v.groups:
            entries.append((v.index, g.group, g.weight))
            groups = max(groups, g.group + 1)
    if not entries:
        return 0, None
    weights = _zeros("d", nv * groups)
    for v, g, w in entries:
        weights[v * groups + g] = w
    return groups, weights


def _read_shape_keys(mesh, positions):
    """The shape keys' settings (list of dicts, basis first) and their offsets from the
    mesh's positions (``array('d')``, 3 × keys per vertex), or ``(None, None)``."""
    key = mesh.shape_keys
    if key is None or len(key.key_blocks) == 0:
        return None, None
    nv = len(positions) // 3
    blocks = list(key.key_blocks)
    nk = len(blocks)
    offsets = _zeros("d", 3 * nk * nv)
    settings = []
    co = _zeros("f", 3 * nv)
    for k, kb in enumerate(blocks):
        kb.data.foreach_get("co", co)
        for v in range(nv):
            at = 3 * (nk * v + k)
            for c in range(3):
                offsets[at + c] = co[3 * v + c] - positions[3 * v + c]
        settings.append({
            "name": kb.name,
            "value": kb.value,
            "slider_min": kb.slider_min,
            "slider_max": kb.slider_max,
            "mute": kb.mute,
            "interpolation": kb.interpolation,
            "vertex_group": kb.vertex_group,
            "relative_key": kb.relative_key.name if kb.relative_key else "",
        })
    settings[0]["use_relative"] = key.use_relative
    return settings, offsets


def _read_vertex_creases(mesh, nv):
    values = _vertex_creases(mesh, nv)
    return values if values is not None and any(values) else None


# ---------------------------------------------------------------------------- katachi


def _to_katachi(lib, src):
    """A new :class:`ffi.Mesh` of ``src`` whose edges carry their tags (index + 1)."""
    mesh = create_mesh(lib, src)
    try:
        n = len(src.used_edges)
        if n:
            pairs = _zeros("I", 2 * n)
            tags = _zeros("d", n)
            ev = src.edge_verts
            for i, e in enumerate(src.used_edges):
                pairs[2 * i] = ev[2 * e]
                pairs[2 * i + 1] = ev[2 * e + 1]
                tags[i] = e + 1.0
            lib.call("katachi_mesh_set_edge_sharpnesses", mesh.handle, _u32(pairs), _f64(tags), n)
    except BaseException:
        mesh.close()
        raise
    return mesh


class CutResult:
    """What katachi's cut gave, in arrays (result ids), plus its report."""

    def __init__(self):
        self.info = None  # ffi.KatachiCutInfo
        self.positions = None  # array('d'), 3 per result vertex
        self.corners = None  # array('I'), 3 per result triangle
        self.face_origin = None  # array('I'), input face of each triangle
        self.vertex_original = None  # array('I'), the vertex each result vertex copies
        self.edge_tags = {}  # (a, b) with a < b -> input edge index
        self.paths = []  # [(vertex ids, closed)]
        self.moved = []  # [(vertex, from xyz, to xyz, pixels)]
        self.dropped = {}  # stage -> array('I') of stroke point indices
        self.uvs = None  # array('d'), 2 × maps per result corner
        self.weights = None  # array('d'), groups per result vertex
        self.key_offsets = None  # array('d'), 3 × keys per result vertex


def cut(lib, src, stroke_px, view_proj, viewport, options):
    """Cuts ``src`` (a :class:`CutSource`) through katachi; returns a :class:`CutResult`.
    Raises :class:`ffi.KatachiError` (nothing is changed then)."""
    out = CutResult()
    with _to_katachi(lib, src) as mesh:
        result = ffi.cut_by_stroke(lib, mesh, stroke_px, view_proj, viewport, options)
    with result as c:
        info = c.info()
        out.info = info
        if info.path_count == 0:
            return out  # nothing was cut: the caller leaves the mesh alone
        h = c.handle
        out.face_origin = _zeros("I", info.face_count)
        lib.call("katachi_cut_copy_face_origin", h, _u32(out.face_origin), info.face_count)
        out.vertex_original = _zeros("I", info.vertex_count)
        lib.call(
            "katachi_cut_copy_vertex_original", h, _u32(out.vertex_original), info.vertex_count
        )

        offsets = _zeros("I", info.path_count + 1)
        verts = _zeros("I", info.path_vertex_count)
        lib.call(
            "katachi_cut_copy_paths", h, _u32(offsets), len(offsets), _u32(verts), len(verts)
        )
        pieces = _zeros("I", info.path_count)
        closed = _zeros("I", info.path_count)
        lib.call(
            "katachi_cut_copy_path_pieces", h, _u32(pieces), _u32(closed), info.path_count
        )
        out.paths = [
            (verts[offsets[i]:offsets[i + 1]], bool(closed[i])) for i in range(info.path_count)
        ]

        n = info.moved_vertex_count
        if n:
            mv = _zeros("I", n)
            frm, to, px = _zeros("d", 3 * n), _zeros("d", 3 * n), _zeros("d", n)
            lib.call(
                "katachi_cut_copy_moved_vertices", h, _u32(mv), _f64(frm), _f64(to), _f64(px), n
            )
            out.moved = [
                (mv[i], tuple(frm[3 * i:3 * i + 3]), tuple(to[3 * i:3 * i + 3]), px[i])
                for i in range(n)
            ]

        for stage, count in _dropped_counts(info).items():
            points = _zeros("I", count)
            if count:
                lib.call("katachi_cut_copy_dropped_points", h, stage, _u32(points), count)
            out.dropped[stage] = points

        maps = len(src.uv_loops)
        if maps:
            values = src.corner_uvs()
            out.uvs = _zeros("d", 2 * maps * info.corner_count)
            lib.call(
                "katachi_cut_interpolate_corner_data",
                h,
                _f64(values),
                len(values),
                2 * maps,
                _f64(out.uvs),
                len(out.uvs),
            )

        out.weights = _vertex_data(lib, h, src.weights, src.group_count, info.vertex_count)
        if src.shape_keys:
            dim = 3 * len(src.shape_keys)
            out.key_offsets = _vertex_data(lib, h, src.key_offsets, dim, info.vertex_count)

        mhandle = POINTER(ffi.KatachiMesh)()
        lib.call("katachi_cut_mesh", h, byref(mhandle))
    with ffi.Mesh(lib, mhandle) as m:
        counts = m.counts()
        out.positions = _copy_positions(lib, m, counts)
        sizes, _, out.corners = _copy_faces(lib, m, counts)
        if any(s != 3 for s in sizes):
            raise ConversionError("katachi's cut gave a face that is not a triangle (a bug)")
        ns = counts.sharp_edge_count
        pairs, tags = _zeros("I", 2 * ns), _zeros("d", ns)
        if ns:
            lib.call("katachi_mesh_copy_sharp_edges", m.handle, _u32(pairs), _f64(tags), ns)
        for i in range(ns):
            a, b = pairs[2 * i], pairs[2 * i + 1]
            e = int(tags[i]) - 1
            if 0 <= e < src.edge_count:
                out.edge_tags[(a, b) if a < b else (b, a)] = e
    return out


def _vertex_data(lib, handle, values, dim, vertex_count):
    if values is None or dim == 0:
        return None
    out = _zeros("d", dim * vertex_count)
    lib.call(
        "katachi_cut_interpolate_vertex_data",
        handle,
        _f64(values),
        len(values),
        dim,
        _f64(out),
        len(out),
    )
    return out


def _dropped_counts(info):
    return {
        ffi.KATACHI_CUT_STAGE_PREPROCESSING: info.dropped_preprocessing_count,
        ffi.KATACHI_CUT_STAGE_FIRST_NORMALIZATION: info.dropped_first_normalization_count,
        ffi.KATACHI_CUT_STAGE_SECOND_NORMALIZATION: info.dropped_second_normalization_count,
        ffi.KATACHI_CUT_STAGE_OFF_MESH: info.dropped_off_mesh_count,
    }


# ---------------------------------------------------------------------------- writing


class _Built:
    """The result in Blender's terms, before it becomes a mesh."""

    def __init__(self):
        self.loop_sizes = array.array("I")
        self.loop_verts = array.array("I")
        self.face_origin = array.array("I")
        self.uvs = []  # per map: array('f'), 2 per loop
        self.kept_faces = 0  # input faces given back whole


def _vertex_bases(src, res):
    """Per result vertex: the result vertex it copies (an opened cut's copies of path
    vertices, from ``katachi_cut_copy_vertex_original``), else itself."""
    return res.vertex_original


def _path_edges(res):
    """The cut paths' edges, as sorted result-vertex pairs (ids before opening)."""
    edges = set()
    for verts, closed in res.paths:
        n = len(verts)
        for i in range(n - 1 + (1 if closed and n > 2 else 0)):
            a, b = verts[i], verts[(i + 1) % n]
            edges.add((a, b) if a < b else (b, a))
    return edges


def _build(src, res, keep_polygons):
    """Faces and corner data of the result: whole input faces where the cut left them whole
    (``keep_polygons``), katachi's triangles elsewhere, in input face order."""
    b = _Built()
    nv_in = src.vertex_count
    base = _vertex_bases(src, res)
    maps = len(src.uv_loops)
    b.uvs = [array.array("f") for _ in range(maps)]
    tris = [[] for _ in range(src.face_count)]
    for t, f in enumerate(res.face_origin):
        tris[f].append(t)
    path_edges = _path_edges(res)
    # Input vertex each result vertex stands for (-1: a new vertex).
    def source(k):
        k = base[k]
        return k if k < nv_in else -1

    corners, uvs = res.corners, res.uvs
    for f in range(src.face_count):
        n = src.loop_sizes[f]
        ts = tris[f]
        whole = None
        if keep_polygons and len(ts) == n - 2:
            whole = _whole_face(src, f, ts, corners, source, path_edges)
        if whole is not None:
            b.kept_faces += 1
            b.loop_sizes.append(n)
            b.loop_verts.extend(whole)
            b.face_origin.append(f)
            s = src.loop_starts[f]
            for m in range(maps):
                b.uvs[m].extend(src.uv_loops[m][2 * s:2 * (s + n)])
            continue
        for t in ts:
            b.loop_sizes.append(3)
            b.loop_verts.extend(corners[3 * t:3 * t + 3])
            b.face_origin.append(f)
            for m in range(maps):
                for j in range(3):
                    at = 2 * (maps * (3 * t + j) + m)
                    b.uvs[m].append(uvs[at])
                    b.uvs[m].append(uvs[at + 1])
    return b, base


def _whole_face(src, f, ts, corners, source, path_edges):
    """Face ``f``'s result vertices in its own corner order when its triangles ``ts`` are
    still just its triangulation (same corners, nothing across it), else None."""
    s, n = src.corner_start[f], src.loop_sizes[f]
    own = src.corners[s:s + n]
    own_set = set(own)
    if len(own_set) != n:
        return None
    stand_in = {}  # input vertex -> the result vertex the triangles use for it
    for t in ts:
        for k in corners[3 * t:3 * t + 3]:
            v = source(k)
            if v < 0 or v not in own_set or stand_in.setdefault(v, k) != k:
                return None
    if len(stand_in) != n:
        return None
    # A cut path along a diagonal of the face (between two of its corners, not a side).
    if n > 3:
        sides = set()
        for i in range(n):
            a, c = own[i], own[(i + 1) % n]
            sides.add((a, c) if a < c else (c, a))
        for i in range(n):
            for j in range(i + 2, n):
                a, c = stand_in[own[i]], stand_in[own[j]]
                key = (a, c) if a < c else (c, a)
                side = (own[i], own[j]) if own[i] < own[j] else (own[j], own[i])
                if key in path_edges and side not in sides:
                    return None
    return [stand_in[v] for v in own]


def to_blender(src, res, source_mesh, name, keep_polygons=True):
    """A new Blender mesh from the cut ``res`` of ``src``; materials and UV map names come
    from ``source_mesh`` (not changed). The cut paths' edges (both sides of an opened cut)
    and their vertices are the only selected elements. Returns ``(mesh, kept_faces)``."""
    built, base = _build(src, res, keep_polygons)
    me = bpy.data.meshes.new(name)
    try:
        _fill(me, src, res, built, base, source_mesh)
    except BaseException:
        bpy.data.meshes.remove(me)
        raise
    return me, built.kept_faces


def _fill(me, src, res, built, base, source_mesh):
    nv = len(res.positions) // 3
    nf = len(built.loop_sizes)
    nl = len(built.loop_verts)
    me.vertices.add(nv)
    me.vertices.foreach_set("co", array.array("f", res.positions))
    # Loose edges first: calc_edges keeps the edges a mesh has.
    nloose = len(src.loose_edges)
    if nloose:
        me.edges.add(nloose)
        loose = array.array("I")
        for e in src.loose_edges:
            loose.extend(src.edge_verts[2 * e:2 * e + 2])
        me.edges.foreach_set("vertices", loose)
    add_faces(me, built.loop_sizes, built.loop_verts)

    origin = built.face_origin
    me.polygons.foreach_set("material_index", array.array("I", (src.materials[o] for o in origin)))
    me.polygons.foreach_set("use_smooth", [src.smooth[o] for o in origin])
    for mat in source_mesh.materials:
        me.materials.append(mat)

    me.update(calc_edges=True)
    repair_selection_attributes(me)
    ne = len(me.edges)
    if len(me.loops) != nl or len(me.polygons) != nf:
        raise ConversionError("Blender changed the cut mesh while building it (a bug)")

    for name, uv in zip(src.uv_names, built.uvs):
        add_uv_map(me, name, uv)
    if 0 <= src.active_render_uv < len(me.uv_layers):
        me.uv_layers[src.active_render_uv].active_render = True
    if 0 <= src.active_uv < len(me.uv_layers):
        me.uv_layers.active_index = src.active_uv

    # Edges: the input edge each lies on, from katachi's tags (or, for an opened cut's copy
    # side, the tag of the edge it copies); the cut paths' edges are selected.
    ev = _zeros("I", 2 * ne)
    me.edges.foreach_get("vertices", ev)
    edge_origin = [-1] * ne
    selected = _bools(ne)
    path_edges = _path_edges(res)
    tags = res.edge_tags
    for e in range(ne):
        a, b = ev[2 * e], ev[2 * e + 1]
        key = (a, b) if a < b else (b, a)
        o = tags.get(key)
        ba, bb = base[a], base[b]
        bkey = (ba, bb) if ba < bb else (bb, ba)
        if o is None and bkey != key:
            o = tags.get(bkey)
        if o is not None:
            edge_origin[e] = o
        if bkey in path_edges:
            selected[e] = True
    if nloose:  # Blender 3.x's calc_edges may reorder the edges it keeps
        where = {}
        for e in range(ne):
            a, b = ev[2 * e], ev[2 * e + 1]
            where[(a, b) if a < b else (b, a)] = e
        for o in src.loose_edges:
            a, b = src.edge_verts[2 * o], src.edge_verts[2 * o + 1]
            e = where.get((a, b) if a < b else (b, a))
            if e is None:
                raise ConversionError(f"Blender dropped loose edge {a}-{b} (a bug)")
            edge_origin[e] = o
    _write_edge_data(me, src, edge_origin)

    vc = None
    if src.vertex_creases is not None:
        nv_in = src.vertex_count
        vc = _zeros("f", nv)
        for k in range(nv):
            o = base[k]
            if o < nv_in:
                vc[k] = src.vertex_creases[o]
        if ATTRIBUTE_CREASES:
            attr = me.attributes.get("crease_vert") or me.attributes.new("crease_vert", "FLOAT", "POINT")
            attr.data.foreach_set("value", vc)
            vc = None
    if vc is not None or res.weights is not None:
        write_with_bmesh(me, vc, res.weights, src.group_count)

    # Hidden (Edit mode's Hide): a face as its input face; a vertex or edge when every face
    # around it is hidden (loose ones as they were), so no shown face has hidden corners.
    vhide, ehide = _hidden(me, src, built, edge_origin, nv, ne)
    # Selection: the cut's shown edges and their vertices, nothing else.
    vsel = _bools(nv)
    for e in range(ne):
        if selected[e] and not ehide[e]:
            vsel[ev[2 * e]] = vsel[ev[2 * e + 1]] = True
        else:
            selected[e] = False
    me.vertices.foreach_set("select", vsel)
    me.edges.foreach_set("select", selected)
    me.polygons.foreach_set("select", _bools(nf))
    if any(src.face_hide) or any(src.vertex_hide):
        me.polygons.foreach_set("hide", [src.face_hide[o] for o in built.face_origin])
        me.vertices.foreach_set("hide", vhide)
        me.edges.foreach_set("hide", ehide)

    finish(me, source_mesh, "cut")
    if src.shape_keys or src.group_names:
        _write_object_data(me, src, res)


def _hidden(me, src, built, edge_origin, nv, ne):
    """Per vertex and per edge of the new mesh: hidden or not (see :func:`_fill`)."""
    vhide, ehide = _bools(nv), _bools(ne)
    if not (any(src.face_hide) or any(src.vertex_hide)):
        return vhide, ehide
    shown_v = bytearray(nv)
    has_face_v = bytearray(nv)
    k = 0
    for f, n in enumerate(built.loop_sizes):
        shown = not src.face_hide[built.face_origin[f]]
        for v in built.loop_verts[k:k + n]:
            has_face_v[v] = 1
            if shown:
                shown_v[v] = 1
        k += n
    nv_in = src.vertex_count
    for v in range(nv):
        if has_face_v[v]:
            vhide[v] = not shown_v[v]
        elif v < nv_in:
            vhide[v] = bool(src.vertex_hide[v])
    corner_edges = _zeros("I", len(me.loops))
    me.loops.foreach_get("edge_index", corner_edges)
    shown_e = bytearray(ne)
    has_face_e = bytearray(ne)
    k = 0
    for f, n in enumerate(built.loop_sizes):
        shown = not src.face_hide[built.face_origin[f]]
        for e in corner_edges[k:k + n]:
            has_face_e[e] = 1
            if shown:
                shown_e[e] = 1
        k += n
    for e in range(ne):
        if has_face_e[e]:
            ehide[e] = not shown_e[e]
        elif edge_origin[e] >= 0:
            ehide[e] = bool(src.edge_hide[edge_origin[e]])
    return vhide, ehide


def _write_object_data(me, src, res):
    """The vertex group names and the shape keys (each one the new positions plus its
    carried offsets) on the new mesh. A mesh gets these only through an object, so a
    temporary one (in no scene) lends itself."""
    tmp = bpy.data.objects.new("katachi mesh data", me)
    try:
        for name, lock in src.group_names:
            tmp.vertex_groups.new(name=name).lock_weight = lock
        if src.shape_keys:
            _add_shape_keys(tmp, me, src.shape_keys, res.positions, res.key_offsets)
    finally:
        bpy.data.objects.remove(tmp)


def _add_shape_keys(tmp, me, settings, positions, offsets):
    nk = len(settings)
    nv = len(positions) // 3
    blocks = []
    co = _zeros("f", 3 * nv)
    for k, s in enumerate(settings):
        kb = tmp.shape_key_add(name=s["name"], from_mix=False)
        for v in range(nv):
            at = 3 * (nk * v + k)
            for c in range(3):
                co[3 * v + c] = positions[3 * v + c] + offsets[at + c]
        kb.data.foreach_set("co", co)
        for name in ("slider_min", "slider_max", "value", "mute", "interpolation",
                     "vertex_group"):
            setattr(kb, name, s[name])
        blocks.append(kb)
    by_name = {kb.name: kb for kb in blocks}
    for kb, s in zip(blocks, settings):
        if s["relative_key"] in by_name:
            kb.relative_key = by_name[s["relative_key"]]
    me.shape_keys.use_relative = settings[0].get("use_relative", True)


def _write_edge_data(me, src, edge_origin):
    for name, (kind, values) in src.edge_data.items():
        if kind in ("flag", "bool attribute"):
            out = [o >= 0 and bool(values[o]) for o in edge_origin]
        else:
            out = array.array("f", (values[o] if o >= 0 else 0.0 for o in edge_origin))
        if kind in ("flag", "float"):
            me.edges.foreach_set(name, out)
        else:
            attr = me.attributes.get(name)
            if attr is None:
                attr = me.attributes.new(name, "BOOLEAN" if kind == "bool attribute" else "FLOAT", "EDGE")
            attr.data.foreach_set("value", out)


# ---------------------------------------------------------------------------- report


STAGE_NAMES = {
    ffi.KATACHI_CUT_STAGE_PREPROCESSING: "in preprocessing",
    ffi.KATACHI_CUT_STAGE_FIRST_NORMALIZATION: "by the first normalization",
    ffi.KATACHI_CUT_STAGE_SECOND_NORMALIZATION: "by the second normalization",
    ffi.KATACHI_CUT_STAGE_OFF_MESH: "off the mesh",
}


def largest_move(res, matrix_world):
    """The largest snapping move in world units (``matrix_world`` applied) and in pixels."""
    world = px = 0.0
    for _, frm, to, pixels in res.moved:
        a = matrix_world @ _vec(frm)
        b = matrix_world @ _vec(to)
        world = max(world, (a - b).length)
        px = max(px, pixels)
    return world, px


def _vec(t):
    from mathutils import Vector

    return Vector(t)


def describe(res, matrix_world):
    """One sentence on what the cut did: paths, new faces and vertices, moved vertices and
    the largest move, dropped stroke points per stage."""
    i = res.info
    parts = [
        f"{i.path_count} cut path{'s' if i.path_count != 1 else ''}",
        f"{i.new_face_count} new faces ({i.split_face_count} triangles split)",
        f"{i.new_vertex_count} new vertices",
    ]
    if i.moved_vertex_count:
        world, px = largest_move(res, matrix_world)
        parts.append(
            f"{i.moved_vertex_count} vertices moved onto the stroke "
            f"(the largest by {_length(world)}, {px:.1f} px)"
        )
    else:
        parts.append("no vertex moved")
    dropped = [
        f"{len(points)} {STAGE_NAMES[stage]}" for stage, points in res.dropped.items() if points
    ]
    counts = _dropped_counts(i)
    if not res.dropped:  # nothing was cut: the counts alone
        dropped = [f"{n} {STAGE_NAMES[s]}" for s, n in counts.items() if n]
    parts.append("stroke points dropped: " + (", ".join(dropped) if dropped else "none"))
    return "; ".join(parts)


def _length(x):
    if x == 0.0:
        return "0"
    digits = max(0, 3 - int(math.floor(math.log10(abs(x)))))
    return f"{x:.{digits}f}"


def warnings(res):
    """What the user should know besides the summary (sentences, maybe none)."""
    i = res.info
    out = []
    if i.unjoined_count:
        out.append(f"{i.unjoined_count} stretches of the stroke could not be made into edges")
    if i.clipped_face_count:
        out.append(f"{i.clipped_face_count} faces crossing the view's near plane were not cut")
    if i.degenerate_face_count:
        out.append(f"{i.degenerate_face_count} faces without area near the stroke were not cut")
    return out

