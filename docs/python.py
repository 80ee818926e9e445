# %% [markdown]
# # fenestra from Python: automatic portals on box-hole, measured
#
# This notebook (a Python file in percent format: open it in Jupyter with jupytext, in VS
# Code, or run it with `python docs/python.py`) reproduces one of fenestra's own results end
# to end: the seed-000 box lit through a hole in its ceiling, rendered at equal time by
# `af_hf` (path tracing with next-event estimation and MIS) and by `lp_hf` with portals
# estimated automatically, measured against a long reference. Install the module first
# (`pip install ./crates/fenestra-py`, see README); `FENESTRA_NOTEBOOK_QUICK=1` runs it small
# (the test suite does).

# %%
import os

import numpy as np

import fenestra as fe

quick = os.environ.get("FENESTRA_NOTEBOOK_QUICK") == "1"
size = (64, 64) if quick else (128, 128)
seconds = 2.0 if quick else 4.0
reference_spp = 1024 if quick else 4096

scene = fe.load("builtin:box-hole")
scene

# %% [markdown]
# The reference: af_hf with many samples, in a seed of its own (a render and its reference
# must not share random numbers).

# %%
reference = fe.render(scene, "af_hf", spp=reference_spp, resolution=size, seed=99)
reference

# %% [markdown]
# Equal time: each technique gets the same seconds, preparation (portal estimation) included.

# %%
techniques = {
    "af_hf": dict(integrator="af_hf"),
    "lp_hf, estimated portals": dict(integrator="lp_hf", portals="auto"),
}
renders = {
    name: fe.render(scene, time=seconds, resolution=size, seed=1, **options)
    for name, options in techniques.items()
}
results = {name: fe.compare(img, reference) for name, img in renders.items()}
for name, c in results.items():
    img = renders[name]
    print(
        f"{name:26} {img.stats['spp']:6d} spp  MSE {c.mse:.3e}  rel. MSE {c.rel_mse:.3e}"
        f"  efficiency {c.efficiency:.4g}"
    )
ratio = results["lp_hf, estimated portals"].efficiency / results["af_hf"].efficiency
print(f"lp_hf with estimated portals: {ratio:.1f}x af_hf's efficiency at {seconds} s each")

# %% [markdown]
# Both techniques estimate the same image: the z-test over the whole image and over 16x16
# blocks, with each render's own variance, finds no difference beyond noise.

# %%
agreement = fe.compare(renders["lp_hf, estimated portals"], renders["af_hf"])
print(agreement)

# %% [markdown]
# Where the error is: each technique's squared error per pixel, on one scale.

# %%
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
if plt is not None:
    top = max(np.percentile(c.error_map, 99.5) for c in results.values())
    fig, axes = plt.subplots(2, 3, figsize=(10, 7), constrained_layout=True)
    tone = lambda a: np.clip(a / (4 * reference.array.mean()), 0, 1) ** (1 / 2.2)
    axes[0, 0].imshow(tone(reference.array))
    axes[0, 0].set_title(f"reference ({reference_spp} spp)")
    for k, (name, c) in enumerate(results.items()):
        axes[0, k + 1].imshow(tone(renders[name].array))
        axes[0, k + 1].set_title(f"{name}\n{renders[name].stats['spp']} spp in {seconds} s")
        im = axes[1, k + 1].imshow(c.error_map, cmap="inferno", vmin=0, vmax=top)
        axes[1, k + 1].set_title(f"squared error, MSE {c.mse:.2e}")
    fig.colorbar(im, ax=axes[1, 1:], shrink=0.8)
    axes[1, 0].axis("off")
    axes[1, 0].text(0, 0.5, f"efficiency ratio\n{ratio:.1f}x", fontsize=16)
    for ax in axes[0]:
        ax.axis("off")
    out = os.environ.get("FENESTRA_NOTEBOOK_FIGURE")
    if out:
        fig.savefig(out, dpi=64)
