"""The bench noise estimated without ``--noise-mm`` at 2-20 mm stations (issue 25, item 3).

Run:  uv run python benchmarks/bench_noise_estimator.py [--skis 5 6 1001 1002 1003 issue25]
      [--seeds 1-20] [--noise-um 5]

Benches from the independent reference bench (``skisnow.bench.reference_bench``: finite
differences in mixed form at 1 mm, contact at every node; never the fit's forward model) of
random plausible skis and issue 25's ski, noise-free at 2 mm stations (cached), subsampled to 4,
10 and 20 mm, seeded Gaussian noise added. Two plans: ``shop`` (20-120 kg at -40 and -120 mm,
12 profiles) and ``three`` (20, 40, 60 kg at -120 mm). Two estimators of
:func:`skisnow.identify._noise.estimate_noise`: ``single`` (each profile's fourth differences,
``across=False``: the estimator before the fourth pass) and ``across`` (the deviations from the
mean of the profiles at the same stations, the default now). Printed per plan × spacing ×
estimator: the mean estimate over skis × seeds relative to the truth (target: within ±15 %),
its range, its scatter, and the share of runs whose 95 % interval (``NoiseEstimate.interval``)
holds the truth.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import PLANS, _skis, true_ski

SPACINGS_MM = (2, 4, 10, 20)
SUBPLANS = {"shop": None, "three": ((20.0, 40.0, 60.0), -120.0)}


def clean_bench(name: str, cache: Path):
    """The noise-free shop plan of ``name`` at 2 mm stations (cached)."""
    from skisnow.bench import read_bench, reference_bench, write_bench

    cache.mkdir(parents=True, exist_ok=True)
    path = cache / f"ref_{name}_shop_2mmstations_1mm.csv"
    if path.exists():
        return read_bench(path).table
    plan = {**PLANS["shop"], "station_step": 0.002}
    bench = reference_bench(true_ski(name), **plan, dx=1e-3)
    write_bench(bench, path)
    return bench.table


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["5", "6", "1001", "1002", "1003", "issue25"])
    ap.add_argument("--seeds", default="1-20", help="a range a-b of noise seeds")
    ap.add_argument("--noise-um", type=float, default=5.0)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    a = ap.parse_args()
    from skisnow.identify._noise import estimate_noise

    lo, hi = (int(v) for v in a.seeds.split("-"))
    sigma = a.noise_um * 1e-6
    print(f"load average at start: {os.getloadavg()}")
    rows: dict = {}
    for name in _skis(a.skis):
        t = clean_bench(name, Path(a.cache))
        for plan, sub in SUBPLANS.items():
            sel = t if sub is None else t[t.mass_kg.isin(sub[0]) & (t.load_position_mm == sub[1])]
            for dx in SPACINGS_MM:
                grid = sel[np.isclose(np.round(sel.x_mm) % dx, 0.0)] if dx > 2 else sel
                groups = [(g.x_mm.to_numpy() * 1e-3, g.height_mm.to_numpy() * 1e-3)
                          for _, g in grid.groupby(["mass_kg", "load_position_mm"])]  # fmt: skip
                for seed in range(lo, hi + 1):
                    rng = np.random.default_rng(seed)
                    prof = [(x, h + rng.normal(0.0, sigma, h.size)) for x, h in groups]
                    for est, across in (("single", False), ("across", True)):
                        e = estimate_noise(prof, across=across)
                        inside = e.interval[0] <= sigma <= e.interval[1]
                        rows.setdefault((plan, dx, est), []).append((e.pooled / sigma, inside))
    print("| plan | stations mm | estimator | mean / truth | range | scatter (sd) | "
          "interval holds the truth | runs |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for (plan, dx, est), v in rows.items():
        r = np.array([x[0] for x in v])
        cov = np.mean([x[1] for x in v])
        print(f"| {plan} | {dx} | {est} | {r.mean():.3f} | {r.min():.2f}-{r.max():.2f} | "
              f"{r.std():.3f} | {100 * cov:.0f} % | {r.size} |")  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
