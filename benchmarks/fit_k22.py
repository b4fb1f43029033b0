"""Refit the reproduction skis (issue 30) on the issue's tolerances, as a smooth penalty.

    nice -n 10 uv run python benchmarks/fit_k22.py --ski skate --knots dense \
        --start benchmarks/calibration/calibration_skate_k22_v1.json --minutes 20 --seed 1 \
        --log benchmarks/calibration/fit_k22_skate.jsonl --out benchmarks/calibration --tag _v2

The ski is the calibration's spline ski (:func:`skisnow.calibrate.make_ski`: log EI and free
camber at knots, PCHIP; positive EI by construction, the camber in the calibration's box). The
route is the beam route of :func:`skisnow.paper.solve_caption_case` (the beam on the rigid plane
-> the rigid loaded profile -> strip half-space with force and moment balance, E_base 900 MPa,
nu 0.3). The penalty is the issue's tolerances, each number scaled by its own tolerance
(:data:`skisnow.paper.REPRODUCTION_TOLERANCES`: each length and mean pressure's relative error
/ 10 %, each load share's error / 3 points, the shares Figures 4 and 7 imply included), as

    f = sum_e [ 0.1 e^2 + 10 max(0, |e| - MARGIN)^2 ] + 9 (wrong patch counts + extra zones)

(MARGIN 0.85: a number counts once it is inside 85 % of its tolerance; the small quadratic
keeps the rest centred). Optimiser: SciPy's differential evolution in a box around the start(s)
(the starts members; ``--minutes 0``: none), then Powell from the best; ``--cap C`` saturates
each number's error at C tolerances (the fit may then give up a zone to meet others: what a
count of zones within asks); every improvement is appended to ``--log``
(JSON lines: evaluation, CPU seconds, penalty, zones and numbers within, the vector), so a run
stopped at its wall budget loses nothing. The record written (``--out``) is a calibration
record that ``skisnow calibrate --write-shipped`` turns into the reproduction ski.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import time
from pathlib import Path

import numpy as np
from scipy.optimize import differential_evolution, minimize

from skisnow.calibrate import (
    DENSE_KNOTS,
    KNOTS,
    FitOptions,
    bounds,
    make_ski,
    record_vector,
    report,
)
from skisnow.paper import CAPTIONS, REPRODUCTION_TOLERANCES, compare_case, solve_caption_case

TOL = REPRODUCTION_TOLERANCES
MARGIN = 0.85
BAD = 1e6


def rows_of(kind: str, v: np.ndarray) -> list:
    """The caption rows (beam route) of the ski of parameter vector ``v``."""
    ski = make_ski(kind, v)
    rows = []
    for case in CAPTIONS:
        if case.ski == kind:
            rows.extend(compare_case(case, solve_caption_case(case, ski), tolerances=TOL))
    return rows


def errors(rows: list) -> tuple[list[float], int]:
    """Every held caption number's error in tolerance units, and the count of patch misses."""
    e: list[float] = []
    patch = 0
    for r in rows:
        if r.paper is None:
            patch += 1
            continue
        for x, t in ((r.length_error, TOL.length), (r.pressure_error, TOL.pressure)):
            e.append(min(abs(x) / t, 50.0) if x is not None and math.isfinite(x) else 50.0)
        if not r.share_implied or TOL.implied_shares:
            e.append(abs(r.share_error) / TOL.share)
        if r.paper.patches is not None and r.patches != r.paper.patches:
            patch += min(abs(r.patches - r.paper.patches), 2)
    return e, patch


def penalty(e: list[float], patch: int, cap: float = math.inf) -> float:
    """The hinge penalty of the module docstring; ``cap`` saturates each number's error (a
    number far off costs no more than one ``cap`` tolerances off: the fit may give up a zone
    to meet others, as a count of zones within asks)."""
    a = np.minimum(np.asarray(e), cap)
    return float(np.sum(0.1 * a**2 + 10.0 * np.maximum(0.0, a - MARGIN) ** 2) + 9.0 * patch)


