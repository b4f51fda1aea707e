"""Frame 90 rendered alone in a fresh process equals frame 90 reached by scrubbing.

    blender -b --factory-startup --addons drape OUT/carpet.blend --python-exit-code 1 \
        --python blender/tests/test_fresh_render.py -f 90 -- --out OUT

or, with the `bpy` module, where there is no command line to render from:

    python blender/tests/test_fresh_render.py -- --out OUT --blend OUT/carpet.blend --frame 90

which enables the add-on, opens the file and renders that one frame as an
animation, as `-f` does. The script records, when the render ends, the cloth
the render saw; the comparison runs once the picture is written
(test_compare_renders.py).
"""

import sys
from pathlib import Path

import bpy
import addon_utils  # noqa: E402  (importable once bpy is: Blender's scripts path)
from bpy.app.handlers import persistent

sys.path.insert(0, str(Path(__file__).resolve().parent))
import common  # noqa: E402

ARGS = common.arguments()
OUT = Path(ARGS["out"])


@persistent
def record(scene, *_):
    common.save_positions(OUT / "fresh_90.json", scene)
    (OUT / "fresh_frame.txt").write_text(f"{scene.frame_current} {scene.frame_subframe}\n")


bpy.app.handlers.render_post.append(record)
if "blend" in ARGS:
    common.enable_addon()
    bpy.ops.wm.open_mainfile(filepath=ARGS["blend"])
    scene = bpy.context.scene
    scene.frame_start = scene.frame_end = int(ARGS["frame"])
    bpy.ops.render.render(animation=True)
    common.finish()
else:
    assert addon_utils.check("drape")[1], "the Drape add-on is not enabled"
