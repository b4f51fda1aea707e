#!/usr/bin/env python3
"""Writes the mesh colliders the tests read (run from this folder):

- table.obj: a 1.2 x 0.8 m table, top 0.74 m high and 4 cm thick, on four
  5 cm legs; every part a closed box, wound outwards.
- ball.glb: a 0.3 m ball (an icosphere, 1280 triangles) in a binary glTF,
  its node moved up 1 m, so reading it must apply the node's transform.
- broken.obj: faces naming vertices the file does not have.
"""
import json
import math
import struct


def box(center, size):
    cx, cy, cz = center
    hx, hy, hz = (s / 2 for s in size)
    vertices = [(cx + (hx if i & 1 else -hx), cy + (hy if i & 2 else -hy), cz + (hz if i & 4 else -hz)) for i in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return vertices, quads


def write_table():
    parts = [box((0.0, 0.72, 0.0), (1.2, 0.04, 0.8))]
    for x in (-0.55, 0.55):
        for z in (-0.35, 0.35):
            parts.append(box((x, 0.35, z), (0.05, 0.7, 0.05)))
    lines = ["# A table: top and four legs, each a closed box (make_meshes.py)."]
    base = 0
    for vertices, quads in parts:
        lines += [f"v {x:.4f} {y:.4f} {z:.4f}" for x, y, z in vertices]
        lines += ["f " + " ".join(str(base + i + 1) for i in q) for q in quads]
        base += len(vertices)
    open("table.obj", "w").write("\n".join(lines) + "\n")


def icosphere(subdivisions):
    t = (1 + 5 ** 0.5) / 2
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
                (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    vertices = [tuple(c / math.sqrt(sum(d * d for d in v)) for c in v) for v in vertices]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        middles = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in middles:
                m = [(vertices[a][k] + vertices[b][k]) / 2 for k in range(3)]
                n = math.sqrt(sum(c * c for c in m))
                vertices.append(tuple(c / n for c in m))
                middles[key] = len(vertices) - 1
            return middles[key]

        faces = [f for a, b, c in faces for f in
                 ((a, middle(a, b), middle(c, a)), (b, middle(b, c), middle(a, b)), (c, middle(c, a), middle(b, c)),
                  (middle(a, b), middle(b, c), middle(c, a)))]
    return vertices, faces


def write_ball():
    vertices, faces = icosphere(3)
    radius = 0.3
    positions = b"".join(struct.pack("<3f", *(c * radius for c in v)) for v in vertices)
    indices = b"".join(struct.pack("<3I", *f) for f in faces)
    blob = positions + indices
    lo = [min(v[k] for v in vertices) * radius for k in range(3)]
    hi = [max(v[k] for v in vertices) * radius for k in range(3)]
    document = {
        "asset": {"version": "2.0", "generator": "drape tests/data/meshes/make_meshes.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "ball", "mesh": 0, "translation": [0.0, 1.0, 0.0]}],
        "meshes": [{"name": "ball", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(positions), "target": 34962},
            {"buffer": 0, "byteOffset": len(positions), "byteLength": len(indices), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(vertices), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": 3 * len(faces), "type": "SCALAR"},
        ],
    }
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    blob += b"\0" * (-len(blob) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(blob), 0x004E4942) + blob
    open("ball.glb", "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


def write_broken():
    open("broken.obj", "w").write("# Faces name vertices that are not there (make_meshes.py).\nv 0 0 0\nv 1 0 0\nf 1 2 7\n")


write_table()
write_ball()
write_broken()
