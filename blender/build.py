"""Packages the add-on from blender/drape and the wheel that maturin built.

    python3 blender/build.py WHEEL OUT

writes OUT/drape/ (the legacy add-on for Blender 3.4–4.1, the wheel's native
module inside it as drape/drape.abi3.so), OUT/drape.zip (the same, for
Preferences ▸ Add-ons ▸ Install) and OUT/extension/ (the Blender 4.2+
extension's source: the add-on with the wheel under wheels/, listed in
blender_manifest.toml; `blender --command extension build` zips it).
"""

import re
import shutil
import sys
import zipfile
from pathlib import Path

SOURCE = Path(__file__).resolve().parent / "drape"
NATIVE = "drape/drape.abi3.so"


def copy_sources(target: Path) -> None:
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(SOURCE, target, ignore=shutil.ignore_patterns("__pycache__", "*.so"))


def main(wheel: Path, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    legacy = out / "drape"
    copy_sources(legacy)
    with zipfile.ZipFile(wheel) as archive:
        (legacy / "drape.abi3.so").write_bytes(archive.read(NATIVE))
    shutil.make_archive(str(out / "drape"), "zip", out, "drape")

    extension = out / "extension"
    copy_sources(extension)
    (extension / "wheels").mkdir()
    shutil.copy2(wheel, extension / "wheels" / wheel.name)
    manifest = extension / "blender_manifest.toml"
    text = manifest.read_text()
    text, count = re.subn(r"(?m)^wheels = \[\]$", f'wheels = ["./wheels/{wheel.name}"]', text)
    if count != 1:
        sys.exit("blender_manifest.toml has no `wheels = []` line to fill")
    manifest.write_text(text)
    print(f"legacy add-on: {legacy}\nextension source: {extension}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(Path(sys.argv[1]), Path(sys.argv[2]))
