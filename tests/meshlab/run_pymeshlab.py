"""The MeshLab plugin in MeshLab 2025.07, as pymeshlab 2025.7 runs it.

    python run_pymeshlab.py --plugin libfilter_katachi.so --katachi CLI --lib libkatachi.so \
        --models DIR --work DIR [-k NAME]

Run by `cargo xtask meshlab-plugin --test` with the venv's Python (pymeshlab==2025.7.post1
from PyPI). `pymeshlab.load_plugin` loads the plugin the way a user does; then each filter
runs through `MeshSet.apply_filter` with pymeshlab's own names (the dialog's words) and is
compared with the katachi CLI (cases.py), every bad input must raise pymeshlab's exception
with katachi's message and leave the layers as they were, and the process must live to
print the closing `N passed, M failed`.

License: MIT OR Apache-2.0.
"""

import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(os.path.dirname(HERE), "python")]

import numpy as np  # noqa: E402  (pymeshlab's own dependency)
import pymeshlab  # noqa: E402

import cases  # noqa: E402
from katachi_mesh import Katachi, Mesh  # noqa: E402

SUBDIVIDE = "katachi_solid_aware_subdivision"
CUT = "katachi_cut_by_polyline"


#: Every MeshSet the tests make, kept alive to the end. pymeshlab 2025.7 has a use-after-free:
#: after a filter fails (an MLException, from any plugin: MeshLab's own
#: compute_selection_by_condition_per_vertex with a bad expression does it too), the next
#: load_new_mesh in any MeshSet logs into the failed MeshSet's log, freed memory once that
#: MeshSet is gone (valgrind: libio_base's open, GLLogStream::log into a block freed with the
#: MeshSet; then malloc aborts). Not the plugin's doing.
_meshsets = []


def new_meshset():
    ms = pymeshlab.MeshSet()
    _meshsets.append(ms)
    return ms


def python_name(label):
    """pymeshlab's spelling of a name (MeshLab 2022+'s rule, from its documentation)."""
    out = label.lower().replace(" ", "_").replace("/", "_").replace("-", "_")
    return "".join(c for c in out if c not in "().,'\":+")


def layer_state(ms):
    """Everything observable about the MeshSet: its layers, which is current, and each
    layer's vertices (bit patterns, so NaN equals itself), faces and selections."""
    state = [ms.mesh_number(), ms.current_mesh_id()]
    for i in range(ms.mesh_number()):  # ids 0..n-1: the tests delete no layer
        m = ms.mesh(i)
        state.append((m.vertex_number(), m.face_number(),
                      m.vertex_matrix().tobytes(), m.face_matrix().tobytes(),
                      m.vertex_selection_array().tobytes(), m.face_selection_array().tobytes()))
    return state


def result_mesh(ms):
    m = ms.current_mesh()
    return Mesh([tuple(p) for p in m.vertex_matrix().tolist()],
                [list(f) for f in m.face_matrix().tolist()])


