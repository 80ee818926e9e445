"""The report of a render made against a reference image: fenestra's own figures (`fenestra
compare`: relative MSE, mean, region error, efficiency), its convergence curve (relative MSE
after every pass, from the render's sidecar) and the pictures, as one HTML page."""

import html
import json
import math
import os
import shutil
import subprocess


def _curve_svg(points, width=480, height=260):
    """Relative MSE against seconds, both axes logarithmic, as inline SVG."""
    pts = [(p["time_s"], p["rel_mse"]) for p in points if p["time_s"] > 0 and p["rel_mse"] > 0]
    if len(pts) < 2:
        return "<p>Too few passes for a convergence curve.</p>"
    xs, ys = [math.log10(t) for t, _ in pts], [math.log10(e) for _, e in pts]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)

    def sx(x):
        return 50 + (width - 60) * (x - x0) / ((x1 - x0) or 1)

    def sy(y):
        return height - 40 - (height - 60) * (y - y0) / ((y1 - y0) or 1)

    path = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(xs, ys))
    return (
        f'<svg width="{width}" height="{height}" xmlns="http://www.w3.org/2000/svg" font-size="11">'
        f'<polyline fill="none" stroke="#c0392b" stroke-width="2" points="{path}"/>'
        f'<text x="50" y="{height - 10}">{10 ** x0:.3g} s</text>'
        f'<text x="{width - 60}" y="{height - 10}">{10 ** x1:.3g} s</text>'
        f'<text x="2" y="{sy(y1) + 4:.0f}">{10 ** y1:.3g}</text>'
        f'<text x="2" y="{sy(y0) + 4:.0f}">{10 ** y0:.3g}</text>'
        f'<text x="{width / 2 - 60}" y="{height - 10}">time (log), relative MSE (log)</text></svg>'
    )


def write(binary, folder, image, reference):
    """Writes folder/report.html for `image` (fenestra's EXR, its PNG and JSON beside it)
    against `reference`; returns its path."""
    os.makedirs(folder, exist_ok=True)
    out = subprocess.run(
        [binary, "compare", "--ref", reference, image, "--json", "--error-maps"],
        check=True,
        capture_output=True,
        text=True,
    )
    figures = json.loads(out.stdout)[0]
    stem = image[: -len(".exr")]
    with open(stem + ".json") as f:
        sidecar = json.load(f)
    for suffix in (".png", ".error.png"):
        if os.path.dirname(stem) != folder:
            shutil.copy(stem + suffix, os.path.join(folder, "render" + suffix))
    rows = "".join(
        f"<tr><td>{html.escape(k)}</td><td>{v:.6g}</td></tr>"
        for k, v in figures.items()
        if isinstance(v, (int, float))
    )
    page = f"""<!doctype html><meta charset="utf-8"><title>fenestra report</title>
<style>body{{font-family:sans-serif;margin:2em}} td{{padding:2px 12px}} img{{image-rendering:pixelated;width:480px}}</style>
<h1>{html.escape(sidecar.get("scene", ""))}: {html.escape(sidecar.get("integrator", ""))}, {sidecar.get("spp")} spp, {sidecar.get("time_s", 0):.2f} s</h1>
<p>Against {html.escape(reference)}{" (interrupted: partial result)" if sidecar.get("interrupted") else ""}.</p>
<table>{rows}</table>
<h2>Convergence</h2>{_curve_svg(sidecar.get("convergence", []))}
<h2>Image and its error</h2>
<img src="render.png" alt="the render"> <img src="render.error.png" alt="relative squared error">
<p>Error map: per-pixel relative squared error (luminance), 1e-4 black to 10 pale yellow.</p>
"""
    path = os.path.join(folder, "report.html")
    with open(path, "w") as f:
        f.write(page)
    return path
