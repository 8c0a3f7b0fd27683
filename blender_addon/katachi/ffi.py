"""ctypes bindings to the katachi C library (``include/katachi.h``).

The library, ``libkatachi.so``, ships beside this file. It is loaded on first use, not at
add-on registration, so that a missing or mismatched library is reported by the operator
that needed it (``self.report``) instead of breaking Blender's add-on list.

Only conversion lives here: every function returns a ``KatachiStatus``, and :func:`check`
turns a failure into :class:`KatachiError` carrying ``katachi_last_error_message()``.

The structs, the callback types (``CFUNCTYPE``, the header's function-pointer typedefs) and
the ``FUNCTIONS`` table mirror the header field by field and argument by argument;
``tests/blender_bindings.rs`` parses this file and fails when they drift apart (a
``POINTER(T)`` stands for ``T *`` or ``const T *``: ctypes has no const).
"""

import ctypes
import os
from ctypes import (
    CFUNCTYPE,
    POINTER,
    c_bool,
    c_char,
    c_char_p,
    c_double,
    c_float,
    c_int64,
    c_size_t,
    c_uint32,
    c_void_p,
)

#: The ABI this add-on was written against (``KATACHI_ABI_VERSION`` in the header).
KATACHI_ABI_VERSION = 2

#: The library's file name, looked for beside this module.
LIBRARY_NAME = "libkatachi.so"

# ---- enums (checked against include/katachi.h by tests/blender_bindings.rs) ----
KATACHI_STATUS_OK = 0
KATACHI_STATUS_NULL_POINTER = 1
KATACHI_STATUS_INVALID_ARGUMENT = 2
KATACHI_STATUS_BUFFER_TOO_SMALL = 3
KATACHI_STATUS_BAD_INPUT = 4
KATACHI_STATUS_BAD_TOPOLOGY = 5
KATACHI_STATUS_IO_ERROR = 6
KATACHI_STATUS_INTERNAL_ERROR = 7
KATACHI_STATUS_CANCELLED = 8
KATACHI_HOLE_METHOD_SMOOTH = 0
KATACHI_HOLE_METHOD_SHARP = 1
KATACHI_BOUNDARY_EDGE_ONLY = 0
KATACHI_BOUNDARY_EDGE_AND_CORNER = 1
KATACHI_CREASE_METHOD_UNIFORM = 0
KATACHI_CREASE_METHOD_CHAIKIN = 1
KATACHI_FACE_VARYING_SMOOTH = 0
KATACHI_FACE_VARYING_LINEAR_CORNERS_ONLY = 1
KATACHI_FACE_VARYING_LINEAR_BOUNDARIES = 2
KATACHI_FACE_VARYING_LINEAR_ALL = 3
KATACHI_SHARPNESS_SCALE_SHARPNESS = 0
KATACHI_SHARPNESS_SCALE_CREASE = 1
KATACHI_CUT_MODE_VISIBLE_ONLY = 0
KATACHI_CUT_MODE_THROUGH_ALL = 1
KATACHI_CUT_STAGE_PREPROCESSING = 0
KATACHI_CUT_STAGE_FIRST_NORMALIZATION = 1
KATACHI_CUT_STAGE_SECOND_NORMALIZATION = 2
KATACHI_CUT_STAGE_OFF_MESH = 3
# ---- end of enums ----

#: ``KatachiStatus`` is a ``uint32_t`` in C.
KatachiStatus = c_uint32


class KatachiMesh(ctypes.Structure):
    """Opaque mesh handle (only ever used through a pointer)."""


class KatachiSubdivision(ctypes.Structure):
    """Opaque subdivision-result handle (only ever used through a pointer)."""


class KatachiCut(ctypes.Structure):
    """Opaque stroke-cut-result handle (only ever used through a pointer)."""


class KatachiCutPolygons(ctypes.Structure):
    """Opaque handle of a cut in the input's own layout (only ever used through a pointer)."""


# ---- structs (checked against include/katachi.h by tests/blender_bindings.rs) ----
class KatachiMeshCounts(ctypes.Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("vertex_count", c_uint32),
        ("face_count", c_uint32),
        ("loop_count", c_uint32),
        ("corner_count", c_uint32),
        ("sharp_edge_count", c_uint32),
        ("sharp_vertex_count", c_uint32),
    ]


class KatachiMeshInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("vertex_count", c_uint32),
        ("unreferenced_vertex_count", c_uint32),
        ("face_count", c_uint32),
        ("faces_with_holes_count", c_uint32),
        ("edge_count", c_uint32),
        ("boundary_edge_count", c_uint32),
        ("boundary_loop_count", c_uint32),
        ("component_count", c_uint32),
        ("non_manifold_edge_count", c_uint32),
        ("inconsistent_edge_count", c_uint32),
        ("non_manifold_vertex_count", c_uint32),
        ("coincident_vertex_count", c_uint32),
        ("zero_area_face_count", c_uint32),
        ("sharp_edge_count", c_uint32),
        ("sharp_vertex_count", c_uint32),
        ("euler_characteristic", c_int64),
        ("genus", c_int64),
        ("is_closed", c_bool),
        ("is_manifold", c_bool),
        ("has_bounding_box", c_bool),
        ("bounding_box_min", c_double * 3),
        ("bounding_box_max", c_double * 3),
    ]


class KatachiSubdivideOptions(ctypes.Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("levels", c_uint32),
        ("holes", c_uint32),
        ("boundary", c_uint32),
        ("crease_method", c_uint32),
        ("recover_faces_with_holes", c_uint32),
        ("coplanar_angle_tolerance", c_double),
        ("feature_angle_degrees", c_double),
        ("split_faces_with_holes", c_uint32),
    ]


class KatachiSubdivisionInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("levels", c_uint32),
        ("vertex_count", c_uint32),
        ("face_count", c_uint32),
        ("loop_count", c_uint32),
        ("corner_count", c_uint32),
        ("edge_count", c_uint32),
        ("sharp_edge_count", c_uint32),
        ("sharp_vertex_count", c_uint32),
        ("input_vertex_count", c_uint32),
        ("input_face_count", c_uint32),
        ("input_corner_count", c_uint32),
        ("fallback_face_count", c_uint32),
    ]


class KatachiCutOptions(ctypes.Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("mode", c_uint32),
        ("open", c_uint32),
        ("max_faces_split", c_uint32),
        ("snap_vertex_ratio", c_double),
        ("snap_segment_ratio", c_double),
        ("corner_angle_degrees", c_double),
        ("min_stroke_px", c_double),
        ("depth_eps_rel", c_double),
    ]


class KatachiCutInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("vertex_count", c_uint32),
        ("face_count", c_uint32),
        ("corner_count", c_uint32),
        ("input_vertex_count", c_uint32),
        ("input_corner_count", c_uint32),
        ("new_vertex_count", c_uint32),
        ("new_face_count", c_uint32),
        ("split_face_count", c_uint32),
        ("moved_vertex_count", c_uint32),
        ("piece_count", c_uint32),
        ("path_count", c_uint32),
        ("path_vertex_count", c_uint32),
        ("dropped_preprocessing_count", c_uint32),
        ("dropped_first_normalization_count", c_uint32),
        ("dropped_second_normalization_count", c_uint32),
        ("dropped_off_mesh_count", c_uint32),
        ("snaps_refused_count", c_uint32),
        ("ends_moved_to_edges_count", c_uint32),
        ("clipped_face_count", c_uint32),
        ("degenerate_face_count", c_uint32),
        ("rerouted_count", c_uint32),
        ("unjoined_count", c_uint32),
        ("max_move_world", c_double),
        ("max_move_px", c_double),
        ("mean_edge_length_px", c_double),
        ("mean_edge_length_world", c_double),
    ]


class KatachiCutPolygonsInfo(ctypes.Structure):
    _fields_ = [
        ("struct_size", c_uint32),
        ("vertex_count", c_uint32),
        ("face_count", c_uint32),
        ("corner_count", c_uint32),
        ("edge_count", c_uint32),
        ("kept_face_count", c_uint32),
        ("path_edge_count", c_uint32),
    ]
# ---- end of structs ----

