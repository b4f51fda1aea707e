#!/usr/bin/env python3
"""Builds walker.glb, Drape's skinned, animated reference character (standard library only).

Run from the repository root:

    python3 assets/make_walker.py

It writes assets/walker.glb: a ~1.75 m humanoid (glTF 2.0, Y up, metres, facing +Z,
feet on y = 0) whose body is 16 smooth closed shapes merged into one indexed
triangle primitive of about 10 000 vertices, skinned to a 19-joint skeleton, plus a
looping one-second walk-in-place animation ("Walk", keys every 1/24 s).
The output is the same bytes on every run.
"""
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "walker.glb")

COLOR = [0.35, 0.42, 0.55, 1.0]
FPS, KEYS = 24, 25  # one 1 s stride cycle, first and last key equal
DENSE = 2000  # profile samples used to space rings evenly by arc length


# --- small vector helpers -------------------------------------------------------------

def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def mul(a, k):
    return tuple(x * k for x in a)


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    return mul(a, 1.0 / math.sqrt(dot(a, a)))


def mirror(p):
    return (-p[0], p[1], p[2])


# --- skeleton -------------------------------------------------------------------------

# (name, parent, rest position in world space). Names ending ".S" exist once per side;
# positions are the left (+X) side's and are mirrored for the right.
CENTRE = [
    ("root", None, (0.0, 0.0, 0.0)),
    ("hips", "root", (0.0, 0.95, 0.0)),
    ("spine", "hips", (0.0, 1.08, 0.0)),
    ("chest", "spine", (0.0, 1.30, 0.0)),
    ("neck", "chest", (0.0, 1.50, 0.0)),
    ("head", "neck", (0.0, 1.58, 0.0)),
]
ARM = [
    ("shoulder.S", "chest", (0.04, 1.43, 0.0)),
    ("upper_arm.S", "shoulder.S", (0.19, 1.45, 0.0)),
    ("forearm.S", "upper_arm.S", (0.22, 1.15, -0.01)),
    ("hand.S", "forearm.S", (0.245, 0.89, 0.0)),
]
LEG = [
    ("thigh.S", "hips", (0.09, 0.92, 0.0)),
    ("shin.S", "thigh.S", (0.09, 0.50, 0.01)),
    ("foot.S", "shin.S", (0.09, 0.085, -0.01)),
]
SIDES = (("L", lambda p: p), ("R", mirror))


def sided(name, side):
    return name[:-1] + side if name.endswith(".S") else name


def skeleton():
    """[(name, parent, world position)] with parents before children."""
    joints = list(CENTRE)
    for group in (ARM, LEG):
        for side, place in SIDES:
            joints += [(sided(n, side), sided(p, side), place(pos)) for n, p, pos in group]
    return joints


def world_pos(joints, name):
    """Rest world position of a joint as listed (the origin for no parent)."""
    return next((pos for n, _, pos in joints if n == name), (0.0, 0.0, 0.0))


# --- body shapes ----------------------------------------------------------------------

# Each part is a superellipse profile (exponent p: 2 = ellipsoid, higher = flatter sides)
# swept round the axis from end A to end B, tapering from radius ra to rb, its cross
# section scaled by (sideways, other way). Its skin follows `bones` along the axis, handing
# over from one to the next at the next bone's joint over +-width metres.
# (name, A, B, ra, rb, scale, p, rings, segments, bones, handover widths)
CENTRE_PARTS = [
    ("pelvis", (0, 0.83, 0), (0, 1.10, 0), 0.15, 0.15, (1.1, 0.75), 3, 20, 32, ["hips", "spine"], [0.06]),
    ("torso", (0, 1.02, 0), (0, 1.50, 0), 0.14, 0.16, (1.05, 0.68), 3, 32, 32,
     ["hips", "spine", "chest"], [0.06, 0.08]),
    ("neck", (0, 1.42, 0), (0, 1.60, 0), 0.055, 0.05, (1, 1), 4, 10, 16, ["chest", "neck", "head"], [0.03, 0.03]),
    ("head", (0, 1.51, 0.015), (0, 1.75, 0.015), 0.095, 0.095, (0.8, 1.0), 2, 24, 28, ["head"], []),
]
SIDE_PARTS = [
    ("upper_arm", (0.185, 1.50, 0), (0.222, 1.11, -0.01), 0.055, 0.042, (1, 1), 3, 32, 20,
     ["shoulder.S", "upper_arm.S", "forearm.S"], [0.05, 0.05]),
    ("forearm", (0.218, 1.19, -0.01), (0.247, 0.87, 0), 0.044, 0.032, (0.9, 1), 3, 30, 18,
     ["upper_arm.S", "forearm.S", "hand.S"], [0.05, 0.03]),
    ("hand", (0.246, 0.915, 0), (0.256, 0.72, 0.01), 0.04, 0.04, (0.5, 1.1), 2.5, 16, 16,
     ["forearm.S", "hand.S"], [0.03]),
    ("thigh", (0.09, 0.99, 0), (0.09, 0.46, 0.01), 0.085, 0.055, (1, 1), 3, 44, 24,
     ["hips", "thigh.S", "shin.S"], [0.06, 0.06]),
    ("shin", (0.09, 0.55, 0.01), (0.09, 0.05, -0.01), 0.056, 0.04, (1, 1), 3, 44, 20,
     ["thigh.S", "shin.S", "foot.S"], [0.06, 0.035]),
    ("foot", (0.09, 0.05, -0.075), (0.095, 0.042, 0.17), 0.05, 0.042, (0.9, 1.0), 3, 20, 20, ["foot.S"], []),
]


