"""Where the identification's EI error and the bands' under-coverage come from (issue 25, item 1).

Run:  uv run python benchmarks/bench_identify_diagnosis.py [--skis 1 2 3 4] [--noise-um 5]
      [--variants default clean truth lam0.1 lam10 lam1000 n30 n120] [--out FILE]

For each ski (``skisnow.bench.random_ski``) the shop plan of
``benchmarks/bench_identify_coverage.py`` (6 masses at 2 positions, stations every 10 mm) on the
independent reference bench at 1 mm, seeded noise; then ``identify_ski`` in variants that
separate the causes:

* ``default``: as shipped (GCV λ, 60 log-EI coefficients);
* ``clean``: the noise-free bench with the noise σ given: what is left is bias (smoothing, basis,
  mesh), not noise;
* ``truth``: started at the true ski: a local-minimum / optimiser cause shows as a difference
  from ``default``;
* ``lamX``: λ fixed at X (smoothing weight: too strong → bias, too weak → variance);
* ``nK``: K log-EI coefficients (resolution of the basis);
* ``gcv`` / ``evidence``: λ by GCV / by the Laplace evidence, bands with the smoothing-bias term
  (``gcv-nb`` / ``evidence-nb`` without it, ``gcv-disc`` with the model discrepancy too);
* ``basis``: not a fit: the best least-squares approximation of the true log EI in the spline
  basis of 60 coefficients over the determined span (the floor a perfect fit could reach).

Printed per row: EI rms [%] and z0 rms [µm] over the determined stations (as the coverage
benchmark), the shares inside the 95 % bands, the rms of the standardised errors (error / sd; 1
for calibrated bands), the chosen λ and the misfit. Rows are appended to ``--out`` (JSON lines)
as they finish. Report the load average (``uptime``) with the times.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import itertools
import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from bench_identify_coverage import bench_of, errors, true_ski


def zscores(res, true) -> tuple[float, float]:
    """rms of error / sd over determined stations: EI (log), z0 (modulo the weighted line)."""
    s = res.ski
    ex, de = np.asarray(s.stiffness_x), np.asarray(s.stiffness_determined)
    le = np.log(np.asarray(s.stiffness_values) / true.stiffness(ex))
    ze = le[de] / np.asarray(s.stiffness_log_sd)[de]
    cx, dz = np.asarray(s.camber_x), np.asarray(s.camber_determined)
    sdz = np.asarray(s.camber_sd)[dz]
    d = (np.asarray(s.camber_values) - true.free_camber(cx))[dz]
    a = np.stack([np.ones(d.size), cx[dz]], axis=1)
    w = 1.0 / np.maximum(sdz, 1e-7) ** 2
    coef = np.linalg.solve(a.T @ (a * w[:, None]), a.T @ (w * d))
    zz = (d - a @ coef) / sdz
    return float(np.sqrt(np.mean(ze**2))), float(np.sqrt(np.mean(zz**2)))


def basis_floor(true, n: int, span: tuple[float, float]) -> float:
    """rms [%] of the best spline approximation of the true log EI (n coefficients on the
    identification's uniform knots over the running surface), over ``span`` at 20 mm."""
    from skisnow.identify._model import _design, _uniform_bspline

    t, _ = _uniform_bspline(true.x_tail, true.x_tip, n)
    xf = np.linspace(true.x_tail, true.x_tip, 4000)
    coef = np.linalg.lstsq(_design(t, xf), np.log(true.stiffness(xf)), rcond=None)[0]
    xs = np.arange(max(span[0], -0.45), min(span[1], 0.40), 0.02)
    err = _design(t, xs) @ coef - np.log(true.stiffness(xs))
    return float(100 * np.sqrt(np.mean(np.expm1(err) ** 2)))


def along(res, true, step: float = 0.1) -> str:
    """EI error [%] (rms) in windows of ``step`` along the determined span, tail to tip:
    where the error is (the span's ends or everywhere)."""
    s = res.ski
    ex, de = np.asarray(s.stiffness_x), np.asarray(s.stiffness_determined)
    err = 100 * np.expm1(np.log(np.asarray(s.stiffness_values) / true.stiffness(ex)))
    x, e = ex[de], err[de]
    if x.size == 0:
        return ""
    edges = np.arange(np.floor(x[0] / step) * step, x[-1] + step, step)
    out = []
    for a, b in itertools.pairwise(edges):
        m = (x >= a) & (x < b)
        if m.any():
            out.append(f"{a * 1e3:.0f}:{np.sqrt(np.mean(e[m] ** 2)):.1f}")
    return " ".join(out)


def run(args: tuple) -> dict:
    name, noise_um, variant, cache, plan, dx_mm = args
    from skisnow.identify import identify_ski

    true = true_ski(name)
    kw: dict = {}
    if variant == "clean":
        bench = bench_of(name, plan, 0.0, Path(cache), dx_mm)
        kw["noise"] = noise_um * 1e-6
    else:
        bench = bench_of(name, plan, noise_um, Path(cache), dx_mm)
    if variant == "truth":
        kw["initial"] = true
    elif variant in ("gcv", "evidence", "gcv-nb", "evidence-nb", "gcv-disc"):
        # -nb: bands without the smoothing-bias term; -disc: with the model discrepancy
        kw["criterion"] = variant.split("-")[0]
        kw["smoothing_bands"] = not variant.endswith("-nb")
        kw["discrepancy_bands"] = variant.endswith("-disc")
    elif variant.startswith("lam"):
        kw["regularisation"] = float(variant[3:])
    elif variant.startswith("n") and variant[1:].isdigit():
        kw["n_stiffness"] = int(variant[1:])
    t0 = time.process_time()
    res = identify_ski(bench, **kw)
    cpu = time.process_time() - t0
    e = errors(res, true)
    z_e, z_z = zscores(res, true)
    span = np.asarray(res.ski.stiffness_x)[np.asarray(res.ski.stiffness_determined)]
    return {
        "ski": name, "plan": plan, "dx_mm": dx_mm, "noise": noise_um, "variant": variant, **e,
        "along": along(res, true), "causes": ",".join(res.causes), "nfev": res.n_evaluations,
        "z_ei": z_e, "z_z0": z_z,
        "lam": res.regularisation, "misfit": res.misfit, "exit": 0 if res.converged else 3,
        "cpu": cpu, "basis60": basis_floor(true, 60, (span[0], span[-1])),
        "basis30": basis_floor(true, 30, (span[0], span[-1])),
        "basis120": basis_floor(true, 120, (span[0], span[-1])),
    }  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["1", "2", "3", "4"])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0])
    ap.add_argument("--variants", nargs="+",
                    default=["default", "clean", "truth", "lam0.1", "lam10", "lam1000", "n30",
                             "n120"])  # fmt: skip
    ap.add_argument("--plan", default="shop", choices=["shop", "full"])
    ap.add_argument("--dx-mm", type=float, default=1.0,
                    help="grid of the reference bench [mm] (issue 25: 1 mm)")  # fmt: skip
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument("--out", default="identify_diagnosis.jsonl")
    a = ap.parse_args()
    jobs = [(s, n, v, a.cache, a.plan, a.dx_mm)
            for s in a.skis for n in a.noise_um for v in a.variants]  # fmt: skip
    print(f"load average at start: {os.getloadavg()}")
    cols = [
        "ski",
        "noise",
        "variant",
        "ei_rms",
        "z0_rms",
        "ei_in",
        "ei_n",
        "z0_in",
        "z0_n",
        "z_ei",
        "z_z0",
        "lam",
        "misfit",
        "exit",
        "cpu",
        "basis30",
        "basis60",
        "basis120",
        "causes",
        "along",
    ]
    print(" | ".join(cols))
    with ProcessPoolExecutor(max_workers=max(1, a.jobs)) as pool, open(a.out, "a") as fh:
        for row in pool.map(run, jobs):
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            print(" | ".join(f"{row[c]:.3g}" if isinstance(row[c], float) else str(row[c])
                             for c in cols), flush=True)  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
