"""Prints the tables of docs/lpca.md from the stats.json files of scripts/lpca-bench."""
import json
import sys
from pathlib import Path

out = Path(sys.argv[1])


def stats(name):
    return json.loads((out / name / "stats.json").read_text())


def same(a, b):
    return (out / a / "assignments.npy").read_bytes() == (out / b / "assignments.npy").read_bytes()


def per_dim(s):
    rows = {}
    for it in s["outcome"]["iterations"]:
        rows.setdefault(it["dim"], []).append(it)
    return rows


print("## Classification per iteration against subspace dimension (4,096 vertices, k = 128)\n")
print("| dim | LPCA s | SC-LPCA s (of which D, M) | speed-up | LPCA distances | SC-LPCA distances | ratio |")
print("|---|---|---|---|---|---|---|")
a, b = per_dim(stats("dims-lpca")), per_dim(stats("dims-sc-lpca"))
for dim in sorted(a):
    # Last iteration at each dimension (the first at dimension 0 follows seeding).
    x, y = a[dim][-1], b[dim][-1]
    print(f"| {dim} | {x['seconds']:.2f} | {y['seconds']:.2f} ({y['overhead_seconds']:.2f}) | {x['seconds'] / y['seconds']:.1f}x "
          f"| {x['distance_evals']:,} | {y['distance_evals']:,} | {x['distance_evals'] / y['distance_evals']:.1f}x |")
ta = stats("dims-lpca")["outcome"]["classification_seconds"]
tb = stats("dims-sc-lpca")["outcome"]["classification_seconds"]
print(f"\nWhole schedule: LPCA {ta:.1f} s, SC-LPCA {tb:.1f} s ({ta / tb:.1f}x); identical assignments: {same('dims-lpca', 'dims-sc-lpca')}; "
      f"phi {stats('dims-sc-lpca')['outcome']['phi']:.4e}, relative squared error {stats('dims-sc-lpca')['outcome']['relative_squared_error']:.3e}\n")

print("## Against the number of clusters (4,096 vertices, schedule 0:2,4:1,12:1)\n")
print("| k | dim | LPCA s | SC-LPCA s | speed-up | identical |")
print("|---|---|---|---|---|---|")
for k in (32, 64, 128, 256):
    a, b = per_dim(stats(f"k{k}-lpca")), per_dim(stats(f"k{k}-sc-lpca"))
    for dim in sorted(a):
        x, y = a[dim][-1], b[dim][-1]
        print(f"| {k} | {dim} | {x['seconds']:.2f} | {y['seconds']:.2f} | {x['seconds'] / y['seconds']:.1f}x | {same(f'k{k}-lpca', f'k{k}-sc-lpca')} |")

print("\n## Seeding (16,384 vertices, k = 256), then 10 SortMeans iterations\n")
print("| seeding | latency s | distances | phi after seeding + 10 iterations | relative squared error |")
print("|---|---|---|---|---|")
for init in ("random", "distance-sum", "kmeans++", "sortmeans++"):
    o = stats(f"init-{init}")["outcome"]
    lat = o["init"]["seconds"] + (o["initial_classification"]["seconds"] if o.get("initial_classification") else 0.0)
    evals = o["init"]["distance_evals"] + (o["initial_classification"]["distance_evals"] if o.get("initial_classification") else 0)
    print(f"| {init} | {lat:.2f} | {evals:,} | {o['phi']:.4e} | {o['relative_squared_error']:.4e} |")

print("\n## BTF-like data (4096 texels x 256, 32 clusters, l = 8)\n")
print("| dim | LPCA s | SC-LPCA s | speed-up | LPCA distances | SC-LPCA distances |")
print("|---|---|---|---|---|---|")
a, b = per_dim(stats("btf-lpca")), per_dim(stats("btf-sc-lpca"))
for dim in sorted(a):
    x, y = a[dim][-1], b[dim][-1]
    print(f"| {dim} | {x['seconds']:.3f} | {y['seconds']:.3f} | {x['seconds'] / y['seconds']:.1f}x | {x['distance_evals']:,} | {y['distance_evals']:,} |")
print(f"\nidentical assignments: {same('btf-lpca', 'btf-sc-lpca')}")