def main():
    ap = argparse.ArgumentParser()
    for a in ("--plugin", "--katachi", "--lib", "--models", "--work"):
        ap.add_argument(a, required=True)
    ap.add_argument("-k")
    args = ap.parse_args()
    run = cases.Run("pymeshlab", args.k)
    kat = Katachi(args.lib)
    work = args.work

    run.case("self_test", lambda: cases.self_test(run))

    # Loading, names and parameters.
    def load():
        pymeshlab.load_plugin(args.plugin)
        names = pymeshlab.filter_list()
        run.check(SUBDIVIDE in names and CUT in names,
                  f"load_plugin: the filters are {SUBDIVIDE} and {CUT} (from the menu names "
                  f"'{cases.SUBDIVIDE}' and '{cases.CUT}')")
        run.check(python_name(cases.SUBDIVIDE) == SUBDIVIDE
                  and python_name(cases.CUT) == CUT,
                  "the pymeshlab names are the menu names as pymeshlab spells them")
    load()  # always: every case needs it
    if run.failed:
        run.finish()

    def parameters():
        # print_filter_parameter_list prints name : type = default per parameter.
        expected = {
            SUBDIVIDE: ["levels", "faces_with_holes", "recover_faces_with_holes",
                        "feature_angle_degrees", "boundary", "new_layer"],
            CUT: ["view", "view_as_text", "stroke", "faces_to_cut", "open_the_cut",
                  "new_layer"],
        }
        labels = {
            "levels": "Levels", "faces_with_holes": "Faces with holes",
            "recover_faces_with_holes": "Recover faces with holes",
            "feature_angle_degrees": "Feature angle (degrees)", "boundary": "Boundary",
            "new_layer": "New layer", "view": "View", "view_as_text": "View as text",
            "stroke": "Stroke", "faces_to_cut": "Faces to cut",
            "open_the_cut": "Open the cut",
        }
        for name, params in expected.items():
            r, w = os.pipe()
            saved = os.dup(1)
            sys.stdout.flush()
            os.dup2(w, 1)
            try:
                pymeshlab.print_filter_parameter_list(name)
                sys.stdout.flush()
            finally:
                os.dup2(saved, 1)
                os.close(w)
            text = os.fdopen(r).read()
            found = [line.strip().split(" ")[0] for line in text.splitlines()
                     if line.startswith("\t")]
            run.check(found == params, f"{name}: parameters {found}, expected {params}")
            run.check(all(python_name(labels[p]) == p for p in params),
                      f"{name}: each parameter is named after its label in the dialog")
    run.case("parameters", parameters)

    models = args.models
    for name, path, opts in cases.subdivision_cases(models, work, kat, "obj"):
        run.case(name, lambda name=name, path=path, opts=opts:
                 subdivision(run, args, kat, name, path, opts))
    tet = cases.BAD_SUBDIVISIONS[-1][1]
    for name, mesh, opts, message in cases.BAD_SUBDIVISIONS + [
            # The harness's other bad subdivisions (plugin_harness.cpp, 2020.09).
            ("levels_0", tet, {"levels": 0}, "levels is 0"),
            ("feature_angle_200", tet, {"feature_angle": 200.0},
             "option feature angle: 200 degrees")]:
        run.case(name, lambda name=name, mesh=mesh, opts=opts, message=message:
                 bad_subdivision(run, args, name, mesh, opts, message))

    def empty_layer():
        # The plugin declares that its filters need faces (MM_FACENUMBER): pymeshlab refuses
        # a layer without any before the filter runs, as MeshLab greys the menu entry out.
        ms = new_meshset()
        ms.add_mesh(pymeshlab.Mesh(np.array(tet[0], dtype=np.float64)), "points")
        for f in (SUBDIVIDE, CUT):
            refused(run, f"empty_layer {f}", ms, lambda f=f: ms.apply_filter(f),
                    "does not have Any Faces", by="pymeshlab")
    run.case("empty_layer", empty_layer)
    cut_cases, bad_cuts = cases.cut_cases(models, work, kat)
    for case in cut_cases:
        run.case(case.name, lambda case=case: cut(run, args, kat, case))
    for case, no_view, message in bad_cuts:
        run.case(case.name, lambda case=case, no_view=no_view, message=message:
                 bad_cut(run, case, no_view, message))
    # The harness's other bad cuts (plugin_harness.cpp runs them in 2020.09), here in 2025.07.
    grid_case = bad_cuts[1][0]
    for name, change, mesh, message in more_bad_cuts(grid_case):
        run.case(name, lambda name=name, change=change, mesh=mesh, message=message:
                 refused_cut(run, name, grid_case, change, mesh, message))
    run.finish()


def more_bad_cuts(case):
    """(name, parameter changes, mesh or None for the grid, katachi's message)."""
    n = 10
    g = cases.grid(n)
    nan_vertex = [list(p) for p in g.positions]
    nan_vertex[3][2] = float("nan")
    # A fin on the edge (2, 2)-(3, 2), which the stroke crosses: three faces share it.
    fin = (g.positions + [(2.5, 2.0, 1.0)],
           g.faces + [[2 * (n + 1) + 2, 2 * (n + 1) + 3, len(g.positions)]])
    xml = case.camera.xml()
    return [
        ("cut_one_point", {"stroke": "100 100"}, None, "the stroke has 1 point"),
        ("cut_empty_stroke", {"stroke": ""}, None, "the stroke has 0 point"),
        ("cut_nan_in_stroke", {"stroke": "100 100; nan 200; 300 300"}, None,
         "stroke point 1"),
        ("cut_odd_count", {"stroke": "100 100 200"}, None, "odd count"),
        ("cut_bad_view_text", {"view_as_text": "<VCGCamera/>"}, None, "TranslationVector"),
        ("cut_lens_distortion",  # distortion counts for a perspective camera
         {"view_as_text": xml.replace('LensDistortion="0 0"', 'LensDistortion="0.01 0"')
          .replace('CameraType="1"', 'CameraType="0"')}, None, "lens distortion"),
        ("cut_camera_type_7",
         {"view_as_text": xml.replace('CameraType="1"', 'CameraType="7"')}, None,
         "CameraType is 7"),
        ("cut_nan_vertex", {}, (nan_vertex, g.faces), "vertex 3"),
        # The top view has 50 pixels a unit, (5, 5) at the centre: x = 175 is X = 2.5.
        ("cut_non_manifold_edge", {"stroke": "175 100; 176 200"}, fin, "is non-manifold"),
    ]


def refused_cut(run, name, case, change, mesh, message):
    ms = new_meshset()
    if mesh is None:
        ms.load_new_mesh(case.input)
    else:
        ms.add_mesh(pymeshlab.Mesh(np.array(mesh[0], dtype=np.float64),
                                   np.array(mesh[1], dtype=np.int32)), name)
    params = dict(case.params(), **change)
    refused(run, name, ms, lambda: ms.apply_filter(CUT, **params), message)


