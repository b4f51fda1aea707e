#!/usr/bin/env python3
"""Builds layout_camera.glb, a layout file with an animated camera (standard library only).

Run from the repository root:

    python3 assets/make_layout_camera.py

It writes assets/layout_camera.glb (glTF 2.0, Y up, metres), the kind of file a layout
artist exports for a shot:

- "dolly", a node that one animation ("Dolly", LINEAR, 0 to 1 s) moves from x = -1 to
  x = +1, carrying two cameras:
  - "ShotCam", 1.5 m up and 4 m back (+Z), tilted 10 degrees down, a perspective camera
    with yfov 0.5 rad, aspectRatio 16:9, znear 0.1;
  - "Dutch", at the same place, rolled 15 degrees about its line of sight, yfov 0.5 rad,
    no aspect ratio;
- "Plan", an orthographic camera 8 m up looking straight down;
- "slate", a 0.3 m box standing at (0, 0, -1), so the file shows something.

A glTF camera looks down its node's -Z with +Y up. The output is the same bytes on
every run.
"""
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "layout_camera.glb")


def quat(axis, degrees):
    """Unit quaternion (x, y, z, w) turning `degrees` about a unit `axis`."""
    half = math.radians(degrees) / 2
    return [a * math.sin(half) for a in axis] + [math.cos(half)]


class Buffer:
    """Binary chunk plus its bufferViews and accessors (one tightly packed view per accessor)."""

    def __init__(self):
        self.data, self.views, self.accessors = bytearray(), [], []

    def add(self, rows, kind, component, bounds=False):
        width = {"SCALAR": 1, "VEC3": 3}[kind]
        flat = [x for row in rows for x in (row if isinstance(row, (tuple, list)) else (row,))]
        code = {5123: "H", 5126: "f"}[component]
        raw = struct.pack("<%d%s" % (len(flat), code), *flat)
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)})
        self.data += raw + b"\0" * (-len(raw) % 4)  # keep every view 4-byte aligned
        accessor = {"bufferView": len(self.views) - 1, "componentType": component, "count": len(rows), "type": kind}
        if bounds:  # min/max of the stored (float32-rounded) values
            stored = struct.unpack("<%d%s" % (len(flat), code), raw)
            accessor["min"] = [min(stored[c::width]) for c in range(width)]
            accessor["max"] = [max(stored[c::width]) for c in range(width)]
        self.accessors.append(accessor)
        return len(self.accessors) - 1


def box(buf, half):
    """A closed box of half-size `half` about the origin: POSITION and indices accessors."""
    corners = [(x, y, z) for x in (-half, half) for y in (-half, half) for z in (-half, half)]
    # Each face counter-clockwise seen from outside (corner index = 4x + 2y + z).
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    triangles = [i for a, b, c, d in faces for i in (a, b, c, a, c, d)]
    return buf.add(corners, "VEC3", 5126, bounds=True), buf.add(triangles, "SCALAR", 5123)


def build():
    buf = Buffer()
    positions, indices = box(buf, 0.15)
    times = buf.add([0.0, 1.0], "SCALAR", 5126, bounds=True)
    moves = buf.add([(-1.0, 0.0, 0.0), (1.0, 0.0, 0.0)], "VEC3", 5126)
    nodes = [
        {"name": "dolly", "translation": [-1.0, 0.0, 0.0], "children": [1, 2]},
        {"name": "ShotCam", "camera": 0, "translation": [0.0, 1.5, 4.0], "rotation": quat((1, 0, 0), -10)},
        {"name": "Dutch", "camera": 1, "translation": [0.0, 1.5, 4.0], "rotation": quat((0, 0, 1), 15)},
        {"name": "Plan", "camera": 2, "translation": [0.0, 8.0, 0.0], "rotation": quat((1, 0, 0), -90)},
        {"name": "slate", "mesh": 0, "translation": [0.0, 0.15, -1.0]},
    ]
    document = {
        "asset": {"version": "2.0", "generator": "Drape assets/make_layout_camera.py"},
        "scene": 0,
        "scenes": [{"name": "layout", "nodes": [0, 3, 4]}],
        "nodes": nodes,
        "cameras": [
            {"name": "ShotCamLens", "type": "perspective",
             "perspective": {"yfov": 0.5, "aspectRatio": 16 / 9, "znear": 0.1, "zfar": 100.0}},
            {"name": "DutchLens", "type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}},
            {"name": "PlanLens", "type": "orthographic",
             "orthographic": {"xmag": 4.0, "ymag": 4.0, "znear": 0.1, "zfar": 20.0}},
        ],
        "meshes": [{"name": "slate", "primitives": [
            {"attributes": {"POSITION": positions}, "indices": indices, "material": 0, "mode": 4}]}],
        "materials": [{"name": "slate", "pbrMetallicRoughness": {
            "baseColorFactor": [0.8, 0.3, 0.2, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8}}],
        "animations": [{"name": "Dolly",
                        "samplers": [{"input": times, "output": moves, "interpolation": "LINEAR"}],
                        "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}],
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data)}],
    }
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary = bytes(buf.data)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


if __name__ == "__main__":
    data = build()
    with open(OUT, "wb") as f:
        f.write(data)
    print("wrote %s: %d bytes" % (OUT, len(data)))