def parts():
    """Every body part with its side resolved (left parts mirrored to make the right)."""
    out = list(CENTRE_PARTS)
    for name, a, b, ra, rb, sc, p, rings, segs, bones, widths in SIDE_PARTS:
        for side, place in SIDES:
            out.append((name + "." + side, place(a), place(b), ra, rb, sc, p, rings, segs,
                        [sided(n, side) for n in bones], widths))
    return out


def profile(ra, rb, length, p, rings):
    """(axial, radial) of `rings` points between the poles, evenly spaced by arc length."""
    dense = []
    for i in range(DENSE + 1):
        s = (1 - math.cos(math.pi * i / DENSE)) / 2  # crowd samples at the poles, where r changes fastest
        bulge = max(0.0, 1 - abs(2 * s - 1) ** p) ** (1 / p)
        dense.append((s * length, (ra + (rb - ra) * s) * bulge))
    arc = [0.0]
    for (h0, r0), (h1, r1) in zip(dense, dense[1:]):
        arc.append(arc[-1] + math.hypot(h1 - h0, r1 - r0))
    out, j = [], 0
    for k in range(1, rings + 1):
        target = arc[-1] * k / (rings + 1)
        while arc[j + 1] < target:
            j += 1
        f = (target - arc[j]) / (arc[j + 1] - arc[j])
        out.append(tuple(x0 + (x1 - x0) * f for x0, x1 in zip(dense[j], dense[j + 1])))
    return out


def shape(a, b, ra, rb, sc, p, rings, segs):
    """Positions and outward (counter-clockwise) triangles of one closed part.

    Vertex 0 is the pole at A, then `rings` rings of `segs` vertices, then the pole at B."""
    v = unit(sub(b, a))
    u = unit(sub((1.0, 0.0, 0.0), mul(v, v[0])))  # sideways: world X made perpendicular to the axis
    w = cross(u, v)  # (u, v, w) right-handed, so the winding below faces outwards
    length = math.sqrt(dot(sub(b, a), sub(b, a)))
    pts = [a]
    for h, r in profile(ra, rb, length, p, rings):
        centre = add(a, mul(v, h))
        for j in range(segs):
            t = 2 * math.pi * j / segs
            pts.append(add(centre, add(mul(u, r * sc[0] * math.cos(t)), mul(w, r * sc[1] * math.sin(t)))))
    pts.append(b)
    ring = lambda k, j: 1 + k * segs + j % segs
    tris = [(0, ring(0, j), ring(0, j + 1)) for j in range(segs)]
    for k in range(rings - 1):
        for j in range(segs):
            tris += [(ring(k, j), ring(k + 1, j + 1), ring(k, j + 1)), (ring(k, j), ring(k + 1, j), ring(k + 1, j + 1))]
    top = len(pts) - 1
    tris += [(top, ring(rings - 1, j + 1), ring(rings - 1, j)) for j in range(segs)]
    return pts, tris


def smooth_normals(pts, tris):
    """Area-weighted vertex normals (the parts are smooth, so no hard edges are wanted)."""
    acc = [(0.0, 0.0, 0.0)] * len(pts)
    for i, j, k in tris:
        n = cross(sub(pts[j], pts[i]), sub(pts[k], pts[i]))
        for m in (i, j, k):
            acc[m] = add(acc[m], n)
    return [unit(n) for n in acc]