# ---- callbacks (checked against include/katachi.h by tests/blender_bindings.rs) ----
# CFUNCTYPE(return type, argument types...): a C function-pointer typedef.
KatachiProgressFn = CFUNCTYPE(None, c_uint32, c_uint32, c_void_p)
KatachiCutProgressFn = CFUNCTYPE(c_uint32, c_uint32, c_uint32, c_void_p)
# ---- end of callbacks ----


_MeshP = POINTER(KatachiMesh)
_SubP = POINTER(KatachiSubdivision)

# ---- functions (checked against include/katachi.h by tests/blender_bindings.rs) ----
# name: (return type, [argument types])
FUNCTIONS = {
    "katachi_last_error_message": (c_char_p, []),
    "katachi_status_name": (c_char_p, [c_uint32]),
    "katachi_abi_version": (c_uint32, []),
    "katachi_version_string": (c_char_p, []),
    "katachi_mesh_create": (KatachiStatus, [POINTER(c_double), c_uint32, POINTER(c_uint32), c_uint32, POINTER(c_uint32), c_uint32, POINTER(c_uint32), c_uint32, POINTER(POINTER(KatachiMesh))]),
    "katachi_mesh_free": (None, [POINTER(KatachiMesh)]),
    "katachi_mesh_counts_default": (KatachiMeshCounts, []),
    "katachi_mesh_counts": (KatachiStatus, [POINTER(KatachiMesh), POINTER(KatachiMeshCounts)]),
    "katachi_mesh_copy_positions": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_double), c_size_t]),
    "katachi_mesh_copy_faces": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),
    "katachi_mesh_set_edge_sharpnesses": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_uint32), POINTER(c_double), c_size_t]),
    "katachi_mesh_copy_sharp_edges": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_uint32), POINTER(c_double), c_size_t]),
    "katachi_mesh_copy_vertex_sharpness": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_double), c_size_t]),
    "katachi_mesh_set_all_vertex_sharpness": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_double), c_size_t]),
    "katachi_mesh_create_polygons_f32": (KatachiStatus, [POINTER(c_float), c_uint32, POINTER(c_uint32), POINTER(c_uint32), c_uint32, POINTER(c_uint32), c_uint32, POINTER(POINTER(KatachiMesh))]),
    "katachi_mesh_set_edge_sharpness_f32": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_uint32), POINTER(c_float), c_uint32, POINTER(c_uint32), c_uint32, c_uint32, POINTER(c_uint32)]),
    "katachi_mesh_set_vertex_sharpness_f32": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_float), c_uint32, c_uint32]),
    "katachi_mesh_info_default": (KatachiMeshInfo, []),
    "katachi_mesh_inspect": (KatachiStatus, [POINTER(KatachiMesh), POINTER(KatachiMeshInfo)]),
    "katachi_subdivide_options_default": (KatachiSubdivideOptions, []),
    "katachi_subdivision_info_default": (KatachiSubdivisionInfo, []),
    "katachi_subdivide": (KatachiStatus, [POINTER(KatachiMesh), POINTER(KatachiSubdivideOptions), POINTER(POINTER(KatachiSubdivision))]),
    "katachi_subdivide_with_progress": (KatachiStatus, [POINTER(KatachiMesh), POINTER(KatachiSubdivideOptions), KatachiProgressFn, c_void_p, POINTER(POINTER(KatachiSubdivision))]),
    "katachi_subdivision_free": (None, [POINTER(KatachiSubdivision)]),
    "katachi_subdivision_info": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(KatachiSubdivisionInfo)]),
    "katachi_subdivision_mesh": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(POINTER(KatachiMesh))]),
    "katachi_subdivision_copy_face_origin": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_uint32), c_size_t]),
    "katachi_subdivision_copy_fallback_faces": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_uint32), c_size_t]),
    "katachi_subdivision_copy_positions_f32": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_float), c_size_t]),
    "katachi_subdivision_copy_polygons": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),
    "katachi_subdivision_copy_edges": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),
    "katachi_subdivision_copy_edge_sharpness_f32": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_float), c_size_t, c_uint32]),
    "katachi_subdivision_copy_vertex_sharpness_f32": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_float), c_size_t, c_uint32]),
    "katachi_subdivision_carry_face_data": (KatachiStatus, [POINTER(KatachiSubdivision), c_void_p, c_size_t, c_uint32, c_void_p, c_size_t]),
    "katachi_subdivision_refine_corner_data_f32": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_float), c_size_t, c_uint32, c_uint32, POINTER(c_float), c_size_t]),
    "katachi_subdivision_fallback_reason": (KatachiStatus, [POINTER(KatachiSubdivision), c_uint32, POINTER(c_char), c_size_t]),
    "katachi_subdivision_refine_face_varying": (KatachiStatus, [POINTER(KatachiSubdivision), POINTER(c_double), c_size_t, c_uint32, POINTER(c_uint32), c_size_t, c_uint32, POINTER(c_double), c_size_t]),
    "katachi_mesh_split_faces_with_holes": (KatachiStatus, [POINTER(KatachiMesh), POINTER(POINTER(KatachiMesh)), POINTER(c_uint32), c_size_t]),
    "katachi_cut_options_default": (KatachiCutOptions, []),
    "katachi_cut_info_default": (KatachiCutInfo, []),
    "katachi_cut_by_stroke": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_double), c_uint32, POINTER(c_double), POINTER(c_double), POINTER(KatachiCutOptions), POINTER(POINTER(KatachiCut))]),
    "katachi_cut_by_stroke_with_progress": (KatachiStatus, [POINTER(KatachiMesh), POINTER(c_double), c_uint32, POINTER(c_double), POINTER(c_double), POINTER(KatachiCutOptions), KatachiCutProgressFn, c_void_p, POINTER(POINTER(KatachiCut))]),
    "katachi_cut_free": (None, [POINTER(KatachiCut)]),
    "katachi_cut_info": (KatachiStatus, [POINTER(KatachiCut), POINTER(KatachiCutInfo)]),
    "katachi_cut_mesh": (KatachiStatus, [POINTER(KatachiCut), POINTER(POINTER(KatachiMesh))]),
    "katachi_cut_copy_face_origin": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_uint32), c_size_t]),
    "katachi_cut_copy_vertex_original": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_uint32), c_size_t]),
    "katachi_cut_copy_paths": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),
    "katachi_cut_copy_path_pieces": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_uint32), POINTER(c_uint32), c_size_t]),
    "katachi_cut_copy_moved_vertices": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_uint32), POINTER(c_double), POINTER(c_double), POINTER(c_double), c_size_t]),
    "katachi_cut_copy_dropped_points": (KatachiStatus, [POINTER(KatachiCut), c_uint32, POINTER(c_uint32), c_size_t]),
    "katachi_cut_interpolate_corner_data": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_double), c_size_t, c_uint32, POINTER(c_double), c_size_t]),
    "katachi_cut_interpolate_vertex_data": (KatachiStatus, [POINTER(KatachiCut), POINTER(c_double), c_size_t, c_uint32, POINTER(c_double), c_size_t]),
    "katachi_cut_polygons_info_default": (KatachiCutPolygonsInfo, []),
    "katachi_cut_polygons": (KatachiStatus, [POINTER(KatachiCut), POINTER(KatachiMesh), POINTER(c_uint32), c_uint32, POINTER(c_uint32), c_uint32, c_uint32, POINTER(POINTER(KatachiCutPolygons))]),
    "katachi_cut_polygons_free": (None, [POINTER(KatachiCutPolygons)]),
    "katachi_cut_polygons_info": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(KatachiCutPolygonsInfo)]),
    "katachi_cut_polygons_copy_positions": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(c_double), c_size_t]),
    "katachi_cut_polygons_copy_positions_f32": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(c_float), c_size_t]),
    "katachi_cut_polygons_copy_polygons": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),
    "katachi_cut_polygons_copy_edges": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),
    "katachi_cut_polygons_copy_origins": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t, POINTER(c_uint32), c_size_t]),
    "katachi_cut_polygons_copy_path_edges": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(c_uint32), c_size_t]),
    "katachi_cut_polygons_carry_face_data": (KatachiStatus, [POINTER(KatachiCutPolygons), c_void_p, c_size_t, c_uint32, c_void_p, c_size_t]),
    "katachi_cut_polygons_carry_edge_data": (KatachiStatus, [POINTER(KatachiCutPolygons), c_void_p, c_size_t, c_uint32, c_void_p, c_size_t]),
    "katachi_cut_polygons_carry_vertex_data": (KatachiStatus, [POINTER(KatachiCutPolygons), c_void_p, c_size_t, c_uint32, c_void_p, c_size_t]),
    "katachi_cut_polygons_carry_corner_data_f32": (KatachiStatus, [POINTER(KatachiCutPolygons), POINTER(c_float), c_size_t, c_uint32, POINTER(c_float), c_size_t]),
}
# ---- end of functions ----

