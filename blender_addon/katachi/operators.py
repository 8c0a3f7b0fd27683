"""The add-on's operators: what runs when a menu entry is chosen.

An operator gathers the meshes, hands them to katachi (``convert``, ``cutting``), and only
when every one of them has its result built does it touch the scene: either all of the
objects are changed or, on any error, none is and the error is reported with katachi's
message.

- ``katachi.subdivide``: solid-aware Catmull-Clark subdivision.
- ``katachi.cut_by_stroke``: the Cut by Stroke tool. Invoked from a 3D Viewport it is
  modal: drag with the left mouse button to draw, release (or Enter) to cut, Esc or the
  right mouse button to cancel; the stroke is drawn over the viewport meanwhile. The drawn
  stroke and the view are kept in the operator's properties, so the redo panel (and a
  script) can run the same cut again with other settings.
- ``katachi.cut_by_annotation``: the same cut along the active annotation stroke, seen
  through the 3D Viewport or a camera; needs no window, so scripts and tests use it.
"""

import contextlib

import bmesh
import bpy
from bpy.props import (
    CollectionProperty,
    EnumProperty,
    FloatVectorProperty,
    IntProperty,
    StringProperty,
)

from . import convert, cutting, ffi, stroke
from .properties import (
    CUT_VIEWS,
    UV_VALUES,
    CutProperties,
    KATACHI_PG_stroke_point,
    SubdivideProperties,
)


class KATACHI_OT_subdivide(SubdivideProperties, bpy.types.Operator):
    """Catmull-Clark subdivision by katachi: creases, faces with holes (a Boolean's output), UV maps and materials follow"""

    bl_idname = "katachi.subdivide"
    bl_label = "Subdivide (solid-aware)"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        if context.mode == "EDIT_MESH":
            return True
        return context.mode == "OBJECT" and bool(context.selected_objects)

    def draw(self, context):
        self.draw_properties(self.layout)

    def execute(self, context):
        edit = context.mode == "EDIT_MESH"
        objects = list(context.objects_in_mode if edit else context.selected_objects)
        found = _mesh_groups(self, objects, "no mesh object is selected")
        if found is None:
            return {"CANCELLED"}
        groups, targets, skipped = found
        lib = _load(self)
        if lib is None:
            return {"CANCELLED"}

        wm = context.window_manager
        wm.progress_begin(0, 100 * len(groups))
        created = {}
        done = False
        warnings = []
        faces_before = faces_after = 0
        try:
            for n, (key, (mesh, objs)) in enumerate(groups.items()):
                obj = objs[0]
                where = obj.name

                def progress(fraction, base=100 * n):
                    wm.progress_update(base + int(100 * fraction))

                with _readable(mesh, obj, edit) as source:
                    try:
                        data = convert.InputMesh(source)
                        options = self.katachi_options(lib)
                        result = convert.subdivide(
                            lib, data, options, UV_VALUES[self.uv_smooth], progress
                        )
                        created[key] = convert.to_blender(result, source, mesh.name)
                    except (ffi.KatachiError, convert.ConversionError) as e:
                        self.report({"ERROR"}, f"katachi: {where}: {e}")
                        return {"CANCELLED"}
                faces_before += data.face_count
                faces_after += len(created[key].polygons)
                if data.loose_edge_count:
                    warnings.append(
                        f"{where}: {data.loose_edge_count} loose edges (in no face) were dropped"
                    )
                warnings.extend(f"{where}: {w}" for w in result.warnings)
                for face, why in result.fallback:
                    warnings.append(
                        f"{where}: face {face} could not be bridged ({why}); method [b] was used"
                    )
                progress(1.0)
            done = True
        finally:
            wm.progress_end()
            if not done:  # an error: the results built so far are thrown away
                for new in created.values():
                    bpy.data.meshes.remove(new)

        # Every result is built: now, and only now, the objects change.
        for key, (mesh, objs) in groups.items():
            _replace_mesh(mesh, objs, created[key], edit)

        for w in warnings:
            self.report({"WARNING"}, f"katachi: {w}")
        _report_skipped(self, skipped)
        self.report(
            {"INFO"},
            f"katachi: subdivided {len(targets)} object(s), {faces_before} -> {faces_after} faces",
        )
        return {"FINISHED"}


