"""What the headless Blender tests share: arguments, the add-on, OBJ reading, the Cycles set-up.

The tests run in Blender (`blender -b --python TEST -- ARGS`) with the legacy
add-on, and in the `bpy` module (`python TEST -- ARGS`) with the extension
installed from its zip; nothing else differs.
"""

import array
import sys
from pathlib import Path

import bpy
import addon_utils  # noqa: E402  (importable once bpy is: Blender's scripts path)

ROOT = Path(__file__).resolve().parents[2]
CARPET = ROOT / "scenes" / "magic_carpet.ron"
TOLERANCE_M = 1e-6


def arguments():
    """`--name value` pairs after Blender's `--`."""
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return {args[k].lstrip("-"): args[k + 1] for k in range(0, len(args) - 1, 2)}


def enable_addon():
    """Enables the installed Drape add-on and returns its package: `drape` as a legacy
    add-on, `bl_ext.REPO.drape` as an extension."""
    names = [m.__name__ for m in addon_utils.modules() if m.__name__ == "drape" or m.__name__.endswith(".drape")]
    assert len(names) == 1, f"expected one Drape add-on installed, found {names}"
    addon_utils.enable(names[0], default_set=True, handle_error=None)
    assert addon_utils.check(names[0])[1], f"{names[0]} did not enable"
    package = sys.modules[names[0]]
    print(f"Blender {bpy.app.version_string}: add-on {names[0]}, module {package.native.module.__file__}")
    return package


def obj_positions_z_up(path):
    """An OBJ export's positions in Blender's axes: (x, y, z) → (x, −z, y)."""
    flat = array.array("f")
    for line in Path(path).read_text().splitlines():
        if line.startswith("v "):
            x, y, z = (float(value) for value in line.split()[1:4])
            flat.extend((x, -z, y))
    return flat


def evaluated_positions(obj):
    """The object's evaluated mesh (what the viewport and renders show), local space."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    flat = array.array("f", bytes(12 * len(mesh.vertices)))
    mesh.vertices.foreach_get("co", flat)
    evaluated.to_mesh_clear()
    return flat


def save_positions(path, scene):
    """Every Drape object's "Drape" shape key, by object name, as JSON (floats exact)."""
    import json

    saved = {}
    for obj in scene.objects:
        if obj.type == "MESH" and obj.drape.scene_path:
            key = obj.data.shape_keys.key_blocks["Drape"]
            positions = array.array("f", bytes(12 * len(key.data)))
            key.data.foreach_get("co", positions)
            saved[obj.name] = list(positions)
    Path(path).write_text(json.dumps(saved))


def max_difference(a, b):
    assert len(a) == len(b), (len(a), len(b))
    return max(abs(x - y) for x, y in zip(a, b))


def set_up_tiny_cycles(scene, obj, size_px=64):
    """Cycles at a few samples: a white emitting cloth on a transparent film, so a pixel's
    alpha is the cloth's coverage and nothing but the cloth's motion changes it."""
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 8
    scene.cycles.use_denoising = False
    scene.cycles.seed = 0
    scene.render.resolution_x = scene.render.resolution_y = size_px
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA"
    material = bpy.data.materials.new("Drape test emission")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(emission.outputs[0], output.inputs[0])
    obj.data.materials.append(material)
    # Look straight down on where the carpet flies (Blender −Y is Drape's +Z).
    camera_data = bpy.data.cameras.new("Drape test camera")
    camera_data.type = "ORTHO"
    camera_data.ortho_scale = 5.0
    camera = bpy.data.objects.new("Drape test camera", camera_data)
    camera.location = (0.0, -1.2, 8.0)
    scene.collection.objects.link(camera)
    scene.camera = camera


def render_to(scene, path):
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)


def alpha_of(path):
    image = bpy.data.images.load(str(path))
    pixels = array.array("f", bytes(4 * len(image.pixels)))
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels[3::4]


def pixels_of(path):
    image = bpy.data.images.load(str(path))
    pixels = array.array("f", bytes(4 * len(image.pixels)))
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels


# The `bpy` module has no Blender executable.
AS_MODULE = not bpy.app.binary_path


def finish(status=0):
    """Ends the script with `status`. Blender's executable carries on (renders `-f`, quits);
    the `bpy` module 4.2 leaves at once: at interpreter exit it crashes (SIGSEGV in
    bpy_class_free, after Python is finalized) once any class with a property update
    callback was registered, the add-on's or a three-line one's, so the exit status would
    say nothing about the tests."""
    if AS_MODULE:
        import os

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    if status:
        sys.exit(status)


def run(test_case_class):
    """Runs a unittest class and ends with status 1 on any failure."""
    import unittest

    suite = unittest.defaultTestLoader.loadTestsFromTestCase(test_case_class)
    result = unittest.TextTestRunner(stream=sys.stdout, verbosity=2).run(suite)
    finish(0 if result.wasSuccessful() else 1)
