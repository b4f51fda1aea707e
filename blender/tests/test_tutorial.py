"""The cape tutorial of docs/blender.md, headless: the walker imported with Blender's own
glTF importer and made cyclic, the bundled cape added at the origin, and the cape's seam
riding on Blender's chest bone at frames and sub-frames of both walk cycles.

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_tutorial.py

(or `python blender/tests/test_tutorial.py` with the `bpy` module), with the add-on
installed as for test_live.py.
"""

import sys
import unittest
from pathlib import Path

import bpy
from mathutils import Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
import common  # noqa: E402

CAPE = common.ROOT / "scenes" / "cape.ron"
WALKER = common.ROOT / "assets" / "walker.glb"
SEAM = [(0, 0), (4, 0), (9, 0), (14, 0), (18, 0)]


def allow_numpy_bool():
    """What the docs' startup script does for Debian's Blender 3.4, whose glTF importer
    still uses `numpy.bool`, removed in numpy 1.24 (it was the builtin bool)."""
    import numpy

    if "bool" not in vars(numpy):
        numpy.bool = bool


class CapeOnTheWalker(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        package = common.enable_addon()
        scene = cls.scene = bpy.context.scene
        # Step 1: 24 fps, frames 0–48.
        scene.render.fps, scene.render.fps_base = 24, 1.0
        scene.frame_start, scene.frame_end = 0, 48
        # Step 2: the walker, with the walk repeated as Make Cyclic does (a Cycles modifier per curve).
        allow_numpy_bool()
        assert bpy.ops.import_scene.gltf(filepath=str(WALKER)) == {"FINISHED"}
        cls.rig = next(o for o in bpy.data.objects if o.type == "ARMATURE")
        action = cls.rig.animation_data.action
        for curve in action.fcurves:
            curve.modifiers.new("CYCLES")
        action.update_tag()
        # Step 3: the cape at the 3D cursor, at the origin.
        scene.cursor.location = (0.0, 0.0, 0.0)
        assert bpy.ops.object.drape_add_cloth(filepath=str(CAPE)) == {"FINISHED"}
        cls.cape = bpy.context.object
        cls.native = package.cloth.load(str(CAPE))

    def chest(self):
        return self.rig.matrix_world @ self.rig.pose.bones["chest"].matrix

    def test_the_walk_imports_at_drapes_frames_and_repeats(self):
        self.assertEqual(tuple(self.rig.animation_data.action.frame_range), (0.0, 24.0))
        heights = []
        for frame in (6.5, 30.5):
            self.scene.frame_set(int(frame), subframe=frame % 1)
            heights.append(self.chest().translation.z)
        self.assertLess(heights[0], 1.29, "the chest bobs down mid-stride")
        self.assertAlmostEqual(heights[0], heights[1], places=6)

    def test_the_seam_rides_on_blenders_chest_bone_at_every_frame_and_subframe(self):
        self.scene.frame_set(0)
        chest_at_0 = self.chest()
        seam_at_0 = [self.cape.matrix_world @ Vector(p) for p in self.seam()]
        worst = 0.0
        for frame, subframe in ((3, 0.0), (6, 0.5), (12, 0.0), (18, 0.25), (30, 0.5), (37, 0.5), (47, 0.75)):
            self.scene.frame_set(frame, subframe=subframe)
            carried = self.chest() @ chest_at_0.inverted()
            for (i, j), now, then in zip(SEAM, self.seam(), seam_at_0):
                distance = ((carried @ then) - self.cape.matrix_world @ Vector(now)).length
                worst = max(worst, distance)
                self.assertLess(distance, common.TOLERANCE_M, f"pin ({i}, {j}) at {frame + subframe}")
            # The whole cape is Drape's frame for that time.
            drape_now = self.native.evaluate((frame + subframe) / self.native.fps, z_up=True)
            self.assertLessEqual(common.max_difference(common.evaluated_positions(self.cape), drape_now), common.TOLERANCE_M)
        print(f"cape seam: largest distance from where Blender's chest bone carries it {worst:.3g} m")

    def seam(self):
        positions = common.evaluated_positions(self.cape)
        columns, _ = self.native.grid
        return [positions[3 * (j * columns + i):3 * (j * columns + i) + 3] for i, j in SEAM]


if __name__ == "__main__":
    common.run(CapeOnTheWalker)