def smoothstep(e0, e1, x):
    t = min(1.0, max(0.0, (x - e0) / (e1 - e0)))
    return t * t * (3 - 2 * t)


def chain_weights(point, a, axis, bones, widths, world):
    """{bone: weight} for a point, blending along the part's axis at each joint of the chain."""
    s = dot(sub(point, a), axis)
    weights, rest = {}, 1.0
    for k, bone in enumerate(bones[:-1]):
        at = dot(sub(world[bones[k + 1]], a), axis)
        onward = smoothstep(at - widths[k], at + widths[k], s)
        weights[bone] = rest * (1 - onward)
        rest *= onward
    weights[bones[-1]] = rest
    return weights


def pack_weights(weights, index):
    """Four (joint, weight) slots; weights are multiples of 1/65536 so they sum to exactly 1 in float32."""
    top = sorted(weights.items(), key=lambda kv: (-kv[1], index[kv[0]]))[:4]
    q = [(index[n], round(wt * 65536)) for n, wt in top]
    q = [(j, n) for j, n in q if n >= 64]  # drop influences under ~0.1 %
    q[0] = (q[0][0], 65536 - sum(n for _, n in q[1:]))
    q += [(0, 0)] * (4 - len(q))
    return [j for j, _ in q], [n / 65536 for _, n in q]


def build_mesh(world, index):
    """Merged positions, normals, joints, weights and triangles of every part."""
    pos, nrm, jnt, wgt, tris = [], [], [], [], []
    for name, a, b, ra, rb, sc, p, rings, segs, bones, widths in parts():
        pts, local = shape(a, b, ra, rb, sc, p, rings, segs)
        axis = unit(sub(b, a))
        base = len(pos)
        pos += pts
        nrm += smooth_normals(pts, local)
        for pt in pts:
            j, wt = pack_weights(chain_weights(pt, a, axis, bones, widths, world), index)
            jnt.append(j)
            wgt.append(wt)
        tris += [(i + base, j + base, k + base) for i, j, k in local]
    return pos, nrm, jnt, wgt, tris


# --- animation ------------------------------------------------------------------------

def quat(axis, degrees):
    h = math.radians(degrees) / 2
    return tuple(c * math.sin(h) for c in axis) + (math.cos(h),)


X, Y = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)


def walk_pose(t, hips_y):
    """Local rotations {joint: quaternion} and the hips translation at time t in [0, 1).

    Positive rotation about X swings a hanging limb backwards, so thighs and arms swing
    forwards with negative angles and knees bend with positive ones."""
    phase = 2 * math.pi * t
    pose = {}
    for side, shift in (("L", 0.0), ("R", math.pi)):
        ph = phase + shift
        swing = math.sin(ph)  # +1: this leg fully forward
        knee = 50 * ((1 + math.cos(ph)) / 2) ** 2  # most bent mid-swing, straight mid-stance
        thigh = -25 * swing
        pose["thigh." + side] = quat(X, thigh)
        pose["shin." + side] = quat(X, knee)
        pose["foot." + side] = quat(X, -0.8 * (thigh + knee))  # keep the sole near level
        pose["upper_arm." + side] = quat(X, 20 * swing)  # arm goes back as its leg goes forward
        pose["forearm." + side] = quat(X, -(15 + 5 * (1 - swing)))  # bend more when swung forward
    # Shoulders turn against the leading leg.
    pose["spine"] = quat(Y, 3 * math.sin(phase))
    pose["chest"] = quat(Y, 5 * math.sin(phase))
    # Lowest at double support (t = 1/4, 3/4), where both feet are off the vertical.
    bob = -0.03 * (1 - math.cos(2 * phase)) / 2
    return pose, (0.0, hips_y + bob, 0.0)


def animation_keys(hips_y):
    """Key times and per-channel values; the last key repeats the first so the loop is seamless."""
    times = [i / FPS for i in range(KEYS)]
    poses = [walk_pose((i % FPS) / FPS, hips_y) for i in range(KEYS)]
    rotations = {name: [pose[name] for pose, _ in poses] for name in poses[0][0]}
    return times, rotations, [hips for _, hips in poses]


# --- glTF / GLB writing ---------------------------------------------------------------

COMPONENTS = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}
FORMATS = {5121: "B", 5123: "H", 5125: "I", 5126: "f"}


