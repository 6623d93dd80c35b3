#!/usr/bin/env python3
"""Writes a small synthetic Bakery SH set (formats/bakers/bakery-sh.json) and a mesh covering it.

Usage: make_bakery_set.py DIR  ->  DIR/Scene_LM0_L0.hdr (Radiance RGBE, flat scanlines),
DIR/Scene_LM0_L1x.tga, _L1y.tga, _L1z.tga (uncompressed 24-bit, top-left origin) and
DIR/quad.obj (one quad over the whole lightmap, its UVs the lightmap's, normal +z). Deterministic:
plain Python, no random numbers, the same bytes on every run.
"""
import math
import os
import struct
import sys

W = H = 48


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mant, e = math.frexp(m)
    scale = mant * 256.0 / m
    return bytes((int(r * scale), int(g * scale), int(b * scale), e + 128))


def main(out):
    os.makedirs(out, exist_ok=True)
    base = os.path.join(out, "Scene_LM0")
    # L0: a smooth coloured gradient, strictly positive (the L1 ratios divide by it).
    l0 = [[(0.4 + 0.5 * x / W, 0.3 + 0.6 * y / H, 0.5 + 0.3 * math.sin(0.2 * (x + y))) for x in range(W)] for y in range(H)]
    with open(base + "_L0.hdr", "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W))
        for row in l0:
            for r, g, b in row:
                f.write(rgbe(r, g, b))
    # L1 per axis: t = L1/(4 L0) + 0.5 in 8 bits, kept well inside (0, 1).
    for axis, (fx, fy, phase) in {"x": (0.13, 0.07, 0.0), "y": (0.05, 0.11, 1.0), "z": (0.09, 0.04, 2.0)}.items():
        with open(base + "_L1%s.tga" % axis, "wb") as f:
            f.write(struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, W, H, 24, 0x20))
            for y in range(H):
                for x in range(W):
                    t = [0.5 + 0.25 * math.sin(fx * x + fy * y + phase + c) for c in range(3)]
                    r, g, b = (int(round(255 * v)) for v in t)
                    f.write(bytes((b, g, r)))
    with open(os.path.join(out, "quad.obj"), "w") as f:
        f.write("o quad\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n")
        f.write("vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n")
        f.write("f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")


if __name__ == "__main__":
    main(sys.argv[1])
