"""Builds a skinned, animated character in Blender, exports it with Blender's
own glTF exporter, and writes what Blender shows at several frames, so
tests/references.rs can check that Drape plays the file exactly so.

    blender -b --factory-startup --python blender_rig.py -- OUT_DIR FRAME...

Writes OUT_DIR/rig.glb and OUT_DIR/blender.json: the scene's fps and, per
FRAME, every bone's head and tail and every vertex of the evaluated mesh, in
glTF's axes (Y up: Blender's (x, y, z) is glTF's (x, z, -y)), in metres.

The character: a 12-sided tube 2 m long along Blender's Z, skinned to a
chain of three bones (each vertex shared by at most the two nearest bones,
weights normalised), the bones turned by Bezier keyframes about different
axes, the root bone moved, and a shape key that swells the top, keyed from
0 to 1. Frame 0 is the animation's start.
"""
import json
import math
import sys

import bpy
import bmesh

out_dir = sys.argv[sys.argv.index("--") + 1].rstrip("/")
frames = [int(f) for f in sys.argv[sys.argv.index("--") + 2 :]]

for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
scene = bpy.context.scene
scene.render.fps = 24
scene.frame_start = 0
scene.frame_end = 48

# The tube: rings every 0.1 m from z = 0 to 2.
mesh = bpy.data.meshes.new("tube")
bm = bmesh.new()
rings = []
for r in range(21):
    z = r * 0.1
    rings.append([bm.verts.new((0.2 * math.cos(a * math.tau / 12), 0.2 * math.sin(a * math.tau / 12), z)) for a in range(12)])
for lower, upper in zip(rings, rings[1:]):
    for a in range(12):
        b = (a + 1) % 12
        bm.faces.new((lower[a], lower[b], upper[b], upper[a]))
bm.faces.new(list(reversed(rings[0])))
bm.faces.new(rings[-1])
bm.to_mesh(mesh)
bm.free()
tube = bpy.data.objects.new("tube", mesh)
scene.collection.objects.link(tube)

# Three bones up the tube: 0–0.7, 0.7–1.4, 1.4–2.0.
armature_data = bpy.data.armatures.new("rig")
armature = bpy.data.objects.new("rig", armature_data)
scene.collection.objects.link(armature)
bpy.context.view_layer.objects.active = armature
bpy.ops.object.mode_set(mode="EDIT")
names = ["root", "middle", "top"]
joints = [0.0, 0.7, 1.4, 2.0]
parent = None
for name, head, tail in zip(names, joints, joints[1:]):
    bone = armature_data.edit_bones.new(name)
    bone.head = (0.0, 0.0, head)
    bone.tail = (0.0, 0.0, tail)
    if parent is not None:
        bone.parent = parent
        bone.use_connect = True
    parent = bone
bpy.ops.object.mode_set(mode="OBJECT")

# Weights: each vertex between the middles of the two bones it lies between.
middles = [(h + t) / 2 for h, t in zip(joints, joints[1:])]
groups = [tube.vertex_groups.new(name=name) for name in names]
for vertex in mesh.vertices:
    z = vertex.co.z
    if z <= middles[0]:
        weights = {0: 1.0}
    elif z >= middles[-1]:
        weights = {2: 1.0}
    else:
        k = 0 if z < middles[1] else 1
        s = (z - middles[k]) / (middles[k + 1] - middles[k])
        weights = {k: 1.0 - s, k + 1: s}
    for group, weight in weights.items():
        if weight > 0.0:
            groups[group].add([vertex.index], weight, "REPLACE")
modifier = tube.modifiers.new("rig", "ARMATURE")
modifier.object = armature
tube.parent = armature

# A shape key that swells the top, keyed 0 → 1.
tube.shape_key_add(name="Basis")
swell = tube.shape_key_add(name="swell")
for point, vertex in zip(swell.data, mesh.vertices):
    if vertex.co.z > 1.5:
        point.co = (vertex.co.x * 1.5, vertex.co.y * 1.5, vertex.co.z)
swell.value = 0.0
swell.keyframe_insert("value", frame=0)
swell.value = 1.0
swell.keyframe_insert("value", frame=36)

# Bezier keys: the root slides and turns about Z, the middle bends about X,
# the top about Y.
pose = armature.pose.bones
for bone in pose:
    bone.rotation_mode = "XYZ"
keys = {
    0: {"root": ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)), "middle": (0.0, 0.0, 0.0), "top": (0.0, 0.0, 0.0)},
    16: {"root": ((0.3, 0.0, 0.1), (0.0, 0.0, 40.0)), "middle": (35.0, 0.0, 0.0), "top": (0.0, -25.0, 0.0)},
    40: {"root": ((-0.2, 0.4, 0.0), (0.0, 0.0, -20.0)), "middle": (-20.0, 0.0, 10.0), "top": (0.0, 50.0, 0.0)},
}
for frame, angles in keys.items():
    location, root_rotation = angles["root"]
    pose["root"].location = location
    pose["root"].rotation_euler = [math.radians(a) for a in root_rotation]
    pose["middle"].rotation_euler = [math.radians(a) for a in angles["middle"]]
    pose["top"].rotation_euler = [math.radians(a) for a in angles["top"]]
    pose["root"].keyframe_insert("location", frame=frame)
    for bone in pose:
        bone.keyframe_insert("rotation_euler", frame=frame)

bpy.ops.export_scene.gltf(filepath=out_dir + "/rig.glb", export_format="GLB", export_animations=True, export_morph=True)


def gltf_axes(v):
    return [v[0], v[2], -v[1]]


report = {"fps": scene.render.fps, "frames": []}
for frame in frames:
    scene.frame_set(frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = tube.evaluated_get(depsgraph)
    posed = evaluated.to_mesh()
    vertices = [gltf_axes(evaluated.matrix_world @ v.co) for v in posed.vertices]
    evaluated.to_mesh_clear()
    bones = {
        bone.name: {"head": gltf_axes(armature.matrix_world @ bone.head), "tail": gltf_axes(armature.matrix_world @ bone.tail)}
        for bone in armature.pose.bones
    }
    report["frames"].append({"frame": frame, "vertices": vertices, "bones": bones})
with open(out_dir + "/blender.json", "w") as file:
    json.dump(report, file)
print("wrote", out_dir + "/rig.glb", "and blender.json for frames", frames)
