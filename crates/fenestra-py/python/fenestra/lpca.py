"""Local PCA (seed 003 ch. 3) on NumPy matrices, as `fenestra lpca` runs it.

    fit = fe.lpca.fit(data, clusters=16)                  # SortCluster-LPCA, seed 003's schedule
    fit.assignments, fit.distances                        # each row's cluster and distance
    fit.means[k], fit.bases[k]                            # subspace k: (d,) and (dim, d)
    fe.lpca.fit(data, 16, algorithm="lpca").assignments   # the same (SC-LPCA == LPCA)
    fit.classify(other_rows)                              # the nearest subspace of new rows

A schedule of "0:N" makes it k-means (algorithm "lpca") or SortMeans ("sc-lpca").
"""

import json

import numpy as np

from . import _native

__all__ = ["Fit", "fit"]


def _rows(data):
    a = np.ascontiguousarray(data, dtype="<f4")
    if a.ndim != 2:
        raise ValueError(f"expected a matrix (rows, columns), got shape {a.shape}")
    return a.tobytes(), a.shape


class Fit:
    """Fitted local subspaces: assignments and distances of the rows they were fitted to,
    each subspace's mean and orthonormal basis, and the run's statistics (phi, relative
    squared error, seeding and every iteration, as `fenestra lpca` writes them)."""

    def __init__(self, assignments, distances, models, stats):
        self.assignments = np.frombuffer(assignments, dtype="<u4")
        self.distances = np.frombuffer(distances, dtype="<f8")
        self.means = [np.frombuffer(m, dtype="<f8") for m, _ in models]
        self.bases = [
            np.frombuffer(b, dtype="<f8").reshape(-1, len(mean))
            for (_, b), mean in zip(models, self.means)
        ]
        self.stats = json.loads(stats)
        self.phi = self.stats["phi"]
        self.relative_squared_error = self.stats["relative_squared_error"]

    def classify(self, data):
        """The nearest subspace of each row of `data` and the distance to it."""
        values, shape = _rows(data)
        models = [(m.tolist(), b.ravel().tolist()) for m, b in zip(self.means, self.bases)]
        assign, dist = _native.classify(values, shape, models)
        return np.frombuffer(assign, dtype="<u4"), np.frombuffer(dist, dtype="<f8")

    def __repr__(self):
        return (f"<fenestra.lpca.Fit {len(self.means)} subspaces, phi {self.phi:.6e}, "
                f"relative squared error {self.relative_squared_error:.4e}>")


def fit(data, clusters, *, schedule=None, algorithm=None, init=None, seed=0, threads=None):
    """Fits `clusters` local subspaces to the rows of `data` (float32 matrix). schedule:
    "dim:iterations,..." (default seed 003's "0:15,2:10,4:7,8:5,12:4,16:2,24:1"); algorithm:
    "sc-lpca" (default) or "lpca"; init: "sortmeans++" (default), "kmeans++", "random" or
    "distance-sum"; threads: workers (default all cores; the result is the same for any)."""
    values, shape = _rows(data)
    return Fit(*_native.fit(values, shape, clusters, schedule=schedule, algorithm=algorithm,
                            init=init, seed=seed, threads=threads))
