"""The drape module, wherever this add-on's packaging put it.

The legacy add-on carries it as drape/drape.abi3.so (the add-on's package is
itself named drape, so the module is a submodule there); a Blender 4.2+
extension installs the wheel, and the module is a top-level import.
"""

try:
    from . import drape as module  # noqa: F401  (legacy add-on)
except ImportError:
    import importlib

    module = importlib.import_module("drape")
    if not hasattr(module, "Scene"):
        raise ImportError("the drape module (the Python wheel) is not installed beside the add-on")
