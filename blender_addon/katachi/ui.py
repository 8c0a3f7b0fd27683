"""Where the operators appear: Object ▸ katachi in Object mode, Mesh ▸ katachi in Edit mode,
and Cut by Stroke in the 3D Viewport's toolbar in Edit mode (after the Knife)."""

import bpy

from .operators import (
    KATACHI_OT_cut_by_annotation,
    KATACHI_OT_cut_by_stroke,
    KATACHI_OT_subdivide,
)


class KATACHI_MT_object(bpy.types.Menu):
    bl_idname = "KATACHI_MT_object"
    bl_label = "katachi"

    def draw(self, context):
        layout = self.layout
        layout.operator(KATACHI_OT_subdivide.bl_idname, icon="MOD_SUBSURF")
        layout.separator()
        layout.operator(KATACHI_OT_cut_by_annotation.bl_idname, icon="GREASEPENCIL")


class KATACHI_MT_edit_mesh(bpy.types.Menu):
    bl_idname = "KATACHI_MT_edit_mesh"
    bl_label = "katachi"

    def draw(self, context):
        layout = self.layout
        layout.operator(KATACHI_OT_subdivide.bl_idname, icon="MOD_SUBSURF")
        layout.label(text="Subdivides whole meshes, not only the selection")
        layout.separator()
        # From a menu the tool waits for the first left-button press to start drawing.
        layout.operator_context = "INVOKE_REGION_WIN"
        layout.operator(KATACHI_OT_cut_by_stroke.bl_idname, icon="LINE_DATA")
        layout.operator(KATACHI_OT_cut_by_annotation.bl_idname, icon="GREASEPENCIL")


def _object_menu(self, context):
    self.layout.separator()
    self.layout.menu(KATACHI_MT_object.bl_idname)


def _edit_mesh_menu(self, context):
    self.layout.separator()
    self.layout.menu(KATACHI_MT_edit_mesh.bl_idname)


classes = (KATACHI_MT_object, KATACHI_MT_edit_mesh)

#: (menu, draw function) pairs appended on register and removed on unregister.
MENU_ENTRIES = (
    (bpy.types.VIEW3D_MT_object, _object_menu),
    (bpy.types.VIEW3D_MT_edit_mesh, _edit_mesh_menu),
)


class KATACHI_TL_cut_by_stroke(bpy.types.WorkSpaceTool):
    bl_space_type = "VIEW_3D"
    bl_context_mode = "EDIT_MESH"
    bl_idname = "katachi.cut_by_stroke_tool"
    bl_label = "Cut by Stroke"
    bl_description = (
        "Cut the mesh along a stroke: drag with the left mouse button, release to cut "
        "(katachi, after Mitani and Suzuki)"
    )
    bl_icon = "ops.node.links_cut"
    bl_widget = None
    bl_keymap = (
        (KATACHI_OT_cut_by_stroke.bl_idname, {"type": "LEFTMOUSE", "value": "PRESS"}, None),
    )

    def draw_settings(context, layout, tool):
        props = tool.operator_properties(KATACHI_OT_cut_by_stroke.bl_idname)
        layout.prop(props, "mode")
        layout.prop(props, "open")
        layout.prop(props, "keep_polygons")


#: Whether the toolbar tool got registered (register_tool needs the window manager's key
#: configurations, which a Blender without them, e.g. some background runs, lacks).
_tool_registered = False


def register_menus():
    global _tool_registered
    for menu, fn in MENU_ENTRIES:
        menu.append(fn)
    try:
        bpy.utils.register_tool(
            KATACHI_TL_cut_by_stroke, after={"builtin.knife"}, separator=False, group=False
        )
        _tool_registered = True
    except Exception as e:  # the menu entries still work
        print(f"katachi: the Cut by Stroke tool was not added to the toolbar: {e}")


def unregister_menus():
    global _tool_registered
    if _tool_registered:
        bpy.utils.unregister_tool(KATACHI_TL_cut_by_stroke)
        _tool_registered = False
    for menu, fn in MENU_ENTRIES:
        menu.remove(fn)
