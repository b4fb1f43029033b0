"""The Figure 8/9 map at 10× its resolution on a Dask ``distributed`` cluster, 1 → 2 workers.

    uv run python benchmarks/bench_distributed.py                     # LocalCluster, 1 and 2
    uv run python benchmarks/bench_distributed.py --workers 1,2,4     # more local workers
    uv run python benchmarks/bench_distributed.py --scheduler tcp://host:8786   # a running one

The map of Kalliorinne et al. (2023), Figures 8–9: skate ski, x_m = −120 mm, strip model, 4096
stations, masses 5–130 kg, snow moduli 20–400 MPa in 20 MPa steps. At 10× its resolution the
masses go in 0.1 kg steps (1251 masses × 20 moduli = 25,020 contact solves, 10× the paper's
2,520 points), each (modulus) column one chunk of 1251 warm-started solves — chunks as the sweep
engine makes them (:func:`skisnow.sweep.run_sweep`): the workers compute, this process writes the
Zarr store. The workers are separate processes (``LocalCluster(processes=True)``, one thread
each), so the same code runs on a cluster of machines: give ``--scheduler`` the address of any
``dask.distributed`` scheduler (``dask scheduler`` + ``dask worker`` on other hosts, or a batch
cluster from ``dask-jobqueue``; see docs/performance/speed.md).

Prints, per cluster size: the cluster's start-up, the compute time (first task to last write),
solves per second, CPU-milliseconds per solve per worker, the speed-up over one worker and the
parallel efficiency; then the cost of a national team's season of maps (every ski × every
day's snow, one such map per ski per day, ``--skis`` × ``--days``) on a 64-core cluster,
extrapolated from the measured per-worker throughput and efficiency. The machine may be
shared: the load average is printed before and after every run.
"""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np


def load() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--workers", default="1,2", help="local cluster sizes to run (comma list)")
    ap.add_argument("--scheduler", default=None, help="address of a running scheduler")
    ap.add_argument("--mass-step-kg", type=float, default=0.1, help="0.1: 10x the paper's 1 kg")
    ap.add_argument(
        "--skis", type=int, default=400, help="skis of a national team (season estimate)"
    )
    ap.add_argument("--days", type=int, default=150, help="days of snow in a season (estimate)")
    ap.add_argument("--cores", type=int, default=64, help="cores of the batch cluster (estimate)")
    args = ap.parse_args()

    from distributed import Client

    from skisnow.sweep import SweepSpec, run_sweep
    from skisnow.sweep._run import local_cluster

    masses = np.round(np.arange(5.0, 130.0 + 1e-9, args.mass_step_kg), 6)
    spec = SweepSpec(
        skis=("skate",),
        masses=masses,
        load_positions=(-0.120,),
        snow_moduli=np.arange(20.0, 401.0, 20.0) * 1e6,
        model="strip",
        profile_source="beam",
        n_points=4096,
    )
    n_solves = spec.n_points_total
    paper_points = 126 * 20
    print(
        f"Figure 8/9 map at {n_solves / paper_points:.1f}x its resolution: {len(masses)} "
        f"masses x {len(spec.snow_moduli)} moduli = {n_solves} solves in "
        f"{len(spec.chunks())} chunks; {os.cpu_count()} CPUs here"
    )
    rows = []
    tmp = Path(tempfile.mkdtemp(prefix="bench_distributed_"))
    try:
        runs = [None] if args.scheduler else [int(w) for w in args.workers.split(",")]
        for n in runs:
            before = load()
            t0 = time.perf_counter()
            if n is None:
                cluster, client = None, Client(args.scheduler)
            else:
                cluster = local_cluster(n)
                client = Client(cluster)
            startup = time.perf_counter() - t0
            workers = len(client.scheduler_info(n_workers=-1).get("workers", {}))
            run = run_sweep(spec, tmp / f"w{workers}.zarr", client=client)
            client.close()
            if cluster is not None:
                cluster.close()
            rows.append((workers, startup, run.compute_time, before, load()))
            print(
                f"  {workers} worker(s): start-up {startup:.1f} s, compute {run.compute_time:.1f}"
                f" s, {n_solves / run.compute_time:.0f} solves/s; load {before} -> {load()}"
            )
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    base = rows[0]
    print(
        "\n| workers | start-up s | compute s | solves/s | ms/solve/worker | speed-up | "
        "efficiency | load before -> after |\n|---|---|---|---|---|---|---|---|"
    )
    for w, s, c, b, a in rows:
        speed = base[2] / c * (base[0] if base[0] else 1)
        print(
            f"| {w} | {s:.1f} | {c:.1f} | {n_solves / c:.0f} | {1e3 * c * w / n_solves:.2f} | "
            f"{speed / base[0]:.2f} | {speed / base[0] / (w / base[0]):.2f} | {b} -> {a} |"
        )

    # the season: one Figure 8/9 map (2,520 solves) per ski per day of snow
    w1, _, c1, _, _ = base
    per_solve = c1 * w1 / n_solves  # worker-seconds per solve, first run
    w, _, c, _, _ = rows[-1]
    eff = (c1 * w1) / (c * w)  # parallel efficiency of the last run against the first
    season = args.skis * args.days * paper_points
    core_hours = season * per_solve / 3600
    print(
        f"\nSeason estimate: {args.skis} skis x {args.days} days x {paper_points} solves = "
        f"{season:.3g} solves at {per_solve * 1e3:.2f} worker-ms per solve (measured with "
        f"{w1} worker) = {core_hours:.0f} core-hours; on {args.cores} cores "
        f"{core_hours / args.cores:.1f} h wall with independent chunks scaling perfectly, "
        f"{core_hours / args.cores / max(eff, 1e-9):.1f} h at the efficiency measured here "
        f"({eff:.2f}, {w} against {w1} workers: meaningful only on an idle machine). "
        "Money = core-hours x the cluster's price per core-hour."
    )


if __name__ == "__main__":  # required: Dask workers re-import the main module
    main()
