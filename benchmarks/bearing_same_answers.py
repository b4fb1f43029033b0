"""Same answers: every output array of the bearing model before and after a change of its search.

    # in a tree with the code before the change (e.g. git worktree add --detach /tmp/before main)
    uv run python <this tree>/benchmarks/bearing_same_answers.py save /tmp/bearing_before.npz
    # in the tree with the change
    uv run python benchmarks/bearing_same_answers.py compare /tmp/bearing_before.npz

Cases: issue 29's benchmark case (preset S3, 1 mm² at 1 µm, 31 grain sizes 450–750 µm, stride
1, 2 threads; every array of :class:`~skisnow.micro.BearingSweep`), and the per-position maps
(fractional area, penetration, first contact, positions) of :func:`~skisnow.micro.bearing_area`
on the benchmark map at 450 and 750 µm (stride 1) and 600 µm (stride 2), on three other seeds of
S3 (0.5 mm, 300 µm) and on presets S1 and S5 (0.6 mm, 400 µm), each with the exact sphere and
the paraboloid. ``compare`` prints, per array that is not bitwise equal, its largest relative
difference and how many entries differ, then the count of bitwise-equal arrays. The sweep's
wall and CPU time are printed too (a rough figure: ``bench_speed.py --rows bearing`` is the
benchmark).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from skisnow.micro import bearing_area, bearing_sweep, grind_preset, ice_hardness, lowpass

MAP_FIELDS = ("fractional_area", "penetration", "first_contact", "positions")
SWEEP_FIELDS = (
    "diameters",
    "fractional_area",
    "fractional_area_std",
    "mean_penetration",
    "max_penetration",
    "n_positions",
)


def outputs() -> dict[str, np.ndarray]:
    """Every compared array, by name."""
    hard = ice_hardness(-2.0)
    res: dict[str, np.ndarray] = {}
    topo = lowpass(grind_preset("S3", size=1e-3, dx=1e-6))
    w0, c0 = time.perf_counter(), time.process_time()
    from bench_speed import BEARING_CASE

    sweep = bearing_sweep(topo, hardness=hard, **BEARING_CASE)
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"sweep (compile included): {wall:.1f} s wall, {cpu:.1f} s CPU, load {load}")
    for f in SWEEP_FIELDS:
        res[f"sweep_{f}"] = getattr(sweep, f)
    # (preset, map side [m], seed, diameter [m], stride)
    cases = [("S3", 1e-3, 0, 450e-6, 1), ("S3", 1e-3, 0, 750e-6, 1), ("S3", 1e-3, 0, 600e-6, 2)]
    cases += [("S3", 0.5e-3, seed, 300e-6, 1) for seed in (1, 2, 3)]
    cases += [(preset, 0.6e-3, 4, 400e-6, 1) for preset in ("S1", "S5")]
    for preset, size, seed, d, stride in cases:
        tp = lowpass(grind_preset(preset, size=size, dx=1e-6, seed=seed))
        for shape in ("sphere", "paraboloid"):
            m = bearing_area(
                tp, diameter=d, pressure=20e3, hardness=hard, stride=stride, shape=shape
            )
            key = f"{preset}_{size * 1e3:g}mm_seed{seed}_{d * 1e6:.0f}um_stride{stride}_{shape}"
            for f in MAP_FIELDS:
                res[f"{key}_{f}"] = getattr(m, f)
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mode", choices=("save", "compare"))
    ap.add_argument("file", help="the .npz file of the arrays before the change")
    args = ap.parse_args()
    res = outputs()
    if args.mode == "save":
        np.savez(args.file, **res)
        print(f"{len(res)} arrays saved to {args.file}")
        return
    ref = np.load(args.file)
    equal = 0
    worst = 0.0
    for k, v in res.items():
        r = ref[k]
        if r.shape != v.shape:
            print(f"{k}: shape {v.shape}, before {r.shape}")
            worst = np.inf
            continue
        if np.array_equal(r, v):
            equal += 1
            continue
        rel = float(np.max(np.abs(r - v) / np.maximum(np.abs(r), np.finfo(float).tiny)))
        worst = max(worst, rel)
        print(f"{k}: largest relative difference {rel:.3e}, {np.count_nonzero(r != v)} of {r.size}")
    print(f"{equal} of {len(res)} arrays bitwise equal; largest relative difference {worst:.3e}")


if __name__ == "__main__":
    main()
