"""A render node's check before it renders a .blend with Drape cloths.

    blender -b shot.blend --python-exit-code 1 --python preflight.py

Exits with status 1, naming the problem, when the Drape add-on is not
enabled or a Drape object's scene file cannot be read: without it, a node
would render the cloth's saved shape silently instead of Drape's frame.
"""

import sys

import addon_utils
import bpy


def drape_add_on():
    """The enabled add-on's package: `drape` as a legacy add-on, `bl_ext.REPO.drape` as an extension."""
    for name, module in list(sys.modules.items()):
        if (name == "drape" or name.endswith(".drape")) and hasattr(module, "cloth") and addon_utils.check(name)[1]:
            return module
    return None


add_on = drape_add_on()
if add_on is None:
    raise SystemExit("Drape pre-flight: the Drape add-on is not enabled on this machine")
cloth = add_on.cloth

problems = []
for obj in bpy.data.objects:
    if not cloth.is_drape_object(obj):
        continue
    path = cloth.scene_file(obj)
    try:
        scene = cloth.load(path)
    except cloth.drape.SceneError as error:
        problems.append(f"{obj.name_full}: {error}")
        continue
    if len(obj.data.vertices) != scene.point_count:
        problems.append(f"{obj.name_full}: {path} has {scene.point_count} points, the mesh {len(obj.data.vertices)}")
    else:
        print(f"Drape pre-flight: {obj.name_full} reads {path}")
if problems:
    raise SystemExit("Drape pre-flight failed:\n  " + "\n  ".join(problems))
print("Drape pre-flight passed")
