"""The captions' penalty along a line between two classic-k22 skis (issue 30, eighth pass).

    uv run python benchmarks/scan_k22_joint.py \
        --a benchmarks/calibration/calibration_classic_k22_p6powellcap2.json \
        --b benchmarks/calibration/calibration_classic_k22_p6.json --steps 11

Both records must have the same knots (log EI and z0 at knots, :func:`skisnow.calibrate.
make_ski`); the ski at t is the parameter vector (1 - t) a + t b. Per t: zones and numbers
within on the beam route (:func:`fit_k22.tally`), the hinge penalty capped at 2 and uncapped
(:func:`fit_k22.penalty`), which zones are within (one letter per zone of the classic's five
cases, in :data:`skisnow.paper.CAPTIONS` order: A Fig. 4 stone, Fig. 7 50 and 200 MPa, B Fig. 6
-210 mm, C Fig. 6 -70 mm), and the rear zone's centroid [mm] on the stone under profile A
(30 kg, -120 mm) and profile B (60 kg, -210 mm): the sixth pass's designs want about -401 and
-331 mm. Each row is a beam-route evaluation (~40 ms CPU); the table is what the docs quote.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np
from fit_k22 import errors, penalty, pinned_knots, rows_of, tally

from skisnow.calibrate import KNOTS, make_ski, record_vector
from skisnow.paper import CAPTIONS, solve_caption_case


def rear_centroid_mm(ski, mass: float, position: float) -> float:  # type: ignore[no-untyped-def]
    """The rear zone's centroid [mm] on the stone at (mass [kg], position [m])."""
    stone = next(c for c in CAPTIONS if c.ski == "classic" and c.counter_modulus >= 1e10)
    case = dataclasses.replace(stone, mass=mass, load_position=position)
    iv = solve_caption_case(case, ski).rear.intervals
    w = np.array([b - a for a, b in iv])
    mid = np.array([0.5 * (a + b) for a, b in iv])
    return float(1e3 * np.sum(w * mid) / np.sum(w)) if w.size else float("nan")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--a", type=Path, required=True)
    ap.add_argument("--b", type=Path, required=True)
    ap.add_argument("--steps", type=int, default=11)
    ap.add_argument("--t-min", type=float, default=0.0)
    ap.add_argument("--t-max", type=float, default=1.0)
    args = ap.parse_args()
    da, db = (json.loads(p.read_text()) for p in (args.a, args.b))
    if da["ei_knots_m"] != db["ei_knots_m"] or da["camber_knots_m"] != db["camber_knots_m"]:
        raise SystemExit("the two records must have the same knots")
    KNOTS["classic"] = pinned_knots("classic", da["ei_knots_m"], da["camber_knots_m"])
    va, vb = record_vector("classic", da), record_vector("classic", db)
    print("| t | zones | numbers | penalty cap 2 | uncapped | within (A 4/7/7, B, C) "
          "| rear centroid A / B on the stone [mm] |")  # fmt: skip
    print("| ---: | ---: | ---: | ---: | ---: | --- | --- |")
    for t in np.linspace(args.t_min, args.t_max, args.steps):
        v = (1.0 - t) * va + t * vb
        try:
            rows = rows_of("classic", v)
        except Exception as exc:
            print(f"| {t:.2f} | failed: {type(exc).__name__} | | | | | |")
            continue
        e, patch = errors(rows)
        zones, n_ok, n = tally(rows)
        ok = "".join("Y" if r.ok else "n" for r in rows)
        ski = make_ski("classic", v)
        ca, cb = rear_centroid_mm(ski, 30.0, -0.120), rear_centroid_mm(ski, 60.0, -0.210)
        print(f"| {t:.2f} | {zones}/{len(rows)} | {n_ok}/{n} | {penalty(e, patch, 2.0):.1f} "
              f"| {penalty(e, patch):.1f} | {ok} | {ca:.0f} / {cb:.0f} |", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
