"""Is the zero-load extrapolation of the lightest profiles near the true z0? (issue 25, ninth pass)

Run:  uv run python benchmarks/bench_z0_anchor.py 1001:5 1002:5 1003:5 issue25:5 24:5 20:5
      uv run python benchmarks/bench_z0_anchor.py --plan full 1001:5 1002:5 1003:5 issue25:5

On the independent reference benches of ``bench_identify_coverage.py`` (shop plan: 20 and 40
kg; ``--plan full``: 10 and 20 kg; seeded noise and noise-free): at each load position the
two lightest profiles extrapolated linearly to zero load, h₁ − m₁ (h₂ − h₁) / (m₂ − m₁),
averaged over the positions, against the true free camber (both modulo their line over
−0.9…+0.9 m): its rms error and the quadratic part of it (a bowl).
Exact only where the contact does not change between the two loads (tips only); a small error
would make it a prior that holds the fit's z0 bowl.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import bench_of, true_ski

from skisnow.identify._cases import _bench_cases

CACHE = Path.home() / ".cache" / "skisnow-identify-bench"


def anchor_error(
    name: str, noise_um: float, plan: str = "shop"
) -> tuple[float, float, tuple[float, float]]:
    """``(rms, quadratic part rms, the two masses)`` [m] of the zero-load extrapolation."""
    b = bench_of(name, plan, noise_um, CACHE)
    raw = _bench_cases(b, b.ski_name(None))
    est = []
    for pos in sorted({c[1] for c in raw}):
        cs = sorted([c for c in raw if c[1] == pos], key=lambda c: c[0])
        (m1, _, x1, h1), (m2, _, x2, h2) = cs[0], cs[1]
        x = np.intersect1d(np.round(x1, 6), np.round(x2, 6))
        f1, f2 = np.interp(x, x1, h1), np.interp(x, x2, h2)
        est.append((x, f1 - m1 * (f2 - f1) / (m2 - m1)))
    x = est[0][0]
    a = np.mean([np.interp(x, e[0], e[1]) for e in est], axis=0)
    m = (x > -0.9) & (x < 0.9)
    d = a[m] - true_ski(name).free_camber(x[m])
    d = d - np.polyval(np.polyfit(x[m], d, 1), x[m])
    q = np.polyval(np.polyfit(x[m], d, 2), x[m])
    q = q - np.polyval(np.polyfit(x[m], q, 1), x[m])
    return float(np.sqrt(np.mean(d**2))), float(np.sqrt(np.mean(q**2))), (m1, m2)


def main() -> None:
    args = sys.argv[1:]
    plan = "shop"
    if args[:1] == ["--plan"]:
        plan, args = args[1], args[2:]
    print("| ski | noise µm | masses kg | anchor z0 error rms µm | its bowl (quadratic) µm |")
    print("| --- | --- | --- | --- | --- |")
    for item in args:
        name, noise = item.split(":")
        for nz in (float(noise), 0.0):
            rms, quad, (m1, m2) = anchor_error(name, nz, plan)
            print(f"| {name} | {nz:g} | {m1:g}, {m2:g} | {rms * 1e6:.1f} | {quad * 1e6:.1f} |")


if __name__ == "__main__":
    main()
