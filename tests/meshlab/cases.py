"""The MeshLab plugin's test cases, shared by MeshLab 2020.09 (meshlabserver,
`run_meshlabserver.py`) and MeshLab 2025.07 (pymeshlab, `run_pymeshlab.py`).

Each host applies the same filters with the same parameters to the same meshes, and its
result is compared with `katachi`'s CLI given the same options:

- subdivision: [`compare`]: the same vertices (MeshLab stores floats, so within `REL_TOL` of
  the diagonal) and MeshLab's triangles exactly triangulate the CLI's polygons;
- cut: [`compare_indexed`]: vertex for vertex and triangle for triangle, with the view the
  filter reports (its view-projection matrix) given to the CLI;
- bad inputs: katachi's message, the layer unchanged, the host still running.

Also the small runner both scripts use (`Run`: one line per check, closing
`N passed, M failed`).

License: MIT OR Apache-2.0.
"""

import json
import math
import os
import subprocess
import sys
import traceback

from katachi_mesh import Mesh  # tests/python: katachi's reader and writer (C ABI)

SUBDIVIDE = "katachi: Solid-aware subdivision"
CUT = "katachi: Cut by polyline"

#: Position tolerance, relative to the CLI result's bounding-box diagonal: MeshLab 2020.09
#: stores floats and writes 7 significant digits.
REL_TOL = 1e-5


# ---------------------------------------------------------------------------------------
# The runner


class Run:
    """Checks with one line each, a `-k` filter on case names, and the closing summary."""

    def __init__(self, label, only=None):
        self.label, self.only = label, only
        self.passed = self.failed = 0

    def wanted(self, name):
        return self.only is None or self.only in name

    def check(self, ok, what):
        print(f"{'ok  ' if ok else 'FAIL'} {self.label}: {what}", flush=True)
        if ok:
            self.passed += 1
        else:
            self.failed += 1
        return ok

    def case(self, name, body):
        """Runs `body()` (which makes its own checks) as case `name`; an exception fails it."""
        if not self.wanted(name):
            return
        try:
            body()
        except Exception:  # a broken case is a failed check, and the others still run
            self.check(False, f"{name}: raised\n{traceback.format_exc()}")

    def finish(self):
        print(f"{self.passed} passed, {self.failed} failed", flush=True)
        sys.exit(0 if self.failed == 0 and self.passed > 0 else 1)


# ---------------------------------------------------------------------------------------
# Inputs


def plate_with_hole():
    """A square plate 4 x 4 x 1 with a 2 x 2 square hole through it, every face triangulated
    (what a boolean leaves): 16 vertices, 32 triangles, closed, genus 1."""
    outer = [(-2.0, -2.0), (2.0, -2.0), (2.0, 2.0), (-2.0, 2.0)]
    inner = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
    # Vertex ids: bottom outer 0-3, bottom inner 4-7, top outer 8-11, top inner 12-15.
    positions = [(x, y, z) for z in (0.0, 1.0) for (x, y) in outer + inner]
    bo, bi, to, ti = 0, 4, 8, 12
    faces = []
    for k in range(4):
        n = (k + 1) % 4
        for a, b, c, d in ((to + k, to + n, ti + n, ti + k),   # top, facing +z
                           (bo + k, bi + k, bi + n, bo + n),   # bottom, facing -z
                           (bo + k, bo + n, to + n, to + k),   # outer wall
                           (bi + k, ti + k, ti + n, bi + n)):  # hole wall
            faces += [[a, b, c], [a, c, d]]
    return Mesh(positions, faces)


def grid(n):
    """An n x n grid of unit squares in the plane z = 0, each square two triangles facing +z."""
    positions = [(float(i), float(j), 0.0) for j in range(n + 1) for i in range(n + 1)]
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 2, a + n + 1
            faces += [[a, b, c], [a, c, d]]
    return Mesh(positions, faces)


def rounded_to_f32(mesh):
    """`mesh` with every coordinate rounded to the nearest float, so that MeshLab 2020.09
    (which stores floats) and the CLI (doubles) read the same numbers."""
    import struct
    f32 = lambda x: struct.unpack("f", struct.pack("f", x))[0]
    return Mesh([tuple(f32(c) for c in p) for p in mesh.positions], mesh.faces)


