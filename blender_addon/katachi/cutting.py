"""Blender meshes through katachi's stroke cut (``katachi_cut_by_stroke``) and back.

Nothing geometric happens here, and nothing is done element by element over the mesh: the
input's arrays are read whole (``convert.InputMesh``), katachi cuts them and gives the
result in the input's own layout (``katachi_cut_polygons``): the arrays Blender stores, with
every face's input face, every edge's input edge and every corner's input corner, so
Blender's per-element data is carried by katachi in bulk and written with ``foreach_set``.

How each kind of data follows the cut:

- Vertices: input vertex ``v`` is result vertex ``v`` (maybe moved onto the stroke); new
  vertices follow. Creases and hide flags are carried (an opened cut's copy of a vertex
  takes its original's, other new vertices none); vertex group weights and shape keys (as
  offsets from the mesh's own positions, so a key follows a vertex snapping moves) go
  through ``katachi_cut_interpolate_vertex_data``: a new vertex gets the blend of the
  triangle it was made in.
- Faces keep their index; a face the cut left whole is given back as the polygon it was
  (``keep_polygons``), a cut one as its triangles, appended after the input's faces.
  Materials, smooth shading and hide flags follow the face each one came from.
- Edges keep their index too (loose ones included); the pieces of a split edge, the copies
  made by opening and the edges made inside faces are appended. Crease, bevel weight, seam,
  sharp and freestyle marks follow the input edge each one lies on; edges made inside faces
  get none. The cut paths' edges (both sides of an opened cut) and their vertices are the
  only selected elements.
- Corners: UV maps through ``katachi_cut_polygons_carry_corner_data_f32`` (a corner at an
  input vertex keeps its UV, one at a new vertex gets the blend of its triangle's).

With faces hidden in Edit mode, the new vertices and edges that only hidden faces use are
hidden too (a pass over the faces in Python, only then).
"""

import array
import math
from ctypes import POINTER, byref

import bpy

from . import ffi
from .convert import (
    ATTRIBUTE_CREASES,
    INDEX,
    NEW_API,
    ConversionError,
    InputMesh,
    _any_nonzero,
    _bools,
    _f32,
    _f64,
    _float_attribute,
    _u32,
    _void,
    _zeros,
    finish,
    write_arrays,
    write_with_bmesh,
)

#: Per-edge data carried: RNA properties of ``MeshEdge`` (both versions).
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
        self.data = d = InputMesh(mesh)
        self.group_names = [(g.name, g.lock_weight) for g in vertex_groups]
        nv, ne, nf = d.vertex_count, d.edge_count, d.face_count
        self.vertex_count, self.edge_count = nv, ne
        self.face_count, self.corner_count = nf, d.corner_count
        self.positions = None  # doubles, only for shape keys (read with them)
        self.edge_data = _read_edge_data(mesh, ne)
        self.vertex_creases = d.vertex_creases
        self.hide = _read_hide(mesh, nv, ne, nf)
        self.group_count, self.weights = (
            _read_weights(mesh, nv) if self.group_names else (0, None)
        )
        self.shape_keys, self.key_offsets = None, None
        if mesh.shape_keys is not None and len(mesh.shape_keys.key_blocks):
            self.positions = array.array("d", d.positions)
            self.shape_keys, self.key_offsets = _read_shape_keys(mesh, self.positions)


def _read_hide(mesh, nv, ne, nf):
    """``(vertex, edge, face)`` hide flags as bytearrays, or None when nothing is hidden."""
    if NEW_API:
        names = ((".hide_vert", "POINT", nv), (".hide_edge", "EDGE", ne), (".hide_poly", "FACE", nf))
        flags = []
        for name, domain, n in names:
            attr = mesh.attributes.get(name)
            values = bytearray(n)
            if attr is not None and attr.domain == domain and attr.data_type == "BOOLEAN":
                attr.data.foreach_get("value", values)
            flags.append(values)
    else:
        flags = []
        for items, n in ((mesh.vertices, nv), (mesh.edges, ne), (mesh.polygons, nf)):
            values = _bools(n)
            items.foreach_get("hide", values)
            flags.append(bytearray(values))
    if not any(_any_nonzero(f) for f in flags):
        return None
    return tuple(flags)


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




# ---------------------------------------------------------------------------- katachi


def _create(lib, d):
    """A new :class:`ffi.Mesh` of ``d``'s faces (an :class:`InputMesh`), in Blender's layout."""
    handle = POINTER(ffi.KatachiMesh)()
    lib.call(
        "katachi_mesh_create_polygons_f32",
        _f32(d.positions),
        d.vertex_count,
        _u32(d.face_starts),
        _u32(d.face_sizes) if d.face_sizes is not None else None,
        d.face_count,
        _u32(d.corners),
        d.corner_count,
        byref(handle),
    )
    return ffi.Mesh(lib, handle)


