"""object.drape: which scene file an object shows, and when."""

import bpy

from . import cloth


def _show_again(settings, context):
    obj = settings.id_data
    if cloth.is_drape_object(obj) and settings.live:
        cloth.show_frame(obj, context.scene)


class DrapePinAtKey(bpy.types.PropertyGroup):
    co: bpy.props.FloatVectorProperty(
        name="Position", size=3, subtype="TRANSLATION",
        description="Where the pin's bone put it at this key's frame, in the cloth object's space",
    )
    sampled: bpy.props.BoolProperty(name="Sampled", default=False)


class DrapePin(bpy.types.PropertyGroup):
    """One pin of the scene file, optionally carried by a Blender object or bone."""

    grid: bpy.props.IntVectorProperty(name="Grid", size=2, description="The pin's grid index (i, j)")
    target: bpy.props.PointerProperty(
        name="Object", type=bpy.types.Object,
        description="The object (or armature, with a bone) that carries this pin; empty: the scene file's pin",
    )
    bone: bpy.props.StringProperty(name="Bone", description="The bone of the armature that carries the pin")
    offset: bpy.props.FloatVectorProperty(
        name="Offset", size=3, subtype="TRANSLATION",
        description="The pin in the bone's (or object's) space, set by Bind Pins",
    )
    at_keys: bpy.props.CollectionProperty(type=DrapePinAtKey)


class DrapeObjectSettings(bpy.types.PropertyGroup):
    scene_path: bpy.props.StringProperty(
        name="Scene File",
        description="The Drape scene (.ron) this object shows",
        subtype="FILE_PATH",
        update=_show_again,
    )
    time_offset_frames: bpy.props.FloatProperty(
        name="Time Offset",
        description="Blender frame at which the Drape scene's time 0 plays",
        default=0.0,
        update=_show_again,
    )
    live: bpy.props.BoolProperty(
        name="Live",
        description="Evaluate Drape at every frame change (off: the mesh keeps what it has, e.g. a bake)",
        default=True,
        update=_show_again,
    )
    follow_target: bpy.props.PointerProperty(
        name="Follow",
        description="The object (or armature, with a bone) that Follow Bone parents the cloth to",
        type=bpy.types.Object,
    )
    follow_bone: bpy.props.StringProperty(
        name="Bone",
        description="The bone of the Follow armature that carries the cloth (empty: the object itself)",
    )
    pins: bpy.props.CollectionProperty(type=DrapePin)


classes = (DrapePinAtKey, DrapePin, DrapeObjectSettings)


def register():
    bpy.types.Object.drape = bpy.props.PointerProperty(type=DrapeObjectSettings)


def unregister():
    del bpy.types.Object.drape
