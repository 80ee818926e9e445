"""Render a scene exported by `fenestra scene export` with Mitsuba 3; beside OUT.exr, OUT.json
holds the scene's load time, the render's time (kernel compilation included for the LLVM
variant) and the image's mean per channel (Mitsuba's log goes to stdout).

Usage: python render.py SCENE.pbrt VARIANT WIDTHxHEIGHT SPP MAX_DEPTH RR_DEPTH THREADS SEED OUT.exr
"""

import json
import os
import sys
import tempfile
import time

import drjit as dr
import mitsuba as mi
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pbrt_to_mitsuba  # noqa: E402


def main():
    path, variant, resolution, spp, max_depth, rr_depth, threads, seed, out = sys.argv[1:10]
    mi.set_variant(variant)
    dr.set_thread_count(int(threads))
    with tempfile.TemporaryDirectory() as folder:
        scene_dict, replaced = pbrt_to_mitsuba.convert(
            path, int(spp), int(max_depth), int(rr_depth), folder,
            [int(v) for v in resolution.split("x")])
        start = time.perf_counter()
        scene = mi.load_dict(scene_dict)
        loaded = time.perf_counter()
        image = mi.render(scene, seed=int(seed))
        pixels = np.array(image, dtype=np.float64)  # waits for the render to finish
        done = time.perf_counter()
    mi.util.write_bitmap(out, image)
    with open(os.path.splitext(out)[0] + ".json", "w") as f:
        json.dump({
            "variant": variant,
            "load_s": loaded - start,
            "render_s": done - loaded,
            "mean": pixels[..., :3].mean(axis=(0, 1)).tolist(),
            "replaced": replaced,
        }, f)


if __name__ == "__main__":
    main()
