"""The add-on inside Blender, headless:

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_live.py -- \
        --exports DIR --out DIR

with the add-on on BLENDER_USER_SCRIPTS (or `python blender/tests/test_live.py -- …`
with the `bpy` module and the extension installed), and DIR holding `drape export` OBJs of
the magic carpet's frames 0, 37, 38, 90 and 120 (magic_carpet_NNNN.obj).
Leaves OUT/carpet.blend (at frame 0) and OUT/scrubbed_90.{png,json} for
test_fresh_render.py, which renders frame 90 in a fresh process.
"""

import array
import os
import re
import statistics
import sys
import tempfile
import time
import unittest
from pathlib import Path

import bpy
from mathutils import Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
import common  # noqa: E402

ARGS = common.arguments()
EXPORTS = Path(ARGS["exports"])
OUT = Path(ARGS["out"])

# A 128 × 128 curtain with a sway and a wave: the speed case.
CURTAIN_128 = """(
    version: 1,
    name: "Curtain 128",
    cloth: (size: (2.0, 2.0), grid: (128, 128)),
    timeline: (fps: 24.0, start: 0, end: 120),
    keys: [(frame: 0, pins: [(grid: (0, 0), pos: (-0.9, 2.0, 0.0)), (grid: (127, 0), pos: (0.9, 2.0, 0.0))])],
    layers: [
        Sway((name: "breeze", magnitude: 0.2, direction: (0.0, 0.0, 1.0), frequency: 0.5)),
        Wave((name: "ripple", magnitude: 0.02, frequency: 6.0, speed: 2.0, direction_deg: 90.0)),
    ],
)
"""


def exported(frame):
    return common.obj_positions_z_up(EXPORTS / f"magic_carpet_{frame:04}.obj")


def remove(obj):
    mesh = obj.data
    bpy.data.objects.remove(obj)
    bpy.data.meshes.remove(mesh)


