"""Where the operators appear: Object ▸ katachi in Object mode, Mesh ▸ katachi in Edit mode."""

import bpy

from .operators import KATACHI_OT_subdivide


class KATACHI_MT_object(bpy.types.Menu):
    bl_idname = "KATACHI_MT_object"
    bl_label = "katachi"

    def draw(self, context):
        self.layout.operator(KATACHI_OT_subdivide.bl_idname, icon="MOD_SUBSURF")


class KATACHI_MT_edit_mesh(bpy.types.Menu):
    bl_idname = "KATACHI_MT_edit_mesh"
    bl_label = "katachi"

    def draw(self, context):
        layout = self.layout
        layout.operator(KATACHI_OT_subdivide.bl_idname, icon="MOD_SUBSURF")
        layout.label(text="Subdivides whole meshes, not only the selection")


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


def register_menus():
    for menu, fn in MENU_ENTRIES:
        menu.append(fn)


def unregister_menus():
    for menu, fn in MENU_ENTRIES:
        menu.remove(fn)