#: Functions returning a status (the others cannot fail).
_STATUS_FUNCTIONS = {name for name, (res, _) in FUNCTIONS.items() if res is KatachiStatus}


class KatachiError(Exception):
    """A katachi call failed; ``str(error)`` is katachi's message naming what and where."""

    def __init__(self, message, status=KATACHI_STATUS_INTERNAL_ERROR, function=""):
        super().__init__(message)
        self.status = status
        self.function = function


class Library:
    """The loaded ``libkatachi.so`` with its prototypes set, one attribute per function."""

    def __init__(self, path):
        if not os.path.isfile(path):
            raise KatachiError(
                f"the katachi library is missing: {path} (reinstall the add-on from its zip)",
                KATACHI_STATUS_INTERNAL_ERROR,
            )
        try:
            self._dll = ctypes.CDLL(path)
        except OSError as e:
            raise KatachiError(f"cannot load the katachi library {path}: {e}") from e
        self.path = path
        for name, (restype, argtypes) in FUNCTIONS.items():
            try:
                fn = getattr(self._dll, name)
            except AttributeError as e:
                raise KatachiError(
                    f"{path} has no function {name}: the library is older than the add-on"
                ) from e
            fn.restype = restype
            fn.argtypes = argtypes
            setattr(self, name, fn)
        abi = self.katachi_abi_version()
        if abi != KATACHI_ABI_VERSION:
            raise KatachiError(
                f"{path} has ABI version {abi}, but the add-on needs {KATACHI_ABI_VERSION}"
            )
        # The structs' sizes as the library sees them (struct_size of the defaults).
        for default, struct in (
            (self.katachi_mesh_counts_default, KatachiMeshCounts),
            (self.katachi_mesh_info_default, KatachiMeshInfo),
            (self.katachi_subdivide_options_default, KatachiSubdivideOptions),
            (self.katachi_subdivision_info_default, KatachiSubdivisionInfo),
            (self.katachi_cut_options_default, KatachiCutOptions),
            (self.katachi_cut_info_default, KatachiCutInfo),
        ):
            size = default().struct_size
            if size != ctypes.sizeof(struct):
                raise KatachiError(
                    f"{struct.__name__} is {size} bytes in {path} but {ctypes.sizeof(struct)} "
                    "in the add-on: the library does not match the add-on"
                )

    @property
    def version(self):
        return self.katachi_version_string().decode("utf-8")

    def last_error(self):
        msg = self.katachi_last_error_message()
        return msg.decode("utf-8", "replace") if msg else ""

    def call(self, name, *args):
        """Calls a status-returning function; raises :class:`KatachiError` on failure."""
        status = getattr(self, name)(*args)
        if status != KATACHI_STATUS_OK:
            raise KatachiError(self.last_error() or self.status_name(status), status, name)
        return status

    def status_name(self, status):
        return self.katachi_status_name(status).decode("ascii", "replace")