class Buffer:
    """Binary chunk plus its bufferViews and accessors (one tightly packed view per accessor)."""

    def __init__(self):
        self.data, self.views, self.accessors = bytearray(), [], []

    def add(self, rows, kind, component, target=None, bounds=False):
        flat = [x for row in rows for x in (row if isinstance(row, (tuple, list)) else (row,))]
        raw = struct.pack("<%d%s" % (len(flat), FORMATS[component]), *flat)
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)}
        if target:
            view["target"] = target
        self.data += raw + b"\0" * (-len(raw) % 4)  # keep every view 4-byte aligned
        accessor = {"bufferView": len(self.views), "componentType": component,
                    "count": len(rows), "type": kind}
        if bounds:  # min/max of the stored (float32-rounded) values, as the validator compares them
            stored = struct.unpack("<%d%s" % (len(flat), FORMATS[component]), raw)
            n = COMPONENTS[kind]
            accessor["min"] = [min(stored[c::n]) for c in range(n)]
            accessor["max"] = [max(stored[c::n]) for c in range(n)]
        self.views.append(view)
        self.accessors.append(accessor)
        return len(self.accessors) - 1


def glb(document, binary):
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary = bytes(binary) + b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def build():
    joints = skeleton()
    # Rounded parent-relative offsets; world positions are rebuilt from them so that the
    # inverse bind matrices match the node transforms exactly.
    local, world = {}, {}
    for name, parent, pos in joints:
        local[name] = tuple(round(c - pc, 6) for c, pc in zip(pos, world_pos(joints, parent)))
        world[name] = add(world[parent], local[name]) if parent else local[name]
    skinned = [name for name, _, _ in joints if name != "root"]
    index = {name: i for i, name in enumerate(skinned)}
    node = {name: i for i, (name, _, _) in enumerate(joints)}

    buf = Buffer()
    pos, nrm, jnt, wgt, tris = build_mesh(world, index)
    attributes = {
        "POSITION": buf.add(pos, "VEC3", 5126, 34962, bounds=True),
        "NORMAL": buf.add(nrm, "VEC3", 5126, 34962),
        "JOINTS_0": buf.add(jnt, "VEC4", 5121 if len(skinned) < 256 else 5123, 34962),
        "WEIGHTS_0": buf.add(wgt, "VEC4", 5126, 34962),
    }
    indices = buf.add([i for t in tris for i in t], "SCALAR", 5123 if len(pos) < 65536 else 5125, 34963)
    # Rest rotations are identity, so each inverse bind matrix is a translation by -world.
    ibm = buf.add([(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0) + mul(world[n], -1) + (1,) for n in skinned], "MAT4", 5126)

    times, rotations, hips = animation_keys(local["hips"][1])
    time_acc = buf.add(times, "SCALAR", 5126, bounds=True)
    tracks = [(name, "rotation", values, "VEC4") for name, values in rotations.items()]
    tracks.append(("hips", "translation", hips, "VEC3"))
    samplers, channels = [], []
    for name, path, values, kind in tracks:
        channels.append({"sampler": len(samplers), "target": {"node": node[name], "path": path}})
        samplers.append({"input": time_acc, "interpolation": "LINEAR", "output": buf.add(values, kind, 5126)})

    nodes = []
    for name, parent, _ in joints:
        entry = {"name": name}
        if any(local[name]):
            entry["translation"] = list(local[name])
        children = [node[n] for n, p, _ in joints if p == name]
        if children:
            entry["children"] = children
        nodes.append(entry)
    nodes.append({"name": "body", "mesh": 0, "skin": 0})
    document = {
        "asset": {"version": "2.0", "generator": "Drape assets/make_walker.py"},
        "scene": 0,
        "scenes": [{"name": "walker", "nodes": [node["root"], len(nodes) - 1]}],
        "nodes": nodes,
        "meshes": [{"name": "body", "primitives": [
            {"attributes": attributes, "indices": indices, "material": 0, "mode": 4}]}],
        "materials": [{"name": "body", "pbrMetallicRoughness": {
            "baseColorFactor": COLOR, "metallicFactor": 0.0, "roughnessFactor": 0.8}}],
        "skins": [{"name": "walker", "skeleton": node["root"], "inverseBindMatrices": ibm,
                   "joints": [node[n] for n in skinned]}],
        "animations": [{"name": "Walk", "channels": channels, "samplers": samplers}],
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data) + (-len(buf.data) % 4)}],
    }
    return glb(document, buf.data), len(pos), len(tris)


if __name__ == "__main__":
    data, vertices, triangles = build()
    with open(OUT, "wb") as f:
        f.write(data)
    print("wrote %s: %d vertices, %d triangles, %d bytes" % (OUT, vertices, triangles, len(data)))
