"""Time the virtual camber bench: the paper's full sequence for both shipped skis.

Run:  uv run python benchmarks/bench_bench.py [--repeat N]

Prints a table: ski, profiles, rows, solves' pivoting iterations (mean / max), wall time, time per
profile, and the warm-start gain against cold starts. Target (issue 2): both skis < 10 s.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from rich.console import Console
from rich.table import Table

from skisnow.bench import DEFAULT_LOAD_POSITIONS, DEFAULT_MASSES, run_bench
from skisnow.ski import SHIPPED_SKIS, get_ski, solve_beam


def _iterations(name: str, warm: bool) -> tuple[list[int], float]:
    ski = get_ski(name)
    its = []
    t0 = time.perf_counter()
    for p in DEFAULT_LOAD_POSITIONS:
        prev = None
        for m in DEFAULT_MASSES:
            sol = solve_beam(ski, mass=m, load_position=p, warm_start=prev if warm else None)
            its.append(sol.iterations)
            prev = sol
    return its, time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3, help="timed repetitions (best is shown)")
    args = parser.parse_args()
    console = Console(width=150)
    table = Table(title="Virtual bench: full sequence (26 masses x 6 positions, 1 mm sampling)")
    for col in (
        "ski",
        "profiles",
        "rows",
        "iters warm mean/max",
        "iters cold mean/max",
        "solve warm (s)",
        "solve cold (s)",
        "run_bench best (s)",
        "per profile (ms)",
    ):
        table.add_column(col, justify="right")
    total = 0.0
    for name in SHIPPED_SKIS:
        get_ski(name)
        run_bench(name, masses=[10.0], load_positions=[-0.1])  # assemble + cache the beam
        times = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            data = run_bench(name)
            times.append(time.perf_counter() - t0)
        best = min(times)
        total += best
        warm, t_warm = _iterations(name, True)
        cold, t_cold = _iterations(name, False)
        n = len(data.conditions)
        table.add_row(
            name,
            str(n),
            str(len(data.table)),
            f"{np.mean(warm):.1f} / {max(warm)}",
            f"{np.mean(cold):.1f} / {max(cold)}",
            f"{t_warm:.2f}",
            f"{t_cold:.2f}",
            f"{best:.2f}",
            f"{1e3 * best / n:.1f}",
        )
    console.print(table)
    load = os.getloadavg()
    console.print(
        f"both skis: {total:.2f} s (target < 10 s); load average {load[0]:.2f} {load[1]:.2f} "
        f"{load[2]:.2f} on {os.cpu_count()} CPUs"
    )


if __name__ == "__main__":
    main()
