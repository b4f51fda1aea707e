#!/usr/bin/env python3
"""Paints the magic carpet shot's background plate, magic_carpet_plate.png
(1280 x 720, the shot camera's picture): a desert at dusk in the flat,
banded manner of a 2D film's painted background - a graded sky in bands, a
low moon, far hills with a domed city, near dunes with lit crests - over a
faint brush grain. Run from anywhere with numpy: /usr/bin/python3 make_plate.py.
"""
import os

import numpy as np

from make_textures import write_png

WIDTH, HEIGHT = 1280, 720
HERE = os.path.dirname(os.path.abspath(__file__))
RNG = np.random.default_rng(1001)


def rgb(hex_colour):
    return np.array([int(hex_colour[i:i + 2], 16) for i in (1, 3, 5)], dtype=np.float64)


def mix(a, b, t):
    t = np.clip(t, 0.0, 1.0)[..., None]
    return a * (1.0 - t) + b * t


def smooth_noise(n, scale, octaves=3):
    """1D value noise over n samples, features about `scale` samples wide."""
    out = np.zeros(n)
    amplitude = 1.0
    for _ in range(octaves):
        knots = RNG.uniform(-1.0, 1.0, int(n / scale) + 3)
        x = np.arange(n) / scale
        i = x.astype(int)
        f = x - i
        f = f * f * (3 - 2 * f)
        out += amplitude * (knots[i] * (1 - f) + knots[i + 1] * f)
        scale /= 2.0
        amplitude /= 2.0
    return out


def paint():
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float64)
    horizon = 0.64 * HEIGHT

    # Sky: indigo to rose to amber, in eight painted bands with soft seams.
    t = np.clip(y / horizon, 0.0, 1.0)
    bands = 8
    banded = np.floor(t * bands) / bands
    seam = np.clip((t * bands - np.floor(t * bands) - 0.85) / 0.15, 0.0, 1.0)
    t = banded + seam / bands
    stops = [(0.0, rgb("#1b1d4a")), (0.45, rgb("#4b2f6b")), (0.75, rgb("#b4587a")), (1.0, rgb("#f0a45c"))]
    sky = np.zeros((HEIGHT, WIDTH, 3))
    for (t0, c0), (t1, c1) in zip(stops, stops[1:]):
        inside = (t >= t0) & (t <= t1)
        sky[inside] = mix(c0, c1, (t[inside] - t0) / (t1 - t0))
    image = sky

    # A low moon with a soft halo.
    mx, my, radius = 0.8 * WIDTH, 0.2 * HEIGHT, 46.0
    distance = np.hypot(x - mx, y - my)
    image = mix(image, rgb("#f6d9a8"), 0.35 * np.exp(-((distance - radius).clip(0) / 70.0) ** 2) * (distance > radius))
    image = mix(image, rgb("#fff1cf"), (radius + 0.5 - distance))
    # Stars in the upper sky.
    for _ in range(70):
        sx, sy = RNG.uniform(0, WIDTH), RNG.uniform(0, 0.38 * HEIGHT)
        size = RNG.uniform(0.8, 1.8)
        image = mix(image, rgb("#fff6e0"), (size - np.hypot(x - sx, y - sy)) * 0.9)

    # Far hills: a cool violet line with a domed city on it.
    far = horizon - 18 - 26 * smooth_noise(WIDTH, 260.0)
    city = np.zeros(WIDTH)
    for cx, width, height, dome in [(250, 70, 46, 30), (315, 40, 30, 18), (380, 90, 58, 40), (455, 36, 24, 16)]:
        xs = np.arange(WIDTH)
        wall = (np.abs(xs - cx) <= width / 2) * height
        dome_h = np.sqrt(np.clip(dome**2 - (xs - cx) ** 2, 0, None)) * (np.abs(xs - cx) <= dome)
        city = np.maximum(city, wall + dome_h * (wall > 0))
    for mx_, tall in [(200, 150), (300, 96), (440, 170), (520, 110)]:
        xs = np.arange(WIDTH)
        city = np.maximum(city, np.maximum((np.abs(xs - mx_) <= 5) * tall, (np.abs(xs - mx_) <= 1) * (tall + 14)))
    far_top = far - city
    image = mix(image, rgb("#5a3f78"), np.clip(y - far_top[None, :] + 0.5, 0, 1))
    # Lit windows in the city.
    for _ in range(26):
        wx = RNG.uniform(190, 530)
        wy = far[int(wx)] - RNG.uniform(8, 40)
        if wy > far_top[int(wx)] + 4:
            image = mix(image, rgb("#ffcc66"), 1.5 - np.maximum(np.abs(x - wx), np.abs(y - wy) / 1.6))

    # Dunes, far to near: warmer and darker, each with a lit crest.
    layers = [
        (horizon + 30, 34.0, 420.0, rgb("#8a4d5e"), rgb("#c9786a")),
        (horizon + 95, 44.0, 520.0, rgb("#a65d4c"), rgb("#e39a62")),
        (horizon + 185, 40.0, 700.0, rgb("#7a3f3a"), rgb("#d8864f")),
    ]
    for base, amplitude, scale, body, crest in layers:
        line = base - amplitude * smooth_noise(WIDTH, scale, octaves=2)
        depth = y - line[None, :]
        shade = mix(crest, body, np.clip(depth / 26.0, 0, 1))
        # The side turned from the low sun, a shade darker, fading in with the slope.
        slope = np.gradient(line)[None, :]
        shade = mix(shade, body * 0.82, np.clip(slope / 0.25, 0, 1) * np.clip((depth - 4) / 14, 0, 1))
        image = mix(image, shade, np.clip(depth + 0.5, 0, 1))

    # Brush grain: long horizontal strokes, a few percent of brightness.
    strokes = np.sin(y * 0.9 + 3.0 * np.sin(x * 0.013 + y * 0.05)) * np.sin(x * 0.021 + y * 0.37)
    image *= (1.0 + 0.025 * np.round(strokes * 2) / 2)[..., None]
    return np.clip(np.round(image), 0, 255)


if __name__ == "__main__":
    write_png(os.path.join(HERE, "magic_carpet_plate.png"), paint())