def _tet(z, last):
    return ([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, z)],
            [[0, 2, 1], [0, 1, 3], [1, 2, 3], last])


#: Bad subdivision inputs: name, (positions, faces), options, katachi's message. katachi
#: refuses these meshes, so its writer cannot make them: `off_text` writes them.
BAD_SUBDIVISIONS = [
    ("repeated_vertex", _tet(1.0, [0, 0, 2]), {}, "katachi_mesh_create: face 3"),
    ("nan_coordinate", _tet(float("nan"), [0, 3, 2]), {"new_layer": False},
     "katachi_mesh_create: vertex 3"),
    ("nine_levels", _tet(1.0, [0, 3, 2]), {"levels": 9}, "katachi_subdivide: option levels"),
]


def off_text(positions, faces):
    """OFF text for a mesh katachi would refuse to write."""
    lines = ["OFF", f"{len(positions)} {len(faces)} 0"]
    lines += [" ".join("nan" if math.isnan(c) else repr(c) for c in p) for p in positions]
    lines += [" ".join(str(v) for v in [len(f)] + f) for f in faces]
    return "\n".join(lines) + "\n"


class Subdivision:
    """The subdivision filter's options, as a script, pymeshlab and the CLI take them."""

    def __init__(self, levels=1, sharp_holes=False, recover=False, feature_angle=0.0,
                 edge_and_corner=False, new_layer=True):
        self.levels, self.sharp_holes, self.recover = levels, sharp_holes, recover
        self.feature_angle, self.edge_and_corner = feature_angle, edge_and_corner
        self.new_layer = new_layer

    @staticmethod
    def of(d):
        return Subdivision(**d)

    def params(self):
        """pymeshlab's keyword arguments (enums by their GUI text)."""
        return {
            "levels": self.levels,
            "faces_with_holes": "Sharp [b]" if self.sharp_holes else "Smooth [a]",
            "recover_faces_with_holes": self.recover,
            "feature_angle_degrees": float(self.feature_angle),
            "boundary": "Edge and corner" if self.edge_and_corner else "Edge only",
            "new_layer": self.new_layer,
        }

    def mlx(self):
        """A filter script. meshlabserver 2020.09 asserts when a script omits a parameter, so
        every parameter is given."""
        def en(name, v, a, b):
            return (f'  <Param type="RichEnum" name="{name}" value="{int(v)}" enum_val0="{a}" '
                    f'enum_val1="{b}" enum_cardinality="2"/>\n')

        def bl(name, v):
            return f'  <Param type="RichBool" name="{name}" value="{str(v).lower()}"/>\n'
        return ("<!DOCTYPE FilterScript>\n<FilterScript>\n"
                f' <filter name="{SUBDIVIDE}">\n'
                f'  <Param type="RichInt" name="levels" value="{self.levels}"/>\n'
                + en("faces_with_holes", self.sharp_holes, "Smooth [a]", "Sharp [b]")
                + bl("recover_faces_with_holes", self.recover)
                + f'  <Param type="RichFloat" name="feature_angle_degrees" '
                  f'value="{self.feature_angle}"/>\n'
                + en("boundary", self.edge_and_corner, "Edge only", "Edge and corner")
                + bl("new_layer", self.new_layer)
                + " </filter>\n</FilterScript>\n")

    def cli_args(self):
        a = ["--levels", str(self.levels)]
        if self.sharp_holes:
            a += ["--holes", "sharp"]
        if self.recover:
            a.append("--solid")
        if self.feature_angle != 0.0:
            a += ["--feature-angle", repr(float(self.feature_angle))]
        if self.edge_and_corner:
            a += ["--boundary", "edge-and-corner"]
        return a


