#!/usr/bin/env python3
"""Write the irradiance along the normal (I_z) of each path-traced truth bake as a half-float EXR.

Usage: python3 scripts/truth-iz-exr.py OUT_DIR [TRUTH_DIR ...]   (default: tests/data/truth/*)

For each bake folder (truth.json + truth.bin or truth.bin.zst, the layout src/lab/truth_file.cpp
reads): the first plane (normal 0 = the tangent-frame z) times pi, texels outside the coverage
plane set to 0 (the gutters black, as the bake leaves them), written as OUT_DIR/truth_<folder>_iz.exr
(R, G, B half, uncompressed scanlines). This is the wider BC6H corpus of docs/bc6h-real.md
"A wider real corpus: the path-traced bakes' I_z"; feed it to
`EXTRA_DIR=OUT_DIR bash scripts/peer-basis-bc6h.sh ...` or `ahdpack bench bc6h OUT_DIR`.
Standard library only (zstd through the `zstd` command for the .zst bins).
"""
import glob
import json
import math
import os
import struct
import subprocess
import sys


def read_bin(folder):
    path = os.path.join(folder, "truth.bin")
    if os.path.exists(path):
        with open(path, "rb") as f:
            return f.read()
    return subprocess.run(["zstd", "-dc", path + ".zst"], check=True, stdout=subprocess.PIPE).stdout


def attr(name, kind, value):
    return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value


def write_exr(path, w, h, rgb):
    """rgb: w*h*3 floats, row-major, top row first."""
    chans = b"".join(c + b"\0" + struct.pack("<iB3xii", 1, 0, 1, 1) for c in (b"B", b"G", b"R")) + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = (b"\x76\x2f\x31\x01" + struct.pack("<i", 2) + attr("channels", "chlist", chans) +
              attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box) +
              attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0") +
              attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
              attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)) +
              attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line_bytes = w * 3 * 2
    first = len(header) + 8 * h
    offsets = b"".join(struct.pack("<Q", first + y * (8 + line_bytes)) for y in range(h))
    lines = []
    for y in range(h):
        row = rgb[y * w * 3:(y + 1) * w * 3]
        data = b"".join(struct.pack("<%de" % w, *row[c::3]) for c in (2, 1, 0))  # B, G, R
        lines.append(struct.pack("<ii", y, line_bytes) + data)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header + offsets + b"".join(lines))
    os.replace(tmp, path)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    folders = sys.argv[2:] or sorted(glob.glob(os.path.join(os.path.dirname(__file__), "..", "tests", "data", "truth", "*")))
    os.makedirs(out, exist_ok=True)
    for folder in folders:
        with open(os.path.join(folder, "truth.json")) as f:
            j = json.load(f)
        w, h, count = j["width"], j["height"], len(j["normals"])
        n3 = w * h * 3
        raw = read_bin(folder)
        if len(raw) != (count + 3) * n3 * 2:
            sys.exit("%s: truth.bin size does not match truth.json" % folder)
        e0 = struct.unpack_from("<%de" % n3, raw, 0)
        cov = struct.unpack_from("<%de" % n3, raw, (count + 2) * n3 * 2)
        rgb = [0.0] * n3
        for i in range(w * h):
            if cov[i * 3] > 0.5:
                for c in range(3):
                    rgb[i * 3 + c] = e0[i * 3 + c] * math.pi
        dst = os.path.join(out, "truth_%s_iz.exr" % os.path.basename(os.path.normpath(folder)))
        write_exr(dst, w, h, rgb)
        print(dst, "%dx%d" % (w, h))


if __name__ == "__main__":
    main()
