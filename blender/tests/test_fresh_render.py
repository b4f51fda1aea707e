"""Frame 90 rendered alone in a fresh process equals frame 90 reached by scrubbing.

    blender -b --factory-startup --addons drape OUT/carpet.blend --python-exit-code 1 \
        --python blender/tests/test_fresh_render.py -f 90 -- --out OUT

The script runs before the render: it records, when the render ends, the
cloth the render saw; the comparison runs once Blender has written the
picture (test_compare_renders.py).
"""

import sys
from pathlib import Path

import addon_utils
import bpy
from bpy.app.handlers import persistent

sys.path.insert(0, str(Path(__file__).resolve().parent))
import common  # noqa: E402

OUT = Path(common.arguments()["out"])


@persistent
def record(scene, *_):
    common.save_positions(OUT / "fresh_90.json", scene)
    (OUT / "fresh_frame.txt").write_text(f"{scene.frame_current} {scene.frame_subframe}\n")


assert addon_utils.check("drape")[1], "the Drape add-on is not enabled"
bpy.app.handlers.render_post.append(record)
