"""The opt-in population prior against the default fit (issue 25, eighth pass).

Run:  uv run python benchmarks/bench_identify_prior.py [--skis 1001 1002 1003 issue25]
      [--plans shop full] [--noise-um 5] [--jobs 2] [--out FILE]

For each ski (``bench_identify_coverage.true_ski``), plan and noise, on the independent reference
bench (``bench_identify_coverage.bench_of``: 1 mm finite differences, seeded noise, seed 1):
``identify_ski`` with its defaults, then with ``prior=population_prior(kind)`` (2000 skis of
``skisnow.bench.random_ski`` of the ski's kind, seeds 100000-101999, floors 0.05 in log EI and
2 µm in z0: chosen before any fit was run, from ``bench_identify_limit.py``'s linear study).
Nothing is tuned on these skis: every row is a prediction. Printed per fit: EI rms [%] over the
determined stations within -450…+400 mm (as ``bench_identify_coverage.py``) and over all of
-450…+400 mm (``EI win``: the prior changes which stations count as determined), z0 rms [µm]
modulo the line over the determined stations, held-out profiles [µm], misfit [σ], exit code
(0 converged, 3 not) and causes, the shares of determined stations inside the 95 % bands (EI,
z0), CPU s of the identification (the population's draw separately, ``prior CPU``). Skis
1001-1003 are draws of the same generator and issue 25's ski is ``plausible_ski`` with
parameters inside its classic ranges: the prior flatters all four. ``shipped:classic`` and
``shipped:skate`` (``--skis``) are the shipped spline skis (``skisnow.ski.get_ski``, calibrated
to the paper's captions): not of the generator's family, the fair test. Report the load
average.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor
from functools import cache
from pathlib import Path

import numpy as np
from bench_identify_coverage import bench_of, errors, held_out, true_ski

CACHE = Path.home() / ".cache" / "skisnow-identify-bench"


@cache
def _prior(kind: str):
    from skisnow.identify import population_prior

    t0 = time.process_time()
    pr = population_prior(kind)
    return pr, time.process_time() - t0


def window_rms(res, true) -> float:
    """EI rms [%] over every station of -450…+400 mm, determined or not."""
    s = res.ski
    ex = np.asarray(s.stiffness_x)
    m = (ex >= -0.45) & (ex <= 0.40)
    le = np.log(np.asarray(s.stiffness_values)[m] / true.stiffness(ex[m]))
    return float(100 * np.sqrt(np.mean(np.expm1(le) ** 2)))


def run(args: tuple) -> dict:
    name, plan, noise, variant, cache_dir = args
    from skisnow.identify import identify_ski

    true = true_ski(name)
    bench = bench_of(name, plan, noise, Path(cache_dir))
    kw, prior_cpu = {}, 0.0
    if variant == "prior":
        kw["prior"], prior_cpu = _prior(true.kind)
    t0 = time.process_time()
    res = identify_ski(bench, **kw)
    cpu = time.process_time() - t0
    return {"ski": name, "plan": plan, "noise": noise, "variant": variant, **errors(res, true),
            "ei_win": window_rms(res, true), "held_out": held_out(res.ski, true),
            "misfit": res.misfit, "exit": 0 if res.converged else 3,
            "causes": ",".join(res.causes), "cpu": cpu, "prior_cpu": prior_cpu,
            "load": os.getloadavg()[0]}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["1001", "1002", "1003", "issue25"])
    ap.add_argument("--plans", nargs="+", default=["shop", "full"])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0])
    ap.add_argument("--variants", nargs="+", default=["default", "prior"])
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--cache", default=str(CACHE))
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    jobs = [(s, p, n, v, a.cache) for p in a.plans for s in a.skis for n in a.noise_um
            for v in a.variants]  # fmt: skip
    print(f"load average at start: {os.getloadavg()}")
    print("| ski | plan | noise µm | fit | EI rms % | EI win % | z0 rms µm | held-out µm | "
          "misfit σ | exit | EI in band | z0 in band | CPU s | prior CPU s | load |")  # fmt: skip
    print("| " + " | ".join(["---"] * 15) + " |")
    with ProcessPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for r in pool.map(run, jobs):
            if a.out:
                with open(a.out, "a") as fh:
                    fh.write(json.dumps(r) + "\n")
            print(f"| {r['ski']} | {r['plan']} | {r['noise']:g} | {r['variant']} | "
                  f"{r['ei_rms']:.2f} | {r['ei_win']:.2f} | {r['z0_rms']:.2f} | "
                  f"{r['held_out']:.2f} | {r['misfit']:.3f} | {r['exit']} {r['causes']} | "
                  f"{r['ei_in']}/{r['ei_n']} | {r['z0_in']}/{r['z0_n']} | {r['cpu']:.1f} | "
                  f"{r['prior_cpu']:.1f} | {r['load']:.1f} |", flush=True)  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