def tally(rows: list) -> tuple[int, int, int]:
    """(zones within, numbers within, numbers held) as ``skisnow captions`` counts them."""
    zones = sum(r.ok for r in rows)
    e, patch = errors(rows)
    n_patch = sum(1 for r in rows if r.paper is not None and r.paper.patches is not None)
    n_ok = sum(x <= 1.0 + 1e-12 for x in e) + n_patch - patch
    return zones, n_ok, len(e) + n_patch + sum(r.paper is None for r in rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ski", choices=("skate", "classic"), required=True)
    ap.add_argument("--knots", choices=("default", "dense"), default="default")
    ap.add_argument("--start", action="append", required=True, help="calibration record(s)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--popsize", type=int, default=6)
    ap.add_argument("--sigma", type=float, default=0.03, help="start cloud, fraction of box")
    ap.add_argument("--minutes", type=float, default=10.0, help="wall budget of the DE")
    ap.add_argument("--powell-minutes", type=float, default=3.0)
    ap.add_argument("--cap", type=float, default=math.inf, help="saturate each error (tol. units)")
    ap.add_argument("--log", type=Path, required=True)
    ap.add_argument("--out", type=Path, default=Path("benchmarks/calibration"))
    ap.add_argument("--tag", default="_v2")
    a = ap.parse_args()
    kind = a.ski
    if a.knots == "dense":
        KNOTS.update(DENSE_KNOTS)
    starts = [record_vector(kind, json.loads(Path(s).read_text())) for s in a.start]
    lo, hi = bounds(kind)
    lo = np.minimum(lo, np.min(starts, axis=0))
    hi = np.maximum(hi, np.max(starts, axis=0))
    state = {"n": 0, "best": math.inf, "v": starts[0]}
    t0 = time.process_time()
    w0 = time.monotonic()

    def f(u: np.ndarray) -> float:
        v = lo + (hi - lo) * np.clip(u, 0.0, 1.0)
        state["n"] += 1
        try:
            rows = rows_of(kind, v)
        except Exception:  # no wax pocket, the load off the supports, ...
            return BAD
        val = penalty(*errors(rows), cap=a.cap)
        if val < state["best"]:
            state["best"], state["v"] = val, v
            zones, n_ok, n = tally(rows)
            rec = {
                "evaluation": state["n"], "cpu_s": round(time.process_time() - t0, 1),
                "penalty": round(val, 4), "zones_within": zones, "of": len(rows),
                "numbers_within": n_ok, "numbers": n, "knots": a.knots, "seed": a.seed,
                "vector": [round(float(x), 6) for x in v],
            }  # fmt: skip
            with a.log.open("a") as fh:
                fh.write(json.dumps(rec) + "\n")
            print(f"[{state['n']:6d} {rec['cpu_s']:7.1f} s] {val:9.3f} zones {zones}/"
                  f"{len(rows)} numbers {n_ok}/{n}", flush=True)  # fmt: skip
        return val

    us = [np.clip((v - lo) / (hi - lo), 0.0, 1.0) for v in starts]
    rng = np.random.default_rng(a.seed)
    n_pop = a.popsize * us[0].size
    centre = np.array([us[i * len(us) // n_pop] for i in range(n_pop)])
    init = np.clip(centre + a.sigma * rng.standard_normal((n_pop, us[0].size)), 0.0, 1.0)
    for j, u in enumerate(us):
        init[j * n_pop // len(us)] = u
    if a.minutes > 0:  # --minutes 0: Powell from the (first) start alone
        de = differential_evolution(
            f, [(0.0, 1.0)] * us[0].size, init=init, maxiter=100000, seed=a.seed, polish=False,
            tol=0.0, mutation=(0.4, 0.9), recombination=0.7,
            callback=lambda *_: time.monotonic() - w0 > 60 * a.minutes,
        )  # fmt: skip
        print(f"DE: {de.nit} generations, {de.nfev} evaluations, penalty {de.fun:.3f}")
        state["generations"] = de.nit
    else:
        f(us[0])
    w1 = time.monotonic()
    u_best = np.clip((state["v"] - lo) / (hi - lo), 0.0, 1.0)

    class _Stop(Exception):
        pass

    def g(u: np.ndarray) -> float:
        if time.monotonic() - w1 > 60 * a.powell_minutes:
            raise _Stop
        return f(u)

    with contextlib.suppress(_Stop):
        minimize(g, u_best, method="Powell", bounds=[(0.0, 1.0)] * u_best.size,
                 options={"xtol": 1e-4, "ftol": 1e-6})  # fmt: skip
    v = state["v"]
    opts = FitOptions(plausibility=False, tolerances=TOL)
    doc = report(kind, v, opts)
    doc |= {
        "reproduction": True, "plausibility_terms": False, "knots": a.knots,
        "tolerances": {"length": TOL.length, "pressure": TOL.pressure, "share": TOL.share,
                       "implied_shares": TOL.implied_shares},
        "fit": "benchmarks/fit_k22.py", "penalty": state["best"], "margin": MARGIN,
        "cap": a.cap if math.isfinite(a.cap) else None,
        "starts": a.start, "seed": a.seed, "popsize": a.popsize, "sigma": a.sigma,
        "evaluations": state["n"], "generations_run": state.get("generations", 0),
        "generations": state.get("generations", 0),
        "cpu_seconds": round(time.process_time() - t0, 1),
    }  # fmt: skip
    path = a.out / f"calibration_{kind}_k22{a.tag}.json"
    path.write_text(json.dumps(doc, indent=1))
    print(f"-> {path} (zones within {tally(rows_of(kind, v))[0]})")


if __name__ == "__main__":
    main()
