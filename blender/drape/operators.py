"""Add ▸ Drape Cloth, Reload, Bake to a point cache, Follow Bone and Bind Pins."""

import os
import struct

import bpy
from bpy_extras.io_utils import ImportHelper
from mathutils import Matrix

from . import cloth, timing
from .native import module as drape


class DRAPE_OT_add_cloth(bpy.types.Operator, ImportHelper):
    """Add a cloth animated live by a Drape scene file (.ron)"""

    bl_idname = "object.drape_add_cloth"
    bl_label = "Drape Cloth"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".ron"
    filter_glob: bpy.props.StringProperty(default="*.ron", options={"HIDDEN"})

    @classmethod
    def poll(cls, context):
        return context.mode == "OBJECT"

    def execute(self, context):
        try:
            obj = cloth.create(context, self.filepath)
        except drape.SceneError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        obj.location = context.scene.cursor.location
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        warning = timing.fps_mismatch(context.scene.render, cloth.load(cloth.scene_file(obj)).fps)
        if warning:
            self.report({"WARNING"}, warning)
        return {"FINISHED"}


class DRAPE_OT_reload(bpy.types.Operator):
    """Read the scene file again (rebuilding the mesh if its grid changed)"""

    bl_idname = "object.drape_reload"
    bl_label = "Reload"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return cloth.is_drape_object(context.object)

    def execute(self, context):
        obj = context.object
        try:
            scene = cloth.load(cloth.scene_file(obj), force=True)
        except drape.SceneError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        cloth.sync_pins(obj, scene)
        if len(obj.data.vertices) != scene.point_count or obj.data.shape_keys is None:
            cloth.rebuild(obj, context.scene)
        else:
            cloth.show_frame(obj, context.scene)
        return {"FINISHED"}


def write_pc2(path, frames, point_count, start_frame):
    """A PC2 point cache: header, then each frame's float32 x, y, z in vertex order."""
    with open(path, "wb") as out:
        out.write(struct.pack("<12siiffi", b"POINTCACHE2\0", 1, point_count, float(start_frame), 1.0, len(frames)))
        for frame in frames:
            out.write(frame.tobytes())


class DRAPE_OT_bake(bpy.types.Operator):
    """Bake the cloth at every frame of the scene's range to a PC2 point cache read by a Mesh Cache modifier.
    The live evaluation is turned off; sub-frames are then interpolated between frames"""

    bl_idname = "object.drape_bake"
    bl_label = "Bake to Point Cache"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return cloth.is_drape_object(context.object) and bool(bpy.data.filepath)

    def execute(self, context):
        obj, bl_scene = context.object, context.scene
        try:
            scene = cloth.load(cloth.scene_file(obj))
        except drape.SceneError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        render = bl_scene.render
        frames = []
        for frame in range(bl_scene.frame_start, bl_scene.frame_end + 1):
            t = timing.drape_seconds(frame, 0.0, obj.drape.time_offset_frames, render.fps, render.fps_base)
            frames.append(scene.evaluate(t, z_up=True))
        path = bpy.path.abspath(f"//drape_cache/{bpy.path.clean_name(obj.name)}.pc2")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_pc2(path, frames, scene.point_count, bl_scene.frame_start)
        modifier = obj.modifiers.get("Drape Cache") or obj.modifiers.new("Drape Cache", "MESH_CACHE")
        modifier.cache_format = "PC2"
        modifier.filepath = bpy.path.relpath(path)
        modifier.frame_start = bl_scene.frame_start
        # The cache holds positions in the object's own axes already.
        modifier.forward_axis, modifier.up_axis = "POS_Y", "POS_Z"
        obj.drape.live = False
        self.report({"INFO"}, f"baked {len(frames)} frames to {path}")
        return {"FINISHED"}