def _mesh_groups(op, objects, none_message):
    """The mesh objects among ``objects``, grouped by mesh (objects sharing one mesh are
    changed once): ``(groups, targets, skipped)`` with ``groups`` {mesh pointer: (mesh,
    objects)}, or None after reporting why nothing can be changed (``none_message``: no
    mesh object among them)."""
    targets = [o for o in objects if o.type == "MESH"]
    skipped = [o for o in objects if o.type != "MESH"]
    if not targets:
        names = ", ".join(f"{o.name} ({o.type.lower()})" for o in skipped) or "nothing"
        op.report({"ERROR"}, f"katachi: {none_message} (selected: {names})")
        return None
    for o in targets:
        if o.library is not None or o.data.library is not None:
            op.report(
                {"ERROR"},
                f"katachi: {o.name}: its mesh is linked from a library and cannot be changed",
            )
            return None
    groups = {}
    for o in targets:
        groups.setdefault(o.data.as_pointer(), (o.data, []))[1].append(o)
    return groups, targets, skipped


def _load(op):
    """The katachi library, or None after reporting why it cannot be loaded."""
    try:
        return ffi.load()
    except ffi.KatachiError as e:
        op.report({"ERROR"}, f"katachi: {e}")
        return None


@contextlib.contextmanager
def _readable(mesh, obj, edit):
    """``mesh`` to read from. In Edit mode the edits are flushed to the mesh and read from a
    copy (Blender hides a mesh's UV data while it is being edited), removed afterwards."""
    if not edit:
        yield mesh
        return
    obj.update_from_editmode()
    source = mesh.copy()
    try:
        yield source
    finally:
        bpy.data.meshes.remove(source)


def _replace_mesh(mesh, objs, new, edit):
    """Puts the built mesh ``new`` in the place of ``mesh``: its content into the edited mesh
    in Edit mode (``new`` is removed), else as the mesh of ``objs`` (taking the name of
    ``mesh`` when nothing else uses that)."""
    if edit:
        bm = bmesh.from_edit_mesh(mesh)
        bm.clear()
        bm.from_mesh(new)
        bmesh.update_edit_mesh(mesh)
        bpy.data.meshes.remove(new)
        return
    for o in objs:
        o.data = new
    if mesh.users == 0:
        name = mesh.name
        bpy.data.meshes.remove(mesh)
        new.name = name


def _report_skipped(op, skipped):
    if skipped:
        op.report(
            {"WARNING"},
            "katachi: skipped objects that are not meshes: " + ", ".join(o.name for o in skipped),
        )


def _cut_targets(op, context):
    """The mesh objects to cut: those in Edit mode, or the selected ones (the active first)
    in Object mode; ``(edit, groups, skipped)`` with ``groups`` {mesh pointer: (mesh,
    objects)}, or None after reporting why there is nothing to cut."""
    edit = context.mode == "EDIT_MESH"
    if edit:
        objects = list(context.objects_in_mode)
    else:
        objects = list(context.selected_objects)
        active = context.active_object
        if active is not None and active in objects:  # the active object first
            objects.remove(active)
            objects.insert(0, active)
        if not objects and active is not None:
            objects = [active]
    found = _mesh_groups(op, objects, "no mesh object to cut")
    if found is None:
        return None
    groups, _, skipped = found
    return edit, groups, skipped


def run_cut(op, context, pixels, view):
    """Cuts the target meshes along ``pixels`` (katachi pixels, flat) seen through ``view``
    (a :class:`stroke.View`) with ``op``'s settings; all or nothing."""
    found = _cut_targets(op, context)
    if found is None:
        return {"CANCELLED"}
    edit, groups, skipped = found
    lib = _load(op)
    if lib is None:
        return {"CANCELLED"}
    options = op.cut_options(lib)

    created = {}  # mesh pointer -> (new mesh, result, object, faces before, kept faces)
    nothing = []
    done = False
    try:
        for key, (mesh, objs) in groups.items():
            obj = objs[0]
            with _readable(mesh, obj, edit) as source:
                try:
                    src = cutting.CutSource(source, obj.vertex_groups)
                    view_proj, viewport = view.for_object(obj.matrix_world)
                    res = cutting.cut(
                        lib, src, pixels, view_proj, viewport, options, op.keep_polygons
                    )
                    if res.info.path_count == 0:
                        nothing.append((obj, res))
                        continue
                    new, kept = cutting.to_blender(src, res, source, mesh.name)
                    created[key] = (new, res, obj, src.face_count, kept)
                except (ffi.KatachiError, convert.ConversionError) as e:
                    op.report({"ERROR"}, f"katachi: {obj.name}: {e}")
                    return {"CANCELLED"}
        done = True
    finally:
        if not done:  # an error: the results built so far are thrown away
            for new, *_ in created.values():
                bpy.data.meshes.remove(new)

    for obj, res in nothing:
        op.report(
            {"WARNING"},
            f"katachi: {obj.name}: the stroke crossed no face that could be cut; nothing "
            f"changed ({cutting.describe(res, obj.matrix_world)})",
        )
    if not created:
        return {"CANCELLED"}

    # Every result is built: now, and only now, the objects change.
    for key, (new, res, obj, before, kept) in created.items():
        _replace_mesh(*groups[key], new, edit)
    if edit:
        # The cut's edges are selected: show them when only faces are being selected.
        ts = context.tool_settings
        if tuple(ts.mesh_select_mode) == (False, False, True):
            ts.mesh_select_mode = (False, True, False)
    for key, (new, res, obj, before, kept) in created.items():
        after = len(obj.data.polygons) if not edit else len(bmesh.from_edit_mesh(obj.data).faces)
        for w in cutting.warnings(res):
            op.report({"WARNING"}, f"katachi: {obj.name}: {w}")
        op.report(
            {"INFO"},
            f"katachi: {obj.name}: {before} -> {after} faces; "
            f"{cutting.describe(res, obj.matrix_world)}",
        )
    _report_skipped(op, skipped)
    return {"FINISHED"}


