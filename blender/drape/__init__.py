"""Drape inside Blender: a live cloth that Blender evaluates at any frame and
sub-frame, with no bake. The same folder is a legacy add-on for Blender
3.4–4.1 and a Blender 4.2+ extension (blender_manifest.toml)."""

# Blender lists legacy add-ons by reading this file from the first line that
# starts with `bl_info`: no line above the dict may start with that word.

bl_info = {
    "name": "Drape",
    "description": "Live fake-dynamics cloth from a Drape scene file (.ron)",
    "author": "Drape developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D ▸ Add ▸ Drape Cloth; Properties ▸ Object ▸ Drape",
    "category": "Animation",
}

import bpy  # noqa: E402

from . import handlers, operators, panel, properties  # noqa: E402

_modules = (properties, operators, panel, handlers)


def register():
    for module in _modules:
        for cls in getattr(module, "classes", ()):
            bpy.utils.register_class(cls)
        if hasattr(module, "register"):
            module.register()


def unregister():
    for module in reversed(_modules):
        if hasattr(module, "unregister"):
            module.unregister()
        for cls in reversed(getattr(module, "classes", ())):
            bpy.utils.unregister_class(cls)
