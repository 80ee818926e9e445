"""fenestra from Python: load a scene, render it with any integrator, compare estimators.

    import fenestra as fe
    scene = fe.load("builtin:box-hole")
    ref = fe.render(scene, "af_hf", spp=4096, seed=99)
    img = fe.render(scene, "lp_hf", portals="auto", time=2.0)
    img.array            # float32 (height, width, 3), linear RGB
    fe.compare(img, ref) # MSE, relative MSE, efficiency, error map; z-test with variances

Renders go through the command line's own jobs: `fe.render(scene, **kw)` makes the image
`fenestra render SCENE` makes with the same flags, bit for bit. Integrator options are
keyword arguments named after their flags (`--max-depth` is `max_depth`, `--sdrc-a` is
`sdrc_a`); `fe.options()` lists them with their defaults and help.
"""

import json
import math
import operator

from . import _native
from ._native import FenestraError, Scene
from .image import Comparison, Image, denoise
from .progress import reporter
from . import lpca, portals, relight
from .scene_dict import load_dict

__version__ = _native.VERSION
__all__ = [
    "Comparison",
    "FenestraError",
    "Image",
    "Scene",
    "compare",
    "denoise",
    "integrators",
    "load",
    "load_dict",
    "lpca",
    "merge",
    "options",
    "portals",
    "read",
    "relight",
    "render",
]


def load(source, **scene_options):
    """Loads a scene: "builtin:NAME", or a pbrt-v4, glTF 2.0, OBJ or PLY file.

    Keywords are `fenestra render`'s scene flags: strict, environment (an image file),
    sky=True with sky_turbidity, sky_albedo, sun=(elevation, azimuth) or sun_time and
    location=(latitude, longitude), sun_strength; environment_rotation, environment_strength,
    environment_up ("z", "-y", ...), camera (a glTF camera's name or index).
    """
    if "environment" in scene_options and scene_options["environment"] is not None:
        scene_options["environment"] = str(scene_options["environment"])
    if scene_options.get("camera") is not None:
        scene_options["camera"] = str(scene_options["camera"])
    return _native.load(str(source), **scene_options)


def _plain(name, value):
    """An option's value as JSON holds it (NumPy scalars become numbers; JSON has no NaN or
    infinity, which no option takes)."""
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        raise FenestraError(f"{name}: must be a finite number, got {value!r}")
    if isinstance(value, (bool, int, float, str)):
        return value
    raise TypeError(
        f"{name}: expected a number, text or bool, got {type(value).__name__}"
    )


def _whole(name, value, least):
    """`value` as a Python int (NumPy integers too), at least `least`, or an error naming
    `name`."""
    try:
        n = operator.index(value)
    except TypeError:
        n = None
    if n is None or isinstance(value, bool) or n < least:
        raise FenestraError(f"{name} must be a whole number of at least {least}, got {value!r}")
    return n


def render(
    scene,
    integrator=None,
    *,
    spp=None,
    time=None,
    seed=0,
    threads=None,
    resolution=None,
    samples=None,
    crop=None,
    backend=None,
    progress=True,
    options=None,
    features=False,
    denoise=False,
    **keywords,
):
    """Renders `scene` (a Scene, or what `load` takes) with `integrator` (default: the
    command line's, af_hf) and returns an Image.

    spp: samples per pixel (default: the scene's; with time, a cap). time: seconds to
    render for, preparation included. seed: a pixel's samples depend only on it, the pixel
    and the sample index. threads: workers (default: all cores). resolution: (width,
    height). samples=(a, b): only sample indices a..b-1 of every pixel (a piece of a split
    render; `merge` joins the pieces). crop=(x0, y0, x1, y1): only that tile. backend:
    "embree" or "obvhs". progress: True for a tqdm bar (if tqdm is installed), False for
    none, or a callable progress(stage, done, total, notes). options: a dict of option keys
    ("sdrc.a") to values; every other keyword is an integrator option by its keyword.
    features: take the denoising features (image.albedo, image.normal). denoise: True (the
    command line's mode, accurate), or a mode ("accurate", "fast") to denoise with Intel Open Image Denoise as `--denoise` does
    (features taken): image.denoised() is then the result, and image.write writes it too.

    The interpreter is released while the render runs. Ctrl-C (KeyboardInterrupt) stops it
    and returns what was rendered, with image.interrupted set.
    """
    if not isinstance(scene, Scene):
        scene = load(scene)
    if spp is not None:
        spp = _whole("spp", spp, 1)
    if time is not None and not (math.isfinite(time) and time > 0):
        raise FenestraError(f"time must be a positive number of seconds, got {time!r}")
    given = dict(options or {})
    given.update(keywords)
    text = json.dumps({name: _plain(name, v) for name, v in given.items()})
    with reporter(progress) as report:
        native = _native.render(
            scene,
            integrator,
            text,
            spp=spp,
            time=time,
            seed=seed,
            threads=threads,
            resolution=None if resolution is None else tuple(resolution),
            samples=None if samples is None else tuple(samples),
            crop=None if crop is None else tuple(crop),
            backend=backend,
            progress=report,
            features=bool(features),
            denoise=bool(denoise),
            denoise_mode=_denoise_mode(denoise),
        )
    image = Image._of_render(native)
    if image.interrupted:
        import warnings

        warnings.warn(
            f"render interrupted: kept {image.stats.get('spp', 0)} samples per pixel",
            stacklevel=2,
        )
    return image


def _denoise_mode(denoise):
    """The mode `render`'s denoise names (None: the default's, or no denoise)."""
    if isinstance(denoise, str):
        return denoise
    if denoise in (True, False, None):
        return None
    raise FenestraError(f"denoise must be True, False or a mode's name, got {denoise!r}")


def merge(parts, total=None):
    """Merges the pieces of a split render (the .exr files their Image.write wrote, or
    their .film files) into the Image one render of them all makes, bit for bit."""
    return Image._of_render(_native.merge([str(p) for p in parts], total))


def read(path):
    """An image file (EXR, HDR, PFM, PNG) as an Image, for comparisons (with its albedo and
    normal if it is an EXR that holds them as layers, as `--features` writes)."""
    return Image._of_file(str(path))


def compare(img, reference, alpha=0.01, region=16):
    """Compares `img` with `reference` (Images, or float32 (height, width, 3) arrays).

    Returns a Comparison: MSE, relative MSE, MAE, image means, 8x8 region error, efficiency
    (1 / (MSE x seconds), when img knows its render time), the per-pixel squared error as
    an array, and, when both carry their variances, the z-test of agreement at `alpha`
    (whole image and region x region blocks) and the image mean's shift in standard errors.
    """
    return Comparison._of(img, reference, alpha, region)


def options():
    """Every integrator option: dicts of key, keyword, group, help, default, choices."""
    return json.loads(_native.options())["options"]


def integrators():
    """Every integrator and light sampler: {"integrators": [...], "light_samplers": [...]},
    each a list of {"name", "about"}."""
    table = json.loads(_native.options())
    return {k: table[k] for k in ("integrators", "light_samplers")}
