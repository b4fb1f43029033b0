"""Which captions pull against each other: force one missed caption zone, see which leave.

Run:  uv run python benchmarks/caption_tradeoffs.py REC.json [--weight 5] [--iterations 15]

From a calibration record of ``skisnow calibrate`` (``benchmarks/calibrate_skis.py``; default or
``--knots dense``, usually a ``--caption-only`` fit, a local optimum of the caption misfit), for
every caption zone the recorded ski misses a bounded least squares (as the polish of the
calibration: trust-region reflective, forward differences, the record's knots and box) on the
caption residuals only, that zone's residuals weighted ``--weight``. What the forced ski gains on
that zone and loses on the others is the trade-off of the pipeline (beam on the rigid plane → rigid
profile → strip half-space, Kalliorinne et al. 2023): zones that leave the tolerance when another is
forced in pull against it. Also printed: the middle of each zone's extent (first to last contact)
[mm]: the moment balance (eq. 3) fixes the load shares by where the zones carry, with two zones
share_front = (x_m − x_rear) / (x_front − x_rear) at their load centres.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from skisnow import calibrate as cs
from skisnow.ski import SPLINE_KNOTS


def table(kind: str, v: np.ndarray, solved: list | None = None) -> tuple[float, list[dict]]:
    """Caption misfit and the rows (errors, ok) of a parameter vector (``solved`` as in
    ``calibrate_skis.caption_residuals``)."""
    ski = cs.make_ski(kind, v)
    res, rows = cs.caption_residuals(ski, solved)
    return float(np.sum(np.square(res))), [r.as_dict() | {"ok": r.ok} for r in rows]


def zone_middles(solved: list) -> dict[str, dict[str, float]]:
    """Middle [mm] of every zone's extent (first to last contact), per solved caption case."""
    out = {}
    for case, zones in solved:
        out[case.label] = {
            n: round(0.5 * (zones[n].start + zones[n].end) * 1e3, 0)
            for n in ("rear", "middle", "front")
            if zones[n].patches
        }
    return out


def brief(rows: list[dict]) -> str:
    """The zones out of tolerance, with their errors."""
    bad = []
    for d in rows:
        if d["ok"]:
            continue
        part = [f"{d['case'].split(' classic ')[-1]} {d['zone']}"]
        for key, unit in (("length_error_pct", "% L"), ("pressure_error_pct", "% p")):
            if d[key] is not None and math.isfinite(d[key]):
                part.append(f"{d[key]:+.0f}{unit}")
        if d["share_error_points"] is not None:
            part.append(f"{d['share_error_points']:+.0f} pt share")
        if d["paper_patches"] is not None and d["patches"] != d["paper_patches"]:
            part.append(f"{d['patches']}/{d['paper_patches']} patches")
        bad.append(" ".join(part))
    return "; ".join(bad) if bad else "none"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("record", type=Path)
    ap.add_argument("--weight", type=float, default=5.0, help="weight of the forced zone")
    ap.add_argument("--iterations", type=int, default=15, help="least-squares iterations")
    args = ap.parse_args()
    doc = json.loads(args.record.read_text())
    kind = doc["ski"]
    for knots in (SPLINE_KNOTS, cs.DENSE_KNOTS):
        if list(knots[kind][1]) == doc["camber_knots_m"]:
            cs.KNOTS[kind] = knots[kind]
    v0 = cs.record_vector(kind, doc)
    lo, hi = cs.bounds(kind)
    u0 = np.clip((v0 - lo) / (hi - lo), 0.0, 1.0)
    v0 = lo + (hi - lo) * u0
    solved: list = []
    misfit, rows = table(kind, v0, solved)
    n_ok = sum(d["ok"] for d in rows)
    n_e, n_z = len(doc["ei_knots_m"]), len(doc["camber_knots_m"])
    print(f"{args.record.name}: {n_e} log-EI + {n_z} camber knots, caption misfit "
          f"{misfit:.1f}, {n_ok}/{len(rows)} zones within")  # fmt: skip
    print(f"  out: {brief(rows)}")
    print(f"  zone centres [mm]: {json.dumps(zone_middles(solved))}")
    slices: list = []  # where each zone's residuals stand, from the residuals themselves
    cs.caption_residuals(cs.make_ski(kind, v0), layout=slices)
    n_res = cs.residuals(kind, v0, cs.FitOptions(plausibility=False)).size
    for d in rows:
        if d["ok"]:
            continue
        (sl,) = [s for c, z, s in slices if c == d["case"] and z == d["zone"]]
        w = np.ones(n_res)
        w[sl] = args.weight

        def fun(u: np.ndarray, w: np.ndarray = w) -> np.ndarray:
            v = lo + (hi - lo) * np.clip(u, 0.0, 1.0)
            return w * cs.residuals(kind, v, cs.FitOptions(plausibility=False), n_res)

        ls = least_squares(
            fun, u0, bounds=(0.0, 1.0), method="trf", diff_step=0.01, max_nfev=args.iterations
        )
        v = lo + (hi - lo) * ls.x
        m, r = table(kind, v)
        forced = [x for x in r if x["case"] == d["case"] and x["zone"] == d["zone"]]
        print(f"\nforce {d['case']} {d['zone']} (weight {args.weight:g}): misfit {misfit:.1f} -> "
              f"{m:.1f}, {sum(x['ok'] for x in r)}/{len(r)} zones within; the forced zone "
              f"{'within' if forced and forced[0]['ok'] else 'still out'}")  # fmt: skip
        print(f"  out: {brief(r)}")


if __name__ == "__main__":
    main()
