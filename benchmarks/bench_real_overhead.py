"""The real contact's overhead on the Figure 8/9 chunks (issue 28's < 20 % target), alone.

    uv run python benchmarks/bench_real_overhead.py               # 5 alternated repeats
    uv run python benchmarks/bench_real_overhead.py --profile     # + where the real part goes

The chunk function of the Figure 8/9 sweep (skate at −120 mm, 126 masses × 5 moduli = 630 cases,
4096 stations, warm starts, beam profiles computed once) in this process, without and with the
real contact (base S3, machine-made snow; the micro curves computed or read from the cache
first), alternated ``--repeat`` times; the CPU time of each kept at its minimum (the machine may
be shared) and the ratio printed with the load average. The same measurement as the chunk row
of ``bench_multiscale.py``, without its micro-curve rows.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="alternated repeats")
    ap.add_argument("--profile", action="store_true", help="profile one run with the real part")
    args = ap.parse_args()

    from skisnow.snow import get_snow, snow_record
    from skisnow.sweep import SweepSpec, contact_chunk
    from skisnow.sweep._point import loaded_profiles

    spec = SweepSpec(
        skis=("skate",), masses=np.arange(5.0, 131.0, 1.0), load_positions=(-0.12,),
        snow_moduli=(20e6, 100e6, 200e6, 300e6, 400e6), n_points=4096,
    )  # fmt: skip
    snow = json.dumps(snow_record(get_snow("machine-made")), sort_keys=True)
    real_spec = replace(spec, base="S3", snow=snow)
    real_spec.micro_curves()
    profiles = loaded_profiles(spec, "skate", -0.12)
    for s in (spec, real_spec):  # warm-up
        contact_chunk(s, "skate", -0.12, 100e6, profiles)
    print("load before:", " ".join(f"{v:.2f}" for v in os.getloadavg()))
    cpu: dict[str, list[float]] = {"without": [], "with": []}
    for _ in range(args.repeat):
        for label, s in (("without", spec), ("with", real_spec)):
            c0 = time.process_time()
            for e in spec.snow_moduli:
                contact_chunk(s, "skate", -0.12, e, profiles)
            cpu[label].append(time.process_time() - c0)
    n = len(spec.masses) * len(spec.snow_moduli)
    for label, v in cpu.items():
        print(f"{label} real contact: CPU {', '.join(f'{t:.3f}' for t in v)} s ({n} cases)")
    ratio = min(cpu["with"]) / min(cpu["without"])
    print(f"CPU ratio with/without (minima): {ratio:.3f}   [target < 1.20]")
    print("load after:", " ".join(f"{v:.2f}" for v in os.getloadavg()))
    if args.profile:
        import cProfile
        import pstats

        prof = cProfile.Profile()
        prof.enable()
        for e in spec.snow_moduli:
            contact_chunk(real_spec, "skate", -0.12, e, profiles)
        prof.disable()
        stats = pstats.Stats(prof).sort_stats("cumulative")
        stats.print_stats("multiscale|pipeline/_real|_real_point|contact_chunk", 12)


if __name__ == "__main__":
    main()
