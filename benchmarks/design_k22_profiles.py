"""Issue 30, sixth pass, step 1: design the classic's three loaded profiles from the captions.

    nice -n 10 uv run python benchmarks/design_k22_profiles.py --profile A --minutes 8 \
        --seed 1 --log benchmarks/calibration/design_k22_A.jsonl

On the paper's rigid route each caption of the classic depends on ONE loaded profile on the
stone (Kalliorinne et al. 2023, eq. 1; the bench at the case's mass and load position), pressed
as a rigid body into the elastic half-space with force and moment balance (eq. 3, E_base
900 MPa, nu 0.3). Three profiles carry all eleven zones:

* ``A`` -- 30 kg at -120 mm: Figure 4 (stone) and Figure 7 (50 and 200 MPa);
* ``B`` -- 60 kg at -210 mm: Figure 6, left (100 MPa);
* ``C`` -- 60 kg at -70 mm: Figure 6, right (100 MPa; a middle zone of one patch).

Each profile is designed ALONE here, with no ski behind it: a rigid profile on the stations of
the caption route (2048 from tail to tip) made of local zone shapes,

    h(x) = min( FAR, min_k [ d_k + s_k(x - c_k) ] ),

one shape per zone (rear, front; and middle for C): a PCHIP through heights above the zone's
reference point c_k at u = -/+ :data:`ZONE_U` (every height >= 0, so h >= 0: PCHIP does not
undershoot), 0 at u = 0, and 2 mm above the outer height at +/- 0.25 m. The rear and front
shapes touch the plane (d = 0): the profile rests on the line through them, as a loaded ski on
the stone does (a linear term is free anyway: the half-space solve finds the rigid tilt); the
middle shape of C sits ``d_M`` >= 0 above it (0: it touches the stone). Far from the zones
(more than 0.25 m from every c_k) the profile is FAR = 3 mm: heights there never meet snow.
The zones are grouped with a fixed kick zone (``--kick-zone``, default the shipped
classic-k22's, -298.3 .. +362.0 mm), so a designed profile is judged exactly as a ski's.

The caption numbers come from :func:`skisnow.pipeline.solve_case` with the profile given (the
door :func:`skisnow.paper.solve_caption_case` uses), compared by
:func:`skisnow.paper.compare_case` at the reproduction tolerances; the objective is
``benchmarks/fit_k22.py``'s hinge penalty (each number's error in its own tolerance, 9 per wrong
patch count or extra zone), plus ``--stay W`` times the distance from the shipped ski's profile
(:func:`stay`: the zone centres in 10 mm, the node heights in 0.1 decade, weighted 1 where
the start is below 0.2 mm and 0.1 above): with W > 0 the fit looks for the designed profile
nearest the shipped ski's, which is what a beam must then follow (step 2). Optimiser:
differential evolution in the box (the start -- the shipped classic-k22's own profile read at
the nodes, or ``--start`` -- a member), then Powell; every
improvement appended to ``--log``; the best profile written to ``--out`` (JSON: parameters,
the zones per case, the profile on the stations in um).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fit_k22 import de_then_powell, errors, penalty, tally

from skisnow.paper import CAPTIONS, REPRODUCTION_TOLERANCES, compare_case
from skisnow.pipeline import solve_case
from skisnow.ski import get_ski

TOL = REPRODUCTION_TOLERANCES
N_POINTS = 2048
FAR = 3e-3
#: Node offsets [m] of every zone shape on each side of its reference point.
ZONE_U = (0.005, 0.012, 0.025, 0.045, 0.070, 0.110)
#: Heights at the nodes: log10 of um, within these bounds (0.01 um .. 2 mm).
LOG_H = (-2.0, math.log10(2000.0))
#: The three profiles: (mass [kg], load position [m], zones).
PROFILES = {
    "A": (30.0, -0.120, ("rear", "front")),
    "B": (60.0, -0.210, ("rear", "front")),
    "C": (60.0, -0.070, ("rear", "middle", "front")),
}
#: Box of each zone's reference point [m].
CENTRE_BOX = {"rear": (-0.70, -0.15), "middle": (-0.25, 0.25), "front": (0.15, 0.80)}
D_MID = (0.0, 300.0)  # the middle shape's height above the line [um]


def cases_of(profile: str) -> list:
    """The classic caption cases a profile carries."""
    m, xm, _ = PROFILES[profile]
    return [c for c in CAPTIONS if c.ski == "classic" and c.mass == m and c.load_position == xm]


def n_params(profile: str) -> int:
    zones = PROFILES[profile][2]
    return len(zones) * (1 + 2 * len(ZONE_U)) + ("middle" in zones)


def box(profile: str) -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the parameter vector: per zone (centre, log10 heights behind, ahead), then
    ``d_M`` [um] for a middle zone."""
    lo, hi = [], []
    for z in PROFILES[profile][2]:
        lo += [CENTRE_BOX[z][0]] + [LOG_H[0]] * (2 * len(ZONE_U))
        hi += [CENTRE_BOX[z][1]] + [LOG_H[1]] * (2 * len(ZONE_U))
    if "middle" in PROFILES[profile][2]:
        lo.append(D_MID[0])
        hi.append(D_MID[1])
    return np.array(lo), np.array(hi)


