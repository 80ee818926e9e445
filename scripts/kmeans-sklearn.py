"""k-means on the same matrix with scikit-learn (Elkan and Lloyd) and with fenestra (Lloyd =
`--algorithm lpca`, SortMeans = `--algorithm sc-lpca`, schedule 0:N), same k, k-means++
seeding, same number of iterations, same machine. Not part of CI.

    pip install scikit-learn numpy
    python3 scripts/kmeans-sklearn.py bench-out/lpca/prt-knot-16k.npy --clusters 256 --iterations 10

scikit-learn stops early when converged (tol=0 and n_init=1 keep it running the given
iterations). Its times include seeding; fenestra's line reports seeding and classification
separately and their sum.
"""
import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
from sklearn.cluster import KMeans

p = argparse.ArgumentParser()
p.add_argument("data")
p.add_argument("--clusters", type=int, default=256)
p.add_argument("--iterations", type=int, default=10)
p.add_argument("--fenestra", default="target/release/fenestra")
args = p.parse_args()

x = np.load(args.data).astype(np.float32)
print(f"{x.shape[0]} x {x.shape[1]}, k = {args.clusters}, {args.iterations} iterations")
for algorithm in ("lloyd", "elkan"):
    km = KMeans(n_clusters=args.clusters, init="k-means++", n_init=1, max_iter=args.iterations, tol=0.0,
                algorithm=algorithm, random_state=1)
    t = time.perf_counter()
    km.fit(x)
    dt = time.perf_counter() - t
    err = km.inertia_ / float((x.astype(np.float64) ** 2).sum())
    print(f"scikit-learn {algorithm:6s}: {dt:7.2f} s, {km.n_iter_} iterations, relative squared error {err:.4e}")
for algorithm, label in (("lpca", "Lloyd"), ("sc-lpca", "SortMeans")):
    with tempfile.TemporaryDirectory() as d:
        t = time.perf_counter()
        subprocess.run([args.fenestra, "lpca", args.data, "--clusters", str(args.clusters), "--schedule", f"0:{args.iterations}",
                        "--algorithm", algorithm, "--init", "kmeans++", "--seed", "1", "-o", d], check=True, capture_output=True)
        dt = time.perf_counter() - t
        o = json.loads((Path(d) / "stats.json").read_text())["outcome"]
        print(f"fenestra {label:9s}: {dt:7.2f} s wall (seeding {o['init']['seconds']:.2f} s, classification "
              f"{o['classification_seconds']:.2f} s), relative squared error {o['relative_squared_error']:.4e}")
