"""Writes a 512x256 latitude-longitude sky that depends on elevation only (blue zenith, pale
horizon, grey ground), as a linear EXR: the same light for renderers whose azimuth conventions
differ. Runs under bpy's Python (Blender writes the EXR).

    python gradient_sky.py -- OUT.exr
"""
import math
import sys

import bpy

out = sys.argv[sys.argv.index('--') + 1]
W, H = 512, 256
zenith, horizon, ground = (0.5, 0.9, 2.0), (1.8, 1.8, 2.0), (0.4, 0.4, 0.4)
img = bpy.data.images.new('sky', W, H, float_buffer=True, alpha=False)
px = []
for y in range(H):  # Blender's rows run bottom to top
    el = math.pi * ((y + 0.5) / H - 0.5)
    if el > 0:
        t = math.sqrt(math.sin(el))
        c = [h + (z - h) * t for z, h in zip(zenith, horizon)]
    else:
        c = list(ground)
    px.extend((c + [1.0]) * W)
img.pixels.foreach_set(px)
img.filepath_raw = out
img.file_format = 'OPEN_EXR'
img.save()
