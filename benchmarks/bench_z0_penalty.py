"""Does the penalty pull the fit started at the truth into the z0 bowl? (issue 25, ninth pass)

Run:  nice -n 10 uv run python benchmarks/bench_z0_penalty.py --store ~/.cache/skisnow-hac
          1002:5 1002:10 1003:10 issue25:10 20:5 22:5 24:5

On shop fits cached by ``bench_band_variants.py --fit``: the fit's own refit
(``bench_z0_basins.refit``, the fit's problem) started at the projected truth
(``bench_z0_basins.py``'s ``truth`` row), under penalties that differ only in one term:

* ``default``: the fit's λ, λ₁ = 1 (the trend term), the ridges on log EI and z0;
* ``λ/100``: the log-EI smoothness a hundred times weaker;
* ``weak trend``: λ₁ = 10⁻⁴;
* ``λ ×100``: the smoothness a hundred times stronger.

Printed: z0 rms µm and EI rms % at the end of each (errors as ``bench_z0_basins.py``), and the
misfit. If a weaker penalty leaves the truth-started fit near the truth's z0, the penalty pulls
the bowl; if not, the data (noise and the bench's model error) do.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from bench_band_variants import STORE
from bench_z0_basins import Scorer, load, refit
from bench_z0_linear_error import truth_parameters

import skisnow.identify._model as model

VARIANTS = {
    "default": (1.0, 1.0),
    "λ/100": (0.01, 1.0),
    "weak trend": (1.0, 1e-4),
    "λ ×100": (100.0, 1.0),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("items", nargs="+", help="ski:noise_um")
    ap.add_argument("--store", default=str(STORE))
    a = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    print("| ski | noise µm | fit λ | penalty | z0 rms µm | EI rms % | misfit σ | CPU s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    lam1 = model._LAMBDA_1
    for item in a.items:
        name, noise = item.split(":")
        g = load(Path(a.store).expanduser(), name, float(noise))
        sc = Scorer(g, name)
        pr, lam = sc.pr, g["lam"]
        p_t = truth_parameters(pr, name)
        for label, (scale, l1) in VARIANTS.items():
            model._LAMBDA_1 = l1
            t0 = time.process_time()
            sc.lam = lam * scale  # the refit's λ; the scores' penalty after λ₁ is restored
            try:
                sol = refit(sc, p_t)
            finally:
                model._LAMBDA_1 = lam1
            r = sc.at(lam * scale).row(sol)
            print(f"| {name} | {noise} | {lam:g} | {label} | {r['z0_rms']:.1f} | "
                  f"{r['ei_rms']:.2f} | {r['misfit']:.4f} | {time.process_time() - t0:.1f} |",
                  flush=True)  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
