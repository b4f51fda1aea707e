"""Drape objects: their scene files, their meshes and the frame they show.

Every frame is Drape's evaluation at that exact time, written into the
object's "Drape" shape key (Cycles blurs only deformations it sees in shape
keys or modifiers). Nothing is cached but the loaded scene files, so a frame
is the same reached by scrubbing, playing or a render farm node.
"""

import array
import os

import bpy
from mathutils import Vector

from . import timing
from .native import module as drape

SHAPE_KEY = "Drape"
BASIS_KEY = "Basis"

# Loaded scene files by absolute path, shared by the objects that show them.
_loaded = {}
# The last problem of each Drape object, by name, for the panel.
_errors = {}


class _Loaded:
    def __init__(self, scene, files, stamp, error=None):
        self.scene = scene
        self.files = files
        self.stamp = stamp
        self.error = error


def _stamp(files):
    stamp = []
    for path in files:
        try:
            info = os.stat(path)
            stamp.append((info.st_mtime_ns, info.st_size))
        except OSError:
            stamp.append(None)
    return tuple(stamp)


def is_drape_object(obj):
    return obj is not None and obj.type == "MESH" and bool(obj.drape.scene_path)


def scene_file(obj):
    return os.path.normpath(bpy.path.abspath(obj.drape.scene_path))


def load(path, force=False):
    """The scene at `path`, read again when it or a file it names changed.

    Raises drape.SceneError (FILE:LINE:COL: …) when it cannot be read; a
    failed reload keeps the failure until a file changes again.
    """
    entry = _loaded.get(path)
    if entry is not None and not force and _stamp(entry.files) == entry.stamp:
        if entry.error is not None:
            raise drape.SceneError(entry.error)
        return entry.scene
    files = entry.files if entry is not None else [path]
    stamp = _stamp(files)  # before reading: a change while reading is seen next time
    try:
        scene = drape.Scene.load(path)
    except drape.SceneError as error:
        _loaded[path] = _Loaded(None, files, stamp, str(error))
        raise
    files = [path] + [str(p) for p in scene.referenced_files()]
    _loaded[path] = _Loaded(scene, files, _stamp(files) if len(files) > 1 else stamp)
    return scene


def changed_files():
    """Paths of loaded scenes whose files changed on disk since they were read."""
    return [path for path, entry in _loaded.items() if _stamp(entry.files) != entry.stamp]


def forget_all():
    _loaded.clear()
    _errors.clear()


def error_of(obj):
    return _errors.get(obj.name_full)


def _set_error(obj, message):
    if _errors.get(obj.name_full) != message:
        print(f"Drape: {obj.name_full}: {message}")
    _errors[obj.name_full] = message


def time_of(obj, bl_scene):
    """Seconds into the Drape scene that `obj` shows at `bl_scene`'s current (sub-)frame."""
    render = bl_scene.render
    return timing.drape_seconds(
        bl_scene.frame_current, bl_scene.frame_subframe, obj.drape.time_offset_frames, render.fps, render.fps_base
    )


_buffers = {}


def _buffer(point_count):
    buf = _buffers.get(point_count)
    if buf is None:
        buf = array.array("f", bytes(4 * 3 * point_count))
        _buffers[point_count] = buf
    return buf


def target_matrix(pin, depsgraph):
    """World matrix of the bone (its head) or object carrying `pin`, as evaluated now; None if it is gone."""
    target = pin.target
    if target is None:
        return None
    evaluated = target.evaluated_get(depsgraph)
    if not pin.bone:
        return evaluated.matrix_world
    if target.type != "ARMATURE" or pin.bone not in evaluated.pose.bones:
        return None
    return evaluated.matrix_world @ evaluated.pose.bones[pin.bone].matrix


def pin_in_object_space(obj, pin, depsgraph):
    """Where `pin`'s bone puts it now, in the cloth object's space (Blender's axes); None if it cannot."""
    matrix = target_matrix(pin, depsgraph)
    if matrix is None:
        return None
    world = matrix @ Vector(pin.offset)
    return obj.evaluated_get(depsgraph).matrix_world.inverted() @ world


def pin_arguments(obj, cloth, depsgraph):
    """The `pins=` argument of evaluate_into: every pin whose bone is bound and sampled at every key."""
    pins = []
    for pin in obj.drape.pins:
        if pin.target is None or len(pin.at_keys) != len(cloth.key_frames):
            continue
        now = pin_in_object_space(obj, pin, depsgraph)
        if now is None:
            continue
        at_keys = [tuple(k.co) if k.sampled else None for k in pin.at_keys]
        pins.append(((pin.grid[0], pin.grid[1]), tuple(now), at_keys))
    return pins


def sync_pins(obj, cloth):
    """One entry of object.drape.pins per pin of the scene file, keeping the bindings of those still there."""
    grids = [tuple(grid) for grid in cloth.pin_grids()]
    pins = obj.drape.pins
    for index in reversed(range(len(pins))):
        if tuple(pins[index].grid) not in grids:
            pins.remove(index)
    have = {tuple(pin.grid) for pin in pins}
    for grid in grids:
        if grid not in have:
            pins.add().grid = grid