def subdivision_cases(models, work, kat, ngon_format):
    """(name, input path, options): the bundled models (tests/data/models) and a triangulated
    plate with a hole, so no corpus is needed. `ngon_format` is the file format the host
    reads n-gons (5 corners and more) correctly from: "off" for MeshLab 2020.09, whose OBJ
    reader asserts on some files; "obj" for MeshLab 2025.07, whose OFF reader builds every
    such polygon's triangles on the mesh's first vertices (vcglib's import_off.h passes the
    polygon's own corner numbers to AddFace)."""
    m = lambda name: os.path.join(models, name)
    plate = os.path.join(work, "plate_with_hole.off")
    kat.write(plate_with_hole(), plate)
    # MeshLab 2020.09's OBJ reader aborts on spot_quadrangulated.obj (an assertion in vcg's
    # import_obj.h), so both sides read the same mesh converted to OFF by katachi.
    spot = os.path.join(work, "spot_quadrangulated.off")
    kat.write(kat.read(m("spot_quadrangulated.obj")), spot)
    # Triangles, squares and pentagons, written by katachi in the host's format; the CLI
    # reads the same file.
    ngons = os.path.join(work, f"rhombicosidodecahedron.{ngon_format}")
    kat.write(kat.read(m("rhombicosidodecahedron.obj")), ngons)
    return [
        ("fandisk_feature30", m("fandisk.off"), Subdivision(feature_angle=30.0)),
        ("fandisk_quads_l2_inplace", m("fandisk_quads.off"),
         Subdivision(levels=2, new_layer=False)),
        ("spot_quads", spot, Subdivision()),
        ("rhombicosidodecahedron_ngons_l2", ngons, Subdivision(levels=2)),
        ("hole_capsule_l2_corner", m("hole_capsule.off"),
         Subdivision(levels=2, edge_and_corner=True)),
        ("plate_recover_smooth_l2", plate, Subdivision(levels=2, recover=True)),
        ("plate_recover_sharp", plate,
         Subdivision(recover=True, sharp_holes=True, new_layer=False)),
        ("plate_triangles", plate, Subdivision()),
    ]


# ---------------------------------------------------------------------------------------
# The cut: cameras and strokes


def _sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _normalize(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


class Camera:
    """A camera in MeshLab's terms (vcg::Shot), written as the `<VCGCamera …/>` element that
    MeshLab's Windows > Copy shot and its project files hold."""

    def __init__(self, eye, target, up, orthographic):
        """At `eye` looking at `target` with `up` up: orthographic 600 x 600 pixels covering
        12 units, or perspective 800 x 600 pixels with a 40° vertical field of view."""
        z = _normalize(_sub(eye, target))
        x = _normalize(_cross(up, z))
        y = _cross(z, x)
        self.eye, self.rows, self.orthographic = list(eye), [x, y, z], orthographic
        if orthographic:
            self.viewport, self.pixel_mm, self.focal_mm = (600, 600), 12.0 / 600.0, 1.0
        else:
            self.viewport, self.pixel_mm = (800, 600), 0.036916077
            self.focal_mm = 600 * self.pixel_mm / (2.0 * math.tan(math.radians(20.0)))

    def xml(self):
        """vcg's text form: the translation vector is minus the viewpoint, the rotation
        matrix row after row."""
        x, y, z = self.rows
        w, h = self.viewport
        num = lambda v: repr(float(v))
        rot = " ".join(num(v) for v in x + [0] + y + [0] + z + [0] + [0, 0, 0, 1])
        tra = " ".join(num(-v) for v in self.eye)
        return (f'<VCGCamera TranslationVector="{tra} 1" RotationMatrix="{rot}" '
                f'CameraType="{int(self.orthographic)}" BinaryData="0" '
                f'FocalMm="{num(self.focal_mm)}" LensDistortion="0 0" '
                f'PixelSizeMm="{num(self.pixel_mm)} {num(self.pixel_mm)}" '
                f'ViewportPx="{w} {h}" CenterPx="{num(w / 2)} {num(h / 2)}"/>')


def xml_escape(s):
    return (s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace('"', "&quot;"))


def wavy_stroke(x0, x1, y, n, amplitude):
    """A polyline from x0 to x1 around height y (vcg pixels, y up) through `n` points,
    waving by up to `amplitude` pixels; x grows, so it never crosses itself. Rounded to 1/4
    pixel: the same numbers in every host and in the CLI's file."""
    out = []
    for i in range(n):
        t = i / (n - 1)
        wave = round(amplitude * math.sin(0.9 * i) * 4.0) / 4.0
        out.append((round((x0 + (x1 - x0) * t) * 4.0) / 4.0, y + wave))
    return out


class CutCase:
    def __init__(self, name, input, camera, stroke, through_all, open, new_layer):
        self.name, self.input, self.camera, self.stroke = name, input, camera, stroke
        self.through_all, self.open, self.new_layer = through_all, open, new_layer

    def stroke_text(self):
        return "; ".join(f"{x!r} {y!r}" for x, y in self.stroke)

    def params(self):
        """pymeshlab's keyword arguments: the view as camera XML (pymeshlab cannot pass a
        shot)."""
        return {
            "view_as_text": self.camera.xml(),
            "stroke": self.stroke_text(),
            "faces_to_cut": "Through all" if self.through_all else "Visible only",
            "open_the_cut": self.open,
            "new_layer": self.new_layer,
        }

    def mlx(self):
        """meshlabserver 2020.09 cannot read a shot from a script (its reader asserts), so the
        script leaves out the first parameter, `view`, and gives the view as camera XML in
        `view_as_text`; every other parameter is given."""
        return ("<!DOCTYPE FilterScript>\n<FilterScript>\n"
                f' <filter name="{CUT}">\n'
                f'  <Param type="RichString" name="view_as_text" '
                f'value="{xml_escape(self.camera.xml())}"/>\n'
                f'  <Param type="RichString" name="stroke" value="{self.stroke_text()}"/>\n'
                f'  <Param type="RichEnum" name="faces_to_cut" value="{int(self.through_all)}" '
                'enum_val0="Visible only" enum_val1="Through all" enum_cardinality="2"/>\n'
                f'  <Param type="RichBool" name="open_the_cut" value="{str(self.open).lower()}"/>\n'
                f'  <Param type="RichBool" name="new_layer" '
                f'value="{str(self.new_layer).lower()}"/>\n'
                " </filter>\n</FilterScript>\n")

    def stroke_json(self, view_proj):
        """The stroke file `katachi cut` reads: the stroke flipped to katachi's pixels (origin
        top-left, y down) and the view-projection matrix the filter reported."""
        h = self.camera.viewport[1]
        return json.dumps({
            "stroke": [[x, h - y] for x, y in self.stroke],
            "view_proj": list(view_proj),
            "viewport": [0, 0, self.camera.viewport[0], h],
            "mode": "through-all" if self.through_all else "visible-only",
            "open": self.open,
        })

    def cli_args(self):
        a = ["--mode", "through-all" if self.through_all else "visible-only"]
        return a + (["--open"] if self.open else [])


def bounding_box(positions):
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]
    return lo, hi


