"""Why the full plan's EI is off (issue 25, fourth pass): the fit on 39 cases, stations every 2 mm.

Run:  uv run python benchmarks/bench_identify_full_plan.py --ski issue25 [--dx-mm 1] [--noise-um 5]
      [--variants default truth lam100 n120 n120+lam100 case-cv evidence] [--out FILE]
      uv run python benchmarks/bench_identify_full_plan.py --ski issue25 --reference 1 0.5 0.25

The full plan of ``benchmarks/bench_identify_coverage.py`` on the independent reference bench
(``skisnow.bench.reference_bench`` at ``--dx-mm``), seeded noise (seed 1), then
``identify_ski`` in variants: ``default`` (GCV); ``truth`` (started at the true ski);
``lamX`` (λ fixed at X); ``nK`` (K log-EI coefficients); ``nK+lamX``; ``case-cv`` /
``evidence`` (the other λ criteria); ``leX`` (beam elements of X mm); ``sigmaX`` (the noise
given, X µm: with ``--noise-um 0`` a fit without noise, the bias alone); ``warm<variant>``
(started at the default fit, run first). Printed per variant: λ, EI rms [%] and z0 rms [µm]
over the determined stations (as the coverage benchmark), misfit and its discrepancy bound [σ],
δ (the excess over the noise) and the estimated mesh error [µm], exit code and cause, the
shares in the 95 % bands, held-out rms [µm], CPU s, and the EI error [%] in 100 mm windows along the
determined span (``along``: where the error is).

``--reference DX...``: no fit; the noise-free reference bench at each grid DX [mm] against the
converged beam (``solve_beam``, continuous contact, 2000 elements) per load case, and the best
spline approximation of the true log EI over -450…+400 mm with 30-240 coefficients (the floor
any fit in that basis has). Report the load average with the times.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import json
import time
from pathlib import Path

import numpy as np
from bench_identify_coverage import bench_of, errors, held_out, true_ski
from bench_identify_diagnosis import along, basis_floor


def options(variant: str, true, base) -> dict:
    kw: dict = {}
    if variant.startswith("warm"):
        kw["initial"] = base.ski
        variant = variant[4:]
    for tok in variant.split("+"):
        if tok.startswith("lam"):
            kw["regularisation"] = float(tok[3:])
        elif tok.startswith("sigma"):
            kw["noise"] = float(tok[5:]) * 1e-6
        elif tok.startswith("le"):
            kw["element_length"] = float(tok[2:]) * 1e-3
        elif tok.startswith("n") and tok[1:].isdigit():
            kw["n_stiffness"] = int(tok[1:])
        elif tok == "truth":
            kw["initial"] = true
        elif tok in ("evidence", "case-cv"):
            kw["criterion"] = tok
        elif tok != "default":
            raise SystemExit(f"unknown variant {tok!r}")
    return kw


def reference(name: str, dxs: list[float], cache: Path) -> None:
    from skisnow.ski import solve_beam

    true = true_ski(name)
    for dx in dxs:
        t = bench_of(name, "full", 0.0, cache, dx).table
        rows = []
        for (m, p), g in t.groupby(["mass_kg", "load_position_mm"]):
            x = g["x_mm"].to_numpy() * 1e-3
            sol = solve_beam(true, mass=m, load_position=p * 1e-3, contact="continuous",
                             n_elements=2000)  # fmt: skip
            e = g["height_mm"].to_numpy() * 1e-3 - sol.sample(x)
            rows.append((1e6 * np.sqrt(np.mean(e**2)), 1e6 * np.abs(e).max()))
        a = np.array(rows)
        print(f"{name}: reference bench at {dx:g} mm against the converged beam: rms "
              f"{np.sqrt(np.mean(a[:, 0] ** 2)):.2f} µm over the 39 cases, worst case "
              f"{a[:, 0].max():.2f} µm rms, largest {a[:, 1].max():.2f} µm")  # fmt: skip
    print(f"{name}: best spline approximation of log EI over -450..+400 mm: "
          + ", ".join(f"{k} coefficients {basis_floor(true, k, (-0.45, 0.40)):.2f} %"
                      for k in (30, 60, 120, 240)))  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ski", default="issue25")
    ap.add_argument("--dx-mm", type=float, default=1.0)
    ap.add_argument("--noise-um", type=float, default=5.0)
    ap.add_argument("--variants", nargs="+", default=["default", "truth", "lam100", "n120+lam100"])
    ap.add_argument("--reference", nargs="*", type=float, default=None)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    cache = Path(a.cache)
    print(f"load average at start: {os.getloadavg()}")
    if a.reference is not None:
        reference(a.ski, a.reference or [1.0], cache)
        return
    from skisnow.identify import identify_ski

    true = true_ski(a.ski)
    bench = bench_of(a.ski, "full", a.noise_um, cache, a.dx_mm)
    base = None
    for v in a.variants:
        t0 = time.process_time()
        res = identify_ski(bench, **options(v, true, base))
        cpu = time.process_time() - t0
        base = res if v == "default" else base
        row = {"ski": a.ski, "dx_mm": a.dx_mm, "noise": a.noise_um, "variant": v,
               **errors(res, true), "lam": res.regularisation, "misfit": res.misfit,
               "bound": float(np.sqrt(res.chi2_bound / res.n_bins)),
               "exit": 0 if res.converged else 3, "causes": ",".join(res.causes), "cpu": cpu,
               "held_out": held_out(res.ski, true), "along": along(res, true),
               "delta_um": res.model_error[0] * 1e6, "mesh_um": res.mesh_error[0] * 1e6,
               "mesh_max_um": res.mesh_error[1] * 1e6,
               "load": os.getloadavg()[0]}  # fmt: skip
        if a.out:
            with open(a.out, "a") as fh:
                fh.write(json.dumps(row) + "\n")
        print(f"{v} | λ {row['lam']:g} | EI {row['ei_rms']:.2f} % | z0 {row['z0_rms']:.2f} µm | "
              f"misfit {row['misfit']:.4f} (bound {row['bound']:.4f}) | "
              f"δ {row['delta_um']:.2f} µm | "
              f"mesh {row['mesh_um']:.2f} µm | exit {row['exit']} "
              f"{row['causes']} | in band {row['ei_in']}/{row['ei_n']}, {row['z0_in']}/"
              f"{row['z0_n']} | held-out {row['held_out']:.2f} µm | CPU {cpu:.1f} s\n"
              f"    along {row['along']}", flush=True)  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
