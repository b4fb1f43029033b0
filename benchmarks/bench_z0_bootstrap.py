"""A parametric-bootstrap band for z0 (issue 25, fourth pass): what it covers and what it costs.

Run:  uv run python benchmarks/bench_z0_bootstrap.py --skis 1:10 2:5 --replicates 8 --jobs 2

For each ski:noise (shop plan, the independent 1 mm reference bench with seeded noise, as in
``bench_identify_coverage.py``): ``identify_ski`` once; then ``--replicates`` benches simulated
from the *identified* ski (the parametric bootstrap, Efron & Tibshirani 1993, ch. 6: the fit's
own forward model, ``run_bench(contact='continuous')`` at the plan's masses, positions and
10 mm stations, Gaussian noise of the estimated σ, seeds 101, 102, ...), each identified again
from the default start. Printed per ski: the z0 coverage of the truth (determined stations,
modulo the weighted line as in the coverage bench) by the Laplace band (±2 sd), by the
bootstrap band (±2 sd of the replicates' z0 about the fit, line removed) and by both combined
(sd² summed), the median half-widths, and the CPU time of the replicates (load average too).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import PLANS, bench_of, true_ski


def _replicate(args: tuple) -> tuple[np.ndarray, np.ndarray, float]:
    ski, sigma, seed = args
    from skisnow.bench import run_bench
    from skisnow.identify import identify_ski

    plan = PLANS["shop"]
    bench = run_bench(ski, masses=plan["masses"], load_positions=plan["load_positions"],
                      dx=plan["station_step"], noise=sigma, seed=seed, boot_length=0.10,
                      n_elements=1600, contact="continuous")  # fmt: skip
    t0 = time.process_time()
    res = identify_ski(bench)
    return np.asarray(res.ski.camber_x), np.asarray(res.ski.camber_values), time.process_time() - t0


def _line_free(d: np.ndarray, x: np.ndarray, w: np.ndarray) -> np.ndarray:
    a = np.stack([np.ones(x.size), x], axis=1)
    coef = np.linalg.lstsq(a * w[:, None], d * w, rcond=None)[0]
    return d - a @ coef


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["1:10", "2:5"], help="ski:noise_um pairs")
    ap.add_argument("--replicates", type=int, default=8)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    a = ap.parse_args()
    from skisnow.identify import identify_ski

    print(f"load average at start: {os.getloadavg()}")
    print("| ski | noise µm | z0 in Laplace band | in bootstrap band | in both | Laplace 2sd µm | "
          "bootstrap 2sd µm | z0 rms µm | replicates | CPU s per replicate |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for item in a.skis:
        name, noise = item.split(":")
        true = true_ski(name)
        res = identify_ski(bench_of(name, "shop", float(noise), Path(a.cache)))
        s = res.ski
        cx, dz = np.asarray(s.camber_x), np.asarray(s.camber_determined)
        sdz = np.asarray(s.camber_sd)[dz]
        z_fit = np.asarray(s.camber_values)
        err = _line_free((z_fit - true.free_camber(cx))[dz], cx[dz], 1 / sdz)
        jobs = [(s, res.noise, 101 + b) for b in range(a.replicates)]
        with ProcessPoolExecutor(max_workers=a.jobs) as pool:
            reps = list(pool.map(_replicate, jobs))
        dev = np.array([_line_free(np.interp(cx, xr, zr)[dz] - z_fit[dz], cx[dz], 1 / sdz)
                        for xr, zr, _ in reps])  # fmt: skip
        sd_boot = np.sqrt(np.mean(dev**2, axis=0))
        sd_both = np.hypot(sdz, sd_boot)
        cov = [float(np.mean(np.abs(err) <= 2 * v)) for v in (sdz, sd_boot, sd_both)]
        cpu = np.median([r[2] for r in reps])
        print(f"| {name} | {noise} | {100 * cov[0]:.0f} % | {100 * cov[1]:.0f} % | "
              f"{100 * cov[2]:.0f} % | {2e6 * np.median(sdz):.1f} | "
              f"{2e6 * np.median(sd_boot):.1f} | {1e6 * np.sqrt(np.mean(err**2)):.1f} | "
              f"{a.replicates} | {cpu:.1f} |", flush=True)  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