def cut_cases(models, work, kat):
    """The cuts: a grid seen from above (orthographic, opened) and fandisk seen obliquely
    (perspective; visible only in a new layer, through all in place). Also returns the grid
    path, the top camera and the grid's stroke for the bad cuts."""
    grid_path = os.path.join(work, "grid_10.off")
    kat.write(grid(10), grid_path)
    fandisk = rounded_to_f32(kat.read(os.path.join(models, "fandisk.off")))
    fandisk_path = os.path.join(work, "fandisk_f32.off")
    kat.write(fandisk, fandisk_path)
    top = Camera([5.0, 5.0, 10.0], [5.0, 5.0, 0.0], [0.0, 1.0, 0.0], True)
    lo, hi = bounding_box(fandisk.positions)
    centre = [0.5 * (lo[k] + hi[k]) for k in range(3)]
    size = max(hi[k] - lo[k] for k in range(3))
    eye = [centre[0] + 1.2 * size, centre[1] + 0.9 * size, centre[2] + 1.6 * size]
    oblique = Camera(eye, centre, [0.0, 0.0, 1.0], False)
    grid_stroke = wavy_stroke(20.0, 580.0, 300.0, 9, 40.0)
    fandisk_stroke = wavy_stroke(40.0, 760.0, 310.0, 25, 30.0)
    cases = [
        CutCase("cut_grid_ortho_open", grid_path, top, grid_stroke, False, True, True),
        CutCase("cut_fandisk_visible", fandisk_path, oblique, fandisk_stroke, False, False,
                True),
        CutCase("cut_fandisk_through_all_inplace", fandisk_path, oblique, fandisk_stroke,
                True, False, False),
    ]
    crossing = [(100.0, 100.0), (500.0, 500.0), (500.0, 100.0), (100.0, 500.0)]
    bad = [
        # name, case, leave the view out, katachi's message
        (CutCase("cut_self_crossing", grid_path, top, crossing, False, False, True), False,
         "katachi_cut_by_stroke: the stroke crosses itself"),
        (CutCase("cut_no_view", grid_path, top, grid_stroke, False, False, False), True,
         "katachi: the view has no viewport"),
    ]
    return cases, bad