def _cut_poll(context):
    if context.mode == "EDIT_MESH":
        return True
    return context.mode == "OBJECT" and context.active_object is not None


class KATACHI_OT_cut_by_stroke(CutProperties, bpy.types.Operator):
    """Cut the mesh along a stroke drawn over the 3D Viewport (katachi, after Mitani and Suzuki): drag to draw, release or Enter to cut, Esc to cancel"""

    bl_idname = "katachi.cut_by_stroke"
    bl_label = "Cut by Stroke"
    bl_options = {"REGISTER", "UNDO"}

    stroke: CollectionProperty(
        type=KATACHI_PG_stroke_point,
        name="Stroke",
        description="The stroke, in pixels from the view's top-left corner, y down",
        options={"HIDDEN", "SKIP_SAVE"},
    )
    view_matrix: FloatVectorProperty(
        name="View Matrix",
        description="The view-projection matrix the stroke was drawn through (world space, "
        "row after row); all zeros: the 3D Viewport the operator runs in",
        size=16, default=(0.0,) * 16, options={"HIDDEN", "SKIP_SAVE"},
    )
    view_size: FloatVectorProperty(
        name="View Size",
        description="Width and height in pixels of the view the stroke was drawn over",
        size=2, default=(0.0, 0.0), options={"HIDDEN", "SKIP_SAVE"},
    )

    @classmethod
    def poll(cls, context):
        return _cut_poll(context)

    def draw(self, context):
        self.draw_cut_properties(self.layout)

    def execute(self, context):
        pixels = [c for p in self.stroke for c in p.co]
        try:
            if self.view_size[0] > 0 and self.view_size[1] > 0:
                view = stroke.stored_view(self.view_matrix, self.view_size)
            else:
                view = stroke.context_view(context)
        except stroke.StrokeError as e:
            self.report({"ERROR"}, f"katachi: {e}")
            return {"CANCELLED"}
        return run_cut(self, context, pixels, view)

    # ---- the modal tool

    def invoke(self, context, event):
        if context.area is None or context.area.type != "VIEW_3D" or context.region is None:
            self.report({"ERROR"}, "katachi: Cut by Stroke is drawn in a 3D Viewport")
            return {"CANCELLED"}
        if context.region.type != "WINDOW" or context.region_data is None:
            self.report({"ERROR"}, "katachi: draw the stroke in the 3D Viewport's main region")
            return {"CANCELLED"}
        self._points = []  # region coordinates, y up
        self._drawing = False
        self._area = context.area
        self._region = context.region
        self._handle = bpy.types.SpaceView3D.draw_handler_add(
            _draw_stroke, (self,), "WINDOW", "POST_PIXEL"
        )
        context.window_manager.modal_handler_add(self)
        self._hint(context, True)
        if event.type == "LEFTMOUSE" and event.value == "PRESS":  # the tool's click
            self._drawing = True
            self._add(event)
        return {"RUNNING_MODAL"}

    def _hint(self, context, on):
        text = (
            "Cut by Stroke: drag with the left mouse button to draw; release or Enter: cut; "
            "Esc or right mouse button: cancel"
        )
        self._area.header_text_set(text if on else None)
        workspace = context.workspace
        if workspace is not None and hasattr(workspace, "status_text_set"):
            workspace.status_text_set(text if on else None)

    def _add(self, event):
        p = (event.mouse_region_x, event.mouse_region_y)
        if not self._points or self._points[-1] != p:
            self._points.append(p)

    def _end(self, context):
        bpy.types.SpaceView3D.draw_handler_remove(self._handle, "WINDOW")
        self._handle = None
        self._hint(context, False)
        self._area.tag_redraw()

    def modal(self, context, event):
        self._area.tag_redraw()
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            self._end(context)
            return {"CANCELLED"}
        if event.type == "LEFTMOUSE":
            if event.value == "PRESS":
                self._points = []
                self._drawing = True
                self._add(event)
            elif event.value == "RELEASE" and self._drawing:
                self._add(event)
                return self._finish(context)
            return {"RUNNING_MODAL"}
        if event.type in {"RET", "NUMPAD_ENTER"} and event.value == "PRESS":
            return self._finish(context)
        if event.type in {"MOUSEMOVE", "INBETWEEN_MOUSEMOVE"}:
            if self._drawing:
                self._add(event)
            return {"RUNNING_MODAL"}
        if not self._drawing and event.type in _NAVIGATION:
            return {"PASS_THROUGH"}  # look around before drawing
        return {"RUNNING_MODAL"}

    def _finish(self, context):
        self._end(context)
        region = self._region
        rv3d = self._area.spaces.active.region_3d
        self.stroke.clear()
        flat = stroke.region_pixels(self._points, region.height)
        for i in range(0, len(flat), 2):
            self.stroke.add().co = (flat[i], flat[i + 1])
        self.view_matrix = stroke.region_view(region, rv3d).row_major()
        self.view_size = (region.width, region.height)
        return self.execute(context)