#: ``--monotone``: the node values are log10 of the height's increments from node to node (the
#: shape rises away from its reference point on both sides: one contact per zone).
MONOTONE = {"on": False}


def zone_shape(x: np.ndarray, centre: float, log_h: np.ndarray) -> np.ndarray:
    """Heights [m] of one zone shape at ``x`` (inf beyond 0.25 m of its centre)."""
    k = len(ZONE_U)
    hb = 10.0 ** log_h[:k] * 1e-6  # behind, nearest first
    hf = 10.0 ** log_h[k:] * 1e-6
    if MONOTONE["on"]:
        hb, hf = np.cumsum(hb), np.cumsum(hf)
    u = np.concatenate([[-0.25], -np.array(ZONE_U)[::-1], [0.0], ZONE_U, [0.25]])
    h = np.concatenate([[hb[-1] + 2e-3], hb[::-1], [0.0], hf, [hf[-1] + 2e-3]])
    du = x - centre
    out = np.full(x.shape, np.inf)
    m = np.abs(du) <= 0.25
    out[m] = PchipInterpolator(u, h)(du[m])
    return out


def profile_heights(profile: str, x: np.ndarray, w: np.ndarray) -> np.ndarray:
    """The designed rigid profile [m] of parameter vector ``w`` on the stations ``x``."""
    zones = PROFILES[profile][2]
    k = 1 + 2 * len(ZONE_U)
    h = np.full(x.shape, FAR)
    for i, z in enumerate(zones):
        p = w[i * k : (i + 1) * k]
        d = w[-1] * 1e-6 if z == "middle" else 0.0
        h = np.minimum(h, d + zone_shape(x, p[0], p[1:]))
    return h


def start_vector(profile: str, x: np.ndarray, h: np.ndarray) -> np.ndarray:
    """A loaded profile (the shipped ski's) read at the nodes: each zone's reference point is
    the lowest station in its centre box, the heights those above the line through the rear
    and front reference points."""
    zones = PROFILES[profile][2]
    cs = {}
    for z in zones:
        lo, hi = CENTRE_BOX[z]
        if z == "middle":
            lo, hi = -0.2, 0.2
        m = (x > lo) & (x < hi)
        cs[z] = float(x[m][np.argmin(h[m])])
    r, f = cs["rear"], cs["front"]
    hr, hf = np.interp([r, f], x, h)
    base = hr + (hf - hr) * (x - r) / (f - r)
    rel = h - base
    w: list[float] = []
    for z in zones:
        c = cs[z]
        ref = float(np.interp(c, x, rel))
        hb = [np.interp(c - u, x, rel) - ref for u in ZONE_U]
        hf_ = [np.interp(c + u, x, rel) - ref for u in ZONE_U]
        vals = np.array(hb + hf_) * 1e6
        if MONOTONE["on"]:  # the increments of the rising envelope on each side
            k = len(ZONE_U)
            env = [np.maximum.accumulate(np.maximum(vals[:k], 0.0)),
                   np.maximum.accumulate(np.maximum(vals[k:], 0.0))]  # fmt: skip
            vals = np.concatenate([np.diff(e, prepend=0.0) for e in env])
        vals = np.clip(vals, 10 ** LOG_H[0], 10 ** LOG_H[1])
        w += [c, *np.log10(vals)]
    if "middle" in zones:
        w.append(float(np.clip(np.interp(cs["middle"], x, rel) * 1e6, *D_MID)))
    return np.array(w)


