"""Installs the Blender 4.2+ extension from its zip, as Preferences ▸ Get Extensions ▸
Install from Disk does, into the user repository:

    python blender/tests/install_extension.py -- --zip OUT/drape-VERSION-PLATFORM.zip

with the `bpy` module (4.2 or later) and BLENDER_USER_RESOURCES naming a scratch
folder. The tests then enable it as `bl_ext.user_default.drape` (common.enable_addon).
"""

import sys
import unittest
from pathlib import Path

import bpy
import addon_utils  # noqa: E402  (importable once bpy is: Blender's scripts path)

sys.path.insert(0, str(Path(__file__).resolve().parent))
import common  # noqa: E402

ZIP = Path(common.arguments()["zip"]).resolve()


class InstallFromDisk(unittest.TestCase):
    def test_the_zip_installs_as_an_extension_whose_wheel_provides_the_module(self):
        result = bpy.ops.extensions.package_install_files(filepath=str(ZIP), repo="user_default", enable_on_install=True)
        self.assertEqual(result, {"FINISHED"})
        repo = next(r for r in bpy.context.preferences.extensions.repos if r.module == "user_default")
        self.assertTrue((Path(repo.directory) / "drape" / "blender_manifest.toml").is_file())
        self.assertTrue(addon_utils.check("bl_ext.user_default.drape")[1])
        # Blender installs the manifest's wheel into its own site-packages, not the add-on's folder.
        import drape

        self.assertTrue(hasattr(drape, "Scene"))
        self.assertNotIn(repo.directory, drape.__file__)
        self.assertIs(sys.modules["bl_ext.user_default.drape"].native.module, drape)
        print(f"installed {ZIP.name} into {repo.directory}; the module from {drape.__file__}")


if __name__ == "__main__":
    common.run(InstallFromDisk)
