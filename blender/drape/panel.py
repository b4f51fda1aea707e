"""Properties ▸ Object ▸ Drape: the scene file, time offset, reload and problems."""

import textwrap

import bpy

from . import cloth, timing
from .native import module as drape


class DRAPE_PT_object(bpy.types.Panel):
    bl_label = "Drape"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "MESH"

    def draw(self, context):
        layout = self.layout
        width = _characters_across(context)
        obj = context.object
        settings = obj.drape
        layout.prop(settings, "scene_path")
        if not settings.scene_path:
            layout.label(text="Not a Drape cloth: Add ▸ Drape Cloth makes one")
            return
        row = layout.row(align=True)
        row.prop(settings, "time_offset_frames")
        row.operator("object.drape_reload", text="", icon="FILE_REFRESH")
        layout.prop(settings, "live")
        try:
            scene = cloth.load(cloth.scene_file(obj))
        except drape.SceneError as error:
            _problem(layout, str(error), width)
            return
        columns, rows = scene.grid
        start, end = scene.frame_range
        layout.label(text=f"{columns} × {rows} points, frames {start}–{end} at {scene.fps:g} fps")
        warning = timing.fps_mismatch(context.scene.render, scene.fps)
        if warning:
            _problem(layout, warning, width, icon="INFO")
        error = cloth.error_of(obj)
        if error:
            _problem(layout, error, width)
        layout.operator("object.drape_bake")
        box = layout.box()
        box.prop(settings, "follow_target")
        target = settings.follow_target
        if target is not None and target.type == "ARMATURE":
            box.prop_search(settings, "follow_bone", target.data, "bones")
        box.operator("object.drape_follow_bone")
        box = layout.box()
        box.label(text="Pins on Blender's character")
        for pin in settings.pins:
            row = box.row(align=True)
            row.label(text=f"pin ({pin.grid[0]}, {pin.grid[1]})")
            row.prop(pin, "target", text="")
            if pin.target is not None and pin.target.type == "ARMATURE":
                row.prop_search(pin, "bone", pin.target.data, "bones", text="")
            if pin.target is not None and len(pin.at_keys) != len(scene.key_frames):
                row.label(text="", icon="ERROR")
        if any(pin.target is not None and len(pin.at_keys) != len(scene.key_frames) for pin in settings.pins):
            _problem(box, "Pins marked with a warning follow their bones once bound: press Bind Pins", width, icon="INFO")
        box.operator("object.drape_bind_pins")


def _characters_across(context):
    """About how many characters a label in this panel shows before Blender elides it."""
    region = getattr(context, "region", None)
    if region is None:
        return 60
    scale = context.preferences.system.ui_scale
    return max(20, int((region.width - 60 * scale) / (7 * scale)))


def problem_lines(text, width):
    """The message in lines of at most `width` characters; a long path is broken too, since
    Blender elides a label's middle, where an error's file:line:column sits."""
    return textwrap.wrap(text, width, break_on_hyphens=False) or [""]


def _problem(layout, text, width, icon="ERROR"):
    box = layout.box()
    for k, line in enumerate(problem_lines(text, width)):
        box.label(text=line, icon=icon if k == 0 else "BLANK1")


classes = (DRAPE_PT_object,)
