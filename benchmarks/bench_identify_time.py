"""The identification's time (issue 25, item 5): shop and full plans, skis × noise -> CPU, wall,
EI and z0 errors, misfit, exit code.

Run:  uv run python benchmarks/bench_identify_time.py [--skis 5-24 1001 1002 1003 issue25]
      [--plans shop full] [--noise-um 5 10] [--repeats 1] [--out rows.jsonl] [--tag TAG]

The benches are those of ``bench_identify_coverage.py`` (the independent 1 mm reference bench of
each true ski, cached in ``--cache``, seeded noise; shop: 6 masses × 2 positions, stations every
10 mm; full: 13 masses × 3 positions, every 2 mm), identified by ``identify_ski`` with its
defaults. CPU is ``time.process_time`` of the identification alone (the bench is made or read
before), wall ``time.perf_counter``; the load average (``os.getloadavg``, 1 min) is printed with
every row: on a shared machine the CPU time of the same run grows with the load (caches,
memory bandwidth), so compare two versions of the code by running them interleaved (``--tag``
and ``--out`` from each worktree into one file), never against a table taken at another time.

The targets: shop plan < 10 s, full plan < 60 s on the 2-core development machine.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_identify_coverage import _skis, bench_of, errors, true_ski


def run_row(name: str, plan: str, noise_um: float, cache: Path) -> dict:
    from skisnow.identify import identify_ski

    bench = bench_of(name, plan, noise_um, cache)
    load0 = os.getloadavg()[0]
    t0, w0 = time.process_time(), time.perf_counter()
    res = identify_ski(bench)
    cpu, wall = time.process_time() - t0, time.perf_counter() - w0
    e = errors(res, true_ski(name))
    return {
        "ski": name, "plan": plan, "noise_um": noise_um, "cpu_s": cpu, "wall_s": wall,
        "ei_pct": e["ei_rms"], "z0_um": e["z0_rms"], "misfit": res.misfit,
        "exit": 0 if res.converged else 3, "lambda": res.regularisation,
        "load": round(0.5 * (load0 + os.getloadavg()[0]), 2),
    }  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["5-24", "1001", "1002", "1003", "issue25"])
    ap.add_argument("--plans", nargs="+", default=["shop"], choices=["shop", "full"])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--repeats", type=int, default=1, help="runs of every row (median)")
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument("--out", help="append every run as a JSON line to this file")
    ap.add_argument("--tag", default="", help="label of this code version in --out")
    args = ap.parse_args()
    rows = []
    print(f"{'plan':5} {'ski':8} {'noise µm':>8} {'CPU s':>7} {'wall s':>7} {'EI %':>6} "
          f"{'z0 µm':>6} {'misfit σ':>8} {'exit':>4} {'load':>5}")  # fmt: skip
    for plan in args.plans:
        for name in _skis(args.skis):
            for noise in args.noise_um:
                runs = [run_row(name, plan, noise, Path(args.cache)) for _ in range(args.repeats)]
                for r in runs:
                    r["tag"] = args.tag
                    if args.out:
                        with open(args.out, "a") as fh:
                            fh.write(json.dumps(r) + "\n")
                row = {**runs[0], "cpu_s": float(np.median([r["cpu_s"] for r in runs])),
                       "wall_s": float(np.median([r["wall_s"] for r in runs]))}  # fmt: skip
                rows.append(row)
                print(f"{plan:5} {name:8} {noise:8g} {row['cpu_s']:7.2f} {row['wall_s']:7.2f} "
                      f"{row['ei_pct']:6.2f} {row['z0_um']:6.2f} {row['misfit']:8.4f} "
                      f"{row['exit']:4d} {row['load']:5.1f}", flush=True)  # fmt: skip
    for plan in args.plans:
        cpu = [r["cpu_s"] for r in rows if r["plan"] == plan]
        if cpu:
            target = 10.0 if plan == "shop" else 60.0
            print(f"{plan}: CPU median {np.median(cpu):.2f} s (range {min(cpu):.2f}-"
                  f"{max(cpu):.2f}), below {target:g} s in {sum(c < target for c in cpu)}/"
                  f"{len(cpu)} rows")  # fmt: skip


if __name__ == "__main__":
    main()