def show_frame(obj, bl_scene, depsgraph=None):
    """Writes Drape's cloth at the scene's current (sub-)frame into the object's shape key.

    Pins bound to bones are read from `depsgraph` (the frame handler's; the
    context's otherwise). Returns True when it did; a problem goes to the
    panel and the console, never raises.
    """
    try:
        cloth = load(scene_file(obj))
    except drape.SceneError as error:
        _set_error(obj, str(error))
        return False
    mesh = obj.data
    keys = mesh.shape_keys
    key = keys.key_blocks.get(SHAPE_KEY) if keys is not None else None
    if key is None:
        _set_error(obj, f'the "{SHAPE_KEY}" shape key is missing: press Reload to rebuild the cloth')
        return False
    if len(mesh.vertices) != cloth.point_count:
        columns, rows = cloth.grid
        _set_error(
            obj,
            f"the scene's cloth is now {columns} × {rows} points and the mesh has {len(mesh.vertices)}: "
            "press Reload to rebuild it",
        )
        return False
    buf = _buffer(cloth.point_count)
    pins = None
    if any(pin.target is not None for pin in obj.drape.pins):
        pins = pin_arguments(obj, cloth, depsgraph or bpy.context.evaluated_depsgraph_get())
    try:
        cloth.evaluate_into(time_of(obj, bl_scene), buf, z_up=True, pins=pins)
    except Exception as error:  # drape.EvaluationError: a bug, shown rather than crashing playback
        _set_error(obj, str(error))
        return False
    key.data.foreach_set("co", buf)
    mesh.update()
    _errors.pop(obj.name_full, None)
    return True


def show_all(bl_scene, depsgraph=None):
    for obj in bl_scene.objects:
        if is_drape_object(obj) and obj.drape.live:
            show_frame(obj, bl_scene, depsgraph)


def fill_mesh(mesh, cloth, bl_scene):
    """Gives an empty mesh Drape's topology, UVs and the Basis and Drape shape keys.

    The Basis is the cloth at the scene file's first frame; the Drape key (value 1)
    holds the frame shown.
    """
    columns, rows = cloth.grid
    first = cloth.evaluate(cloth.frame_range[0] / cloth.fps, z_up=True)
    triangles = cloth.triangles()
    count = len(triangles) // 3
    mesh.vertices.add(cloth.point_count)
    mesh.vertices.foreach_set("co", first)
    mesh.loops.add(len(triangles))
    mesh.loops.foreach_set("vertex_index", triangles)
    mesh.polygons.add(count)
    mesh.polygons.foreach_set("loop_start", array.array("i", range(0, 3 * count, 3)))
    if bpy.app.version < (4, 0, 0):
        mesh.polygons.foreach_set("loop_total", array.array("i", [3]) * count)
    mesh.polygons.foreach_set("use_smooth", [True] * count)
    # Per corner; Drape's v = 0 is the top edge, Blender's v runs upwards.
    uvs = cloth.uvs()
    corner_uvs = array.array("f", bytes(8 * len(triangles)))
    for corner, vertex in enumerate(triangles):
        corner_uvs[2 * corner] = uvs[2 * vertex]
        corner_uvs[2 * corner + 1] = 1.0 - uvs[2 * vertex + 1]
    mesh.uv_layers.new(name="UVMap").data.foreach_set("uv", corner_uvs)
    mesh.update()
    mesh.validate()


def add_shape_keys(obj):
    obj.shape_key_add(name=BASIS_KEY, from_mix=False)
    key = obj.shape_key_add(name=SHAPE_KEY, from_mix=False)
    key.value = 1.0
    key.slider_max = 1.0
    obj.data.shape_keys.use_relative = True


def create(context, path, name=None):
    """A new Drape object showing the scene file at `path`, linked into the active collection.

    Raises drape.SceneError when the file is not a valid scene.
    """
    path = os.path.normpath(bpy.path.abspath(path))
    cloth = load(path, force=True)
    bl_scene = context.scene
    name = name or cloth.name or os.path.splitext(os.path.basename(path))[0]
    mesh = bpy.data.meshes.new(name)
    fill_mesh(mesh, cloth, bl_scene)
    obj = bpy.data.objects.new(name, mesh)
    context.collection.objects.link(obj)
    add_shape_keys(obj)
    sync_pins(obj, cloth)
    obj.drape.scene_path = path  # last: setting it shows the frame
    # Handlers run on the render thread during F12: the interface must stay locked.
    bl_scene.render.use_lock_interface = True
    show_frame(obj, bl_scene)
    return obj


def rebuild(obj, bl_scene):
    """Reads the scene file again and gives the object a new mesh of its current grid."""
    cloth = load(scene_file(obj), force=True)
    old = obj.data
    mesh = bpy.data.meshes.new(old.name)
    fill_mesh(mesh, cloth, bl_scene)
    for material in old.materials:
        mesh.materials.append(material)
    obj.data = mesh
    if old.users == 0:
        bpy.data.meshes.remove(old)
    add_shape_keys(obj)
    sync_pins(obj, cloth)
    return show_frame(obj, bl_scene)
