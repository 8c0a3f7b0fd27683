"""The add-on's operators: what runs when a menu entry is chosen.

An operator gathers the meshes, hands them to katachi (``convert``), and only when every
one of them has its result built does it touch the scene: either all selected objects are
subdivided or, on any error, none is changed and the error is reported with katachi's
message.
"""

import bmesh
import bpy

from . import convert, ffi
from .properties import UV_VALUES, SubdivideProperties


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
        targets = [o for o in objects if o.type == "MESH"]
        skipped = [o for o in objects if o.type != "MESH"]
        if not targets:
            names = ", ".join(f"{o.name} ({o.type.lower()})" for o in skipped) or "nothing"
            self.report({"ERROR"}, f"katachi: no mesh object is selected (selected: {names})")
            return {"CANCELLED"}
        for o in targets:
            if o.library is not None or o.data.library is not None:
                self.report(
                    {"ERROR"},
                    f"katachi: {o.name}: its mesh is linked from a library and cannot be changed",
                )
                return {"CANCELLED"}

        # Objects sharing one mesh are subdivided once.
        groups = {}
        for o in targets:
            groups.setdefault(o.data.as_pointer(), (o.data, []))[1].append(o)

        try:
            lib = ffi.load()
        except ffi.KatachiError as e:
            self.report({"ERROR"}, f"katachi: {e}")
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

                # In Edit mode the edits are flushed to the mesh and read from a copy (Blender
                # hides a mesh's UV data while it is being edited).
                source = mesh
                if edit:
                    obj.update_from_editmode()
                    source = mesh.copy()
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
                finally:
                    if source is not mesh:
                        bpy.data.meshes.remove(source)
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
            new = created[key]
            if edit:
                bm = bmesh.from_edit_mesh(mesh)
                bm.clear()
                bm.from_mesh(new)
                bmesh.update_edit_mesh(mesh)
                bpy.data.meshes.remove(new)
                continue
            for o in objs:
                o.data = new
            if mesh.users == 0:
                name = mesh.name
                bpy.data.meshes.remove(mesh)
                new.name = name

        for w in warnings:
            self.report({"WARNING"}, f"katachi: {w}")
        if skipped:
            self.report(
                {"WARNING"},
                "katachi: skipped objects that are not meshes: "
                + ", ".join(o.name for o in skipped),
            )
        self.report(
            {"INFO"},
            f"katachi: subdivided {len(targets)} object(s), {faces_before} -> {faces_after} faces",
        )
        return {"FINISHED"}


classes = (KATACHI_OT_subdivide,)
