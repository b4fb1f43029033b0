"""Benchmark of the real contact along the ski (issue 28, point 7).

    uv run python benchmarks/bench_multiscale.py            # the targets
    uv run python benchmarks/bench_multiscale.py --quick    # one grind, a small sweep

Targets: the micro curves of one base × snow in under 30 s (five grinds under 2.5 min), and,
once cached, the real contact adds under 5 ms to a 4096-station case and under 20 % to a
Figure 8/9 sweep. Rows:

1. micro curves, cold (an empty cache directory): S3 × machine-made, then S1–S5 — wall and
   process CPU time, and the split between the flat-ice curve and the bearing model;
2. the same curves from the disk cache (a fresh process's first call) and from memory;
3. one 4096-station case (skate, 60 kg at −120 mm, strip): median of repeated solves with and
   without the real contact, and the real contact's evaluation alone (``real_contact`` on the
   solved case);
4. the Figure 8/9 chunk function in this process (skate, 126 masses × the moduli given, warm
   starts): without and with the real contact, alternated ``--chunk-repeat`` times, the
   minimum of each kept (the whole sweep is Dask overhead plus these chunks;
   ``bench_sweep.py`` times the Dask part).

Timings are wall clock with the process CPU time beside them and the load average before and
after: the machine may be shared, and CPU time is the figure that carries over.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np


def _load() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True, check=False).stdout
    except OSError:  # pragma: no cover
        return f"loadavg {os.getloadavg()}"


def _timed(fn, *args, **kw):
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn(*args, **kw)
    return out, time.perf_counter() - t0, time.process_time() - c0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="S3 only; 3 moduli, 26 masses")
    ap.add_argument("--snow", default="machine-made")
    ap.add_argument("--repeat", type=int, default=15, help="repeats of the 4096-station case")
    ap.add_argument("--chunk-repeat", type=int, default=3, help="alternated repeats of the chunks")
    args = ap.parse_args()

    from skisnow.cli._render import print_table
    from skisnow.multiscale import _curves as curves_module
    from skisnow.multiscale import make_base, micro_curves, real_contact
    from skisnow.pipeline import solve_case
    from skisnow.snow import get_snow

    print("load before:", _load().strip())
    snow = get_snow(args.snow)
    rows = []
    with tempfile.TemporaryDirectory(prefix="skisnow-bench-cache-") as cache:
        names = ["S3"] if args.quick else ["S3", "S1", "S2", "S4", "S5"]
        total_wall = total_cpu = 0.0
        for name in names:
            base = make_base(name)
            _ = base.prepared  # preparation (grind + 33 µm low-pass) is the base's, not timed
            curves, wall, cpu = _timed(micro_curves, base, snow, cache_dir=cache)
            total_wall += wall
            total_cpu += cpu
            rows.append(
                [f"micro curves {name} × {snow.name} (cold)", wall, cpu,
                 f"{curves.pressures.size} pressures, {curves.pixel[0] * 1e6:g} µm, "
                 f"{round(curves.map_size[0] * 1e3)} mm map, converged "
                 f"{bool(curves.converged.all())}"]
            )  # fmt: skip
        if len(names) > 1:
            rows.append(["micro curves, five grinds (cold)", total_wall, total_cpu, "target 150 s"])
        curves_module._MEMORY.clear()
        base = make_base("S3")
        curves, wall, cpu = _timed(micro_curves, base, snow, cache_dir=cache)
        rows.append(["micro curves S3, from the disk cache", wall, cpu, f"{curves.from_cache}"])
        _, wall, cpu = _timed(micro_curves, base, snow, cache_dir=cache)
        rows.append(["micro curves S3, from memory", wall, cpu, ""])

        kw = {"mass": 60.0, "load_position": -0.12, "n_points": 4096}
        solve_case("skate", snow=snow, base=base, curves=curves, **kw)  # warm up (JIT, caches)
        solve_case("skate", snow=snow, **kw)
        with_real, without, alone = [], [], []
        for _ in range(args.repeat):
            _, w1, _ = _timed(solve_case, "skate", snow=snow, **kw)
            case, w2, _ = _timed(solve_case, "skate", snow=snow, base=base, curves=curves, **kw)
            without.append(w1)
            with_real.append(w2)
            resolved = case.real.friction
            _, w3, _ = _timed(real_contact, case.solution, curves, resolved)
            alone.append(w3)
        m0, m1, m2 = (statistics.median(v) for v in (without, with_real, alone))
        rows.append(["4096-station case, apparent only (median)", m0, float("nan"), ""])
        rows.append(["4096-station case, with real contact (median)", m1, float("nan"),
                     f"adds {1e3 * (m1 - m0):.2f} ms"])  # fmt: skip
        rows.append(["real contact alone on the case (median)", m2, float("nan"), "target 5 ms"])

        from dataclasses import replace

        from skisnow.snow import snow_record
        from skisnow.sweep import SweepSpec, contact_chunk
        from skisnow.sweep._point import loaded_profiles

        step = 5.0 if args.quick else 1.0
        moduli = (60e6, 200e6, 400e6) if args.quick else (20e6, 100e6, 200e6, 300e6, 400e6)
        spec = SweepSpec(
            skis=("skate",), masses=np.arange(5.0, 131.0, step), load_positions=(-0.12,),
            snow_moduli=moduli, n_points=4096,
        )  # fmt: skip
        import json

        os.environ["SKISNOW_CACHE_DIR"] = cache
        real_spec = replace(spec, base="S3", snow=json.dumps(snow_record(snow), sort_keys=True))
        real_spec.micro_curves()
        profiles = loaded_profiles(spec, "skate", -0.12)
        times: dict[str, list[tuple[float, float]]] = {"without": [], "with": []}
        for s in (spec, real_spec):
            contact_chunk(s, "skate", -0.12, moduli[0], profiles)  # warm up
        for _ in range(args.chunk_repeat):  # alternated, the minimum kept: the machine is shared
            for label, s in (("without", spec), ("with", real_spec)):
                t0, c0 = time.perf_counter(), time.process_time()
                for e in moduli:
                    contact_chunk(s, "skate", -0.12, e, profiles)
                times[label].append((time.perf_counter() - t0, time.process_time() - c0))
        times = {k: (min(w for w, _ in v), min(c for _, c in v)) for k, v in times.items()}
        n = len(spec.masses) * len(moduli)
        for label in ("without", "with"):
            wall, cpu = times[label]
            rows.append([f"Figure 8/9 chunks, {n} cases, {label} real contact (min)", wall, cpu,
                         ""])  # fmt: skip
        ratio = times["with"][1] / times["without"][1]
        rows.append(["Figure 8/9 chunks: CPU ratio with/without", ratio, float("nan"),
                     "target < 1.20"])  # fmt: skip
        # the same, load-robust: the CPU spent inside the real contact's own calls during one
        # run of the chunks, against the rest of that run (both under the same load)
        import skisnow.pipeline._real as real_glue
        from skisnow.sweep import _point

        spent = {"t": 0.0}

        def timed(fn):
            def run(*a, **k):
                c0 = time.process_time()
                try:
                    return fn(*a, **k)
                finally:
                    spent["t"] += time.process_time() - c0

            return run

        originals = (real_glue.case_real, _point._real_point)
        real_glue.case_real, _point._real_point = (timed(f) for f in originals)
        try:
            c0 = time.process_time()
            for e in moduli:
                contact_chunk(real_spec, "skate", -0.12, e, profiles)
            total = time.process_time() - c0
        finally:
            real_glue.case_real, _point._real_point = originals
        rows.append(["Figure 8/9 chunks: real contact's own CPU over the rest (instrumented)",
                     spent["t"] / (total - spent["t"]), float("nan"),
                     f"{1e3 * spent['t'] / n:.2f} ms a case"])  # fmt: skip
    print_table("real contact benchmark", ["step", "wall [s]", "CPU [s]", "note"], rows)
    print("load after:", _load().strip())


if __name__ == "__main__":
    main()