def subdivision(run, args, kat, name, path, opts):
    ms = new_meshset()
    ms.load_new_mesh(path)
    before = layer_state(ms)
    out = ms.apply_filter(SUBDIVIDE, **opts.params())
    layers = ms.mesh_number()
    run.check(layers == (2 if opts.new_layer else 1),
              f"{name}: {layers} layer(s) after the filter")
    if opts.new_layer:
        ms.set_current_mesh(0)
        run.check(layer_state(ms)[2:3] == before[2:3],
                  f"{name}: the input layer is unchanged")
        ms.set_current_mesh(1)
    ml = result_mesh(ms)
    run.check(out.get("triangle_count") == len(ml.faces)
              and out.get("vertex_count") == len(ml.positions),
              f"{name}: apply_filter returns the counts {out}")
    cli_out = os.path.join(args.work, f"{name}_cli.off")
    cases.run_cli(args.katachi, ["subdivide", path, cli_out] + opts.cli_args())
    cli = kat.read(cli_out)
    run.check(out.get("face_count") == len(cli.faces),
              f"{name}: {out.get('face_count')} polygons, the CLI's {len(cli.faces)}")
    try:
        report = cases.compare(ml, cli)
        run.check(True, f"{name}: {report}")
    except AssertionError as e:
        run.check(False, f"{name}: pymeshlab's result differs from the CLI's: {e}")


def refused(run, name, ms, apply, message, by="katachi"):
    """`apply()` must raise pymeshlab's exception with katachi's `message` (or, with
    `by="pymeshlab"`, pymeshlab's own), and leave the MeshSet as it was."""
    before = layer_state(ms)
    try:
        apply()
        run.check(False, f"{name}: the filter succeeded; it must fail with `{message}`")
        return
    except pymeshlab.PyMeshLabException as e:
        text = str(e)
        run.check(message in text and (by != "katachi" or "Details: katachi" in text),
                  f"{name}: refused with {by}'s message `{message}` ({text!r})")
    run.check(layer_state(ms) == before, f"{name}: the layers are unchanged")


def bad_subdivision(run, args, name, mesh, opts, message):
    # Built in memory: pymeshlab's file readers drop such faces and vertices.
    positions, faces = mesh
    ms = new_meshset()
    ms.add_mesh(pymeshlab.Mesh(np.array(positions, dtype=np.float64),
                               np.array(faces, dtype=np.int32)), name)
    run.check(ms.current_mesh().face_number() == len(faces),
              f"{name}: the bad mesh reaches the layer as it is")
    params = cases.Subdivision.of(opts).params()
    refused(run, name, ms, lambda: ms.apply_filter(SUBDIVIDE, **params), message)


def cut(run, args, kat, case):
    name = case.name
    ms = new_meshset()
    ms.load_new_mesh(case.input)
    faces_in = ms.current_mesh().face_number()
    before = layer_state(ms)
    out = ms.apply_filter(CUT, **case.params())
    run.check(ms.mesh_number() == (2 if case.new_layer else 1),
              f"{name}: {ms.mesh_number()} layer(s) after the filter")
    if case.new_layer:
        ms.set_current_mesh(0)
        run.check(layer_state(ms)[2:3] == before[2:3], f"{name}: the input layer is unchanged")
        ms.set_current_mesh(1)
    ml = result_mesh(ms)
    w, h = case.camera.viewport
    view_proj = out.get("view_proj")
    run.check(view_proj is not None and len(view_proj) == 16
              and list(out.get("viewport", [])) == [0, 0, w, h],
              f"{name}: apply_filter returns the view ({w} x {h} pixels) and its matrix")
    run.check(len(ml.faces) > faces_in and out.get("new_face_count", 0) > 0,
              f"{name}: {faces_in} -> {len(ml.faces)} triangles")
    selected = int(np.count_nonzero(ms.current_mesh().vertex_selection_array()))
    run.check(selected == out.get("selected_vertex_count") and selected > 0,
              f"{name}: the {selected} vertices along the cut are selected")
    stroke = os.path.join(args.work, f"{name}_stroke.json")
    with open(stroke, "w") as f:
        f.write(case.stroke_json(view_proj))
    cli_out = os.path.join(args.work, f"{name}_cli.off")
    cases.run_cli(args.katachi, ["cut", case.input, cli_out, "--stroke", stroke]
                  + case.cli_args())
    try:
        report = cases.compare_indexed(ml, kat.read(cli_out))
        run.check(True, f"{name}: {report}")
    except AssertionError as e:
        run.check(False, f"{name}: pymeshlab's result differs from the CLI's: {e}")


def bad_cut(run, case, no_view, message):
    ms = new_meshset()
    ms.load_new_mesh(case.input)
    params = case.params()
    if no_view:
        del params["view_as_text"]
    refused(run, case.name, ms, lambda: ms.apply_filter(CUT, **params), message)


if __name__ == "__main__":
    main()
