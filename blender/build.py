"""Packages the add-on from blender/drape and the wheel that maturin built.

    python3 blender/build.py WHEEL OUT

writes
- OUT/drape/ and OUT/drape.zip: the legacy add-on for Blender 3.4–4.1, the
  wheel's native module inside it as drape/drape.abi3.so (install the zip
  with Preferences ▸ Add-ons ▸ Install);
- OUT/extension/: the Blender 4.2+ extension's source, the add-on with the
  wheel under wheels/, listed in blender_manifest.toml with the platform the
  wheel was built for;
- OUT/drape-VERSION-PLATFORM.zip: that extension, packaged as
  `blender --command extension build --split-platforms` would (Preferences ▸
  Get Extensions ▸ Install from Disk).
"""

import re
import shutil
import sys
import tomllib
import zipfile
from pathlib import Path

SOURCE = Path(__file__).resolve().parent / "drape"
NATIVE = "drape/drape.abi3.so"

# A wheel's platform tag as Blender names platforms (`manylinux_2_28_x86_64` → `linux-x64`).
SYSTEMS = {"manylinux": "linux", "musllinux": "linux", "linux": "linux", "macosx": "macos", "win": "windows"}
MACHINES = {"x86_64": "x64", "amd64": "x64", "aarch64": "arm64", "arm64": "arm64"}


def blender_platform(wheel: Path) -> str:
    tag = wheel.stem.split("-")[-1]
    system = re.match(r"[a-z]+", tag).group(0)
    machine = next((m for m in MACHINES if tag.endswith("_" + m)), None)
    if system not in SYSTEMS or machine is None:
        sys.exit(f"{wheel.name}: no Blender platform for the wheel's platform tag {tag!r}")
    return f"{SYSTEMS[system]}-{MACHINES[machine]}"


def copy_sources(target: Path) -> None:
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(SOURCE, target, ignore=shutil.ignore_patterns("__pycache__", "*.so"))


def fill_manifest(manifest: Path, wheel: Path, platform: str) -> dict:
    text = manifest.read_text()
    filled = f'wheels = ["./wheels/{wheel.name}"]\nplatforms = ["{platform}"]'
    text, count = re.subn(r"(?m)^wheels = \[\]$", filled, text)
    if count != 1:
        sys.exit("blender_manifest.toml has no `wheels = []` line to fill")
    manifest.write_text(text)
    return tomllib.loads(text)


def main(wheel: Path, out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    legacy = out / "drape"
    copy_sources(legacy)
    (legacy / "blender_manifest.toml").unlink()
    with zipfile.ZipFile(wheel) as archive:
        (legacy / "drape.abi3.so").write_bytes(archive.read(NATIVE))
    shutil.make_archive(str(out / "drape"), "zip", out, "drape")

    extension = out / "extension"
    copy_sources(extension)
    (extension / "wheels").mkdir()
    shutil.copy2(wheel, extension / "wheels" / wheel.name)
    platform = blender_platform(wheel)
    manifest = fill_manifest(extension / "blender_manifest.toml", wheel, platform)
    # Blender's layout: the manifest at the archive's root; wheels stored, as they are compressed already.
    package = out / f"{manifest['id']}-{manifest['version']}-{platform.replace('-', '_')}.zip"
    with zipfile.ZipFile(package, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as archive:
        for path in sorted(p for p in extension.rglob("*") if p.is_file()):
            stored = zipfile.ZIP_STORED if path.suffix == ".whl" else None
            archive.write(path, path.relative_to(extension).as_posix(), compress_type=stored)
    print(f"legacy add-on: {legacy}\nextension source: {extension}\nextension: {package}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(Path(sys.argv[1]), Path(sys.argv[2]))