def rising_bone(scene, frames, rise_m):
    """An armature whose bone "hand" rises `rise_m` (its own +Y is world +Z) from frame 0 to `frames`, linearly."""
    armature = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", armature)
    scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    bone = armature.edit_bones.new("hand")
    bone.head, bone.tail = (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    bpy.ops.object.mode_set(mode="OBJECT")
    pose_bone = rig.pose.bones["hand"]
    for frame, rise in ((0, 0.0), (frames, rise_m)):
        pose_bone.location = (0.0, rise, 0.0)
        pose_bone.keyframe_insert("location", frame=frame)
    for curve in rig.animation_data.action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"
    return rig


def bone_through(scene, frames_and_heads):
    """An armature whose bone "hand" has its head at each (frame, world point), moving straight between."""
    armature = bpy.data.armatures.new("Hand rig")
    rig = bpy.data.objects.new("Hand rig", armature)
    scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    bone = armature.edit_bones.new("hand")
    bone.head, bone.tail = (0.0, 0.0, 0.0), (0.0, 0.0, 0.2)
    bpy.ops.object.mode_set(mode="OBJECT")
    pose_bone = rig.pose.bones["hand"]
    for frame, head in frames_and_heads:
        # The rest bone stands at the origin with its +Y along world +Z.
        pose_bone.location = (head.x, head.z, -head.y)
        pose_bone.keyframe_insert("location", frame=frame)
    for curve in rig.animation_data.action.fcurves:
        for point in curve.keyframe_points:
            point.interpolation = "LINEAR"
    return rig


class LiveCloth(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.package = common.enable_addon()
        cls.cloth = cloth = cls.package.cloth
        cls.scene = bpy.context.scene
        result = bpy.ops.object.drape_add_cloth(filepath=str(common.CARPET))
        assert result == {"FINISHED"}, result
        cls.obj = bpy.context.object
        cls.native = cloth.drape.Scene.load(str(common.CARPET))
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def setUp(self):
        self.obj.drape.time_offset_frames = 0.0
        self.scene.render.fps, self.scene.render.fps_base = 24, 1.0

    def test_1_the_add_on_creates_the_carpet_with_drapes_topology(self):
        mesh = self.obj.data
        self.assertEqual(len(mesh.vertices), 21 * 33)
        self.assertEqual(len(mesh.polygons), 20 * 32 * 2)
        self.assertEqual([k.name for k in mesh.shape_keys.key_blocks], ["Basis", "Drape"])
        self.assertEqual(mesh.shape_keys.key_blocks["Drape"].value, 1.0)
        self.assertIn("UVMap", mesh.uv_layers)
        self.assertTrue(self.scene.render.use_lock_interface)
        self.assertEqual(Path(self.obj.drape.scene_path), common.CARPET)
        names = [f.__name__ for f in bpy.app.handlers.frame_change_post]
        self.assertIn("on_frame_change", names)
        corners = array.array("i", bytes(4 * len(mesh.loops)))
        mesh.loops.foreach_get("vertex_index", corners)
        self.assertEqual(list(corners), list(self.native.triangles()))

    def test_2_frames_0_and_120_match_the_command_lines_export(self):
        for frame in (0, 120):
            self.scene.frame_set(frame)
            difference = common.max_difference(common.evaluated_positions(self.obj), exported(frame))
            print(f"frame {frame}: largest difference from drape export {difference:.3g} m")
            self.assertLessEqual(difference, common.TOLERANCE_M, f"frame {frame}")

    def test_3_a_subframe_is_drapes_time_and_lies_between_its_frames(self):
        self.scene.frame_set(37, subframe=0.5)
        ours = common.evaluated_positions(self.obj)
        module = self.native.evaluate(37.5 / self.native.fps, z_up=True)
        self.assertLessEqual(common.max_difference(ours, module), common.TOLERANCE_M)
        before, after = exported(37), exported(38)
        self.assertGreater(common.max_difference(before, after), 1e-3, "the carpet moves between 37 and 38")
        # Each point lies on its way from frame 37 to 38: past the first, short of the
        # second, and off the straight path by under a twentieth of the step.
        for k in range(0, len(ours), 3):
            a, b, c = (Vector(p[k:k + 3]) for p in (before, after, ours))
            step = b - a
            if step.length < 1e-5:
                continue
            along = (c - a).dot(step) / step.length_squared
            off = (c - a - along * step).length / step.length
            self.assertTrue(0.0 < along < 1.0 and off < 0.05, f"point {k // 3}: {along:.3f} along, {off:.3f} off")
        self.assertGreater(common.max_difference(ours, before), 1e-4)
        self.assertGreater(common.max_difference(ours, after), 1e-4)

    def test_4_the_time_offset_and_blenders_fps_map_to_drape_seconds(self):
        self.obj.drape.time_offset_frames = 10
        self.scene.frame_set(47)
        self.assertLessEqual(common.max_difference(common.evaluated_positions(self.obj), exported(37)), 1e-6)
        self.obj.drape.time_offset_frames = 0
        # At 48 fps, Blender's frame 74 is 37/24 s: Drape's frame 37.
        self.scene.render.fps = 48
        self.scene.frame_set(74)
        self.assertLessEqual(common.max_difference(common.evaluated_positions(self.obj), exported(37)), 1e-6)
        warning = self.cloth.timing.fps_mismatch(self.scene.render, self.native.fps)
        self.assertIn("48 fps", warning)
        self.scene.render.fps = 24
        self.assertIsNone(self.cloth.timing.fps_mismatch(self.scene.render, self.native.fps))

    def test_5_errors_show_with_file_line_and_column_and_a_fix_reloads(self):
        folder = Path(self.tmp.name)
        scene_file = folder / "carpet.ron"
        text = common.CARPET.read_text()
        scene_file.write_text(text)
        bpy.ops.object.drape_add_cloth(filepath=str(scene_file))
        obj = bpy.context.object
        self.scene.frame_set(37)
        self.assertIsNone(self.cloth.error_of(obj))
        broken = text.replace("grid: (20, 0)", "grid: (40, 0)", 1)
        scene_file.write_text(broken)
        os.utime(scene_file, ns=(time.time_ns(), time.time_ns() + 10**9))
        self.scene.frame_set(38)
        self.assertRegex(self.cloth.error_of(obj) or "", r"carpet\.ron:\d+:\d+: pin \(40, 0\) is outside")
        # The fix is read at the next frame change, with no reload pressed.
        moved = text.replace("(grid: (20, 0), pos: (0.5, 1.0, 0.0))", "(grid: (20, 0), pos: (0.6, 1.0, 0.0))", 1)
        self.assertNotEqual(moved, text)
        scene_file.write_text(moved)
        os.utime(scene_file, ns=(time.time_ns(), time.time_ns() + 2 * 10**9))
        self.scene.frame_set(0)
        self.assertIsNone(self.cloth.error_of(obj))
        expected = self.cloth.drape.Scene.load(str(scene_file)).evaluate(0.0, z_up=True)
        self.assertLessEqual(common.max_difference(common.evaluated_positions(obj), expected), 1e-6)
        remove(obj)

    def test_6_a_128_by_128_frame_evaluates_in_under_2_ms(self):
        path = Path(self.tmp.name) / "curtain_128.ron"
        path.write_text(CURTAIN_128)
        bpy.ops.object.drape_add_cloth(filepath=str(path))
        obj = bpy.context.object
        native = self.cloth.load(str(path))
        self.assertEqual(native.point_count, 128 * 128)
        buffer = array.array("f", bytes(12 * native.point_count))
        evaluate, whole = [], []
        for frame in range(1, 101):
            start = time.perf_counter()
            native.evaluate_into(frame / 24, buffer, z_up=True)
            evaluate.append(time.perf_counter() - start)
            self.scene.frame_current = frame
            start = time.perf_counter()
            self.cloth.show_frame(obj, self.scene)
            whole.append(time.perf_counter() - start)
        evaluate_ms = 1000 * statistics.median(evaluate)
        whole_ms = 1000 * statistics.median(whole)
        print(
            f"128 × 128 in Blender {bpy.app.version_string}: evaluate_into with the axis conversion "
            f"{evaluate_ms:.2f} ms (median of 100 frames); with the shape key write and mesh.update() {whole_ms:.2f} ms"
        )
        (OUT / "speed.txt").write_text(f"evaluate_into_ms {evaluate_ms:.3f}\nhandler_ms {whole_ms:.3f}\n")
        self.assertLess(evaluate_ms, 2.0)
        remove(obj)

    def test_7_motion_blur_smears_the_cloths_edge(self):
        common.set_up_tiny_cycles(self.scene, self.obj)
        self.scene.frame_set(42)
        self.scene.render.use_motion_blur = False
        common.render_to(self.scene, OUT / "sharp_42.png")
        self.scene.render.use_motion_blur = True
        self.scene.render.motion_blur_shutter = 1.0
        common.render_to(self.scene, OUT / "blurred_42.png")
        self.scene.render.use_motion_blur = False
        sharp, blurred = common.alpha_of(OUT / "sharp_42.png"), common.alpha_of(OUT / "blurred_42.png")
        self.assertGreater(sum(a > 0.5 for a in sharp), 20, "the cloth is in view")
        changed = sum(abs(a - b) > 0.1 for a, b in zip(sharp, blurred))
        partial = [sum(0.05 < a < 0.95 for a in alpha) for alpha in (sharp, blurred)]
        print(f"motion blur: {changed} pixels changed; partly covered pixels {partial[0]} sharp, {partial[1]} blurred")
        self.assertGreater(changed, 10)
        self.assertGreater(partial[1], partial[0])

    def test_8_scrubbing_to_90_for_the_fresh_render(self):
        # A second carpet with its corner pin on an animated bone: the fresh process must
        # relax its keys from the samples kept in the .blend and read the bone at frame 90.
        bpy.ops.object.drape_add_cloth(filepath=str(common.CARPET))
        held = bpy.context.object
        held.name = "Carpet on a hand"
        held.location = (2.0, 0.0, 0.0)
        keys = range(len(self.native.key_frames))
        carried = [Vector(dict(self.native.key_pins(k, z_up=True))[(0, 0)]) + Vector((2.0, 0, 0.02 * k)) for k in keys]
        rig = bone_through(self.scene, list(zip(self.native.key_frames, carried)))
        self.scene.frame_set(0)
        bpy.context.view_layer.objects.active = held
        held.drape.pins[0].target, held.drape.pins[0].bone = rig, "hand"
        self.assertEqual(bpy.ops.object.drape_bind_pins(), {"FINISHED"})
        for frame in (0, 30, 120, 89, 90):
            self.scene.frame_set(frame)
        positions = common.evaluated_positions(self.obj)
        self.assertLessEqual(common.max_difference(positions, exported(90)), common.TOLERANCE_M)
        common.save_positions(OUT / "scrubbed_90.json", self.scene)
        common.render_to(self.scene, OUT / "scrubbed_90.png")
        # The fresh process starts elsewhere and must reach 90 by itself.
        self.scene.frame_set(0)
        self.scene.render.filepath = str(OUT / "fresh_")
        bpy.ops.wm.save_as_mainfile(filepath=str(OUT / "carpet.blend"))

    def test_9_a_cloth_following_an_animated_bone_rides_with_it_at_a_subframe(self):
        bpy.ops.object.drape_add_cloth(filepath=str(common.CARPET))
        obj = bpy.context.object
        rig = rising_bone(self.scene, frames=20, rise_m=2.0)
        self.scene.frame_set(0)
        bpy.context.view_layer.objects.active = obj
        obj.drape.follow_target, obj.drape.follow_bone = rig, "hand"
        self.assertEqual(bpy.ops.object.drape_follow_bone(), {"FINISHED"})
        self.assertEqual((obj.parent, obj.parent_type, obj.parent_bone), (rig, "BONE", "hand"))
        self.scene.frame_set(10, subframe=0.5)
        world = obj.matrix_world
        local = common.evaluated_positions(obj)
        drape_now = self.native.evaluate(10.5 / self.native.fps, z_up=True)
        self.assertLessEqual(common.max_difference(local, drape_now), 1e-6)
        # The pin at grid (0, 0) is Drape's pin where the bone has carried it: 1.05 m up.
        pin = world @ Vector(local[0:3])
        expected = Vector(drape_now[0:3]) + Vector((0.0, 0.0, 2.0 * 10.5 / 20))
        self.assertLess((pin - expected).length, 1e-5, f"{pin} != {expected}")
        bpy.data.objects.remove(rig)
        remove(obj)

    def test_9_a_pin_bound_to_an_animated_bone_sits_on_it_at_a_subframe(self):
        bpy.ops.object.drape_add_cloth(filepath=str(common.CARPET))
        obj = bpy.context.object
        # A hand that carries the corner pin (0, 0) along its path in the file, 2 cm higher
        # at each key than the file has it, moving straight between keys.
        keys = range(len(self.native.key_frames))
        carried = [Vector(dict(self.native.key_pins(k, z_up=True))[(0, 0)]) + Vector((0, 0, 0.02 * k)) for k in keys]
        rig = bone_through(self.scene, list(zip(self.native.key_frames, carried)))
        self.scene.frame_set(0)
        bpy.context.view_layer.objects.active = obj
        self.assertEqual([tuple(pin.grid) for pin in obj.drape.pins], [(0, 0), (20, 0), (0, 32), (20, 32)])
        obj.drape.pins[0].target, obj.drape.pins[0].bone = rig, "hand"
        self.assertEqual(bpy.ops.object.drape_bind_pins(), {"FINISHED"})
        self.assertEqual(self.scene.frame_current, 0)
        for sample, expected in zip(obj.drape.pins[0].at_keys, carried):
            self.assertLess((Vector(sample.co) - expected).length, 1e-5)
        self.scene.frame_set(30, subframe=0.5)
        local = common.evaluated_positions(obj)
        # Between keys 24 and 48 the hand is a quarter of the way plus a 48th.
        now = carried[1].lerp(carried[2], 6.5 / 24)
        self.assertLess((Vector(local[0:3]) - now).length, 1e-5, f"{local[0:3]} != {now}")
        at_keys = [tuple(sample.co) for sample in obj.drape.pins[0].at_keys]
        module = self.native.evaluate(30.5 / 24, z_up=True, pins=[((0, 0), tuple(now), at_keys)])
        self.assertLessEqual(common.max_difference(local, module), 1e-5)
        # The pins left to the scene file stay where its keys put them.
        columns, rows = self.native.grid
        far = 3 * (columns * rows - 1)
        plain = self.native.evaluate(30.5 / 24, z_up=True)
        self.assertLessEqual(common.max_difference(local[far:far + 3], plain[far:far + 3]), 1e-5)
        bpy.data.objects.remove(rig)
        remove(obj)

    def test_9_bake_writes_a_point_cache_that_shows_the_same_frames(self):
        self.assertTrue(bpy.data.filepath, "test_8 saved the file")
        bpy.ops.object.drape_add_cloth(filepath=str(common.CARPET))
        obj = bpy.context.object
        self.scene.frame_start, self.scene.frame_end = 0, 120
        self.assertEqual(bpy.ops.object.drape_bake(), {"FINISHED"})
        self.assertFalse(obj.drape.live)
        self.assertEqual(obj.modifiers["Drape Cache"].type, "MESH_CACHE")
        for frame in (37, 120):
            self.scene.frame_set(frame)
            difference = common.max_difference(common.evaluated_positions(obj), exported(frame))
            self.assertLessEqual(difference, common.TOLERANCE_M, f"frame {frame}")
        remove(obj)

    def test_add_menu_opens_the_file_browser(self):
        calls = []

        class Layout:
            # What Add (VIEW3D_MT_add) sets for its own entries before appended ones draw.
            operator_context = "EXEC_REGION_WIN"

            def operator(self, idname, **_):
                calls.append((idname, self.operator_context))

        self.package.operators.add_menu(type("Menu", (), {"layout": Layout()})(), bpy.context)
        self.assertEqual(calls, [("object.drape_add_cloth", "INVOKE_REGION_WIN")])

    def test_panel_draws_the_settings_and_problems(self):
        handlers, panel = self.package.handlers, self.package.panel

        class Layout:
            """Records what the panel draws; every layout call returns a layout."""

            def __init__(self, drawn):
                self.drawn = drawn

            def __getattr__(self, name):
                def call(*args, **kwargs):
                    self.drawn.append((name, args, kwargs))
                    return Layout(self.drawn)

                return call

        drawn = []
        fake = type("Panel", (), {"layout": Layout(drawn)})()
        bpy.context.view_layer.objects.active = self.obj
        panel.DRAPE_PT_object.draw(fake, bpy.context)
        texts = [kwargs.get("text", "") for _, _, kwargs in drawn]
        self.assertIn("21 × 33 points, frames 0–120 at 24 fps", texts)
        self.assertIn("object.drape_reload", [args[0] for name, args, _ in drawn if name == "operator"])
        # An error's file:line:column stays readable in a narrow panel, however long the path.
        message = "/a/long/folder/of/scenes/that/holds/the/carpet.ron:18:24: pin (40, 0) is outside the 21 × 33 grid"
        lines = panel.problem_lines(message, 30)
        self.assertTrue(all(len(line) <= 30 for line in lines), lines)
        self.assertEqual("".join(lines).replace(" ", ""), message.replace(" ", ""))
        # The file watcher runs without a window too.
        self.assertEqual(handlers._watch(), handlers.WATCH_INTERVAL_S)


if __name__ == "__main__":
    OUT.mkdir(parents=True, exist_ok=True)
    common.run(LiveCloth)
