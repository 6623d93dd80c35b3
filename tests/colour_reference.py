#!/usr/bin/env python3
"""The reference matrices of ColourSpace.NumpyReferenceMatchesEverySpace, computed independently of
ahdpack and OpenColorIO: linear RGB of a space -> linear Rec.709 (D65), derived from the primaries'
and whites' CIE xy (SMPTE RP 177 / the ACES documents S-2014-004 (AP1) and SMPTE ST 2065-1 (AP0))
with a Bradford chromatic adaptation where the whites differ (ACES white -> D65).

Usage: colour_reference.py SPACE   (acescg, aces2065-1, rec2020, p3-d65)
Prints the 3x3 matrix, row-major, 9 numbers on one line (out[r] = sum_c m[r][c] in[c]).
"""
import sys

import numpy as np

D65 = (0.3127, 0.3290)
ACES_WHITE = (0.32168, 0.33767)
SPACES = {
    "rec709": ((0.64, 0.33), (0.30, 0.60), (0.15, 0.06), D65),
    "acescg": ((0.713, 0.293), (0.165, 0.830), (0.128, 0.044), ACES_WHITE),
    "aces2065-1": ((0.7347, 0.2653), (0.0, 1.0), (0.0001, -0.0770), ACES_WHITE),
    "rec2020": ((0.708, 0.292), (0.170, 0.797), (0.131, 0.046), D65),
    "p3-d65": ((0.680, 0.320), (0.265, 0.690), (0.150, 0.060), D65),
}
BRADFORD = np.array([[0.8951, 0.2664, -0.1614], [-0.7502, 1.7135, 0.0367], [0.0389, -0.0685, 1.0296]])


def xyz(xy):
    x, y = xy
    return np.array([x / y, 1.0, (1.0 - x - y) / y])


def rgb_to_xyz(space):
    r, g, b, w = SPACES[space]
    p = np.column_stack([xyz(r), xyz(g), xyz(b)])
    return p * np.linalg.solve(p, xyz(w))  # scale each primary so that RGB (1, 1, 1) is the white, Y = 1


def bradford(src_white, dst_white):
    s, d = BRADFORD @ xyz(src_white), BRADFORD @ xyz(dst_white)
    return np.linalg.inv(BRADFORD) @ np.diag(d / s) @ BRADFORD


def to_rec709(space):
    m = rgb_to_xyz(space)
    white = SPACES[space][3]
    if white != D65:
        m = bradford(white, D65) @ m
    return np.linalg.inv(rgb_to_xyz("rec709")) @ m


if __name__ == "__main__":
    print(" ".join("%.12f" % v for v in to_rec709(sys.argv[1]).flatten()))
