"""Benchmark of the explorer page: build time and page size on the default grid (two skis × 26
masses × 6 load positions × 10 snow moduli = 3120 contact solves, 4096 stations, 512 display
stations).

    uv run python benchmarks/bench_explore.py [--stations 512]

Target: a page under 8 MB. Prints a table, with the machine load before and after.
"""

from __future__ import annotations

import argparse
import os
import time


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--stations", type=int, default=512)
    p.add_argument("--skis", nargs="+", default=["classic", "skate"])
    args = p.parse_args()
    from skisnow.explore import ExplorerGrid, explorer_dataset, render_explorer
    from skisnow.network import camber_profile

    camber_profile(args.skis[0], mass=60.0, load_position=-0.12, source="network")  # warm JAX
    print(f"load before: {os.getloadavg()}")
    grid = ExplorerGrid(n_display=args.stations)
    t0 = time.perf_counter()
    ds = explorer_dataset(args.skis, grid)
    t1 = time.perf_counter()
    page = render_explorer(ds)
    t2 = time.perf_counter()
    n = int(ds["converged"].size)
    rows = [
        ("skis × masses × positions × moduli", f"{len(args.skis)} × {len(grid.masses)} × "
         f"{len(grid.load_positions)} × {len(grid.snow_moduli)} = {n}"),
        ("display stations", str(grid.n_display)),
        ("solve (s)", f"{t1 - t0:.1f}"),
        ("render + pack (s)", f"{t2 - t1:.2f}"),
        ("page size (MB)", f"{len(page.encode()) / 1e6:.2f}"),
        ("converged points", f"{int(ds['converged'].sum())} / {n}"),
    ]  # fmt: skip
    w = max(len(a) for a, _ in rows)
    print(f"| {'quantity'.ljust(w)} | value |\n|{'-' * (w + 2)}|-------|")
    for a, b in rows:
        print(f"| {a.ljust(w)} | {b} |")
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
