"""Compares the fresh process's frame 90 with the scrubbed one (see test_fresh_render.py).

    blender -b --factory-startup --python-exit-code 1 --python blender/tests/test_compare_renders.py -- --out OUT
"""

import json
import sys
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import common  # noqa: E402

OUT = Path(common.arguments()["out"])


class FreshRender(unittest.TestCase):
    def test_the_fresh_render_saw_frame_90(self):
        self.assertEqual((OUT / "fresh_frame.txt").read_text().split(), ["90", "0.0"])

    def test_the_fresh_cloths_equal_the_scrubbed_ones(self):
        fresh = json.loads((OUT / "fresh_90.json").read_text())
        scrubbed = json.loads((OUT / "scrubbed_90.json").read_text())
        # The plain carpet, and the one whose corner pin rides on a bone.
        self.assertEqual(sorted(fresh), ["Carpet on a hand", "Magic carpet"])
        self.assertEqual(sorted(fresh), sorted(scrubbed))
        for name in fresh:
            self.assertEqual(len(fresh[name]), 3 * 21 * 33)
            self.assertLessEqual(common.max_difference(fresh[name], scrubbed[name]), common.TOLERANCE_M, name)

    def test_the_fresh_picture_equals_the_scrubbed_one(self):
        fresh = common.pixels_of(OUT / "fresh_0090.png")
        scrubbed = common.pixels_of(OUT / "scrubbed_90.png")
        self.assertGreater(sum(a > 0.5 for a in scrubbed[3::4]), 20, "the cloth is in view")
        self.assertEqual(common.max_difference(fresh, scrubbed), 0.0)


if __name__ == "__main__":
    common.run(FreshRender)
