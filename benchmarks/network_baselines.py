"""How strong is "interpolating the bench"? Interpolants of a bench on the 25 off-grid cases.

    uv run python benchmarks/network_baselines.py [--skis classic,skate] [--bench dense|paper]

Issue 30 asks every shipped network to be at least twice as accurate as interpolating the bench
it was trained on; ``bench_network.py`` uses bilinear interpolation in (m, x_m) (the target's
baseline). This script measures other interpolants of the same bench profiles on the same 25
load cases off every bench grid (truth: the beam on the rigid plane; µm; near contact where the
beam's profile is below 0.2 mm), with SciPy's ``RegularGridInterpolator`` over (x_m, m) on
whole profiles: ``linear`` (= bilinear, the target's baseline), ``pchip``, ``cubic`` (tensor
cubic splines) and mixed ones (linear in m, cubic / PCHIP in x_m). It prints a table; nothing is
trained.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from bench_network import bench_cube, offgrid_cases
from network_diagnosis import BENCHES
from scipy.interpolate import RegularGridInterpolator, interp1d

from skisnow.bench import run_bench
from skisnow.ski import get_ski


def mixed(cube, m: np.ndarray, p: np.ndarray, kind: str) -> np.ndarray:
    """Linear in the mass, ``kind`` (``cubic`` or ``pchip``) in the load position."""
    ms, ps, _, h = cube
    lin_m = interp1d(ms, h, axis=1)  # (n_pos, k, n_x) after the call
    out = []
    for mk, pk in zip(m, p, strict=True):
        prof = lin_m(mk)  # (n_pos, n_x)
        rgi = RegularGridInterpolator((ps,), prof, method=kind)
        out.append(rgi([pk])[0])
    return np.array(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--skis", default="classic,skate")
    ap.add_argument("--bench", default="dense", choices=sorted(BENCHES))
    args = ap.parse_args()
    print(f"load before: {os.getloadavg()}")
    print(f"{'ski':8} {'interpolant':28} {'mean µm':>8} {'p95':>7} {'max':>7} {'near':>6} cpu s")
    for name in args.skis.split(","):
        ski = get_ski(name)
        masses, positions = BENCHES[args.bench]
        cube = bench_cube(run_bench(ski, masses=masses, load_positions=positions))
        ms, ps, x, h = cube
        mm, pp, truth = offgrid_cases(ski, x)
        near = truth < 0.2e-3
        estimates = {}
        for method in ("linear", "pchip", "cubic"):
            t0 = time.process_time()
            rgi = RegularGridInterpolator((ps, ms), h, method=method)
            estimates[f"{method} in (x_m, m)"] = (
                rgi(np.stack([pp, mm], axis=1)),
                time.process_time() - t0,
            )
        for kind in ("cubic", "pchip"):
            t0 = time.process_time()
            estimates[f"linear in m, {kind} in x_m"] = (
                mixed(cube, mm, pp, kind),
                time.process_time() - t0,
            )
        for label, (est, cpu) in estimates.items():
            e = 1e6 * np.abs(est - truth)
            print(
                f"{name:8} {label:28} {e.mean():8.2f} {np.percentile(e, 95):7.1f} "
                f"{e.max():7.1f} {e[near].mean():6.2f} {cpu:.1f}"
            )
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