class CutResult:
    """What katachi's cut gave, as the arrays Blender stores, plus its report."""

    def __init__(self):
        self.info = None  # ffi.KatachiCutInfo
        self.moved = []  # [(vertex, from xyz, to xyz, pixels)]
        self.dropped = {}  # stage -> array('I') of stroke point indices
        self.kept_faces = 0
        self.positions = None  # array('f'), 3 per vertex
        self.face_starts = None  # array('I')
        self.face_sizes = None  # array('I') (3.4's loop_total)
        self.corners = None  # array(INDEX)
        self.edges = None  # array(INDEX), 2 per edge
        self.corner_edges = None  # array(INDEX)
        self.path_edges = None  # array('I'), edges on the cut paths
        self.materials = None
        self.smooth = None  # 3.4: list per face
        self.sharp_face = None  # 4.0+: bytearray per face
        self.uv_layers = []  # [(name, array('f'))]
        self.edge_data = {}  # name -> (kind, carried values)
        self.vertex_creases = None
        self.hide = None  # (vertex, edge, face) bytearrays
        self.input_counts = (0, 0)  # input vertices and edges (the result's first ones)
        self.weights = None  # array('d'), groups per result vertex
        self.key_offsets = None  # array('d'), 3 × keys per result vertex


def cut(lib, src, stroke_px, view_proj, viewport, options, keep_polygons=True):
    """Cuts ``src`` (a :class:`CutSource`) through katachi; returns a :class:`CutResult`.
    Faces the cut left whole come back as the polygons they were with ``keep_polygons``.
    Raises :class:`ffi.KatachiError` (nothing is changed then)."""
    out = CutResult()
    d = src.data
    poly = POINTER(ffi.KatachiCutPolygons)()
    with _create(lib, d) as mesh:
        with ffi.cut_by_stroke(lib, mesh, stroke_px, view_proj, viewport, options) as c:
            info = out.info = c.info()
            if info.path_count == 0:
                return out  # nothing was cut: the caller leaves the mesh alone
            h = c.handle
            n = info.moved_vertex_count
            if n:
                mv = _zeros("I", n)
                frm, to, px = _zeros("d", 3 * n), _zeros("d", 3 * n), _zeros("d", n)
                lib.call(
                    "katachi_cut_copy_moved_vertices", h, _u32(mv), _f64(frm), _f64(to),
                    _f64(px), n,
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
            out.weights = _vertex_data(lib, h, src.weights, src.group_count, info.vertex_count)
            if src.shape_keys:
                dim = 3 * len(src.shape_keys)
                out.key_offsets = _vertex_data(lib, h, src.key_offsets, dim, info.vertex_count)
            lib.call(
                "katachi_cut_polygons", h, mesh.handle, _u32(d.edges), d.edge_count,
                _u32(d.corner_edges), d.corner_count, 1 if keep_polygons else 0, byref(poly),
            )
    with ffi.CutPolygons(lib, poly) as p:
        _read_result(lib, p, src, out)
    return out


def _read_result(lib, p, src, out):
    d = src.data
    h = p.handle
    i = p.info()
    nv, nf, nc, ne = i.vertex_count, i.face_count, i.corner_count, i.edge_count
    out.kept_faces = i.kept_face_count
    out.input_counts = (d.vertex_count, d.edge_count)
    out.positions = _zeros("f", 3 * nv)
    lib.call("katachi_cut_polygons_copy_positions_f32", h, _f32(out.positions), 3 * nv)
    out.face_starts = _zeros("I", nf)
    out.corners = _zeros(INDEX, nc)
    if not NEW_API:
        out.face_sizes = _zeros("I", nf)
    lib.call(
        "katachi_cut_polygons_copy_polygons", h, _u32(out.face_starts), nf,
        _u32(out.face_sizes) if out.face_sizes is not None else None, nf,
        _u32(out.corners), nc,
    )
    out.edges = _zeros(INDEX, 2 * ne)
    out.corner_edges = _zeros(INDEX, nc)
    lib.call(
        "katachi_cut_polygons_copy_edges", h, _u32(out.edges), 2 * ne,
        _u32(out.corner_edges), nc,
    )
    out.path_edges = _zeros("I", i.path_edge_count)
    if i.path_edge_count:
        lib.call(
            "katachi_cut_polygons_copy_path_edges", h, _u32(out.path_edges), i.path_edge_count
        )

    def carry(what, values, typecode, size, n):
        result = _zeros(typecode, n) if typecode else bytearray(n)
        lib.call(
            f"katachi_cut_polygons_carry_{what}_data", h, _void(values), len(values), size,
            _void(result), n,
        )
        return result

    if _any_nonzero(d.materials):
        out.materials = carry("face", d.materials, INDEX, 4, nf)
    if d.smooth is not None and any(d.smooth):
        out.smooth = list(map(bool, carry("face", bytearray(d.smooth), None, 1, nf)))
    if d.sharp_face is not None:
        out.sharp_face = carry("face", d.sharp_face, None, 1, nf)
    for name, (kind, values) in src.edge_data.items():
        if kind in ("flag", "bool attribute"):
            out.edge_data[name] = (kind, carry("edge", bytearray(values), None, 1, ne))
        else:
            out.edge_data[name] = (kind, carry("edge", values, "f", 4, ne))
    if src.vertex_creases is not None:
        out.vertex_creases = carry("vertex", src.vertex_creases, "f", 4, nv)
    if src.hide is not None:
        vh, eh, fh = src.hide
        out.hide = (carry("vertex", vh, None, 1, nv), carry("edge", eh, None, 1, ne),
                    carry("face", fh, None, 1, nf))
    for name, uv in d.uv_layers:
        carried = _zeros("f", 2 * nc)
        lib.call(
            "katachi_cut_polygons_carry_corner_data_f32", h, _f32(uv), len(uv), 2,
            _f32(carried), len(carried),
        )
        out.uv_layers.append((name, carried))


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


def to_blender(src, res, source_mesh, name):
    """A new Blender mesh from the cut ``res`` of ``src``; materials and UV map names come
    from ``source_mesh`` (not changed). Returns ``(mesh, kept_faces)``."""
    me = bpy.data.meshes.new(name)
    try:
        _fill(me, src, res, source_mesh)
    except BaseException:
        bpy.data.meshes.remove(me)
        raise
    return me, res.kept_faces


def _fill(me, src, r, source_mesh):
    nv, nf = len(r.positions) // 3, len(r.face_starts)
    nc, ne = len(r.corners), len(r.edges) // 2
    write_arrays(
        me,
        r,
        (
            ("material_index", "INT", "FACE", r.materials),
            ("sharp_face", "BOOLEAN", "FACE", r.sharp_face),
            ("crease_vert", "FLOAT", "POINT", r.vertex_creases),
        ),
    )
    _write_edge_data(me, r)
    for mat in source_mesh.materials:
        me.materials.append(mat)
    me.update()
    if not NEW_API and r.vertex_creases is not None or r.weights is not None:
        write_with_bmesh(
            me, None if NEW_API else r.vertex_creases, r.weights, src.group_count
        )
    d = src.data
    if 0 <= d.active_render_uv < len(me.uv_layers):
        me.uv_layers[d.active_render_uv].active_render = True
    if 0 <= d.active_uv < len(me.uv_layers):
        me.uv_layers.active_index = d.active_uv
    if (len(me.vertices), len(me.edges), len(me.loops), len(me.polygons)) != (nv, ne, nc, nf):
        raise ConversionError(
            "Blender changed the cut mesh while building it; the object was left as it was "
            "(please report this as a katachi bug)"
        )
    hidden_edges = _write_hide(me, r, nv, ne)
    # Selection: the cut's shown edges and their vertices, nothing else (written whole: new
    # elements may start selected).
    vsel, esel = bytearray(nv), bytearray(ne)
    for e in r.path_edges:
        if e not in hidden_edges:
            esel[e] = vsel[r.edges[2 * e]] = vsel[r.edges[2 * e + 1]] = 1
    me.vertices.foreach_set("select", list(map(bool, vsel)))
    me.edges.foreach_set("select", list(map(bool, esel)))
    me.polygons.foreach_set("select", _bools(nf))
    finish(me, source_mesh, "cut", validate=False)
    if src.shape_keys or src.group_names:
        _write_object_data(me, src, r)


def _write_hide(me, r, nv, ne):
    """Hide flags as the input's (see the module docs); returns the hidden path edges."""
    if r.hide is None:
        return ()
    vh, eh, fh = r.hide
    vh, eh = bytearray(vh), bytearray(eh)
    # New vertices and edges that only hidden faces use are hidden too.
    shown_v, shown_e = bytearray(nv), bytearray(ne)
    nf = len(r.face_starts)
    nc = len(r.corners)
    for f in range(nf):
        if fh[f]:
            continue
        s = r.face_starts[f]
        end = r.face_starts[f + 1] if f + 1 < nf else nc
        for k in range(s, end):
            shown_v[r.corners[k]] = 1
            shown_e[r.corner_edges[k]] = 1
    nv_in, ne_in = r.input_counts
    for v in range(nv_in, nv):
        vh[v] = vh[v] or not shown_v[v]
    for e in range(ne_in, ne):
        eh[e] = eh[e] or not shown_e[e]
    me.vertices.foreach_set("hide", list(map(bool, vh)))
    me.edges.foreach_set("hide", list(map(bool, eh)))
    me.polygons.foreach_set("hide", list(map(bool, fh)))
    return {e for e in r.path_edges if eh[e]}


def _write_edge_data(me, r):
    for name, (kind, values) in r.edge_data.items():
        if kind == "flag":
            me.edges.foreach_set(name, list(map(bool, values)))
        elif kind == "float":
            me.edges.foreach_set(name, values)
        else:
            attr = me.attributes.get(name)
            if attr is None:
                data_type = "BOOLEAN" if kind == "bool attribute" else "FLOAT"
                attr = me.attributes.new(name, data_type, "EDGE")
            attr.data.foreach_set("value", values)


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