class DRAPE_OT_follow_bone(bpy.types.Operator):
    """Parent the cloth to the Follow object or bone, keeping it where it is: the whole cloth,
    pins included, then rides with it at every frame and sub-frame"""

    bl_idname = "object.drape_follow_bone"
    bl_label = "Follow Bone"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.object
        return cloth.is_drape_object(obj) and obj.drape.follow_target not in (None, obj)

    def execute(self, context):
        obj = context.object
        target, bone = obj.drape.follow_target, obj.drape.follow_bone
        depsgraph = context.evaluated_depsgraph_get()
        evaluated = target.evaluated_get(depsgraph)
        if bone:
            if target.type != "ARMATURE" or bone not in evaluated.pose.bones:
                self.report({"ERROR"}, f"{target.name} has no bone named {bone!r}")
                return {"CANCELLED"}
            pose_bone = evaluated.pose.bones[bone]
            # A bone parent is the bone's tail.
            parent_world = evaluated.matrix_world @ pose_bone.matrix @ Matrix.Translation((0.0, pose_bone.length, 0.0))
        else:
            parent_world = evaluated.matrix_world.copy()
        world = obj.matrix_world.copy()
        obj.parent = target
        obj.parent_type = "BONE" if bone else "OBJECT"
        obj.parent_bone = bone
        obj.matrix_parent_inverse = parent_world.inverted() @ world @ obj.matrix_basis.inverted()
        return {"FINISHED"}


class DRAPE_OT_bind_pins(bpy.types.Operator):
    """Bind each pin that has an object or bone to it where the pin is now, and sample where the
    bone puts it at every key's frame: the keys are relaxed there, and at every other frame and
    sub-frame the pin sits on its bone, read live. The samples live in the .blend, so a farm node
    rendering one frame gets what this machine shows. Sample again after changing the animation
    at a key's frame"""

    bl_idname = "object.drape_bind_pins"
    bl_label = "Bind Pins"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return cloth.is_drape_object(context.object)

    def execute(self, context):
        obj, bl_scene = context.object, context.scene
        try:
            scene = cloth.load(cloth.scene_file(obj))
        except drape.SceneError as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        cloth.sync_pins(obj, scene)
        bound = [pin for pin in obj.drape.pins if pin.target is not None]
        columns = scene.grid[0]
        positions = obj.data.shape_keys.key_blocks[cloth.SHAPE_KEY].data
        depsgraph = context.evaluated_depsgraph_get()
        for pin in bound:
            matrix = cloth.target_matrix(pin, depsgraph)
            if matrix is None:
                self.report({"ERROR"}, f"pin {tuple(pin.grid)}: {pin.target.name} has no bone {pin.bone!r}")
                return {"CANCELLED"}
            # Where the pin is now, on screen, becomes its place on the bone.
            here = obj.matrix_world @ positions[pin.grid[1] * columns + pin.grid[0]].co
            pin.offset = matrix.inverted() @ here
            pin.at_keys.clear()
        frame, subframe = bl_scene.frame_current, bl_scene.frame_subframe
        render = bl_scene.render
        for key_frame in scene.key_frames:
            at = timing.blender_frame(key_frame / scene.fps, obj.drape.time_offset_frames, render.fps, render.fps_base)
            bl_scene.frame_set(at[0], subframe=at[1])
            depsgraph = context.evaluated_depsgraph_get()
            for pin in bound:
                sample = pin.at_keys.add()
                sample.co = cloth.pin_in_object_space(obj, pin, depsgraph)
                sample.sampled = True
        bl_scene.frame_set(frame, subframe=subframe)
        self.report({"INFO"}, f"{len(bound)} pins bound, sampled at {len(scene.key_frames)} keys")
        return {"FINISHED"}


def add_menu(self, context):
    # Add runs its entries without invoking them; this one must open the file browser.
    self.layout.operator_context = "INVOKE_REGION_WIN"
    self.layout.operator(DRAPE_OT_add_cloth.bl_idname, text="Drape Cloth (.ron)", icon="MOD_CLOTH")


classes = (DRAPE_OT_add_cloth, DRAPE_OT_reload, DRAPE_OT_bake, DRAPE_OT_follow_bone, DRAPE_OT_bind_pins)


def register():
    bpy.types.VIEW3D_MT_add.append(add_menu)


def unregister():
    bpy.types.VIEW3D_MT_add.remove(add_menu)
