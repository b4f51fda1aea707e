"""Blender's cloth on the round table, the tool an animator would use instead
of Drape: a square tablecloth dropped flat onto a round table, simulated
frame by frame, headless.

    blender -b --factory-startup -P tablecloth_drop.py -- --grid 64 --frames 100

The scene is `round_table_64.ron`'s (Drape is Y-up, Blender Z-up): a
1.6 m cloth on `grid × grid` points 6 cm above a 4 cm round top of radius
0.5 m at 0.72 m (its centre), a 5 cm leg, a floor. Cloth at Blender's
defaults (cotton-like) with quality 5 (steps per frame) and collision on;
the top, the leg and the floor collide at 3 mm (Drape's default
thickness); no self-collision (Drape's drop needs none either). Prints one
line, `blender grid G frames F simulate_s S last_frame_move_mm M …`: the
simulation time (scene building excluded), how far the cloth's farthest
point moved in the last frame (still moving, or at rest), its highest and
lowest point and how many points ended inside the top.
"""

import argparse
import sys
import time

import bpy


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--grid", type=int, default=64, help="points a side")
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--quality", type=int, default=5)
    return parser.parse_args(argv)


def collider(obj, thickness_m):
    obj.modifiers.new("Collision", "COLLISION")
    obj.collision.thickness_outer = thickness_m


def build(grid, quality, frames):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.frame_start = 1
    scene.frame_end = frames
    thickness_m = 0.003

    bpy.ops.mesh.primitive_cylinder_add(vertices=64, radius=0.5, depth=0.04, location=(0.0, 0.0, 0.72))
    collider(bpy.context.object, thickness_m)
    bpy.ops.mesh.primitive_cylinder_add(vertices=32, radius=0.05, depth=0.7, location=(0.0, 0.0, 0.35))
    collider(bpy.context.object, thickness_m)
    bpy.ops.mesh.primitive_plane_add(size=10.0, location=(0.0, 0.0, 0.0))
    collider(bpy.context.object, thickness_m)

    # Blender's grid counts cuts or points depending on its version: ask for
    # points, then check.
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=grid, y_subdivisions=grid, size=1.6, location=(0.0, 0.0, 0.8))
    cloth = bpy.context.object
    if len(cloth.data.vertices) != grid * grid:
        bpy.ops.object.delete()
        bpy.ops.mesh.primitive_grid_add(
            x_subdivisions=grid - 1, y_subdivisions=grid - 1, size=1.6, location=(0.0, 0.0, 0.8)
        )
        cloth = bpy.context.object
    if len(cloth.data.vertices) != grid * grid:
        raise SystemExit(f"a {grid} × {grid} grid came out with {len(cloth.data.vertices)} points")
    modifier = cloth.modifiers.new("Cloth", "CLOTH")
    modifier.settings.quality = quality
    modifier.collision_settings.use_collision = True
    modifier.collision_settings.distance_min = thickness_m
    modifier.point_cache.frame_start = 1
    modifier.point_cache.frame_end = frames
    return scene, cloth


def positions(cloth):
    evaluated = cloth.evaluated_get(bpy.context.evaluated_depsgraph_get())
    return [v.co.copy() for v in evaluated.data.vertices]


def main():
    args = arguments()
    scene, cloth = build(args.grid, args.quality, args.frames)
    scene.frame_set(1)
    began = time.perf_counter()
    for frame in range(2, args.frames):
        scene.frame_set(frame)
    before = positions(cloth)
    scene.frame_set(args.frames)
    simulate_s = time.perf_counter() - began
    after = positions(cloth)
    move_mm = max((a - b).length for a, b in zip(after, before)) * 1e3
    world = [cloth.matrix_world @ p for p in after]
    # Points inside the top (within its radius, between its faces).
    inside = sum(1 for p in world if p.x * p.x + p.y * p.y < 0.5 * 0.5 and 0.70 < p.z < 0.74)
    print(
        f"blender grid {args.grid} frames {args.frames} simulate_s {simulate_s:.2f} "
        f"last_frame_move_mm {move_mm:.2f} highest_m {max(p.z for p in world):.4f} "
        f"lowest_m {min(p.z for p in world):.4f} inside_top {inside}",
        flush=True,
    )


main()
