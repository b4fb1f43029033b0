"""Why the contact results of an identified ski miss: which quantity, z0 or EI, and how sensitive.

Run:  uv run python benchmarks/bench_identify_contact.py [--ski classic skate stiff]
      [--coverage user full] [--max-nfev 40] [--bump-um 1 2 3]

Two measurements behind the contact column of ``benchmarks/bench_identify.py`` (same virtual
bench, seed 1, 10 µm noise; same contact cases: 30 and 60 kg at x_m = -120 mm on 100 MPa snow,
rigid route, rear/front zone length and mean pressure):

* diagnosis: the relative difference [%] of each of the 8 quantities for the identified ski,
  for the true ski carrying the identified z0 (``trueEI+idZ0``) and for the true ski carrying the
  identified EI (``idEI+trueZ0``): which quantity is off and whether z0 or EI causes it;
* sensitivity (``--bump-um``): the largest change [%] of the 8 quantities when a Gaussian bump of
  ±A (standard deviation 20 mm) is added to the TRUE z0 anywhere between -800 and +800 mm
  (every 20 mm): how well z0 must be known for contact results within a given tolerance.

The zone lengths come from the half-space grid (steps of about 0.46 mm: 1.3 % of the skate's
36 mm front zone), and the mean pressures follow the lengths (same force).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import dataclasses

import numpy as np
from bench_identify import coverage, stiff_test_ski

from skisnow.bench import run_bench
from skisnow.identify import identify_ski
from skisnow.pipeline import solve_case
from skisnow.ski import Ski, get_ski

QUANTITIES = [(m, z, q) for m in (30.0, 60.0) for z in ("rear", "front")
              for q in ("length", "mean_pressure")]  # fmt: skip


def contact(ski: Ski) -> dict:
    out = {}
    for m in (30.0, 60.0):
        r = solve_case(ski, mass=m, load_position=-0.12, snow_modulus=100e6,
                       profile_source="beam")  # fmt: skip
        for zone in ("rear", "front"):
            for q in ("length", "mean_pressure"):
                out[(m, zone, q)] = getattr(r.zones[zone], q)
    return out


def differences(a: dict, b: dict) -> list[float]:
    return [100 * (a[k] / b[k] - 1) if b[k] > 0 else float("nan") for k in QUANTITIES]


def swap(base: Ski, donor: Ski, what: str) -> Ski:
    if what == "z0":
        new = {"camber_x": donor.camber_x, "camber_values": donor.camber_values}
    else:
        new = {"stiffness_x": donor.stiffness_x, "stiffness_values": donor.stiffness_values}
    return dataclasses.replace(base, **new, camber_sd=None, stiffness_log_sd=None)


def true_ski(name: str) -> Ski:
    return stiff_test_ski() if name == "stiff" else get_ski(name)


def diagnosis(name: str, cov: str, max_nfev: int) -> None:
    true = true_ski(name)
    kw, window = coverage(cov)
    bench = run_bench(true, noise=10e-6, seed=1, **kw)
    if window is not None:
        t = bench.table
        keep = (t["x_mm"] > window[0] * 1e3) & (t["x_mm"] < window[1] * 1e3)
        bench = dataclasses.replace(bench, table=t[keep].reset_index(drop=True))
    ident = identify_ski(bench, max_nfev=max_nfev).ski
    ref = contact(true)
    print(f"\n{name} {cov}: true " + " ".join(
        f"{ref[k] * (1e3 if k[2] == 'length' else 1e-3):.1f}" for k in QUANTITIES
    ) + "  [mm | kPa]")  # fmt: skip
    for label, ski in (("ident", ident), ("trueEI+idZ0", swap(true, ident, "z0")),
                       ("idEI+trueZ0", swap(true, ident, "ei"))):  # fmt: skip
        d = differences(contact(ski), ref)
        print(f"  {label:12s} " + " ".join(f"{v:6.2f}" for v in d)
              + f" | max {np.nanmax(np.abs(d)):.2f}", flush=True)  # fmt: skip


def sensitivity(name: str, amplitudes: list[float]) -> None:
    true = true_ski(name)
    ref = contact(true)
    x, z = np.array(true.camber_x), np.array(true.camber_values)
    worst = []
    for amp in amplitudes:
        w = 0.0
        for centre in np.arange(-0.80, 0.80, 0.02):
            for sign in (1.0, -1.0):
                bump = sign * amp * np.exp(-0.5 * ((x - centre) / 0.02) ** 2)
                ski = dataclasses.replace(true, camber_values=tuple(z + bump), camber_sd=None)
                w = max(w, float(np.nanmax(np.abs(differences(contact(ski), ref)))))
        worst.append(w)
    pairs = zip(amplitudes, worst, strict=True)
    print(f"{name}: " + ", ".join(f"±{a * 1e6:g} µm -> {w:.1f} %" for a, w in pairs), flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ski", nargs="+", default=["classic", "skate", "stiff"])
    ap.add_argument("--coverage", nargs="+", default=["user", "full"])
    ap.add_argument("--max-nfev", type=int, default=40)
    ap.add_argument("--bump-um", nargs="*", type=float, default=[1.0, 2.0, 3.0])
    args = ap.parse_args()
    print("quantities: " + " ".join(f"{int(m)}{z[0]}{q[0]}" for m, z, q in QUANTITIES)
          + "  (mass, rear/front, length/mean pressure); differences in %")  # fmt: skip
    for name in args.ski:
        for cov in args.coverage:
            diagnosis(name, cov, args.max_nfev)
    if args.bump_um:
        print("\nlargest contact change from a ±A Gaussian bump (sd 20 mm) on the true z0:")
        for name in args.ski:
            sensitivity(name, [a * 1e-6 for a in args.bump_um])


if __name__ == "__main__":
    main()
