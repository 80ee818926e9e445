"""fenestra's --sky as `fenestra scene export --sky` writes it (scene-data/sky.exr), turned into
Blender's equirectangular convention (mirrored, half a turn): fenestra's phi runs
counter-clockwise from +X, Blender's u = 0.5 - atan2(y, x) / 2 pi. Needs numpy and OpenEXR.

    python sky_for_blender.py EXPORT/scene-data/sky.exr OUT.exr
"""
import sys

import numpy as np
import OpenEXR

src, dst = sys.argv[1:]
with OpenEXR.File(src) as f:
    rgb = np.asarray(f.channels()["RGB"].pixels)
rgb = np.roll(rgb[:, ::-1], rgb.shape[1] // 2, axis=1)
OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
             {"RGB": np.ascontiguousarray(rgb, dtype=np.float32)}).write(dst)
