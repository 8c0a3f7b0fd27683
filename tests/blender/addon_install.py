"""Installs the add-on's zip into the running Blender as a user would."""

import os
import sys

import bpy


def install(zip_path):
    """Installs and enables the add-on from its zip; returns the installed module.

    Blender 4.2 and later: as an extension (Preferences ▸ Get Extensions ▸ Install from
    Disk, into the "user_default" repository). Blender 3.4: as a legacy add-on
    (Preferences ▸ Add-ons ▸ Install…, then enable)."""
    if not os.path.isfile(zip_path):
        raise RuntimeError(f"the add-on zip {zip_path} does not exist")
    if bpy.app.version >= (4, 2, 0):
        result = bpy.ops.extensions.package_install_files(
            filepath=zip_path, repo="user_default", enable_on_install=True
        )
        module = "bl_ext.user_default.katachi"
    else:
        result = bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
        if result != {"FINISHED"}:
            raise RuntimeError(f"addon_install returned {result}")
        result = bpy.ops.preferences.addon_enable(module="katachi")
        module = "katachi"
    if result != {"FINISHED"}:
        raise RuntimeError(f"installing {zip_path} returned {result}")
    if module not in sys.modules:
        raise RuntimeError(f"after installing, module {module} is not loaded")
    return sys.modules[module]
