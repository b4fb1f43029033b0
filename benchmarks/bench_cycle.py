"""Benchmark of a load cycle (``skisnow cycle``): one frame per load case, warm-started along time.

    uv run python benchmarks/bench_cycle.py                    # BLAS threads as the system sets
    uv run python benchmarks/bench_cycle.py --blas-threads 1   # one BLAS thread (shared machine)

Target (issue: technician workflows): a 1 s cycle sampled at 100 frames on 4096 stations in
under 2 s with the rigid route. Each row is one ski × cycle template (body mass 70 kg, snow
100 MPa, the template stretched to 1 s); the route is the network where every frame lies in its
trained domain, else the beam (``--body-mass-kg 85`` pushes the diagonal kick past 130 kg).
The last rows run the flexible route (the ski's beam and the snow solved together,
``--ski-model flexible``) on two cycles, to say what it costs. Times are the best of
``--repeat`` runs after a first run (its time in ``first s`` includes the
network's JIT compilation), with the process CPU time beside the wall time because the machine
is shared; beam profiles are solved in every run (their cache is cleared). The last columns compare
the contact iterations with and without the warm start along time.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys

if __name__ == "__main__":  # thread settings must precede the NumPy import
    _pre = argparse.ArgumentParser(add_help=False)
    _pre.add_argument("--blas-threads", type=int, default=None)
    _known, _ = _pre.parse_known_args()
    if _known.blas_threads is not None:
        for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            os.environ[var] = str(_known.blas_threads)

import time

import numpy as np

from skisnow.pipeline import _profiles as pipeline_profiles
from skisnow.workflows import TEMPLATES, run_cycle, template_history

#: The flexible route (the ski's beam and the snow solved together) on two cycles.
FLEXIBLE_CASES = (("classic", "diagonal"), ("skate", "skate_g3"))


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:  # pragma: no cover
        return "uptime unavailable"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--blas-threads", type=int, default=None)
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--points", type=int, default=4096)
    ap.add_argument("--body-mass-kg", type=float, default=70.0)
    ap.add_argument("--snow-modulus-mpa", type=float, default=100.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skis", default="classic,skate")
    args = ap.parse_args()

    print(f"# {uptime()}")
    print(
        f"# {args.frames} frames over a 1 s cycle, {args.points} stations, body mass "
        f"{args.body_mass_kg:g} kg, snow {args.snow_modulus_mpa:g} MPa, BLAS threads: "
        f"{os.environ.get('OPENBLAS_NUM_THREADS', 'default')}; target < 2 s (rigid route)"
    )
    head = (
        f"{'ski':8} {'cycle':14} {'kg':>4} {'route':8} {'wall s':>7} {'cpu s':>7} "
        f"{'ms/frame':>9} {'first s':>7} "
        f"{'iters warm':>10} {'iters cold':>10} {'target':>7}"
    )
    print(head)
    print("-" * len(head))
    worst = 0.0
    cases = [
        (ski, name, args.body_mass_kg, "rigid")
        for ski in args.skis.split(",")
        for name in TEMPLATES
    ]
    cases.append(("classic", "diagonal", 85.0, "rigid"))  # the kick passes 130 kg: the beam
    cases += [(ski, name, args.body_mass_kg, "flexible") for ski, name in FLEXIBLE_CASES]
    for ski, name, body, model in cases:
        h = template_history(name, body_mass=body, n_frames=args.frames, duration=1.0)
        kw = {
            "snow_modulus": args.snow_modulus_mpa * 1e6,
            "n_points": args.points,
            "keep_fields": False,
            "ski_model": model,
        }
        t0 = time.perf_counter()
        run_cycle(ski, h, **kw)  # first run: network JIT, kernel caches
        first = time.perf_counter() - t0
        best = (np.inf, np.inf)
        ds = None
        for _ in range(args.repeat):
            pipeline_profiles._beam_profile.cache_clear()  # beam profiles are solved every run
            t0, c0 = time.perf_counter(), time.process_time()
            ds = run_cycle(ski, h, **kw)
            t, c = time.perf_counter() - t0, time.process_time() - c0
            best = min(best, (t, c))
        cold = run_cycle(ski, h, warm_start=False, **kw)
        assert ds is not None
        warm_it = int(ds["iterations"].sum())
        cold_it = int(cold["iterations"].sum())
        worst = max(worst, best[0])
        print(
            f"{ski:8} {name:14} {body:4.0f} {ds.attrs['route']:8} {best[0]:7.2f} {best[1]:7.2f} "
            f"{1e3 * best[0] / args.frames:9.1f} {first:7.2f} {warm_it:10d} {cold_it:10d} "
            f"{'met' if best[0] < 2.0 else 'MISSED':>7}"
        )
    print(f"# slowest cycle {worst:.2f} s; {uptime()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
