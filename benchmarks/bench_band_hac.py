"""Correlated-residual band variants on cached fits (issue 25, seventh pass: the default bands).

Run:  nice -n 10 uv run python benchmarks/bench_band_variants.py --fit --skis 1-4
          --noise-um 5 10 --jobs 2 --store DIR
      uv run python benchmarks/bench_band_hac.py --store DIR --skis 1-4
          --variants current option hac-auto neff gp-d-150

Prints, per cached fit and variant, the determined stations whose truth lies inside ±2 sd (EI;
z0 modulo the weighted line, as ``bench_identify_coverage.errors``), the median half-widths
(2 sd: % of EI, µm of z0), the fit's z0 error and the variant's CPU time; then the pooled table.
The point estimate is the cached fit's: a variant is the bands only (see
``band_hac_variants``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from band_hac_variants import covariance, profiles
from bench_band_variants import STORE, cached_fits, coverage
from bench_identify_coverage import _skis


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["1-4"])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--store", default=str(STORE))
    ap.add_argument("--variants", nargs="+", default=["current", "hac-auto"])
    ap.add_argument("--plan", default="shop", choices=["shop", "full"],
                    help="the plan of the cached fits (full: only current, option, hac, neff "
                    "— the gp-… variants build one kernel over all bins)")  # fmt: skip
    a = ap.parse_args()
    skis = [*("1001", "1002", "1003", "issue25")] if a.skis == ["validation"] else _skis(a.skis)
    print(f"load average at start: {os.getloadavg()}")
    pooled: dict = {}
    print("| ski | noise µm | variant | note | EI in band | z0 in band | EI 2sd % | z0 2sd µm "
          "| z0 rms µm | CPU s |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for s, n, true, g in cached_fits(a.store, skis, a.noise_um, a.plan):
        for v in a.variants:
            t0 = time.process_time()
            post, note = covariance(g, v)
            prof = profiles(g, post)
            cpu = time.process_time() - t0
            c = coverage(prof, true)
            c["cpu"] = cpu
            pooled.setdefault((n, v), []).append(c)
            print(f"| {s} | {n:g} | {v} | {note} | {c['ei_in']}/{c['ei_n']} | "
                  f"{c['z0_in']}/{c['z0_n']} | {c['ei_hw']:.1f} | {c['z0_hw']:.1f} | "
                  f"{c['z0_rms']:.1f} | {cpu:.2f} |", flush=True)  # fmt: skip
    print("\n| noise µm | variant | fits | EI in band | z0 in band | median EI 2sd % "
          "| median z0 2sd µm | CPU s median |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for (n, v), cs in sorted(pooled.items()):
        ce = sum(c["ei_in"] for c in cs) / max(sum(c["ei_n"] for c in cs), 1)
        cz = sum(c["z0_in"] for c in cs) / max(sum(c["z0_n"] for c in cs), 1)
        print(f"| {n:g} | {v} | {len(cs)} | {100 * ce:.1f} % | {100 * cz:.1f} % | "
              f"{np.median([c['ei_hw'] for c in cs]):.1f} | "
              f"{np.median([c['z0_hw'] for c in cs]):.1f} | "
              f"{np.median([c['cpu'] for c in cs]):.2f} |")  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