_NAVIGATION = {
    "MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "TRACKPADPAN", "TRACKPADZOOM",
    "NDOF_MOTION", "NUMPAD_0", "NUMPAD_1", "NUMPAD_2", "NUMPAD_3", "NUMPAD_4", "NUMPAD_5",
    "NUMPAD_6", "NUMPAD_7", "NUMPAD_8", "NUMPAD_9", "NUMPAD_PERIOD",
}


def _shader():
    """The built-in flat-colour shader: ``UNIFORM_COLOR`` (Blender 3.4+ and 4.x/5.x), else
    ``2D_UNIFORM_COLOR`` (the older name, removed in 4.0)."""
    import gpu

    for name in ("UNIFORM_COLOR", "2D_UNIFORM_COLOR"):
        try:
            return gpu.shader.from_builtin(name)
        except (ValueError, TypeError):
            continue
    return None


def _draw_stroke(op):
    """Draws the stroke being drawn over the viewport (a ``POST_PIXEL`` draw handler)."""
    import gpu
    from gpu_extras.batch import batch_for_shader

    points = op._points
    if len(points) < 2 or bpy.context.region != op._region:
        return
    shader = _shader()
    if shader is None:
        return
    batch = batch_for_shader(shader, "LINE_STRIP", {"pos": [(x, y) for x, y in points]})
    gpu.state.blend_set("ALPHA")
    try:
        gpu.state.line_width_set(2.0)
    except Exception:  # wide lines are not on every GPU backend
        pass
    shader.bind()
    shader.uniform_float("color", (1.0, 0.55, 0.1, 0.9))
    batch.draw(shader)
    gpu.state.line_width_set(1.0)
    gpu.state.blend_set("NONE")


class KATACHI_OT_cut_by_annotation(CutProperties, bpy.types.Operator):
    """Cut the mesh along the active annotation stroke (the last one drawn), seen through the 3D Viewport or a camera (katachi)"""

    bl_idname = "katachi.cut_by_annotation"
    bl_label = "Cut by Annotation"
    bl_options = {"REGISTER", "UNDO"}

    view: EnumProperty(
        name="View", description="Through which view the stroke is cut",
        items=CUT_VIEWS, default="VIEW",
    )
    camera: StringProperty(
        name="Camera", description="The camera object to cut through (empty: the scene camera)",
        default="",
    )
    stroke_index: IntProperty(
        name="Stroke",
        description="Which stroke of the active annotation layer's current frame "
        "(-1: the last one drawn)",
        default=-1,
    )

    @classmethod
    def poll(cls, context):
        return _cut_poll(context)

    def draw(self, context):
        layout = self.layout
        self.draw_cut_properties(layout)
        layout.prop(self, "view")
        row = layout.row()
        row.active = self.view == "CAMERA"
        row.prop_search(self, "camera", context.scene, "objects")
        layout.prop(self, "stroke_index")

    def execute(self, context):
        try:
            if self.view == "CAMERA":
                view = stroke.camera_view(context, self.camera)
            else:
                view = stroke.context_view(context)
            points, space, what = stroke.annotation_stroke(context.scene, self.stroke_index)
            pixels = stroke.annotation_pixels(points, space, view, what)
        except stroke.StrokeError as e:
            self.report({"ERROR"}, f"katachi: {e}")
            return {"CANCELLED"}
        return run_cut(self, context, pixels, view)


classes = (
    KATACHI_PG_stroke_point,
    KATACHI_OT_subdivide,
    KATACHI_OT_cut_by_stroke,
    KATACHI_OT_cut_by_annotation,
)
