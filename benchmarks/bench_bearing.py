"""Benchmark of the bearing model (issue 6, point 9).

    uv run python benchmarks/bench_bearing.py            # the target case (full raster)
    uv run python benchmarks/bench_bearing.py --quick    # 0.5 mm map, 7 sizes (a smoke run)

Target case: a 1 mm × 1 mm topography at 1 µm pixels (preset S3 after the 33 µm low-pass),
31 grain sizes 450–750 µm, every pixel centre whose footprint fits in the map, 20 kPa, −2 °C.
Prints a table: one size (the middle one) timed single-threaded, per-size positions and A_fr,
the total at raster strides 1, 2, 3 (with the change of the mean A_fr they cause), the naive
footprint search extrapolated from a sample of positions, and the largest difference to it
(the reference implementation) at the smallest, middle and largest size.

Timings: wall clock and the process CPU time, with the load average. On a shared machine the
wall clock of a 2-thread run is inflated by the other jobs; the CPU time per position–size pair
is the figure that carries over: an idle 2-core machine needs ≈ CPU time / 2 (the kernel holds
no GIL and the threads take one grain size each).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from skisnow.micro import (
    bearing_area,
    bearing_area_reference,
    bearing_sweep,
    grind_preset,
    ice_hardness,
    lowpass,
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="0.5 mm map, 7 grain sizes")
    ap.add_argument("--preset", default="S3")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--strides", default="1,2,3", help="raster strides to time")
    args = ap.parse_args()

    size = 0.5e-3 if args.quick else 1e-3
    diameters = np.arange(450, 751, 50 if args.quick else 10) * 1e-6
    if args.quick:
        diameters = diameters * 0.5
    hardness = ice_hardness(-2.0)
    pressure = 20e3
    t0 = time.perf_counter()
    topo = lowpass(grind_preset(args.preset, size=size, dx=1e-6))
    t_prep = time.perf_counter() - t0
    load = os.getloadavg()
    print(
        f"bearing model benchmark: preset {args.preset}, {topo.shape[0]}×{topo.shape[1]} px "
        f"at 1 µm, {diameters.size} grain sizes {diameters[0] * 1e6:.0f}–"
        f"{diameters[-1] * 1e6:.0f} µm, {args.workers} worker thread(s), "
        f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on {os.cpu_count()} CPUs"
    )
    print(f"synthesis + low-pass: {t_prep:.2f} s")
    d_mid = float(diameters[diameters.size // 2])
    bearing_area(topo, diameter=d_mid, pressure=pressure, hardness=hardness, stride=8)  # jit
    w0, c0 = time.perf_counter(), time.process_time()
    one = bearing_area(topo, diameter=d_mid, pressure=pressure, hardness=hardness)
    w1, c1 = time.perf_counter() - w0, time.process_time() - c0
    print(
        f"one size ({d_mid * 1e6:.0f} µm) single-threaded: {len(one.positions)} positions, "
        f"wall {w1:.2f} s, CPU {c1:.2f} s = {c1 / len(one.positions) * 1e6:.2f} µs per position, "
        f"mean A_fr {one.mean_fractional_area:.12g}"
    )
    rows = []
    base = None
    for stride in (int(s) for s in args.strides.split(",")):
        times: list[float] = []
        last = [time.perf_counter()]

        def tick(done: int, total: int, times: list[float] = times, last: list = last) -> None:
            now = time.perf_counter()
            times.append(now - last[0])
            last[0] = now

        t0 = time.perf_counter()
        c0 = time.process_time()
        sweep = bearing_sweep(
            topo,
            diameters=diameters,
            pressure=pressure,
            hardness=hardness,
            stride=stride,
            workers=args.workers,
            progress=tick,
        )
        total = time.perf_counter() - t0
        cpu = time.process_time() - c0
        mean_afr = float(np.mean(sweep.fractional_area))
        if base is None:
            base = sweep.fractional_area
        dev = float(np.max(np.abs(sweep.fractional_area / base - 1)))
        rows.append((stride, int(sweep.n_positions.sum()), total, cpu, mean_afr, dev))
        if stride == 1:
            print("\nper grain size (stride 1):")
            print(f"{'D [µm]':>8} {'positions':>10} {'A_fr':>12} {'mean δ [µm]':>12}")
            for d, n, a, pm in zip(
                sweep.diameters,
                sweep.n_positions,
                sweep.fractional_area,
                sweep.mean_penetration,
                strict=True,
            ):
                print(f"{d * 1e6:8.0f} {n:10d} {a:12.7f} {pm * 1e6:12.4f}")
    # naive search: time a sample of positions and compare (smallest, middle, largest size)
    sample = 200 if not args.quick else 100
    worst = 0.0
    per_pos = 0.0
    for d in (float(diameters[0]), d_mid, float(diameters[-1])):
        stride = max(1, int(np.sqrt((topo.shape[0] - d / 1e-6) ** 2 / sample)))
        kw = {"diameter": d, "pressure": pressure, "hardness": hardness, "stride": stride}
        t0 = time.perf_counter()
        ref = bearing_area_reference(topo, **kw)
        if d == d_mid:
            per_pos = (time.perf_counter() - t0) / len(ref.positions)
        fast = bearing_area(topo, **kw)
        worst = max(worst, float(np.max(np.abs(fast.fractional_area / ref.fractional_area - 1))))
    naive_total = per_pos * rows[0][1] / max(args.workers, 1)

    print(
        f"\n{'method':<34} {'pairs':>9} {'wall [s]':>9} {'CPU [s]':>8} {'µs/pair CPU':>11} "
        f"{'mean A_fr':>14} {'max |ΔA_fr|/A_fr':>18}"
    )
    for stride, npos, total, cpu, mean_afr, dev in rows:
        print(
            f"{'compiled pruned search, stride ' + str(stride):<34} {npos:9d} {total:9.1f} "
            f"{cpu:8.1f} {cpu / npos * 1e6:11.2f} {mean_afr:14.11f} {dev:18.2e}"
        )
    print(
        f"{'naive footprint search (extrap.)':<34} {rows[0][1]:9d} {naive_total:9.0f} "
        f"{'':>8} {'':>11} {'(same)':>14} {worst:18.2e}"
    )
    print(
        f"\nlargest |ΔA_fr|/A_fr against the naive search on {sample} sampled positions at "
        f"{diameters[0] * 1e6:.0f}, {d_mid * 1e6:.0f}, {diameters[-1] * 1e6:.0f} µm: {worst:.1e}"
    )
    print(
        f"speed-up over the naive search at stride 1: {naive_total / rows[0][2]:.0f}×; "
        f"target < 30 s for stride 1: {'met' if rows[0][2] < 30 else 'NOT met'} (wall, this "
        f"load); idle 2-core estimate CPU/2 = {rows[0][3] / 2:.1f} s"
    )
    print(f"load average at the end: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
