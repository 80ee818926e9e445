"""Automatic light portals (seed 000 ch. 4), estimated as `fenestra portals` estimates them.

    est = fe.portals.estimate(scene)            # keywords: the command's flags (theta=3, ...)
    est.portals        # the portals.json records: kind, center, normal, area, vertices/axes
    est.photons        # float32 (n, 3): where the photons landed
    est.clusters       # each cluster's photon indices, largest first
    est.write("portals.json")
    fe.render(scene, "lp_hf", portals="portals.json")
"""

import json
import os

import numpy as np

from . import _native
from .progress import reporter

__all__ = ["Estimate", "estimate"]


class Estimate:
    """What portal estimation found: portals, the photons and clusters they were fitted to."""

    def __init__(self, scene, document, photons, clusters, summary):
        self._scene = scene
        self.document = json.loads(document)
        self.portals = self.document["portals"]
        self.photons = np.frombuffer(photons, dtype=np.float32).reshape(-1, 3)
        self.clusters = [np.asarray(c, dtype=np.int64) for c in clusters]
        self.summary = summary

    def write(self, path):
        """Writes portals.json, which `render(..., portals=path)` reads: whole or not at all
        (through a temporary file beside it), and never over a file of the scene it was
        estimated from (as `fenestra portals` refuses)."""
        text = json.dumps(self.document, indent=2) + "\n"
        _native.write_portals(self._scene, text, os.fspath(path))

    def __len__(self):
        return len(self.portals)

    def __repr__(self):
        return f"<fenestra.portals.Estimate: {self.summary}>"


def estimate(scene, *, threads=None, backend=None, progress=True, **options):
    """Estimates `scene`'s portals (a Scene, or what `fenestra.load` takes). Keywords are
    `fenestra portals`'s flags with underscores (theta, rays, radius, deposit, photons,
    max_beams, settle, eps, min_points, ransac_eps, ransac_tau, ransac_trials, mvce_eps, model,
    seed); None leaves one at its default. Ctrl-C stops it and raises KeyboardInterrupt."""
    from . import Scene, load

    if not isinstance(scene, Scene):
        scene = load(scene)
    options = {name: value for name, value in options.items() if value is not None}
    with reporter(progress) as report:
        found = _native.estimate(
            scene, json.dumps(options), threads=threads, backend=backend, progress=report
        )
    return Estimate(scene, *found)
