"""Images as NumPy arrays: a render's mean and variance, its statistics, its files."""

import json
import pathlib
import warnings

import numpy as np

from . import _native


def _array(data, width, height):
    return np.frombuffer(data, dtype=np.float32).reshape(height, width, 3)


def _bytes(array):
    a = np.ascontiguousarray(array, dtype="<f4")
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"expected an image of shape (height, width, 3), got {a.shape}")
    return a.tobytes(), (a.shape[1], a.shape[0])


def denoise(array, albedo=None, normal=None, mode=None):
    """`array` (float32 (height, width, 3), linear HDR) denoised by Intel Open Image Denoise's
    RT filter, guided by `albedo` and `normal` (both or neither, of the same shape): "accurate"
    (the default, as the command line's) denoises the guides first (Cycles' default), "fast"
    uses them as they are. Returns a new
    array. OIDN comes with scripts/setup (or FENESTRA_OIDN names its folder)."""
    data, size = _bytes(array)
    guides = [None, None]
    if (albedo is None) != (normal is None):
        raise ValueError("give both albedo and normal, or neither")
    if albedo is not None:
        for i, (name, a) in enumerate((("albedo", albedo), ("normal", normal))):
            guide, guide_size = _bytes(a)
            if guide_size != size:
                raise ValueError(f"{name} is {guide_size[0]}x{guide_size[1]}, the image {size[0]}x{size[1]}")
            guides[i] = guide
    out = _native.denoise(data, size, guides[0], guides[1], mode)
    return _array(out, size[0], size[1]).copy()


class Image:
    """A rendered (or read) image.

    array: float32 (height, width, 3), linear RGB, the mean of each pixel's samples.
    variance: the per-pixel variance of that mean (None for an image read from a file).
    stats: the render's statistics, as the JSON sidecar holds them.
    albedo, normal: the denoising features, float32 (height, width, 3) (None unless the render
    took them: features=True or denoise).
    """

    def __init__(self, array, variance=None, stats=None, native=None, albedo=None, normal=None):
        self.array = array
        self.variance = variance
        self.stats = stats or {}
        self.albedo = albedo
        self.normal = normal
        self._native = native

    @classmethod
    def _of_render(cls, native):
        width, height = native.size
        features = native.features()
        albedo, normal = (None, None) if features is None else (
            _array(features[0], width, height),
            _array(features[1], width, height),
        )
        return cls(
            _array(native.pixels(), width, height),
            _array(native.variance(), width, height),
            json.loads(native.stats_json()),
            native,
            albedo,
            normal,
        )

    def denoised(self, mode=None):
        """The image denoised by Intel Open Image Denoise, guided by its features if it has
        them: the render's own result if it was rendered with `denoise` (and `mode` is None or
        its mode), otherwise denoised now (in `mode`, by default the command line's)."""
        done = (self.stats.get("denoiser") or {}).get("mode")
        if self._native is not None and done is not None and mode in (None, done):
            width, height = self._native.size
            return _array(self._native.denoised(), width, height)
        return denoise(self.array, self.albedo, self.normal, mode)

    @classmethod
    def _of_file(cls, path):
        data, width, height = _native.read_image(path)
        features = _native.read_features(path)
        albedo, normal = (None, None) if features is None else (
            _array(features[0], width, height),
            _array(features[1], width, height),
        )
        return cls(_array(data, width, height), albedo=albedo, normal=normal)

    @property
    def light_paths(self):
        """What light paths brought each pixel (float32 (height, width, 3), the part of `array`
        they carried), or None where the render traced none (and for an image read from a
        file)."""
        data = None if self._native is None else self._native.light_paths()
        if data is None:
            return None
        width, height = self._native.size
        return _array(data, width, height)

    @property
    def interrupted(self):
        """Whether the render was stopped before it finished."""
        return bool(self.stats.get("interrupted", False))

    @property
    def time(self):
        """Seconds the render took, preparation included (None if unknown)."""
        return self.stats.get("time_s")

    def write(self, path, exposure=None, variance=False):
        """Writes PATH.exr with its PNG and JSON sidecar beside it (and PATH.var.exr with
        `variance`; a piece of a split render also PATH.film; the features as the EXR's
        albedo and normal layers; a render made with `denoise` PATH.denoised.exr and
        PATH.denoised.png), as `fenestra render` does: an
        interrupted render never replaces a complete one (it goes to PATH.interrupted.exr,
        with a warning), and one stopped before any sample is not written. Returns the path
        written."""
        if self._native is None:
            raise ValueError("only a render writes its files (this image was read)")
        written, note = self._native.write(str(path), exposure, variance)
        if note is not None:
            warnings.warn(note, stacklevel=2)
        return pathlib.Path(written)

    def png(self, exposure=None):
        """The tone-mapped sRGB PNG the command line writes, as bytes."""
        data, size = _bytes(self.array)
        return _native.png(data, size, exposure)

    def _repr_png_(self):
        return self.png()

    def __repr__(self):
        h, w, _ = self.array.shape
        if self._native is None:
            return f"<fenestra.Image {w}x{h}>"
        return f"<fenestra.Image {w}x{h}: {self._native.summary()}>"


class Comparison:
    """An image measured against a reference (see `fenestra.compare`)."""

    def __init__(self, table, error_map):
        m = table["metrics"]
        self.mse = m["mse"]
        self.rel_mse = m["rel_mse"]
        self.mae = m["mae"]
        self.mean = m["mean"]
        self.ref_mean = m["ref_mean"]
        self.region_error = m["region_error"]
        self.worst_share = m["worst_share"]
        self.efficiency = table["efficiency"]
        self.error_map = error_map
        self.agreement = table.get("agreement")
        shift = table.get("mean_shift")
        self.mean_shift = None if shift is None else shift["relative"]
        self.z = None if shift is None else shift["z"]

    @classmethod
    def _of(cls, img, reference, alpha, region):
        a = img.array if isinstance(img, Image) else img
        r = reference.array if isinstance(reference, Image) else reference
        (da, size), (dr, size_r) = _bytes(a), _bytes(r)
        if size != size_r:
            raise ValueError(f"the image is {size[0]}x{size[1]}, the reference {size_r[0]}x{size_r[1]}")
        va = img.variance if isinstance(img, Image) else None
        vr = reference.variance if isinstance(reference, Image) else None
        both = va is not None and vr is not None
        time = img.time if isinstance(img, Image) else None
        table = json.loads(
            _native.compare(
                da,
                dr,
                size,
                time,
                _bytes(va)[0] if both else None,
                _bytes(vr)[0] if both else None,
                alpha,
                region,
            )
        )
        error_map = ((np.asarray(a, np.float64) - np.asarray(r, np.float64)) ** 2).mean(axis=2)
        return cls(table, error_map.astype(np.float32))

    @property
    def agrees(self):
        """Whether the z-test finds the two estimates agree (None without variances)."""
        if self.agreement is None:
            return None
        return self.agreement["whole"]["passed"] and self.agreement["regions"]["passed"]

    def __repr__(self):
        parts = [f"MSE {self.mse:.4g}", f"rel. MSE {self.rel_mse:.4g}"]
        if self.efficiency is not None:
            parts.append(f"efficiency {self.efficiency:.4g}")
        if self.z is not None:
            parts.append(f"mean shift {100 * self.mean_shift:+.3f}% (z = {self.z:+.2f})")
        if self.agrees is not None:
            parts.append("agrees" if self.agrees else "DISAGREES")
        return "<fenestra.Comparison " + ", ".join(parts) + ">"
