"""Loads Drape's PC2, MDD and glTF exports in Blender the way the README says
and compares Blender's mesh at several frames with Drape's OBJ of the same
frame, imported the same way. Exits 1 when any vertex is off by 1e-5 m.

    blender -b --factory-startup --python check_blender.py -- DIR NAME FPS FRAME...

DIR holds NAME.obj (the base mesh), NAME.pc2, NAME.mdd, NAME.glb and
seq/NAME_FFFF.obj for each FRAME; the export's first frame is 0.
"""
import sys

import bpy

directory, name, fps = sys.argv[sys.argv.index("--") + 1 :][:3]
frames = [int(f) for f in sys.argv[sys.argv.index("--") + 4 :]]
directory = directory.rstrip("/") + "/"


def clear():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)


def import_obj(path):
    before = set(bpy.data.objects)
    # The importer's defaults: Forward -Z, Up Y.
    bpy.ops.wm.obj_import(filepath=path, forward_axis="NEGATIVE_Z", up_axis="Y")
    return [o for o in bpy.data.objects if o not in before][0]


def evaluated(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    co = [ev.matrix_world @ v.co for v in mesh.vertices]
    ev.to_mesh_clear()
    return co


def reference(frame):
    obj = import_obj(directory + "seq/%s_%04d.obj" % (name, frame))
    co = evaluated(obj)
    bpy.data.objects.remove(obj)
    return co


def compare(label, co, ref):
    if len(co) != len(ref):
        print(f"{label}: {len(co)} vertices, expected {len(ref)}")
        return float("inf")
    worst = max((a - b).length for a, b in zip(co, ref))
    print(f"{label}: {len(co)} vertices, largest difference {worst:.2e} m")
    return worst


scene = bpy.context.scene
scene.render.fps = int(float(fps))
worst = 0.0
for cache_format in ["PC2", "MDD"]:
    clear()
    obj = import_obj(directory + name + ".obj")
    modifier = obj.modifiers.new("cache", "MESH_CACHE")
    modifier.cache_format = cache_format
    modifier.filepath = directory + name + "." + cache_format.lower()
    modifier.time_mode = "FRAME"
    modifier.play_mode = "SCENE"
    modifier.frame_start = 0
    modifier.frame_scale = 1
    # The modifier's own defaults: they put the cache on the OBJ imported as above.
    modifier.forward_axis = "POS_Y"
    modifier.up_axis = "POS_Z"
    for frame in frames:
        scene.frame_set(frame)
        worst = max(worst, compare(f"{cache_format} frame {frame}", evaluated(obj), reference(frame)))

clear()
# Debian's Blender 3.4 glTF add-on still uses numpy.bool, which numpy 1.24 removed.
import numpy

if not hasattr(numpy, "bool"):
    numpy.bool = bool
bpy.ops.import_scene.gltf(filepath=directory + name + ".glb")
obj = [o for o in bpy.data.objects if o.type == "MESH"][0]
keys = obj.data.shape_keys
action = keys.animation_data.action
print(f"glTF: {len(keys.key_blocks) - 1} shape keys, action over frames {tuple(action.frame_range)}")
for frame in frames:
    scene.frame_set(frame)
    worst = max(worst, compare(f"glTF frame {frame}", evaluated(obj), reference(frame)))

print(f"largest difference over all: {worst:.2e} m")
sys.exit(0 if worst < 1e-5 else 1)
