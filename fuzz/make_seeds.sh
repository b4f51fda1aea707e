#!/usr/bin/env bash
# Copies the repository's own small scenes, meshes, glTF files and images
# into the fuzz targets' seed corpus (fuzz/seeds/TARGET). Inputs a fuzzer
# once failed on are kept beside them in fuzz/regressions/TARGET by hand.
set -euo pipefail
cd "$(dirname "$0")/.."
seeds=fuzz/seeds
rm -rf "$seeds"
mkdir -p "$seeds"/{scene_text,gltf_file,obj_file,image_file}
cp scenes/*.ron tests/data/valid_full.ron "$seeds/scene_text/"
for f in tests/data/malformed/*.ron; do cp "$f" "$seeds/scene_text/malformed_$(basename "$f")"; done
cp assets/layout_camera.glb tests/data/meshes/ball.glb "$seeds/gltf_file/"
cp tests/data/meshes/table.obj tests/data/meshes/broken.obj "$seeds/obj_file/"
cp assets/checker.png assets/carpet.png tests/data/textures/red.jpg "$seeds/image_file/"
python3 fuzz/make_rig_seed.py