_library = None


def library_path():
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), LIBRARY_NAME)


def load():
    """The shared :class:`Library`, loaded on first use."""
    global _library
    if _library is None:
        _library = Library(library_path())
    return _library


# ---- small helpers over raw buffers ----


def ptr(buffer, ctype):
    """A ``POINTER(ctype)`` into a writable buffer (``bytearray``, ``array.array``), or NULL
    for an empty one. The buffer must outlive the call."""
    if len(buffer) == 0:
        return None
    n = memoryview(buffer).nbytes // ctypes.sizeof(ctype)
    return ctypes.cast((ctype * n).from_buffer(buffer), POINTER(ctype))


class _Handle:
    """Owns a katachi handle; frees it with ``FREE`` on :meth:`close` (a context manager)."""

    FREE = None

    def __init__(self, lib, handle):
        self.lib = lib
        self.handle = handle

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        if self.handle:
            getattr(self.lib, self.FREE)(self.handle)
            self.handle = None


class Mesh(_Handle):
    """Owns a ``KatachiMesh*``."""

    FREE = "katachi_mesh_free"

    def counts(self):
        c = self.lib.katachi_mesh_counts_default()
        self.lib.call("katachi_mesh_counts", self.handle, ctypes.byref(c))
        return c

    def inspect(self):
        info = self.lib.katachi_mesh_info_default()
        self.lib.call("katachi_mesh_inspect", self.handle, ctypes.byref(info))
        return info


