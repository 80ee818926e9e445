"""The tables of scripts/denoise-vs-cycles: each run's relative MSE (raw and denoised, by
`fenestra compare`) and HDR-FLIP (denoised) against its renderer's own reference, and the
time each technique needs to reach the FLIP that Cycles + OIDN reaches with the largest
budget; a side-by-side picture of the middle budget's denoised images (OUT/side-by-side.png).

Usage: python3 scripts/cycles/clean_image_table.py OUTDIR "2 8 32"    (numpy, OpenEXR,
flip-evaluator)
"""

import glob, json, math, os, struct, subprocess, sys, zlib

import flip_evaluator as flip
import numpy as np
import OpenEXR

out, budgets = sys.argv[1], [float(b) for b in sys.argv[2].split()]
here = os.path.dirname(os.path.abspath(__file__))
fenestra = os.path.join(here, "..", "..", "target", "release", "fenestra")


def rgb(path):
    with OpenEXR.File(path) as f:
        channels = f.channels()
        for name in ("RGB", "RGBA"):
            if name in channels:
                return np.asarray(channels[name].pixels, dtype=np.float32)[..., :3]
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], -1)


def rel_mse(image, reference):
    done = subprocess.run([fenestra, "compare", "--json", "--ref", reference, image],
                          capture_output=True, text=True, check=True)
    return json.loads(done.stdout)[0]["rel_mse"]


def hdr_flip(image, reference):
    clean = lambda a: np.nan_to_num(np.maximum(a, 0), posinf=0)
    return float(flip.evaluate(clean(rgb(reference)), clean(rgb(image)), "HDR")[1])


refs = {who: os.path.join(out, f"{who}-ref.exr") for who in ("fenestra", "cycles")}
rows = {}
for path in sorted(glob.glob(os.path.join(out, "run-*.exr"))):
    name = os.path.basename(path)
    if ".denoised." in name or name.endswith((".albedo.exr", ".normal.exr")):
        continue
    _, who, technique, budget = name[: -len(".exr")].split("-")
    label = f"{who} {technique}"
    ref = refs[who]
    if who == "fenestra":
        stats = json.load(open(path[: -len(".exr")] + ".json"))
        denoised = path[: -len(".exr")] + ".denoised.exr"
        row = dict(seconds=stats["time_s"], spp=stats["spp"], raw=rel_mse(path, ref),
                   filter_s=stats["denoiser"]["time_s"], image=denoised)
    else:  # Cycles writes its denoised image alone
        row = dict(seconds=float(budget), spp=None, raw=None, filter_s=None, image=path)
    row["rel"] = rel_mse(row["image"], ref)
    row["flip"] = hdr_flip(row["image"], ref)
    rows.setdefault(label, {})[float(budget)] = row

fmt = lambda v, f: "-" if v is None else f % v
print("| technique | budget s | seconds | spp | relMSE raw | relMSE denoised | HDR-FLIP denoised | filter s |")
print("|---|---|---|---|---|---|---|---|")
for label, runs in rows.items():
    for b in budgets:
        r = runs[b]
        print("| %s | %g | %.2f | %s | %s | %.3e | %.4f | %s |" % (
            label, b, r["seconds"], fmt(r["spp"], "%d"), fmt(r["raw"], "%.3e"), r["rel"],
            r["flip"], fmt(r["filter_s"], "%.2f")))


def time_to(runs, target):
    """Seconds to reach FLIP `target` by log-log interpolation between budgets (extrapolated
    beyond them from the nearest segment, and said so)."""
    points = sorted((r["seconds"], r["flip"]) for r in runs.values())
    logs = [(math.log(t), math.log(f)) for t, f in points]
    for (t0, f0), (t1, f1) in zip(logs, logs[1:]):
        if f1 <= math.log(target) <= f0 and f0 != f1:
            return math.exp(t0 + (math.log(target) - f0) * (t1 - t0) / (f1 - f0)), ""
    (t0, f0), (t1, f1) = logs[:2] if math.log(target) > logs[0][1] else logs[-2:]
    if f1 >= f0:
        return math.inf, " (FLIP does not fall)"
    return math.exp(t0 + (math.log(target) - f0) * (t1 - t0) / (f1 - f0)), " (extrapolated)"


top = max(budgets)
cycles = rows.get("cycles oidn")
if cycles:
    target = cycles[top]["flip"]
    print()
    print(f"Time to Cycles + OIDN's {top:g}-s HDR-FLIP ({target:.4f}):")
    print()
    print("| technique | seconds | of Cycles' |")
    print("|---|---|---|")
    for label, runs in rows.items():
        t, note = time_to(runs, target)
        print(f"| {label} | {t:.1f}{note} | {t / cycles[top]['seconds']:.2f}x |")


def png(path, pixels):
    """An 8-bit RGB PNG (zlib, no packages beyond numpy)."""
    h, w, _ = pixels.shape
    raw = b"".join(b"\0" + pixels[y].tobytes() for y in range(h))
    chunk = lambda kind, data: (struct.pack(">I", len(data)) + kind + data
                                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


# The middle budget's denoised images beside the references, at one exposure (the fenestra
# reference's log-average luminance to middle grey).
middle = sorted(budgets)[len(budgets) // 2]
ref = rgb(refs["fenestra"])
lum = ref @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
scale = 0.18 / math.exp(np.log(lum[lum > 0] + 1e-6).mean())
tone = lambda a: (np.where(a * scale <= 0.0031308, 12.92 * a * scale,
                           1.055 * np.power(np.clip(a * scale, 0.0031308, 1.0), 1 / 2.4) - 0.055)
                  .clip(0, 1) * 255 + 0.5).astype(np.uint8)
tiles = [rgb(refs["fenestra"])] + [rgb(rows[l][middle]["image"]) for l in rows] + [rgb(refs["cycles"])]
png(os.path.join(out, "side-by-side.png"), tone(np.concatenate(tiles, axis=1)))
print()
print(f"side-by-side.png: fenestra's reference, {', '.join(rows)} at {middle:g} s, "
      "Cycles' reference")
