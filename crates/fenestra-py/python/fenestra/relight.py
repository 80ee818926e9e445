"""Relighting animations (seed 003 ch. 4) from Python: a precomputation made by `fenestra
relight precompute` opened once, its frames relit under lights given as dicts.

    seq = fe.relight.open("precomputed/")
    seq.frames, seq.lights         # frame count; its own lights (dicts of the lights file)
    img = seq.relight(0)           # an Image, as `fenestra relight render` relights frame 0
    lamp = dict(seq.lights[0], intensity=[20, 18, 15])
    seq.relight(5, lights=[lamp])  # frame 5 under other lights

A light is {"type": "point", "position": [x, y, z], "intensity": [r, g, b]}, {"type":
"spot", "position", "direction", "intensity", "cone_angle", "falloff_start"} or {"type":
"distant", "direction", "irradiance"} (W/sr, W/m^2, degrees): the lights file's entries.
"""

import json

import numpy as np

from . import _native
from .image import Image

__all__ = ["Sequence", "open"]


class Sequence:
    """An opened precomputation."""

    def __init__(self, native, folder):
        self._native = native
        self.folder = folder
        self.frames = native.frames
        self.lights = json.loads(native.lights_json())["lights"]

    def relight(self, frame, lights=None, indirect_only=False):
        """Frame `frame` relit under `lights` (a list of light dicts; default its own), or
        its indirect light alone."""
        text = None if lights is None else json.dumps({"lights": list(lights)})
        data, width, height, seconds = self._native.relight(frame, text, indirect_only)
        array = np.frombuffer(data, dtype=np.float32).reshape(height, width, 3)
        return Image(array, stats={"frame": frame, "time_s": seconds})

    def __repr__(self):
        return f"<fenestra.relight.Sequence {self.folder}: {self.frames} frames, {len(self.lights)} lights>"


def open(folder, *, light_samples=16, threads=None):
    """Opens the precomputation in `folder` (`light_samples` per area light, as `fenestra
    relight render --light-samples`)."""
    return Sequence(_native.open(str(folder), light_samples=light_samples, threads=threads), str(folder))