def stay(profile: str, w: np.ndarray, w0: np.ndarray) -> float:
    """Distance of ``w`` from the start ``w0``: centres in 10 mm, log10 heights in 0.1 decade
    (weight 1 where the start's height is below 200 um, else 0.1), ``d_M`` in 10 um."""
    k = 1 + 2 * len(ZONE_U)
    total = 0.0
    for i, _ in enumerate(PROFILES[profile][2]):
        p, p0 = w[i * k : (i + 1) * k], w0[i * k : (i + 1) * k]
        total += ((p[0] - p0[0]) / 0.01) ** 2
        wt = np.where(p0[1:] < math.log10(200.0), 1.0, 0.1)
        total += float(np.sum(wt * ((p[1:] - p0[1:]) / 0.1) ** 2))
    if "middle" in PROFILES[profile][2]:
        total += ((w[-1] - w0[-1]) / 10.0) ** 2
    return total


def rows_of(profile: str, ski, x: np.ndarray, h: np.ndarray) -> list:
    """Caption rows of a designed profile (the route of :func:`solve_caption_case`, the profile
    given; ``ski`` lends its width and kick zone)."""
    rows = []
    for case in cases_of(profile):
        r = solve_case(
            ski, mass=case.mass, load_position=case.load_position,
            snow_modulus=case.counter_modulus, profile_source="beam", n_points=N_POINTS,
            base=900e6, poisson=0.3, profile=(x, h),
        )  # fmt: skip
        rows.extend(compare_case(case, r.zones, tolerances=TOL, ski="designed"))
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--profile", choices=tuple(PROFILES), required=True)
    ap.add_argument("--start", type=Path, help="a previous --out of this profile")
    ap.add_argument("--kick-zone", type=float, nargs=2, metavar=("START_MM", "END_MM"))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--popsize", type=int, default=6)
    ap.add_argument("--sigma", type=float, default=0.05)
    ap.add_argument("--minutes", type=float, default=8.0)
    ap.add_argument("--powell-minutes", type=float, default=3.0)
    ap.add_argument("--cap", type=float, default=math.inf)
    ap.add_argument("--monotone", action="store_true", help="one contact per zone (MONOTONE)")
    ap.add_argument("--stay", type=float, default=0.0, help="weight of stay() (0: off)")
    ap.add_argument("--log", type=Path, required=True)
    ap.add_argument("--out", type=Path)
    a = ap.parse_args()
    prof = a.profile
    MONOTONE["on"] = a.monotone
    ski = get_ski("classic-k22")
    if a.kick_zone:
        ski = replace(ski, kick_zone=(a.kick_zone[0] * 1e-3, a.kick_zone[1] * 1e-3))
    m, xm, _ = PROFILES[prof]
    ship = solve_case(ski, mass=m, load_position=xm, snow_modulus=100e6, profile_source="beam",
                      n_points=N_POINTS, base=900e6, poisson=0.3)  # fmt: skip
    x = ship.x
    lo, hi = box(prof)
    if a.start:
        lines = a.start.read_text().strip().splitlines()  # an --out, or a log (its last line)
        w0 = np.array(json.loads(lines[-1] if len(lines) > 1 else lines[0])["vector"])
    else:
        w0 = start_vector(prof, x, ship.height)
    w_ship = start_vector(prof, x, ship.height)
    lo, hi = np.minimum(lo, w0), np.maximum(hi, w0)
    state = {"n": 0, "best": math.inf, "w": w0}
    t0 = time.process_time()
    w_clock = time.monotonic()

    def f(u: np.ndarray) -> float:
        w = lo + (hi - lo) * np.clip(u, 0.0, 1.0)
        state["n"] += 1
        try:
            rows = rows_of(prof, ski, x, profile_heights(prof, x, w))
        except Exception:  # the load off the supports, the contact at an end, ...
            return 1e6
        val = penalty(*errors(rows), cap=a.cap) + a.stay * stay(prof, w, w_ship)
        if val < state["best"]:
            state["best"], state["w"] = val, w
            zones, n_ok, n = tally(rows)
            rec = {
                "profile": prof, "evaluation": state["n"],
                "cpu_s": round(time.process_time() - t0, 1), "penalty": round(val, 4),
                "zones_within": zones, "of": len(rows), "numbers_within": n_ok, "numbers": n,
                "seed": a.seed, "stay": a.stay, "distance": round(stay(prof, w, w_ship), 3),
                "vector": [round(float(v), 6) for v in w],
            }  # fmt: skip
            with a.log.open("a") as fh:
                fh.write(json.dumps(rec) + "\n")
            print(f"[{state['n']:6d} {rec['cpu_s']:7.1f} s] {val:9.3f} zones {zones}/"
                  f"{len(rows)} numbers {n_ok}/{n}", flush=True)  # fmt: skip
        return val

    u0 = np.clip((w0 - lo) / (hi - lo), 0.0, 1.0)
    f(u0)
    rng = np.random.default_rng(a.seed)
    n_pop = a.popsize * lo.size
    init = np.clip(u0 + a.sigma * rng.standard_normal((n_pop, lo.size)), 0.0, 1.0)
    init[0] = u0
    de_then_powell(
        f, init, seed=a.seed, minutes=a.minutes, powell_minutes=a.powell_minutes, clock=w_clock,
        best=lambda: np.clip((state["w"] - lo) / (hi - lo), 0, 1),
    )  # fmt: skip
    w = state["w"]
    h = profile_heights(prof, x, w)
    rows = rows_of(prof, ski, x, h)
    zones, n_ok, n = tally(rows)
    print(f"best penalty {state['best']:.3f}: zones {zones}/{len(rows)}, numbers {n_ok}/{n}")
    for r in rows:
        d = r.as_dict()
        print(
            f"  {d['case']:<40s} {d['zone']:<6s} L {d['paper_length_mm'] or 0:6.1f}/"
            f"{d['length_mm']:6.1f}  p {d['paper_mean_pressure_kpa'] or 0:6.1f}/"
            f"{d['mean_pressure_kpa']:6.1f}  s {d['paper_load_share_pct'] or 0:5.1f}/"
            f"{d['load_share_pct']:5.1f}  n {d['patches']}  {'ok' if r.ok else 'MISS'}"
        )
    if a.out:
        doc = {
            "profile": prof, "mass_kg": m, "load_position_mm": xm * 1e3,
            "kick_zone_mm": [k * 1e3 for k in ski.kick_zone], "zone_u_m": list(ZONE_U),
            "monotone": a.monotone,
            "objective": state["best"], "stay": a.stay, "distance": stay(prof, w, w_ship),
            "penalty": penalty(*errors(rows), cap=a.cap), "zones_within": zones, "of": len(rows),
            "numbers_within": n_ok, "numbers": n, "vector": [float(v) for v in w],
            "evaluations": state["n"], "cpu_seconds": round(time.process_time() - t0, 1),
            "seed": a.seed, "rows": [r.as_dict() for r in rows],
            "x_mm": [round(float(v) * 1e3, 4) for v in x],
            "h_um": [round(float(v) * 1e6, 4) for v in h],
        }  # fmt: skip
        a.out.write_text(json.dumps(doc))
        print(f"-> {a.out}")


if __name__ == "__main__":
    main()
