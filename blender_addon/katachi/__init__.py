"""katachi for Blender: solid-aware Catmull-Clark subdivision and cutting by stroke over the
katachi library.

One source tree serves as a legacy add-on (``bl_info``, Blender 3.4 to 4.1, and later
through Install from Disk) and as an extension (``blender_manifest.toml``, Blender 4.2+).
The library, ``libkatachi.so``, ships beside this file and is called through ctypes
(``ffi.py``); ``convert.py`` moves mesh data in bulk for subdivision and ``cutting.py`` for
the stroke cut, ``stroke.py`` turns drawn strokes, annotations, 3D views and cameras into
katachi's pixels and matrices, ``operators.py`` holds the operators, ``properties.py`` their
settings, and ``ui.py`` the menus and the toolbar tool.
"""

bl_info = {
    "name": "katachi",
    "author": "katachi developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Object > katachi; Edit Mode > Mesh > katachi; Edit Mode toolbar",
    "description": "Solid-aware subdivision (creases, faces with holes, UVs); cut by stroke",
    "doc_url": "",
    "category": "Mesh",
}

import bpy

from . import operators, ui

_classes = operators.classes + ui.classes


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    ui.register_menus()


def unregister():
    ui.unregister_menus()
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