# ---------------------------------------------------------------------------------------
# Comparisons


def _diag(positions):
    lo, hi = bounding_box(positions)
    return max(math.sqrt(sum((hi[k] - lo[k]) ** 2 for k in range(3))), sys.float_info.min)


def _dist(p, q):
    return max(abs(p[k] - q[k]) for k in range(3))


def compare(ml, cli):
    """Checks that MeshLab's result `ml` (triangles) is the CLI's `cli` (polygons):

    1. the same number of vertices, and a one-to-one map from MeshLab's vertices to the
       CLI's with every coordinate within `REL_TOL` x the CLI's diagonal (each MeshLab vertex
       has exactly one CLI vertex that close);
    2. through that map, MeshLab's triangles triangulate the CLI's polygons: every triangle
       lies in exactly one CLI polygon (its corners are that polygon's, in its cyclic order,
       so with its orientation), an n-gon gets n - 2 triangles, and each side of the n-gon is
       a side of one of its triangles.

    Vertex order and where a polygon's corner list starts may differ (MeshLab rebuilds
    polygons from faux edges). Returns a one-line summary; raises AssertionError."""
    if len(ml.positions) != len(cli.positions):
        raise AssertionError(f"{len(ml.positions)} vertices in MeshLab's result, "
                             f"{len(cli.positions)} in the CLI's")
    lo, _ = bounding_box(cli.positions)
    diag = _diag(cli.positions)
    tol = REL_TOL * diag
    cell = lambda p: tuple(math.floor((p[k] - lo[k]) / (2 * tol)) for k in range(3))
    buckets = {}
    for j, q in enumerate(cli.positions):
        buckets.setdefault(cell(q), []).append(j)
    mapping, taken, worst = [None] * len(ml.positions), set(), 0.0
    for i, p in enumerate(ml.positions):
        c = cell(p)
        found = [(j, _dist(p, cli.positions[j]))
                 for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                 for j in buckets.get((c[0] + dx, c[1] + dy, c[2] + dz), ())
                 if _dist(p, cli.positions[j]) <= tol]
        if len(found) != 1:
            raise AssertionError(f"MeshLab vertex {i} at {p} has {len(found)} CLI vertices "
                                 f"within {tol:.3e}, not 1")
        j, d = found[0]
        if j in taken:
            raise AssertionError(f"MeshLab vertex {i} and another both match CLI vertex {j}")
        mapping[i] = j
        taken.add(j)
        worst = max(worst, d)
    around = [[] for _ in cli.positions]
    for f, face in enumerate(cli.faces):
        for v in face:
            around[v].append(f)
    tri_count = [0] * len(cli.faces)
    sides = {}
    for t, tri in enumerate(ml.faces):
        if len(tri) != 3:
            raise AssertionError(f"MeshLab face {t} has {len(tri)} corners, not 3")
        a, b, c = (mapping[v] for v in tri)
        homes = [f for f in around[a] if _in_cyclic_order(cli.faces[f], a, b, c)]
        if len(homes) != 1:
            raise AssertionError(f"MeshLab triangle {t} (CLI vertices {a} {b} {c}) lies in "
                                 f"{len(homes)} CLI polygons, not 1")
        tri_count[homes[0]] += 1
        for s in ((a, b), (b, c), (c, a)):
            sides[s] = sides.get(s, 0) + 1
    for f, face in enumerate(cli.faces):
        if tri_count[f] != len(face) - 2:
            raise AssertionError(f"CLI polygon {f} ({len(face)} corners) is covered by "
                                 f"{tri_count[f]} MeshLab triangles, not {len(face) - 2}")
        for k in range(len(face)):
            s = (face[k], face[(k + 1) % len(face)])
            if sides.get(s, 0) != 1:
                raise AssertionError(f"side {s[0]} -> {s[1]} of CLI polygon {f} is a side "
                                     f"of {sides.get(s, 0)} MeshLab triangles, not 1")
    quads = sum(1 for f in cli.faces if len(f) == 4)
    return (f"{len(ml.positions)} vertices (max deviation {worst / diag:.2e} of the "
            f"diagonal), {len(cli.faces)} polygons ({quads} quads) = {len(ml.faces)} MeshLab "
            "triangles: the CLI's")


