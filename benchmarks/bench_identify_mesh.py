"""The identification's mesh (issue 25, seventh pass): the forward model's discretisation error
against an independent bench, and whether the fit's own estimate of it reads it right.

Run:  uv run python benchmarks/bench_identify_mesh.py [--skis issue25 1001 1002 1003]
      [--plan full] [--element-mm 20 10 5 2.5 1.25] [--dx-mm 1] [--out FILE]

For each ski (``true_ski`` of ``benchmarks/bench_identify_coverage.py``: issue 25's ski or a
seeded ``random_ski``):

1. ``p*``: the true ski carried to the fit's parameters (log EI by least squares on the fit's
   60-coefficient B-spline, z0 on its z0 basis, as ``identify_ski(initial=true)`` starts), and
   the *spline ski*: the ski whose EI and z0 are exactly those splines (sampled every 0.5 mm).
2. The reference bench of the spline ski (``skisnow.bench.reference_bench``: finite differences
   in mixed form, contact at every node, ``--dx-mm``; independent of the fit's Hermite beam),
   noise-free, on the plan's load cases and stations, binned as the fit bins (5 mm).
3. For each element length: the fit's forward model (``skisnow.identify._model._Problem``) at
   ``p*`` against that bench — the **actual** discretisation error at fixed parameters (rms over
   the stations, largest bin), and against the library's beam (``skisnow.ski.solve_beam``,
   contact between nodes) converged at 0.5 mm elements — beside the fit's **estimate** of it
   (``skisnow.identify._mesh_error.mesh_error``: the change on the mesh of half the element
   length), and the ratio estimate / actual. Also the basis error: the spline ski's bench
   against the true ski's (what no mesh removes); and the binning: the bins' mean of the
   converged beam against its value at the bins' mean position (what the fit compared before
   issue 25's seventh pass).

No fit is run; report the load average with the times.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import PLANS, bench_of, true_ski


def spline_parameters(true, nodes, n_stiffness: int, n_camber: int):
    """``(p*, spline ski)`` of the module docstring, on a problem with no cases."""
    from skisnow.identify._model import _design, _Problem
    from skisnow.identify._start import _camber_fit

    shell = _Problem([], nodes, n_stiffness, n_camber, 1.0)
    xs = np.linspace(float(nodes[0]), float(nodes[-1]), 4001)
    theta_e = np.linalg.lstsq(_design(shell.t_e, xs), np.log(true.stiffness(xs)), rcond=None)[0]
    phi = _camber_fit(shell, xs) @ true.free_camber(xs)
    p = np.concatenate([theta_e, phi])
    te, tz = shell.split(p)
    z = _design(shell.t_z, xs) @ tz
    z = z - z.min()
    ski = dataclasses.replace(
        true, name=f"{true.name} (spline)", stiffness_x=tuple(xs),
        stiffness_values=tuple(np.exp(_design(shell.t_e, xs) @ te)), camber_x=tuple(xs),
        camber_values=tuple(z), stiffness_log_sd=None, camber_sd=None,
    )  # fmt: skip
    return p, ski


def _heights(problem, p):
    """The model's bin heights [m] at ``p`` (every case) and the bins' counts."""
    r, _ = problem.evaluate(p, jacobian=False)
    w = np.concatenate([c.w * problem.bin_weights[k] / problem.sigma_cases[k]
                        for k, c in enumerate(problem.cases)])  # fmt: skip
    h = np.concatenate([c.h for c in problem.cases])
    return r / w + h, np.concatenate([c.w**2 for c in problem.cases])


def run_ski(name: str, plan: str, elements_mm: list[float], dx_mm: float, cache: Path) -> list:
    from skisnow.bench import reference_bench
    from skisnow.identify._cases import _bench_cases, load_cases
    from skisnow.identify._identify import _camber_coefficients
    from skisnow.identify._mesh_error import mesh_error
    from skisnow.identify._model import _Problem

    true = true_ski(name)
    clean = bench_of(name, plan, 0.0, cache, dx_mm)
    raw_true = _bench_cases(clean, clean.ski_name(None))
    n_camber = _camber_coefficients(raw_true, true.x_tip - true.x_tail)
    nodes0 = np.linspace(true.x_tail, true.x_tip, 201)
    p_star, spline = spline_parameters(true, nodes0, 60, n_camber)
    path = cache / f"ref_{name}_{plan}_{dx_mm:g}mm_spline60_{n_camber}.csv"
    from skisnow.bench import read_bench, write_bench

    t0 = time.process_time()
    if path.exists():
        sb = read_bench(path)
    else:
        sb = reference_bench(spline, **PLANS[plan], dx=dx_mm * 1e-3)
        write_bench(sb, path)
    t_ref = time.process_time() - t0
    raw = _bench_cases(sb, sb.ski_name(None))
    from skisnow._errors import ConvergenceError
    from skisnow.ski import solve_beam

    def converged(m: float, p: float, n_conv: int):
        try:  # 0.5 mm elements; 1 mm where the contact solver stops on its pivot limit there
            return solve_beam(spline, mass=m, load_position=p, contact="continuous",
                              n_elements=n_conv).sample  # fmt: skip
        except ConvergenceError:
            return converged(m, p, n_conv // 2)

    n_conv = round((true.x_tip - true.x_tail) / 0.5e-3)
    conv = [converged(m, p, n_conv) for m, p, *_ in raw]
    d = np.concatenate([c[3] - f(c[2]) for c, f in zip(raw, conv, strict=True)])
    ref_vs_beam = 1e6 * float(np.sqrt(np.mean(d**2)))
    # the binning: the bins' mean of the converged beam against its value at the bins' mean x
    binned, *_ = load_cases(raw, nodes0, 0.10, 0.005)
    b_sq, b_n = 0.0, 0.0
    for c, f in zip(binned, conv, strict=True):
        mean = f(c.x) if c.average is None else c.average @ f(c.stations)
        b_sq += float(np.sum(c.w**2 * (mean - f(c.x)) ** 2))
        b_n += float(np.sum(c.w**2))
    binning = 1e6 * np.sqrt(b_sq / b_n)
    print(f"{name}: bin mean of the converged beam minus its value at the bins' mean x: "
          f"{binning:.2f} µm rms")  # fmt: skip
    print(
        f"{name}: the spline ski's reference bench at {dx_mm:g} mm against the converged beam "
        f"({n_conv} elements): {ref_vs_beam:.3f} µm rms, {1e6 * np.abs(d).max():.2f} max"
    )
    # the basis error: the spline ski's bench against the true ski's (same stations)
    basis = np.concatenate([a[3] - b[3] for a, b in zip(raw, raw_true, strict=True)])
    rows = []
    for le_mm in elements_mm:
        n_el = max(8, round((true.x_tip - true.x_tail) / (le_mm * 1e-3)))
        nodes = np.linspace(true.x_tail, true.x_tip, n_el + 1)
        cases, *_ = load_cases(raw, nodes, 0.10, 0.005)
        problem = _Problem(cases, nodes, 60, n_camber, 1.0)
        t1 = time.process_time()
        hm, cnt = _heights(problem, p_star)
        cpu = time.process_time() - t1
        err = hm - np.concatenate([c.h for c in cases])
        actual = float(np.sqrt(np.sum(cnt * err**2) / np.sum(cnt)))
        # against the library's beam, converged (0.5 mm elements, contact between nodes)
        err_b = hm - np.concatenate([c.average @ conv[k](c.stations) for k, c in enumerate(cases)])
        actual_b = float(np.sqrt(np.sum(cnt * err_b**2) / np.sum(cnt)))
        est = mesh_error(problem, p_star, raw, boot_length=0.10, bin_width=0.005)
        row = {"ski": name, "plan": plan, "element_mm": le_mm, "n_elements": n_el,
               "actual_rms_um": 1e6 * actual, "actual_max_um": 1e6 * float(np.abs(err).max()),
               "estimate_rms_um": 1e6 * est.rms, "estimate_max_um": 1e6 * est.max,
               "ratio": est.rms / actual if actual > 0 else np.nan,
               "beam_rms_um": 1e6 * actual_b, "beam_max_um": 1e6 * float(np.abs(err_b).max()),
               "ref_vs_beam_um": ref_vs_beam, "binning_um": binning,
               "basis_rms_um": 1e6 * float(np.sqrt(np.mean(basis**2))), "eval_cpu": cpu,
               "ref_cpu": t_ref, "dx_mm": dx_mm, "load": os.getloadavg()[0]}  # fmt: skip
        rows.append(row)
        print(f"{name} | {le_mm:g} mm ({n_el}) | actual {row['actual_rms_um']:.3f} µm rms, "
              f"{row['actual_max_um']:.2f} max | estimate {row['estimate_rms_um']:.3f} rms, "
              f"{row['estimate_max_um']:.2f} max | estimate/actual {row['ratio']:.2f} | "
              f"against the converged beam {row['beam_rms_um']:.3f} rms, "
              f"{row['beam_max_um']:.2f} max | basis {row['basis_rms_um']:.2f} µm | "
              f"eval {cpu:.2f} s CPU", flush=True)  # fmt: skip
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["issue25", "1001", "1002", "1003"])
    ap.add_argument("--plan", default="full", choices=list(PLANS))
    ap.add_argument("--element-mm", nargs="+", type=float, default=[20, 10, 5, 2.5, 1.25])
    ap.add_argument("--dx-mm", type=float, default=1.0)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    for s in a.skis:
        for row in run_ski(s, a.plan, a.element_mm, a.dx_mm, Path(a.cache)):
            if a.out:
                with open(a.out, "a") as fh:
                    fh.write(json.dumps(row) + "\n")
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
