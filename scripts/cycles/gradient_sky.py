"""Writes a 512x256 latitude-longitude sky that depends on elevation only (blue zenith, pale
horizon, grey ground) as a Radiance .hdr (flat RGBE scanlines, top row the zenith): the same
light for renderers whose azimuth conventions differ. Plain Python, no packages.

    python gradient_sky.py OUT.hdr
"""
import math
import sys

W, H = 512, 256
ZENITH, HORIZON, GROUND = (0.5, 0.9, 2.0), (1.8, 1.8, 2.0), (0.4, 0.4, 0.4)


def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return bytes(4)
    mant, exp = math.frexp(m)
    s = mant * 256.0 / m
    return bytes([int(c[0] * s), int(c[1] * s), int(c[2] * s), exp + 128])


with open(sys.argv[1], "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W))
    for y in range(H):
        el = math.pi * (0.5 - (y + 0.5) / H)
        if el > 0:
            t = math.sqrt(math.sin(el))
            c = [h + (z - h) * t for z, h in zip(ZENITH, HORIZON)]
        else:
            c = list(GROUND)
        f.write(rgbe(c) * W)
