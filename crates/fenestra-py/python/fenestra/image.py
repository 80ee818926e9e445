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


class Image:
    """A rendered (or read) image.

    array: float32 (height, width, 3), linear RGB, the mean of each pixel's samples.
    variance: the per-pixel variance of that mean (None for an image read from a file).
    stats: the render's statistics, as the JSON sidecar holds them.
    """

    def __init__(self, array, variance=None, stats=None, native=None):
        self.array = array
        self.variance = variance
        self.stats = stats or {}
        self._native = native

    @classmethod
    def _of_render(cls, native):
        width, height = native.size
        return cls(
            _array(native.pixels(), width, height),
            _array(native.variance(), width, height),
            json.loads(native.stats_json()),
            native,
        )

    @classmethod
    def _of_file(cls, path):
        data, width, height = _native.read_image(path)
        return cls(_array(data, width, height))

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
        `variance`; a piece of a split render also PATH.film), as `fenestra render` does: an
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
