#!/usr/bin/env python3
"""Writes seeds/gltf_file/tiny_rig.glb: the smallest GLB with every part a
reference reads — two joints, a skinned quad with a morph target and a PNG
texture, a camera, and an animation with each interpolation — so the glTF
fuzz target starts from a file that reaches the skinning and clip code."""
import json, struct, zlib, pathlib

def png_1x1(rgba):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"\x00" + bytes(rgba)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 1, 1, 8, 6, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))

blob = bytearray()
views, accessors = [], []
def add(data, component, kind, count, target=None, minmax=None):
    while len(blob) % 4:
        blob.append(0)
    view = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
    if target:
        view["target"] = target
    views.append(view)
    blob.extend(data)
    if component is None:
        return len(views) - 1
    accessor = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": kind}
    if minmax:
        accessor["min"], accessor["max"] = minmax
    accessors.append(accessor)
    return len(accessors) - 1

f32 = lambda *v: struct.pack("<%df" % len(v), *v)
quad = [0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0]
pos = add(f32(*quad), 5126, "VEC3", 4, 34962, ([0, 0, 0], [1, 1, 0]))
uv = add(f32(0, 0, 1, 0, 0, 1, 1, 1), 5126, "VEC2", 4, 34962)
joints = add(struct.pack("<16B", *([0, 1, 0, 0] * 4)), 5121, "VEC4", 4, 34962)
weights = add(f32(*([0.75, 0.25, 0, 0] * 4)), 5126, "VEC4", 4, 34962)
morph = add(f32(*([0, 0, 0.1] * 4)), 5126, "VEC3", 4, 34962, ([0, 0, 0.1], [0, 0, 0.1]))
indices = add(struct.pack("<6H", 0, 1, 2, 2, 1, 3), 5123, "SCALAR", 6, 34963)
identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
ibm = add(f32(*identity, *identity), 5126, "MAT4", 2)
times = add(f32(0, 0.5, 1), 5126, "SCALAR", 3, None, ([0], [1]))
moves = add(f32(0, 0, 0, 0, 1, 0, 0, 0, 0), 5126, "VEC3", 3)
turns = add(f32(0, 0, 0, 1, 0, 0.7071, 0, 0.7071, 0, 0, 0, 1), 5126, "VEC4", 3)
cubic = add(f32(*([1, 1, 1] * 9)), 5126, "VEC3", 9)
morph_weights = add(f32(0, 1, 0), 5126, "SCALAR", 3)
image_view = add(png_1x1([200, 30, 30, 255]), None, None, 0)

document = {
    "asset": {"version": "2.0"}, "scene": 0,
    "scenes": [{"nodes": [0, 2, 3]}],
    "nodes": [
        {"name": "root", "children": [1], "translation": [0, 1, 0]},
        {"name": "tip", "translation": [0, 0.5, 0]},
        {"name": "quad", "mesh": 0, "skin": 0, "weights": [0.5]},
        {"name": "lens", "camera": 0, "translation": [0, 1, 5]},
    ],
    "skins": [{"joints": [0, 1], "inverseBindMatrices": ibm}],
    "meshes": [{"name": "quad", "primitives": [{
        "attributes": {"POSITION": pos, "TEXCOORD_0": uv, "JOINTS_0": joints, "WEIGHTS_0": weights},
        "indices": indices, "material": 0, "targets": [{"POSITION": morph}]}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "baseColorTexture": {"index": 0}}}],
    "textures": [{"source": 0}],
    "images": [{"bufferView": image_view, "mimeType": "image/png"}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}],
    "animations": [{"name": "Wave", "samplers": [
        {"input": times, "output": moves, "interpolation": "LINEAR"},
        {"input": times, "output": turns, "interpolation": "STEP"},
        {"input": times, "output": cubic, "interpolation": "CUBICSPLINE"},
        {"input": times, "output": morph_weights, "interpolation": "LINEAR"}],
        "channels": [
            {"sampler": 0, "target": {"node": 0, "path": "translation"}},
            {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
            {"sampler": 2, "target": {"node": 1, "path": "scale"}},
            {"sampler": 3, "target": {"node": 2, "path": "weights"}}]}],
    "accessors": accessors, "bufferViews": views,
}
while len(blob) % 4:
    blob.append(0)
document["buffers"] = [{"byteLength": len(blob)}]
text = json.dumps(document, separators=(",", ":")).encode()
text += b" " * (-len(text) % 4)
glb = (b"glTF" + struct.pack("<II", 2, 12 + 8 + len(text) + 8 + len(blob))
       + struct.pack("<I", len(text)) + b"JSON" + text + struct.pack("<I", len(blob)) + b"BIN\x00" + bytes(blob))
out = pathlib.Path(__file__).parent / "seeds" / "gltf_file" / "tiny_rig.glb"
out.parent.mkdir(parents=True, exist_ok=True)
out.write_bytes(glb)
