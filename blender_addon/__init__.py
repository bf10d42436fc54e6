"""uvflat Unwrap: unwraps the selected faces with the uvflat parameterization library.

A Blender 4.2+ extension (``blender_manifest.toml``) that also loads as a legacy add-on
(``bl_info``). It adds "uvflat Unwrap" (``uv.uvflat_unwrap``) to the UV menu of the 3D Viewport
in Edit Mode and to the UV Editor's UV > Unwrap menu; see ``unwrap.py`` for what it does and ``README.md`` for building and installing.
"""

bl_info = {
    "name": "uvflat Unwrap",
    "author": "uvflat developers",
    "version": (0, 1, 0),
    "blender": (4, 2, 0),
    "location": "3D Viewport > Edit Mode > UV > uvflat Unwrap; UV Editor > UV > Unwrap > uvflat Unwrap",
    "description": "Unwrap selected faces with uvflat (natural conformal, mean value, intrinsic, Tutte, ...)",
    "category": "UV",
}

if "unwrap" in locals():  # reloading (F3 > Reload Scripts): pick up edited modules
    import importlib

    importlib.reload(islands)  # noqa: F821
    importlib.reload(unwrap)  # noqa: F821

import bpy

from . import islands, unwrap


def register() -> None:
    for cls in unwrap.classes:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_uv_map.append(unwrap.menu_func)
    bpy.types.IMAGE_MT_uvs_unwrap.append(unwrap.menu_func)


def unregister() -> None:
    bpy.types.IMAGE_MT_uvs_unwrap.remove(unwrap.menu_func)
    bpy.types.VIEW3D_MT_uv_map.remove(unwrap.menu_func)
    for cls in reversed(unwrap.classes):
        bpy.utils.unregister_class(cls)