class Subdivision(_Handle):
    """Owns a ``KatachiSubdivision*``."""

    FREE = "katachi_subdivision_free"

    def info(self):
        i = self.lib.katachi_subdivision_info_default()
        self.lib.call("katachi_subdivision_info", self.handle, ctypes.byref(i))
        return i


class Cut(_Handle):
    """Owns a ``KatachiCut*`` (a result of ``katachi_cut_by_stroke``)."""

    FREE = "katachi_cut_free"

    def info(self):
        i = self.lib.katachi_cut_info_default()
        self.lib.call("katachi_cut_info", self.handle, ctypes.byref(i))
        return i


class CutPolygons(_Handle):
    """Owns a ``KatachiCutPolygons*`` (a cut in the input's own layout)."""

    FREE = "katachi_cut_polygons_free"

    def info(self):
        i = self.lib.katachi_cut_polygons_info_default()
        self.lib.call("katachi_cut_polygons_info", self.handle, ctypes.byref(i))
        return i


def cut_by_stroke(lib, mesh, stroke_px, view_proj, viewport, options):
    """Cuts ``mesh`` (a :class:`Mesh`, not changed) along ``stroke_px`` (``2 n`` doubles,
    pixels from the viewport's top-left corner, y down) seen through ``view_proj`` (16
    doubles, column-major) and ``viewport`` (``x0, y0, width, height``) with ``options`` (a
    ``KatachiCutOptions``); returns a :class:`Cut`. Each sequence is copied into a
    ``double`` array here."""
    stroke = (c_double * max(len(stroke_px), 1))(*stroke_px)
    vp = (c_double * 16)(*view_proj)
    port = (c_double * 4)(*viewport)
    handle = POINTER(KatachiCut)()
    lib.call(
        "katachi_cut_by_stroke",
        mesh.handle,
        ctypes.cast(stroke, POINTER(c_double)),
        len(stroke_px) // 2,
        ctypes.cast(vp, POINTER(c_double)),
        ctypes.cast(port, POINTER(c_double)),
        ctypes.byref(options),
        ctypes.byref(handle),
    )
    return Cut(lib, handle)


def subdivide(lib, mesh, options, progress=None):
    """Subdivides ``mesh`` (a :class:`Mesh`) with ``options`` (a ``KatachiSubdivideOptions``)
    through ``katachi_subdivide_with_progress``; returns a :class:`Subdivision`.

    ``progress(done, total)`` is called on this thread after each level (``done`` levels of
    ``total`` refined). The work cannot be interrupted: an exception raised by ``progress``
    is kept and raised once katachi has returned (the result is then freed)."""
    handle = POINTER(KatachiSubdivision)()
    raised = []
    if progress is None:
        callback = KatachiProgressFn()  # NULL
    else:

        def on_level(done, total, _user):
            if raised:
                return
            try:
                progress(done, total)
            except BaseException as e:  # ctypes would print and drop it
                raised.append(e)

        # ``callback`` is referenced until the call returns: katachi calls it during the call
        # only, and ctypes frees the trampoline with the last reference.
        callback = KatachiProgressFn(on_level)
    lib.call(
        "katachi_subdivide_with_progress",
        mesh.handle,
        ctypes.byref(options),
        callback,
        None,
        ctypes.byref(handle),
    )
    result = Subdivision(lib, handle)
    if raised:
        result.close()
        raise raised[0]
    return result
