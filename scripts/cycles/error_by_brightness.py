"""relMSE of each run of scripts/interiors-vs-cycles split over five bands of pixels by the
reference's brightness (fenestra's reference sets the bands; each renderer's runs are measured
against its own reference, as the harness's table is), the median over repetitions: where in
the image one renderer's error is lower than the other's.

Usage: python3 scripts/cycles/error_by_brightness.py OUTDIR
"""

import glob, os, re, sys

import numpy as np
import OpenEXR

out = sys.argv[1]


def rgb(path):
    with OpenEXR.File(path) as f:
        channels = f.channels()
        for name in ("RGB", "RGBA"):
            if name in channels:
                return np.asarray(channels[name].pixels, dtype=np.float64)[..., :3]
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float64) for c in "RGB"], -1)


references = {who: rgb(os.path.join(out, who + "-ref.exr")) for who in ("fenestra", "cycles")}
brightness = references["fenestra"].mean(-1)
edges = np.quantile(brightness, [0.2, 0.4, 0.6, 0.8])
band = np.digitize(brightness, edges)
runs = {}
for path in sorted(glob.glob(os.path.join(out, "*-[0-9]*.exr"))):
    name = os.path.basename(path).rsplit("-", 1)[0]
    reference = references[name.split("-")[0]]
    # The same relative error as `fenestra compare`: squared error over (reference^2 + 0.01).
    rel = ((rgb(path) - reference) ** 2 / (reference**2 + 1e-2)).mean(-1)
    runs.setdefault(name, []).append([rel[band == b].sum() / rel.size for b in range(5)])
print("relMSE by the reference's brightness, darkest fifth of the pixels first:")
print("| technique | " + " | ".join("fifth %d" % (b + 1) for b in range(5)) + " | total |")
print("|---|" + "---|" * 6)
for name, shares in runs.items():
    m = np.median(np.array(shares), axis=0)
    print("| %s | %s | %.3e |" % (name, " | ".join("%.2e" % x for x in m), m.sum()))
