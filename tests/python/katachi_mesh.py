"""katachi's own mesh reader and writer for the Python test programs, through its C ABI.

The MeshLab tests (tests/meshlab) and the installed library's tests (tests/c/installed) read
every mesh with katachi's reader (`katachi_mesh_read`) and write the inputs they make with
katachi's writer (`katachi_mesh_write`), over ctypes on a libkatachi.so (the build's, or the
installed one): no parser of their own.

License: MIT OR Apache-2.0.
"""

import ctypes as C


class Mesh:
    """Positions as (x, y, z) tuples and faces as lists of vertex indices (outer loops)."""

    def __init__(self, positions, faces, holes=0):
        self.positions = positions
        self.faces = faces
        #: Loops beyond each face's outer one (faces with holes).
        self.holes = holes

    def __repr__(self):
        return f"Mesh({len(self.positions)} vertices, {len(self.faces)} faces)"


class _Counts(C.Structure):
    _fields_ = [(name, C.c_uint32) for name in (
        "struct_size", "vertex_count", "face_count", "loop_count", "corner_count",
        "sharp_edge_count", "sharp_vertex_count")]


class KatachiError(Exception):
    pass


class Katachi:
    """libkatachi.so, loaded from `path`."""

    def __init__(self, path):
        lib = C.CDLL(str(path))
        P = C.c_void_p
        lib.katachi_last_error_message.restype = C.c_char_p
        lib.katachi_mesh_read.argtypes = [C.c_char_p, C.POINTER(P)]
        lib.katachi_mesh_write.argtypes = [P, C.c_char_p]
        lib.katachi_mesh_free.argtypes = [P]
        lib.katachi_mesh_free.restype = None
        lib.katachi_mesh_counts.argtypes = [P, C.POINTER(_Counts)]
        lib.katachi_mesh_copy_positions.argtypes = [P, C.POINTER(C.c_double), C.c_size_t]
        u32p = C.POINTER(C.c_uint32)
        lib.katachi_mesh_copy_faces.argtypes = [P, u32p, C.c_size_t, u32p, C.c_size_t,
                                                u32p, C.c_size_t]
        lib.katachi_mesh_create.argtypes = [C.POINTER(C.c_double), C.c_uint32, u32p,
                                            C.c_uint32, u32p, C.c_uint32, u32p, C.c_uint32,
                                            C.POINTER(P)]
        self.lib = lib

    def _check(self, status, what):
        if status != 0:
            msg = self.lib.katachi_last_error_message()
            raise KatachiError(f"{what}: {msg.decode() if msg else status}")

    def read(self, path):
        """The mesh in `path` (.obj, .ply, .off), read by katachi."""
        handle = C.c_void_p()
        self._check(self.lib.katachi_mesh_read(str(path).encode(), C.byref(handle)),
                    f"reading {path}")
        try:
            return self._copy(handle)
        finally:
            self.lib.katachi_mesh_free(handle)

    def _copy(self, handle):
        n = _Counts(struct_size=C.sizeof(_Counts))
        self._check(self.lib.katachi_mesh_counts(handle, C.byref(n)), "katachi_mesh_counts")
        pos = (C.c_double * (3 * n.vertex_count))()
        self._check(self.lib.katachi_mesh_copy_positions(handle, pos, len(pos)),
                    "katachi_mesh_copy_positions")
        sizes = (C.c_uint32 * n.loop_count)()
        loops = (C.c_uint32 * n.face_count)()
        corners = (C.c_uint32 * n.corner_count)()
        self._check(self.lib.katachi_mesh_copy_faces(handle, sizes, len(sizes), loops,
                                                     len(loops), corners, len(corners)),
                    "katachi_mesh_copy_faces")
        positions = [tuple(pos[3 * i:3 * i + 3]) for i in range(n.vertex_count)]
        faces, loop, at = [], 0, 0
        for f in range(n.face_count):
            for k in range(loops[f]):
                if k == 0:
                    faces.append(list(corners[at:at + sizes[loop]]))
                at += sizes[loop]
                loop += 1
        return Mesh(positions, faces, n.loop_count - n.face_count)

    def write(self, mesh, path):
        """Writes `mesh` (simple faces) to `path` with katachi's writer."""
        flat = [x for p in mesh.positions for x in p]
        pos = (C.c_double * len(flat))(*flat)
        sizes = (C.c_uint32 * len(mesh.faces))(*[len(f) for f in mesh.faces])
        ones = (C.c_uint32 * len(mesh.faces))(*[1] * len(mesh.faces))
        idx = [v for f in mesh.faces for v in f]
        corners = (C.c_uint32 * len(idx))(*idx)
        handle = C.c_void_p()
        self._check(self.lib.katachi_mesh_create(pos, len(mesh.positions), sizes, len(sizes),
                                                 ones, len(ones), corners, len(corners),
                                                 C.byref(handle)), "katachi_mesh_create")
        try:
            self._check(self.lib.katachi_mesh_write(handle, str(path).encode()),
                        f"writing {path}")
        finally:
            self.lib.katachi_mesh_free(handle)
