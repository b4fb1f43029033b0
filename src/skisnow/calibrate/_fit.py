"""The calibration's fit (differential evolution, then a least-squares polish) and its report.

A seeded differential evolution (:func:`scipy.optimize.differential_evolution`, a population
in a box around the start(s), the starts themselves members), derivative-free because the
patch-count terms jump, then a bounded least-squares polish (:func:`scipy.optimize.least_squares`,
trust-region reflective, forward differences) of the best member: :func:`fit`; the caption table,
the practitioners' numbers, the hinges and the topology of a parameter vector as a calibration
record: :func:`report`.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.optimize import OptimizeResult, differential_evolution, least_squares

from skisnow.calibrate._params import KNOTS, bounds, make_ski, start_vector, unpack
from skisnow.calibrate._residuals import (
    EI_STEP_MAX,
    FitOptions,
    caption_residuals,
    ei_shape_residuals,
    plausibility,
    plausibility_residuals,
    residuals,
    topology,
    topology_residuals,
)

__all__ = ["fit", "report"]


def fit(
    kind: str,
    *,
    seed: int,
    generations: int,
    popsize: int,
    opts: FitOptions,
    start: np.ndarray | None = None,
    sigma: float = 0.08,
    more_starts: tuple[np.ndarray, ...] = (),
    max_seconds: float = math.inf,
    polish_starts: bool = False,
) -> dict:
    """Differential evolution in the unit box around the start(s), then a least-squares polish.

    With ``more_starts`` the population is split into equal clouds around every start, each
    start itself a member. With ``polish_starts`` every start is first polished as the result
    is (``--polish-starts``): a record resampled onto other knots (PCHIP, not exactly
    representable there) is a different ski in the tens of µm that decide the classic's pocket.
    """
    v0 = start_vector(kind) if start is None else start
    lo, hi = bounds(kind)
    u0 = np.clip((v0 - lo) / (hi - lo), 0.0, 1.0)
    us = [u0] + [np.clip((v - lo) / (hi - lo), 0.0, 1.0) for v in more_starts]

    def vec(u: np.ndarray) -> np.ndarray:
        return lo + (hi - lo) * np.clip(u, 0.0, 1.0)

    n_res = residuals(kind, vec(u0), opts).size  # the residual count least squares needs fixed

    def polish(u: np.ndarray) -> OptimizeResult:
        return least_squares(
            lambda u: residuals(kind, vec(u), opts, n_res),
            u, bounds=(0.0, 1.0), method="trf", diff_step=0.01, max_nfev=20 * u0.size,
        )  # fmt: skip

    if polish_starts:
        for i, u in enumerate(us):
            ls = polish(u)
            f0 = float(np.sum(residuals(kind, vec(u), opts, n_res) ** 2))
            print(f"  start {i}: misfit {f0:.3f} -> polished {2 * ls.cost:.3f}", flush=True)
            us[i] = ls.x
        u0 = us[0]
    count = [0]
    best = [math.inf]
    t0 = time.perf_counter()

    def objective(u: np.ndarray) -> float:
        count[0] += 1
        f = float(np.sum(residuals(kind, vec(u), opts, n_res) ** 2))
        if f < best[0]:
            best[0] = f
            print(
                f"  [{kind} {count[0]:5d} {time.perf_counter() - t0:5.0f} s] {f:10.3f}", flush=True
            )
        return f

    # the population: a seeded cloud around the start (sigma of the box), the start itself
    rng = np.random.default_rng(seed)
    n_pop = popsize * u0.size
    centre = np.array([us[i * len(us) // n_pop] for i in range(n_pop)])
    init = np.clip(centre + sigma * rng.standard_normal((n_pop, u0.size)), 0.0, 1.0)
    for j, u in enumerate(us):
        init[j * n_pop // len(us)] = u
    de = differential_evolution(
        objective, [(0.0, 1.0)] * u0.size, init=init, maxiter=generations, seed=seed,
        polish=False, tol=0.0, mutation=(0.4, 0.9), recombination=0.7,
        callback=lambda *_: time.perf_counter() - t0 > max_seconds,
    )  # fmt: skip
    print(f"  DE: {de.nit} generations, {de.nfev} evaluations, misfit {de.fun:.3f}", flush=True)
    ls = polish(de.x)
    u = ls.x if 2 * ls.cost < de.fun else de.x
    print(f"  polish: {ls.nfev} evaluations, misfit {2 * ls.cost:.3f}", flush=True)
    return {
        "vector": vec(u).tolist(), "evaluations": count[0], "generations_run": int(de.nit),
        "seconds": time.perf_counter() - t0,
    }  # fmt: skip


def report(kind: str, v: np.ndarray, opts: FitOptions | None = None) -> dict:
    """Print the caption table, the practitioners' numbers, the hinges and the topology of the
    ski of parameter vector ``v`` (``opts``: default :class:`FitOptions`), and return them as a
    calibration record."""
    opts = FitOptions() if opts is None else opts
    ski = make_ski(kind, v)
    solved: list = []
    _, rows = caption_residuals(ski, solved, tolerances=opts.tolerances)
    prac = plausibility(ski, kick_gap=opts.kick_gap_max_mm is not None)
    topo = topology(ski, solved)
    hinges = plausibility_residuals(kind, prac, opts)
    shape = ei_shape_residuals(kind, v)
    ei, z = unpack(kind, v)
    print(f"\n{kind}: kick zone {ski.kick_zone}")
    print(f"{'case':38s} {'zone':6s} {'mm paper':>8s} {'ski':>6s} {'kPa paper':>9s} {'ski':>6s} "
          f"{'% paper':>7s} {'ski':>4s} {'patches':>7s} ok")  # fmt: skip
    for r in rows:
        d = r.as_dict()
        pl = d["paper_length_mm"]
        pk = d["paper_mean_pressure_kpa"]
        ps = d["paper_load_share_pct"]
        print(
            f"{d['case']:38s} {r.zone:6s} {pl if pl is not None else float('nan'):8.1f} "
            f"{d['length_mm']:6.1f} {pk if pk is not None else float('nan'):9.1f} "
            f"{d['mean_pressure_kpa']:6.1f} {ps if ps is not None else float('nan'):7.0f} "
            f"{d['load_share_pct']:4.0f} {d['patches']:4d}/{d['paper_patches'] or '-'} {r.ok}"
        )
    print("plausibility: " + ", ".join(f"{k}={v:.3g}" for k, v in prac.items()))
    print(f"hinges {[round(h, 3) for h in hinges]} (all hold: {not any(hinges)})")
    print(f"EI shape hinges {[round(h, 3) for h in shape]} (unimodal, steps <= {EI_STEP_MAX}x)")
    print("topology: " + ", ".join(f"{k}={v:.3g}" for k, v in topo.items()))
    caption_misfit = float(np.sum(np.square(caption_residuals(ski, tolerances=opts.tolerances)[0])))
    print(f"caption misfit {caption_misfit:.3f}, all within tolerance: {all(r.ok for r in rows)}")
    return {
        "ski": kind,
        "ei_knots_m": list(KNOTS[kind][0]),
        # full precision: a stiff ski flattened on the stone feels z0 rounded to 0.1 µm on a
        # 5 mm grid (issue 30, sixth pass: the skate-k22's captions moved by up to 1.7 points)
        "ei_n_m2": [float(e) for e in ei],
        "camber_knots_m": list(KNOTS[kind][1]),
        "camber_mm": [float(c) * 1e3 for c in z],
        "kick_zone_m": None if ski.kick_zone is None else [round(k, 4) for k in ski.kick_zone],
        "plausibility": prac,
        "hinge_residuals": hinges,
        "plausible": not any(hinges),
        "ei_shape_residuals": shape,
        "ei_shape_holds": not any(shape),
        "topology": topo,
        "topology_holds": not any(topology_residuals(kind, topo, opts)),
        "caption_misfit": caption_misfit,
        "captions_within_tolerance": all(r.ok for r in rows),
        "captions": [r.as_dict() for r in rows],
    }
