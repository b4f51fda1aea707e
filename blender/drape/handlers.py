"""When Drape evaluates: at every frame change (sub-frames of motion blur
included), after a file loads, and when a scene file changes on disk.

Inputs are read in frame_change_post, once Blender has evaluated the frame;
the handler never calls depsgraph.update() or view_layer.update().
"""

import bpy
from bpy.app.handlers import persistent

from . import cloth

WATCH_INTERVAL_S = 1.0


@persistent
def on_frame_change(scene, depsgraph=None):
    cloth.show_all(scene, depsgraph)


@persistent
def on_load(*_):
    cloth.forget_all()
    for scene in bpy.data.scenes:
        cloth.show_all(scene)


def _watch():
    """Reloads the scene files that changed on disk and shows them again."""
    if cloth.changed_files():
        for scene in bpy.data.scenes:
            cloth.show_all(scene)
        for window in bpy.context.window_manager.windows:
            for area in window.screen.areas:
                area.tag_redraw()
    return WATCH_INTERVAL_S


def register():
    bpy.app.handlers.frame_change_post.append(on_frame_change)
    bpy.app.handlers.load_post.append(on_load)
    if not bpy.app.background:
        bpy.app.timers.register(_watch, first_interval=WATCH_INTERVAL_S, persistent=True)


def unregister():
    if bpy.app.timers.is_registered(_watch):
        bpy.app.timers.unregister(_watch)
    for handlers, function in (
        (bpy.app.handlers.frame_change_post, on_frame_change),
        (bpy.app.handlers.load_post, on_load),
    ):
        while function in handlers:
            handlers.remove(function)
