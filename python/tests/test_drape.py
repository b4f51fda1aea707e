"""The `drape` Python module against the command line's exports.

Run from the repository root with the wheel installed and the release binary
built: `python -m unittest discover -s python/tests -v` (DRAPE_BIN names
another binary). Plain unittest: no third-party package is needed.
"""

import array
import os
import re
import struct
import subprocess
import tempfile
import threading
import unittest
from pathlib import Path

import drape

ROOT = Path(__file__).resolve().parents[2]
DRAPE_BIN = Path(os.environ.get("DRAPE_BIN", ROOT / "target" / "release" / "drape"))
CARPET = ROOT / "scenes" / "magic_carpet.ron"
TOLERANCE_M = 1e-6


def export(scene: Path, out: Path, *args: str) -> None:
    subprocess.run([str(DRAPE_BIN), "export", str(scene), "-o", str(out), *args], check=True,
                   stdout=subprocess.DEVNULL)


def read_obj(path: Path):
    """Positions (flat), UVs (flat, OBJ's v) and 0-based triangle corners of an OBJ export."""
    positions, uvs, corners = [], [], []
    for line in path.read_text().splitlines():
        tag, *rest = line.split()
        if tag == "v":
            positions += [float(x) for x in rest]
        elif tag == "vt":
            uvs += [float(x) for x in rest]
        elif tag == "f":
            corners += [int(corner.split("/")[0]) - 1 for corner in rest]
    return positions, uvs, corners


def read_pc2(path: Path):
    """PC2 frames as flat float lists."""
    data = path.read_bytes()
    _, _, points, _, _, samples = struct.unpack_from("<12sii ffi", data, 0)
    frame_floats = points * 3
    body = struct.unpack_from(f"<{samples * frame_floats}f", data, 32)
    return [body[i * frame_floats:(i + 1) * frame_floats] for i in range(samples)]


def max_difference(a, b) -> float:
    assert len(a) == len(b), (len(a), len(b))
    return max(abs(x - y) for x, y in zip(a, b))


class SceneTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.scene = drape.Scene.load(str(CARPET))
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = Path(cls.tmp.name)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_the_scene_reads_as_the_file_says(self):
        s = self.scene
        self.assertEqual(s.grid, (21, 33))
        self.assertEqual(s.point_count, 21 * 33)
        self.assertEqual(s.fps, 24.0)
        self.assertEqual(s.frame_range, (0, 120))
        self.assertEqual(s.name, "Magic carpet")
        self.assertEqual(Path(s.path), CARPET)
        self.assertIn("magic_carpet.ron", repr(s))
        self.assertTrue(drape.__version__)

    def test_errors_carry_file_line_and_column(self):
        bad = ROOT / "tests" / "data" / "malformed" / "pin_outside_grid.ron"
        with self.assertRaises(drape.SceneError) as caught:
            drape.Scene.load(str(bad))
        self.assertRegex(str(caught.exception), r"pin_outside_grid\.ron:\d+:\d+: pin \(40, 3\) is outside")
        with self.assertRaises(drape.SceneError) as caught:
            drape.Scene.load(str(self.out / "absent.ron"))
        self.assertIn("absent.ron", str(caught.exception))
        self.assertTrue(issubclass(drape.SceneError, Exception))

    def test_topology_and_uvs_match_the_obj_export(self):
        obj = self.out / "topology.obj"
        export(CARPET, obj, "--frame", "0")
        _, uvs, corners = read_obj(obj)
        self.assertEqual(list(self.scene.triangles()), corners)
        ours = self.scene.uvs()
        self.assertEqual(len(ours), 2 * self.scene.point_count)
        # Drape's v = 0 is the top edge; OBJ (and Blender) count v upwards.
        flipped = [value if k % 2 == 0 else 1.0 - value for k, value in enumerate(ours)]
        self.assertLess(max_difference(flipped, uvs), 1e-7)

    def test_frames_match_the_obj_export(self):
        for frame in (0, 37, 120):
            obj = self.out / f"frame_{frame}.obj"
            export(CARPET, obj, "--frame", str(frame))
            positions, _, _ = read_obj(obj)
            ours = self.scene.evaluate(frame / self.scene.fps)
            self.assertLess(max_difference(ours, positions), TOLERANCE_M, f"frame {frame}")

    def test_every_frame_matches_the_point_cache_in_any_order(self):
        pc2 = self.out / "carpet.pc2"
        export(CARPET, pc2, "--frames", "0..120")
        frames = read_pc2(pc2)
        self.assertEqual(len(frames), 121)
        # Backwards: no frame depends on the one before.
        for frame in reversed(range(121)):
            ours = self.scene.evaluate(frame / self.scene.fps)
            self.assertLess(max_difference(ours, frames[frame]), TOLERANCE_M, f"frame {frame}")

    def test_z_up_is_drape_rotated_about_x(self):
        t = 37.5 / self.scene.fps
        y_up = self.scene.evaluate(t)
        z_up = self.scene.evaluate(t, z_up=True)
        for k in range(0, len(y_up), 3):
            x, y, z = y_up[k:k + 3]
            self.assertEqual(tuple(z_up[k:k + 3]), (x, -z, y))
        self.assertEqual(drape.z_up_from_y_up((1.0, 2.0, 3.0)), (1.0, -3.0, 2.0))
        self.assertEqual(drape.y_up_from_z_up((1.0, -3.0, 2.0)), (1.0, 2.0, 3.0))

    def test_evaluate_into_fills_any_float32_buffer(self):
        t = 10 / self.scene.fps
        expected = self.scene.evaluate(t, z_up=True)
        target = array.array("f", bytes(4 * 3 * self.scene.point_count))
        self.scene.evaluate_into(t, target, z_up=True)
        self.assertEqual(target, expected)
        raw = bytearray(4 * 3 * self.scene.point_count)
        self.scene.evaluate_into(t, memoryview(raw).cast("f"), z_up=True)
        self.assertEqual(array.array("f", bytes(raw)), expected)

    def test_evaluate_into_refuses_wrong_buffers_with_clear_messages(self):
        n = 3 * self.scene.point_count
        with self.assertRaisesRegex(ValueError, rf"needs {n}"):
            self.scene.evaluate_into(0.0, array.array("f", bytes(4 * (n - 3))))
        with self.assertRaisesRegex(TypeError, "float32"):
            self.scene.evaluate_into(0.0, array.array("d", bytes(8 * n)))
        with self.assertRaisesRegex(TypeError, "writable"):
            self.scene.evaluate_into(0.0, memoryview(bytes(4 * n)).cast("f"))
        with self.assertRaisesRegex(TypeError, "float32"):
            self.scene.evaluate_into(0.0, [0.0] * n)
        with self.assertRaisesRegex(ValueError, "finite"):
            self.scene.evaluate(float("nan"))

    def test_threads_evaluating_at_once_get_the_same_frames(self):
        times = [f / 24 for f in range(0, 121, 7)]
        expected = {t: self.scene.evaluate(t) for t in times}
        failures = []

        def work():
            for t in times:
                if self.scene.evaluate(t) != expected[t]:
                    failures.append(t)

        threads = [threading.Thread(target=work) for _ in range(4)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        self.assertEqual(failures, [])

    def test_referenced_files_sit_beside_the_scene(self):
        files = [Path(p) for p in self.scene.referenced_files()]
        self.assertEqual([p.name for p in files], ["magic_carpet_plate.png"])
        self.assertTrue(all(p.exists() for p in files))
        cape = drape.Scene.load(str(ROOT / "scenes" / "cape.ron"))
        self.assertTrue(any(re.search(r"\.gl(b|tf)$", str(p)) for p in cape.referenced_files()))


class PinsFromOutside(unittest.TestCase):
    """Pins placed by the caller (Blender's bones) through `pins=`."""

    @classmethod
    def setUpClass(cls):
        cls.scene = drape.Scene.load(str(CARPET))
        # Where the corner pin (0, 0) is at each key, as the file says.
        cls.corner_at_keys = [dict(cls.scene.key_pins(k))[(0, 0)] for k in range(len(cls.scene.key_frames))]

    def test_the_scene_lists_its_keys_and_pins(self):
        self.assertEqual(self.scene.key_frames, [0, 24, 48, 72, 120])
        self.assertEqual(self.scene.pin_grids(), [(0, 0), (20, 0), (0, 32), (20, 32)])

    def test_key_pins_are_the_files_in_either_axes(self):
        self.assertEqual(self.scene.key_pins(0)[0], ((0, 0), (-0.5, 1.0, 0.0)))
        self.assertEqual(self.scene.key_pins(0, z_up=True)[2], ((0, 32), (-0.5, 1.58, 1.0)))
        with self.assertRaisesRegex(ValueError, "no key 5"):
            self.scene.key_pins(5)

    def test_pins_where_the_keys_have_them_change_nothing(self):
        for k, frame in enumerate(self.scene.key_frames):
            t = frame / self.scene.fps
            pins = [((0, 0), self.corner_at_keys[k], self.corner_at_keys)]
            self.assertLess(max_difference(self.scene.evaluate(t, pins=pins), self.scene.evaluate(t)), 1e-6)

    def test_a_moved_pin_sits_on_its_target_and_carries_the_cloth(self):
        t = 30.5 / self.scene.fps
        plain = self.scene.evaluate(t)
        target = (plain[0], plain[1] + 0.05, plain[2])
        moved = self.scene.evaluate(t, pins=[((0, 0), target, self.corner_at_keys)])
        self.assertLess(max_difference(moved[0:3], target), 1e-5)
        columns, rows = self.scene.grid
        far = 3 * (columns * rows - 1)  # the pin at (20, 32) stays where the keys put it
        self.assertLess(max_difference(moved[far:far + 3], plain[far:far + 3]), 1e-5)
        near = 3 * 1  # its neighbour follows most of the way
        self.assertGreater(moved[near + 1] - plain[near + 1], 0.025)

    def test_pins_in_blenders_axes_are_converted_like_positions(self):
        t = 30.5 / self.scene.fps
        plain = self.scene.evaluate(t)
        target = (plain[0], plain[1] + 0.05, plain[2])
        y_up = self.scene.evaluate(t, pins=[((0, 0), target, self.corner_at_keys)])
        z_up = self.scene.evaluate(
            t,
            z_up=True,
            pins=[((0, 0), drape.z_up_from_y_up(target), [drape.z_up_from_y_up(p) for p in self.corner_at_keys])],
        )
        for k in range(0, len(y_up), 3):
            x, y, z = y_up[k:k + 3]
            self.assertLess(max_difference(z_up[k:k + 3], (x, -z, y)), 1e-6)

    def test_pins_that_do_not_fit_are_refused(self):
        with self.assertRaisesRegex(ValueError, "key positions"):
            self.scene.evaluate(0.0, pins=[((0, 0), (0.0, 0.0, 0.0), [None])])
        with self.assertRaisesRegex(ValueError, r"no key of the scene has a pin at grid \(5, 5\)"):
            self.scene.evaluate(0.0, pins=[((5, 5), (0.0, 0.0, 0.0), [None] * 5)])


if __name__ == "__main__":
    unittest.main()
