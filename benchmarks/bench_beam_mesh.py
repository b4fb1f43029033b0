"""Mesh convergence of the beam on the stone (issue 25): loaded heights of ``solve_beam`` at
100-800 Hermite elements, contact resolved between nodes (``contact='continuous'``, the default)
and at the nodes only (``'nodal'``, before issue 25), against the independent finite-difference
bench (:func:`skisnow.bench.reference_profile`, contact at every node of a ``--dx-mm`` grid).

Run:  uv run python benchmarks/bench_beam_mesh.py [--dx-mm 0.25]

Three skis (the shipped classic and skate, issue 25's ski with flat glide zones and waviness),
three load cases each (20 kg at -40 mm, 60 kg at -120 mm, 120 kg at -200 mm); the table gives
the rms and the largest height error [µm] over the reference grid, worst of the three cases,
and the CPU time of a solve. Boot plate 100 mm, uniform, on both sides.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from skisnow.bench import issue25_ski, reference_profile
from skisnow.ski import get_ski, solve_beam

CASES = ((20.0, -0.04), (60.0, -0.12), (120.0, -0.20))
ELEMENTS = (100, 200, 400, 800)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dx-mm", type=float, default=0.25)
    a = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    skis = {"classic": get_ski("classic"), "skate": get_ski("skate"), "issue25": issue25_ski()}
    print("ski | elements | element mm | contact | rms µm | max µm | CPU s per solve")
    for name, ski in skis.items():
        refs = []
        for m, p in CASES:
            ref = reference_profile(ski, mass=m, load_position=p, boot_length=0.10,
                                    dx=a.dx_mm * 1e-3)  # fmt: skip
            keep = (ref.x > ski.x_tail + 1e-9) & (ref.x < ski.x_tip - 1e-9)
            refs.append((m, p, ref.x[keep], ref.height[keep]))
        for n in ELEMENTS:
            for contact in ("continuous", "nodal"):
                rms = worst = 0.0
                t0 = time.process_time()
                for m, p, x, h in refs:
                    sol = solve_beam(ski, mass=m, load_position=p, boot_length=0.10,
                                     n_elements=n, contact=contact)  # fmt: skip
                    e = sol.sample(x) - h
                    rms = max(rms, float(np.sqrt(np.mean(e**2))))
                    worst = max(worst, float(np.max(np.abs(e))))
                cpu = (time.process_time() - t0) / len(refs)
                le = 1e3 * ski.length / n
                print(f"{name} | {n} | {le:.2f} | {contact} | {rms * 1e6:.3f} | "
                      f"{worst * 1e6:.3f} | {cpu:.3f}", flush=True)  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
