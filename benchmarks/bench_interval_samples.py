"""How many posterior samples the intervals of an identified ski's answers need, and whether they
cover the true ski.

Run:  uv run python benchmarks/bench_interval_samples.py [--samples 25 50 100 200 400]
      [--repeats 5] [--coverage 0] [--ski FILE]

The identified ski (unless ``--ski`` names one): the shipped classic's shop bench — 6 masses
(10–60 kg) at two load positions (−120, 0 mm), stations every 20 mm, 5 µm seeded noise — made by
the reference bench (:func:`skisnow.bench.reference_bench`, finite differences independent of the
fit's beam), then :func:`skisnow.identify.identify_ski` (default settings).

1. Sample count. The case: 70 kg at −120 mm on 100 MPa snow (strip, 4096 stations). For each
   sample count n, :func:`skisnow.pipeline.case_intervals` with ``--repeats`` seeds: the Monte
   Carlo error of the interval ends *measured* as the spread (standard deviation) of each end
   across the seeds, as a fraction of the interval's width (median and worst over the answers
   below), beside the bootstrap estimate every interval carries (``mc_error``), and the CPU time
   of one call. The error falls as 1/sqrt(n): pick n where it is small beside the width.
2. Coverage (``--coverage K``): K seeds of the bench noise, each identified, each answer's 95 %
   interval checked against the TRUE classic's answer (a prediction, nothing fitted to it). The
   intervals inherit the identification's bands: where those miss the truth (issue 25's coverage
   study: 72–83 % on shop plans) the contact intervals miss too.

Answers: total contact length, mean and peak pressure, rear and front load share, kick-zone
contact length. Report the printed tables with ``uptime``'s load average.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import time

import numpy as np

from skisnow.bench import reference_bench
from skisnow.identify import identify_ski
from skisnow.pipeline import case_intervals, case_quantities, solve_case
from skisnow.ski import get_ski, read_ski

CASE = dict(mass=70.0, load_position=-0.12, snow_modulus=100e6)
ANSWERS = ("total.length", "total.mean_pressure", "total.max_pressure", "rear.load_share",
           "front.load_share", "kick.length")  # fmt: skip


def identified(seed: int):
    truth = get_ski("classic")
    stations = np.arange(np.ceil(truth.x_tail / 0.02), np.floor(truth.x_tip / 0.02) + 1) * 0.02
    bench = reference_bench(truth, masses=[10, 20, 30, 40, 50, 60], load_positions=[-0.12, 0.0],
                            stations=stations, noise=5e-6, seed=seed)  # fmt: skip
    t = time.process_time()
    res = identify_ski(bench, name=f"classic identified (seed {seed})")
    return res, time.process_time() - t


def sample_count(ski, counts, repeats) -> None:
    case = solve_case(ski, **CASE)
    print(f"\nMonte Carlo error of the 95 % interval ends vs sample count ({repeats} seeds)")
    print(
        "| samples | CPU s / call | measured SD of ends / width: median, worst | bootstrap "
        "estimate: median, worst |"
    )
    print("| --- | --- | --- | --- |")
    for n in counts:
        lows, highs, boot, cpu = [], [], [], []
        for r in range(repeats):
            t = time.process_time()
            iv = case_intervals(case, samples=n, seed=1000 + r)
            cpu.append(time.process_time() - t)
            lows.append([iv.low[a] for a in ANSWERS])
            highs.append([iv.high[a] for a in ANSWERS])
            boot.append([iv.mc_error[a] for a in ANSWERS])
        lo, hi = np.array(lows), np.array(highs)
        width = np.median(hi - lo, axis=0)
        ok = width > 0
        measured = np.maximum(lo.std(axis=0, ddof=1), hi.std(axis=0, ddof=1))[ok] / width[ok]
        b = np.median(np.array(boot), axis=0)[ok]
        print(
            f"| {n} | {np.median(cpu):.2f} | {100 * np.median(measured):.1f} %, "
            f"{100 * measured.max():.1f} % | {100 * np.median(b):.1f} %, "
            f"{100 * b.max():.1f} % |"
        )


def coverage(k: int, samples: int) -> None:
    truth = case_quantities(solve_case(get_ski("classic"), **CASE))
    print(
        f"\nCoverage of the TRUE classic by the 95 % intervals ({samples} samples, "
        f"{k} bench-noise seeds)"
    )
    print("| seed | exit-0 fit | identification CPU s | " + " | ".join(ANSWERS) + " |")
    print("| --- " * (3 + len(ANSWERS)) + "|")
    inside = np.zeros(len(ANSWERS), int)
    for seed in range(k):
        res, cpu = identified(seed)
        iv = case_intervals(solve_case(res.ski, **CASE), samples=samples, seed=seed)
        cells = []
        for i, a in enumerate(ANSWERS):
            hit = iv.low[a] <= truth[a] <= iv.high[a]
            inside[i] += hit
            cells.append(f"{'in' if hit else 'OUT'} ({iv.low[a]:.4g}–{iv.high[a]:.4g}; "
                         f"true {truth[a]:.4g})")  # fmt: skip
        print(f"| {seed} | {res.converged} | {cpu:.0f} | " + " | ".join(cells) + " |")
    print("| inside | | | " + " | ".join(f"{c}/{k}" for c in inside) + " |")
    n = k * len(ANSWERS)
    print(f"total: {inside.sum()}/{n} = {100 * inside.sum() / n:.0f} %")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, nargs="+", default=[25, 50, 100, 200, 400])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--coverage", type=int, default=0)
    ap.add_argument("--ski", default=None)
    args = ap.parse_args()
    if args.ski:
        ski = read_ski(args.ski)
    else:
        res, cpu = identified(seed=100)
        ski = res.ski
        print(
            f"identified the classic's reference shop bench in {cpu:.0f} s CPU: converged "
            f"{res.converged}, misfit {res.misfit:.2f} σ"
        )
    sample_count(ski, args.samples, args.repeats)
    if args.coverage:
        coverage(args.coverage, 200)


if __name__ == "__main__":
    main()