def _in_cyclic_order(face, a, b, c):
    try:
        i, j, k = face.index(a), face.index(b), face.index(c)
    except ValueError:
        return False
    n = len(face)
    dj, dk = (j - i) % n, (k - i) % n
    return 0 < dj < dk


def compare_indexed(ml, cli):
    """Checks that MeshLab's cut `ml` is the CLI's `cli` element for element: the filter
    writes katachi's vertices and triangles in katachi's order, so vertex i is within
    `REL_TOL` x the diagonal of CLI vertex i and triangle i has the same corners in the same
    order. (Opening a cut makes coincident vertices, which a match by position alone cannot
    tell apart.)"""
    if len(ml.positions) != len(cli.positions) or len(ml.faces) != len(cli.faces):
        raise AssertionError(f"MeshLab has {len(ml.positions)} vertices and {len(ml.faces)} "
                             f"faces, the CLI {len(cli.positions)} and {len(cli.faces)}")
    diag = _diag(cli.positions)
    worst = 0.0
    for i, (p, q) in enumerate(zip(ml.positions, cli.positions)):
        d = _dist(p, q)
        if not d <= REL_TOL * diag:
            raise AssertionError(f"vertex {i} is at {p} in MeshLab's result, {q} in the CLI's")
        worst = max(worst, d)
    for f, (a, b) in enumerate(zip(ml.faces, cli.faces)):
        if list(a) != list(b):
            raise AssertionError(f"face {f} is {list(a)} in MeshLab's result, {list(b)} in "
                                 "the CLI's")
    return (f"{len(ml.positions)} vertices (max deviation {worst / diag:.2e} of the "
            f"diagonal) and {len(ml.faces)} triangles: the CLI's")


def self_test(run):
    """The comparisons catch what they must (so a pass means something)."""
    cli = Mesh([(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 1, 0), (1, 1, 0), (2, 1, 0)],
               [[0, 1, 4, 3], [1, 2, 5, 4]])
    perm = [5, 3, 1, 0, 2, 4]  # new index of old vertex i
    pos = [None] * 6
    for i, p in enumerate(cli.positions):
        pos[perm[i]] = p
    tris = [[perm[1], perm[4], perm[3]], [perm[1], perm[3], perm[0]],
            [perm[1], perm[2], perm[5]], [perm[1], perm[5], perm[4]]]
    ml = Mesh(pos, tris)

    def fails(mesh, compare_fn=compare, against=cli):
        try:
            compare_fn(mesh, against)
            return False
        except AssertionError:
            return True
    run.check(not fails(ml), "compare: the same mesh, reordered and triangulated, matches")
    moved = Mesh([list(p) for p in pos], tris)
    moved.positions[2][1] += 1e-3
    flipped = Mesh(pos, [list(reversed(tris[0]))] + tris[1:])
    run.check(fails(moved) and fails(flipped) and fails(Mesh(pos, tris[:-1]))
              and fails(Mesh(pos, [tris[0], tris[0]] + tris[2:])),
              "compare: a moved vertex, a flipped, missing or doubled triangle are caught")
    g = grid(2)
    turned = Mesh(g.positions, [list(f) for f in g.faces])
    turned.faces[3] = turned.faces[3][1:] + turned.faces[3][:1]
    shifted = Mesh([list(p) for p in g.positions], g.faces)
    shifted.positions[4][2] += 1e-3
    run.check(not fails(g, compare_indexed, g) and fails(turned, compare_indexed, g)
              and fails(shifted, compare_indexed, g),
              "compare_indexed: equal meshes match; a turned face or a moved vertex is caught")


def run_cli(katachi, args):
    """Runs the katachi CLI; raises with its output on failure."""
    out = subprocess.run([katachi] + [str(a) for a in args], capture_output=True, text=True)
    if out.returncode != 0:
        raise AssertionError(f"katachi {' '.join(map(str, args))} failed "
                             f"({out.returncode}):\n{out.stdout}{out.stderr}")
