"""The camber network against the beam it emulates, on the shipped skis (issue 26, part 2).

    uv run python benchmarks/route_error.py           # the table (≈ 2 min)

A shipped ski is defined by EI(x) and z0(x): its beam on the rigid plane (the virtual bench)
is the truth of its loaded profile, and the camber network (Kalliorinne et al. 2023, eq. 1) an
emulator trained on it. For a grid of loads, load positions and snow moduli this prints, per
ski, the rigid contact by region through both routes and the network's error against the beam:
total contact length, kick-zone contact length and the region loads. The default profile route
is the one with the smaller error (the beam, by definition of the truth); the network is kept,
its error stated from this table.
"""

from __future__ import annotations

import itertools
import os
import time

import numpy as np

from skisnow.pipeline import solve_case

MASSES = (40.0, 61.0, 80.0, 100.0)
POSITIONS = (-0.120, -0.095, -0.070, 0.0)
MODULI = (20e6, 140e6, 300e6)


def main() -> None:
    t0 = time.process_time()
    print(f"load average {os.getloadavg()[0]:.2f}")
    head = (f"{'ski':8s} {'m kg':>5s} {'x_m mm':>7s} {'E MPa':>6s} {'total beam':>10s} "
            f"{'total net':>10s} {'kick beam':>10s} {'kick net':>9s} "
            f"{'Δshare pts':>10s}")  # fmt: skip
    print(head)
    summary = {}
    for ski in ("classic", "skate"):
        errs_total, errs_kick, errs_share = [], [], []
        for m, xm, e in itertools.product(MASSES, POSITIONS, MODULI):
            out = {}
            for route in ("beam", "network"):
                c = solve_case(ski, mass=m, load_position=xm, snow_modulus=e,
                               profile_source=route, n_points=2048)  # fmt: skip
                out[route] = c.zones
            b, n = out["beam"], out["network"]
            dshare = max(abs(b[r].load_share - n[r].load_share) for r in b.footprint.names)
            errs_total.append(n.total.length - b.total.length)
            errs_kick.append(n["kick_zone"].length - b["kick_zone"].length)
            errs_share.append(dshare)
            print(f"{ski:8s} {m:5.0f} {xm * 1e3:7.0f} {e * 1e-6:6.0f} "
                  f"{b.total.length * 1e3:10.1f} {n.total.length * 1e3:10.1f} "
                  f"{b['kick_zone'].length * 1e3:10.1f} {n['kick_zone'].length * 1e3:9.1f} "
                  f"{dshare * 100:10.1f}")  # fmt: skip
        summary[ski] = (np.array(errs_total), np.array(errs_kick), np.array(errs_share))
    print()
    print("network − beam (the truth):  median |Δ| / max |Δ|")
    for ski, (t, k, s) in summary.items():
        print(f"{ski:8s} total contact {np.median(np.abs(t)) * 1e3:6.1f} / "
              f"{np.abs(t).max() * 1e3:6.1f} mm; kick zone {np.median(np.abs(k)) * 1e3:6.1f} / "
              f"{np.abs(k).max() * 1e3:6.1f} mm; region share {np.median(s) * 100:5.1f} / "
              f"{s.max() * 100:5.1f} points")  # fmt: skip
    print(f"CPU {time.process_time() - t0:.0f} s, load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
