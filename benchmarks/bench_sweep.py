"""Benchmark of the sweeps: the Figure 8/9 sweep of Kalliorinne et al. (2023) — skate ski,
126 masses (5-130 kg) × 20 snow moduli (20-400 MPa) at x_m = -120 mm, strip model, 4096 stations
— on a local Dask cluster of 1 and of 2 workers, and resuming.

    uv run python benchmarks/bench_sweep.py [--quick] [--profile-source network|beam]

Targets (issue 5): < 10 s on this 2-core machine; 2 workers >= 1.7x faster than 1; a resumed
sweep recomputes 0 finished chunks. Prints a table, with the machine load (``uptime``) before
and after, since the machine may be shared.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np


def _uptime() -> str:
    try:
        return subprocess.run(
            ["uptime"], capture_output=True, text=True, check=False
        ).stdout.strip()
    except OSError:
        return f"loadavg {os.getloadavg()}"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--quick", action="store_true", help="5 kg mass steps (26 masses) only")
    p.add_argument("--profile-source", default=None, choices=("network", "beam"))
    p.add_argument("--n-points", type=int, default=4096)
    args = p.parse_args()

    from distributed import Client

    from skisnow.cli._demo import network_or_beam
    from skisnow.cli._render import print_table
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep
    from skisnow.sweep._run import local_cluster

    source = args.profile_source or network_or_beam()[0]
    masses = np.arange(5.0, 131.0, 5.0 if args.quick else 1.0)
    spec = SweepSpec(
        skis=("skate",), masses=masses, load_positions=(-0.120,),
        snow_moduli=np.arange(20.0, 401.0, 20.0) * 1e6, model="strip",
        profile_source=source, n_points=args.n_points,
    )  # fmt: skip
    # Do warm starts along the masses pay? One chunk (all masses, one modulus) in process.
    from dataclasses import replace

    from skisnow.sweep import contact_chunk
    from skisnow.sweep._point import loaded_profiles

    warm_rows = []
    # imports and the network's compilation for this many masses, paid once by every process
    # (and so by neither the 1- nor the 2-worker run below)
    t0 = time.perf_counter()
    profiles = loaded_profiles(spec, "skate", -0.12)
    first_profiles = time.perf_counter() - t0
    t0 = time.perf_counter()
    loaded_profiles(spec, "skate", -0.12)
    warm_profiles = time.perf_counter() - t0
    print(f"loaded profiles of {len(masses)} masses: {first_profiles:.2f} s first call "
          f"(JAX compilation), {warm_profiles:.2f} s after")  # fmt: skip
    contact_chunk(replace(spec, masses=masses[:2]), "skate", -0.12, 100e6)  # imports, caches
    for warm in (True, False):
        s = replace(spec, warm_start=warm)
        t0 = time.perf_counter()
        out = contact_chunk(s, "skate", -0.12, 100e6, profiles)
        dt = time.perf_counter() - t0
        warm_rows.append((f"one chunk ({len(masses)} masses, 100 MPa), "
                          f"{'warm' if warm else 'cold'} starts", dt,
                          float(np.mean(out["iterations"]))))  # fmt: skip
    load_before = _uptime()
    print(f"before: {load_before}")
    print(f"sweep: {spec.n_points_total} contact solves in {len(spec.chunks())} chunks, "
          f"{source} profiles, {spec.n_points} stations, cores: {os.cpu_count()}")  # fmt: skip
    tmp = Path(tempfile.mkdtemp(prefix="bench_sweep_"))
    rows = []
    times = {}
    try:
        for n in (1, 2):
            t0 = time.perf_counter()
            cluster = local_cluster(n)
            client = Client(cluster)
            startup = time.perf_counter() - t0
            store = tmp / f"w{n}.zarr"
            run = run_sweep(spec, store, client=client)
            client.close()
            cluster.close()
            times[n] = run
            rows.append((f"{n} worker{'s' if n > 1 else ''}", spec.n_points_total, startup,
                         run.compute_time, startup + run.wall_time,
                         1e3 * run.compute_time / spec.n_points_total * n))  # fmt: skip
        same = open_sweep(tmp / "w1.zarr").identical(open_sweep(tmp / "w2.zarr"))
        # resume 1: the same sweep again -> nothing to compute
        again = run_sweep(spec, tmp / "w2.zarr", workers=0)
        rows.append(("resume, complete store", 0, 0.0, again.compute_time, again.wall_time, None))
        # resume 2: half of the chunks lost (markers cleared, data spoilt) -> exactly those
        import zarr

        group = zarr.open_group(str(tmp / "w2.zarr"), mode="r+")
        lost = spec.chunks()[::2]
        for i, j, k in lost:
            group["chunk_done"][i, j, k] = 0
            group["area_cm2"][i, :, j, k, :] = -1.0
        t0 = time.perf_counter()
        cluster = local_cluster(2)
        client = Client(cluster)
        part = run_sweep(spec, tmp / "w2.zarr", client=client)
        client.close()
        cluster.close()
        resumed_ok = sorted(part.computed) == sorted(lost)
        equal_after = open_sweep(tmp / "w2.zarr").identical(open_sweep(tmp / "w1.zarr"))
        rows.append((f"resume, {len(lost)} chunks lost (2 workers)", len(lost) * len(masses),
                     0.0, part.compute_time, time.perf_counter() - t0, None))  # fmt: skip
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print_table(
        "bench_sweep: Figure 8/9 sweep (skate, x_m = -120 mm, strip)",
        ["run", "solves", "cluster start (s)", "compute (s)", "total (s)", "ms/solve/worker"],
        rows,
        floatfmt=".3g",
    )
    print_table("warm starts along the load path", ["run", "time (s)", "mean iterations"],
                warm_rows)  # fmt: skip
    speedup = times[1].compute_time / times[2].compute_time
    total1 = rows[0][4]
    total2 = rows[1][4]
    print_table(
        "targets",
        ["target", "measured", "met"],
        [
            ("Figure 8/9 sweep < 10 s (2 workers, compute)", f"{times[2].compute_time:.1f} s",
             times[2].compute_time < 10),
            ("... incl. cluster start", f"{total2:.1f} s", total2 < 10),
            ("2 workers >= 1.7x faster than 1 (compute)", f"{speedup:.2f}x", speedup >= 1.7),
            ("... incl. cluster start", f"{total1 / total2:.2f}x", total1 / total2 >= 1.7),
            ("complete store: chunks recomputed", len(again.computed), len(again.computed) == 0),
            ("lost chunks only recomputed", f"{len(part.computed)} of {len(spec.chunks())}",
             resumed_ok),
            ("1 and 2 workers identical; resumed identical", f"{same} / {equal_after}",
             same and equal_after),
        ],
    )  # fmt: skip
    print(f"after:  {_uptime()}")


if __name__ == "__main__":  # required: Dask workers re-import the main module
    main()
