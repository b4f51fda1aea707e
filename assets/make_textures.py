#!/usr/bin/env python3
"""Draws Drape's two built-in cloth textures (run from anywhere; needs numpy).

carpet.png  - a woven-rug pattern: borders, a central medallion, a diamond field.
checker.png - a UV checker: 8 x 8 cells whose hue runs with u and value with v,
              each with a small inner check and a marker in its top-left corner,
              so stretching, flipping and seams show at a glance.
"""
import os
import struct
import zlib

import numpy as np

SIZE = 512
HERE = os.path.dirname(os.path.abspath(__file__))


def write_png(path, rgb):
    height, width, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].astype(np.uint8).tobytes() for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def carpet():
    y, x = np.mgrid[0:SIZE, 0:SIZE] / (SIZE - 1.0)
    red = np.array([140, 28, 30])
    deep = np.array([70, 14, 24])
    gold = np.array([214, 162, 72])
    navy = np.array([28, 40, 82])
    cream = np.array([232, 214, 170])
    img = np.zeros((SIZE, SIZE, 3)) + red
    # Distance to the nearest edge, in texture units.
    edge = np.minimum(np.minimum(x, 1 - x), np.minimum(y, 1 - y))
    # Diamond lattice over the field.
    dx, dy = (x * 12) % 1 - 0.5, (y * 12) % 1 - 0.5
    diamond = np.abs(dx) + np.abs(dy)
    img[diamond < 0.22] = deep
    img[(diamond > 0.16) & (diamond < 0.22)] = gold
    # Central medallion: nested lozenges.
    cx, cy = np.abs(x - 0.5), np.abs(y - 0.5)
    lozenge = cx / 0.32 + cy / 0.42
    img[lozenge < 1.0] = navy
    img[(lozenge > 0.9) & (lozenge < 1.0)] = gold
    img[(lozenge < 0.62)] = red
    img[(lozenge > 0.55) & (lozenge < 0.62)] = cream
    img[lozenge < 0.25] = gold
    img[lozenge < 0.15] = navy
    # Borders: outer band, a zig-zag band, inner line.
    img[edge < 0.12] = navy
    along = np.where(np.minimum(y, 1 - y) < np.minimum(x, 1 - x), x, y)
    zig = np.abs(((along * 24) % 1) - 0.5)
    band = (edge > 0.035) & (edge < 0.085)
    wave = np.abs((edge - 0.035) / 0.05 - zig * 2) < 0.25
    img[band & wave] = gold
    img[(edge > 0.11) & (edge < 0.12)] = cream
    img[edge < 0.012] = gold
    # A faint weave so the surface does not look painted.
    weave = 0.92 + 0.08 * ((np.floor(x * SIZE / 2) + np.floor(y * SIZE / 2)) % 2)
    return np.clip(img * weave[..., None], 0, 255)


def checker():
    cells = 8
    y, x = np.mgrid[0:SIZE, 0:SIZE]
    cell = SIZE // cells
    ci, cj = x // cell, y // cell
    fx, fy = (x % cell) / cell, (y % cell) / cell
    hue = ci / cells
    value = 0.55 + 0.45 * (1 - cj / (cells - 1))
    # HSV to RGB with saturation 0.6.
    h6 = hue * 6
    k = lambda n: (n + h6) % 6
    f = lambda n: value - value * 0.6 * np.maximum(0, np.minimum(np.minimum(k(n), 4 - k(n)), 1))
    img = np.stack([f(5), f(3), f(1)], axis=-1) * 255
    inner = ((np.floor(fx * 4) + np.floor(fy * 4)) % 2 == 0)
    img[inner] *= 0.82
    marker = (fx < 0.22) & (fy < 0.22) & (fx > 0.06) & (fy > 0.06)
    img[marker] = 245
    border = (fx < 0.02) | (fy < 0.02)
    img[border] = 30
    return img


if __name__ == "__main__":
    write_png(os.path.join(HERE, "carpet.png"), carpet())
    write_png(os.path.join(HERE, "checker.png"), checker())
