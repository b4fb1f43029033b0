"""Benchmark of the flexible ski against the rigid-profile method (per solve and per sweep).

    uv run python benchmarks/bench_flexible.py [--full] [--repeat 5]

1. One solve at 4096 stations, the same case both ways: the rigid route (the beam's loaded
   profile on the stone, then the contact solve; timed with and without the profile) and the
   flexible ski (beam and half-space in one solve). Target: flexible ≤ 2× rigid.
2. The Figure 8/9 sweep (skate, x_m = −120 mm, 20 snow moduli 20–400 MPa, strip, 4096
   stations) in one process, both ways, with beam profiles for the rigid route (the same ski).
   Default: a proxy with 5 kg steps (26 masses, 520 solves each way); ``--full``: the paper's
   126 masses (2520 solves each way). Target: flexible ≤ 3× rigid.

Prints a table, with the machine load (``uptime``) before and after: the machine may be shared.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

#: The flexible ski's benchmark cases: (ski, mass [kg], load position [mm], snow [MPa] or None
#: for the stone); bench_speed.py's flexible row uses the same.
FLEX_CASES = (
    ("classic", 60, -70, 20),
    ("classic", 60, -70, 100),
    ("classic", 60, -70, 400),
    ("classic", 30, -120, None),
    ("skate", 60, -120, 20),
    ("skate", 30, -120, 100),
)


def _uptime() -> str:
    try:
        out = subprocess.run(["uptime"], capture_output=True, text=True, check=False).stdout
        return out.strip()
    except OSError:
        return f"loadavg {os.getloadavg()}"


def _best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--full", action="store_true", help="the paper's 126 masses (1 kg steps)")
    p.add_argument("--repeat", type=int, default=5, help="repetitions of each single solve")
    p.add_argument("--n-points", type=int, default=4096)
    args = p.parse_args()

    from skisnow.cli._render import print_table
    from skisnow.constants import STANDARD_GRAVITY
    from skisnow.contact import STONE, effective_modulus, snow, solve_contact, solve_flexible
    from skisnow.network import camber_profile
    from skisnow.pipeline import stations
    from skisnow.ski import get_ski
    from skisnow.sweep import SweepSpec, run_sweep

    print("load before:", _uptime())
    n = args.n_points
    rows = []
    for name, m, xm_mm, e_mpa in FLEX_CASES:
        ski = get_ski(name)
        x = stations(ski, n)
        xm = xm_mm * 1e-3
        e = effective_modulus(snow(e_mpa * 1e6)) if e_mpa else effective_modulus(STONE)
        load = m * STANDARD_GRAVITY
        _, h = camber_profile(ski, mass=m, load_position=xm, x=x, source="beam")

        def profile(ski=ski, m=m, xm=xm, x=x):
            return camber_profile(ski, mass=m, load_position=xm, x=x, source="beam")

        def rigid(x=x, h=h, load=load, xm=xm, e=e, ski=ski):
            return solve_contact(x, h, load=load, load_position=xm, modulus=e, width=ski.width)

        def flexible(x=x, ski=ski, load=load, xm=xm, e=e):
            return solve_flexible(x, ski.free_camber(x), ski.stiffness(x), load=load,
                                  load_position=xm, modulus=e, width=ski.width)  # fmt: skip

        flexible()
        t_prof = _best(profile, args.repeat)
        t_rigid = _best(rigid, args.repeat)
        t_flex = _best(flexible, args.repeat)
        sol = flexible()
        rows.append((
            f"{name} {m}/{xm_mm}/{'stone' if e_mpa is None else e_mpa}",
            f"{t_rigid * 1e3:.1f}", f"{(t_rigid + t_prof) * 1e3:.1f}", f"{t_flex * 1e3:.1f}",
            f"{t_flex / t_rigid:.2f}", f"{t_flex / (t_rigid + t_prof):.2f}",
            sol.contact.iterations, rigid().iterations,
        ))  # fmt: skip
    print_table(
        f"One solve at {n} stations (best of {args.repeat}); case: ski kg/x_m mm/snow MPa",
        ["case", "rigid [ms]", "rigid+profile [ms]", "flexible [ms]",
         "flex/rigid", "flex/(rigid+prof)", "iters flex", "iters rigid"],
        rows,
    )  # fmt: skip

    masses = np.arange(5.0, 131.0, 1.0 if args.full else 5.0)
    moduli = np.arange(20.0, 401.0, 20.0) * 1e6
    srows = []
    times = {}
    with tempfile.TemporaryDirectory() as tmp:
        for ski_model in ("rigid", "flexible"):
            spec = SweepSpec(
                skis=("skate",), masses=masses, load_positions=(-0.120,), snow_moduli=moduli,
                profile_source="beam", n_points=n, ski_model=ski_model,
            )  # fmt: skip
            t0 = time.perf_counter()
            run_sweep(spec, Path(tmp) / f"{ski_model}.zarr", workers=0)
            times[ski_model] = time.perf_counter() - t0
            n_solves = len(masses) * len(moduli)
            srows.append((ski_model, n_solves, f"{times[ski_model]:.1f}",
                          f"{times[ski_model] / n_solves * 1e3:.1f}"))  # fmt: skip
    srows.append(("flexible / rigid", "", f"{times['flexible'] / times['rigid']:.2f}", ""))
    print_table(
        f"Figure 8/9 sweep, skate, {len(masses)} masses × {len(moduli)} moduli, {n} stations, "
        "one process" + ("" if args.full else " (proxy: 5 kg steps)"),
        ["ski model", "solves", "wall [s]", "per solve [ms]"],
        srows,
    )
    print("load after:", _uptime())


if __name__ == "__main__":
    main()
