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

Fifth pass, two more parametrisations (docs/validation/paper-reproduction.md):

* ``--param features`` (classic): the ski from 25 features of where it stands on the bench
  (:data:`FEATURES`: the unloaded rear and front contacts on the stone, each glide zone's
  half-length and crown, the flanks behind and ahead of them, the kick arch's apex and height,
  the tail and tip heights; five EI levels, at the tail, the two contacts, a middle plateau
  whose ends are features, and the tip), sampled on 10 mm EI and 5 mm camber knots that hold
  the default knots, so the record is read as any other; a start is a feature file (JSON)::

      nice -n 10 uv run python benchmarks/fit_k22.py --ski classic --param features \
          --start benchmarks/calibration/start_classic_k22_features_b.json \
          --start benchmarks/calibration/start_classic_k22_features_hand.json --sigma 0.15 \
          --popsize 6 --minutes 25 --seed 52 \
          --log benchmarks/calibration/fit_k22_classic_features.jsonl

* ``--bump CENTRE HALF HEIGHT`` (with the knots): a cos² bump of z0 (centre [m], half-width
  [m], height [µm], :data:`BUMP_BOUNDS`) optimised with the knot values; the ski carries z0 on
  the 5 mm grid::

      nice -n 10 uv run python benchmarks/fit_k22.py --ski skate \
          --start benchmarks/calibration/calibration_skate_k22_v4.json --bump 0.54 0.015 25 \
          --sigma 0.03 --popsize 5 --minutes 12 --powell-minutes 4 --seed 61 \
          --log benchmarks/calibration/fit_k22_skate_bump.jsonl --tag _v5

Sixth pass: ``--ei-bump CENTRE HALF DEPTH`` (with the knots, alone or with ``--bump``): a cos²
dip (DEPTH < 0) or rise of log EI (centre [m], half-width [m], depth [ln N m²],
:data:`EI_BUMP_BOUNDS`) optimised with the knot values; the ski then carries EI on the 10 mm
grid of :func:`feature_knots` (``benchmarks/scan_k22_front.py`` scans it on a fixed ski).
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import math
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator
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
from skisnow.ski import SPLINE_ENDS, SPLINE_KNOTS

TOL = REPRODUCTION_TOLERANCES
MARGIN = 0.85
BAD = 1e6


# ---- the feature parametrisation (fifth pass): where the ski stands on the bench -------------
#: Grids of ``--param features``: log EI every 10 mm and z0 every 5 mm (both hold the default
#: knots, so :func:`make_ski`, :func:`report` and ``--write-shipped`` read the record as any
#: other), two camber knots pinned where the default knots are (a line is undone by the resting).
FEATURES = (
    # name, low, high, scale ("lin" or "log"), what it is
    ("p_rear", -0.60, -0.30, "lin", "rear contact on the stone, unloaded [m]"),
    ("p_front", 0.36, 0.72, "lin", "front contact on the stone, unloaded [m]"),
    ("g_rear", 0.01, 0.12, "lin", "rear glide zone's half-length, flat to within its crown [m]"),
    ("c_rear", 0.001, 0.3, "log", "rear glide zone's crown: camber at its ends [mm]"),
    ("g_front", 0.01, 0.12, "lin", "front glide zone's half-length, flat to within its crown [m]"),
    ("c_front", 0.001, 0.3, "log", "front glide zone's crown: camber at its ends [mm]"),
    ("l_rear_back", 0.05, 0.35, "lin", "behind the rear glide zone to a control point [m]"),
    ("h_rear_back", 0.005, 2.0, "log", "camber there [mm] (rear glide zone's flatness, back)"),
    ("l_rear_fwd", 0.02, 0.20, "lin", "ahead of the rear glide zone to the arch's rear end [m]"),
    ("h_rear_fwd", 0.005, 3.0, "log", "camber there [mm] (rear glide zone's flatness, forward)"),
    ("apex", 0.05, 0.95, "lin", "kick arch apex, fraction between the arch's ends"),
    ("h_arch", 0.02, 12.0, "log", "kick arch height above its higher end [mm] (kick clearance)"),
    ("l_front_back", 0.02, 0.20, "lin", "behind the front glide zone to the arch's front end [m]"),
    ("h_front_back", 0.005, 3.0, "log", "camber there [mm] (front glide zone's flatness, back)"),
    ("l_front_fwd", 0.05, 0.30, "lin", "ahead of the front glide zone to a control point [m]"),
    ("h_front_fwd", 0.005, 3.0, "log", "camber there [mm] (front glide zone's flatness, forward)"),
    ("h_tail", 0.0, 8.0, "lin", "camber at the tail end, before the tail rise [mm]"),
    ("h_tip", 0.0, 8.0, "lin", "camber at the tip end, before the shovel [mm]"),
    ("ei_tail", 40.0, 30000.0, "log", "EI at the tail end [N m2]"),
    ("ei_rear", 40.0, 30000.0, "log", "EI at the rear contact [N m2]"),
    ("ei_mid", 40.0, 30000.0, "log", "EI of the middle plateau [N m2]"),
    ("ei_front", 40.0, 30000.0, "log", "EI at the front contact [N m2]"),
    ("ei_tip", 40.0, 30000.0, "log", "EI at the tip end [N m2]"),
    ("t_rear", 0.05, 0.95, "lin", "plateau's rear end, fraction from the rear contact to 0"),
    ("t_front", 0.05, 0.95, "lin", "plateau's front end, fraction from 0 to the front contact"),
)


def pinned_knots(
    kind: str, ek: Sequence[float], zk: Sequence[float]
) -> tuple[tuple[float, ...], tuple[float, ...], tuple[int, int]]:
    """(EI knots, camber knots, the camber knots nearest the default knots' two pins): a
    :data:`skisnow.calibrate.KNOTS` entry."""
    _, dz, dpins = SPLINE_KNOTS[kind]
    pins = tuple(int(np.argmin(np.abs(np.asarray(zk) - dz[p]))) for p in dpins)
    return tuple(ek), tuple(zk), pins  # type: ignore[return-value]


def feature_knots(kind: str) -> tuple[tuple[float, ...], tuple[float, ...], tuple[int, int]]:
    """(EI knots every 10 mm, camber knots every 5 mm, the two pinned camber knots)."""
    x_tail, x_tip = SPLINE_ENDS[kind]
    ek = np.round(np.linspace(x_tail, x_tip, round((x_tip - x_tail) / 0.01) + 1), 6)
    zk = np.round(np.linspace(x_tail, x_tip, round((x_tip - x_tail) / 0.005) + 1), 6)
    return pinned_knots(kind, ek, zk)


def feature_bounds() -> tuple[np.ndarray, np.ndarray]:
    """The box of the features in their optimisation scale (log of the "log" ones)."""
    lo = np.array([math.log(f[1]) if f[3] == "log" else f[1] for f in FEATURES])
    hi = np.array([math.log(f[2]) if f[3] == "log" else f[2] for f in FEATURES])
    return lo, hi


def feature_values(w: np.ndarray) -> dict[str, float]:
    """The features by name, in their units, from a vector in the optimisation scale."""
    return {
        f[0]: float(math.exp(x) if f[3] == "log" else x) for f, x in zip(FEATURES, w, strict=True)
    }


def feature_curves(
    kind: str, w: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(EI control knots [m], EI there [N m2], z0 control knots [m], z0 there [mm]).

    z0: PCHIP through 13 control points (tail end; behind the rear glide zone; the rear glide
    zone's ends at its crown and its centre, the rear contact, at 0; the arch's rear end, apex
    and front end; the front glide zone alike; ahead of it; the tip end), every value >= 0,
    so (PCHIP keeps the data's shape: no undershoot) the unloaded
    ski rests on the two contacts exactly. log EI: PCHIP through the tail end, the rear
    contact, the plateau's two ends, the front contact and the tip end.
    """
    f = feature_values(w)
    x_tail, x_tip = SPLINE_ENDS[kind]
    pr, pf, gr, gf = f["p_rear"], f["p_front"], f["g_rear"], f["g_front"]
    cr, cf = f["c_rear"], f["c_front"]
    a, b = pr + gr + f["l_rear_fwd"], pf - gf - f["l_front_back"]
    hr, hf = cr + f["h_rear_fwd"], cf + f["h_front_back"]
    back = max(pr - gr - f["l_rear_back"], x_tail + 0.02)
    ahead = min(pf + gf + f["l_front_fwd"], x_tip - 0.02)
    zx = [x_tail, back, pr - gr, pr, pr + gr, a, a + f["apex"] * (b - a), b, pf - gf, pf,
          pf + gf, ahead, x_tip]  # fmt: skip
    zv = [cr + f["h_rear_back"] + f["h_tail"], cr + f["h_rear_back"], cr, 0.0, cr, hr,
          max(hr, hf) + f["h_arch"], hf, cf, 0.0, cf, cf + f["h_front_fwd"],
          cf + f["h_front_fwd"] + f["h_tip"]]  # fmt: skip
    t1, t2 = pr * (1.0 - f["t_rear"]), pf * f["t_front"]
    ex = [x_tail, pr, t1, t2, pf, x_tip]
    ev = [f["ei_tail"], f["ei_rear"], f["ei_mid"], f["ei_mid"], f["ei_front"], f["ei_tip"]]
    return np.array(ex), np.array(ev), np.array(zx), np.array(zv)


def feature_start(doc: dict) -> np.ndarray:
    """A start in the optimisation scale: a feature file ({name: value}, the units of
    :data:`FEATURES`), a record of ``--param features`` or a line of its log."""
    f = doc.get("parametrisation", {}).get("features") or doc.get("features") or doc
    return np.array([math.log(f[n]) if sc == "log" else f[n] for n, _, _, sc, _ in FEATURES])


def feature_vector(kind: str, w: np.ndarray) -> np.ndarray:
    """The features as a parameter vector of the calibration on :func:`feature_knots`."""
    ek, zk, pins = feature_knots(kind)
    ex, ev, zx, zv = feature_curves(kind, w)
    log_ei = PchipInterpolator(ex, np.log(ev))(np.array(ek))
    z = PchipInterpolator(zx, zv)(np.array(zk))
    za, zb = z[pins[0]], z[pins[1]]
    z = z - (za + (zb - za) * (np.array(zk) - zk[pins[0]]) / (zk[pins[1]] - zk[pins[0]]))
    free = [k for k in range(len(zk)) if k not in pins]
    return np.concatenate([log_ei, z[free]])


#: ``--bump``: a smooth bump added to z0 (cos², height d [µm], half-width [m], centre [m]),
#: optimised with the knots; the ski then carries z0 on the 5 mm grid of :func:`feature_knots`.
BUMP_BOUNDS = ((0.40, 0.75), (0.008, 0.06), (-60.0, 60.0))


def bump_vector(kind: str, base: tuple, w: np.ndarray) -> np.ndarray:
    """A knot vector on ``base`` knots plus (centre, half-width, height) of a bump, as a
    parameter vector on the 5 mm camber grid (EI on the same knots as ``base``)."""
    ek, zk, pins = base
    _, gk, _ = feature_knots(kind)
    gk = np.array(gk)
    gpins = tuple(int(np.argmin(np.abs(gk - zk[p]))) for p in pins)
    n_e = len(ek)
    z = np.zeros(len(zk))
    z[[k for k in range(len(zk)) if k not in pins]] = w[n_e:-3]
    xd, half, d_um = w[-3:]
    t = np.clip((gk - xd) / half, -1.0, 1.0)
    zg = PchipInterpolator(np.array(zk), z)(gk) + d_um * 1e-3 * np.cos(0.5 * np.pi * t) ** 2
    za, zb = zg[gpins[0]], zg[gpins[1]]
    zg = zg - (za + (zb - za) * (gk - gk[gpins[0]]) / (gk[gpins[1]] - gk[gpins[0]]))
    free = [k for k in range(gk.size) if k not in gpins]
    return np.concatenate([w[:n_e], zg[free]])


#: ``--ei-bump``: a cos² dip or rise of log EI (centre [m], half-width [m], depth [ln N m²]:
#: EI times e^depth at the centre), optimised with the knots; EI then on the 10 mm grid.
EI_BUMP_BOUNDS = ((0.30, 0.75), (0.01, 0.12), (-3.5, 3.5))


def ei_bump_log(kind: str, ek: tuple, log_ei: np.ndarray, w3: np.ndarray) -> np.ndarray:
    """log EI on the 10 mm grid of :func:`feature_knots`: the PCHIP of ``log_ei`` at the knots
    ``ek`` plus ``depth`` cos²(π/2 (x − centre)/half) within ``half`` of ``centre``."""
    gk = np.array(feature_knots(kind)[0])
    xd, half, depth = w3
    t = np.clip((gk - xd) / half, -1.0, 1.0)
    return PchipInterpolator(np.array(ek), log_ei)(gk) + depth * np.cos(0.5 * np.pi * t) ** 2


#: ``--min-patch-frac F`` (sixth pass): a zone holding a patch shorter than F of the zone's
#: length (a sliver of a station or two at the edge of contact, not the paper's second patch)
#: has a wrong patch count wherever the paper states one (its count is set to -1: two wrong
#: patches in :func:`errors`), so a sliver neither meets nor escapes a count; 0 (the default):
#: every patch counts, as ``skisnow captions`` counts them.
MIN_PATCH_FRAC = 0.0


def counted(zones):  # type: ignore[no-untyped-def]
    """``zones`` with the patch count of each zone holding a sliver (:data:`MIN_PATCH_FRAC`)
    set to -1."""
    if MIN_PATCH_FRAC <= 0.0:
        return zones
    new = {}
    for name in ("rear", "middle", "front"):
        z = zones[name]
        if z.patches > 1 and any(b - a < MIN_PATCH_FRAC * z.length for a, b in z.intervals):
            new[name] = dataclasses.replace(z, patches=-1)
    return dataclasses.replace(zones, **new) if new else zones


def rows_of(kind: str, v: np.ndarray) -> list:
    """The caption rows (beam route) of the ski of parameter vector ``v``."""
    ski = make_ski(kind, v)
    rows = []
    for case in CAPTIONS:
        if case.ski == kind:
            zones = counted(solve_caption_case(case, ski))
            rows.extend(compare_case(case, zones, tolerances=TOL))
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


def de_then_powell(
    f: Callable[[np.ndarray], float],
    init: np.ndarray,
    *,
    seed: int,
    minutes: float,
    powell_minutes: float,
    clock: float,
    best: Callable[[], np.ndarray],
) -> int | None:
    """The search of every k22 fit on the unit box: SciPy's differential evolution from the
    population ``init`` until ``minutes`` of wall time since ``clock`` (none when 0), then Powell
    from ``best()`` (the best point ``f`` has seen) for ``powell_minutes``. ``f`` keeps its own
    record of the best point and logs it, so a run stopped by either budget loses nothing.
    Returns DE's generations (None without DE)."""
    generations = None
    if minutes > 0:
        de = differential_evolution(
            f, [(0.0, 1.0)] * init.shape[1], init=init, maxiter=100000, seed=seed, polish=False,
            tol=0.0, mutation=(0.4, 0.9), recombination=0.7,
            callback=lambda *_: time.monotonic() - clock > 60 * minutes,
        )  # fmt: skip
        print(f"DE: {de.nit} generations, {de.nfev} evaluations, penalty {de.fun:.3f}")
        generations = de.nit
    w1 = time.monotonic()

    class _Stop(Exception):
        pass

    def g(u: np.ndarray) -> float:
        if time.monotonic() - w1 > 60 * powell_minutes:
            raise _Stop
        return f(u)

    u = best()
    with contextlib.suppress(_Stop):
        minimize(g, u, method="Powell", bounds=[(0.0, 1.0)] * u.size,
                 options={"xtol": 1e-4, "ftol": 1e-6})  # fmt: skip
    return generations


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ski", choices=("skate", "classic"), required=True)
    ap.add_argument(
        "--knots",
        choices=("default", "dense", "record"),
        default="default",
        help="record: the knots of the first --start (e.g. ski_from_profiles.py's)",
    )
    ap.add_argument(
        "--param",
        choices=("knots", "features"),
        default="knots",
        help="knots: log EI and z0 at knots; features: FEATURES (fifth pass)",
    )
    ap.add_argument(
        "--start",
        action="append",
        default=[],
        help="calibration record(s); with --param features: feature files (JSON)",
    )
    ap.add_argument(
        "--bump",
        type=float,
        nargs=3,
        metavar=("CENTRE_M", "HALF_M", "HEIGHT_UM"),
        help="with --param knots: optimise a cos² bump on z0 too, from this start",
    )
    ap.add_argument(
        "--ei-bump",
        type=float,
        nargs=3,
        metavar=("CENTRE_M", "HALF_M", "DEPTH_LN"),
        help="with --param knots: optimise a cos² dip/rise of log EI too, from this start",
    )
    ap.add_argument(
        "--min-patch-frac",
        type=float,
        default=0.0,
        help="a patch under this fraction of its zone makes the zone's count wrong (sixth pass)",
    )
    ap.add_argument(
        "--free-mm",
        type=float,
        nargs=2,
        action="append",
        metavar=("FROM_MM", "TO_MM"),
        help="with --param knots: optimise only the knots in these x ranges [mm] (repeatable;"
        " the others stay at the first start's values; eighth pass)",
    )
    ap.add_argument(
        "--best-of",
        type=Path,
        help="a --free-mm run's log: its best ski replaces the first start (its knots kept;"
        " with --minutes 0 --powell-minutes 0 writes that ski's record)",
    )
    ap.add_argument(
        "--zone-weight",
        type=float,
        default=0.0,
        help="add this per zone not within (the count the shipping rule ranks on; eighth pass)",
    )
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
    global MIN_PATCH_FRAC
    MIN_PATCH_FRAC = a.min_patch_frac
    kind = a.ski
    feats = a.param == "features"
    if feats:  # the grids of the features; a start is a feature file, none: the whole box
        KNOTS[kind] = feature_knots(kind)
        lo, hi = feature_bounds()
        starts = [feature_start(json.loads(Path(s).read_text())) for s in a.start]
        to_v = lambda w: feature_vector(kind, w)  # noqa: E731
    else:
        if not a.start:
            ap.error("--start: at least one calibration record (with --param knots)")
        if a.knots == "dense":
            KNOTS.update(DENSE_KNOTS)
        elif a.knots == "record":  # the first start's knots, the default knots' two pins
            doc = json.loads(Path(a.start[0]).read_text())
            KNOTS[kind] = pinned_knots(kind, doc["ei_knots_m"], doc["camber_knots_m"])
        starts = [record_vector(kind, json.loads(Path(s).read_text())) for s in a.start]
        if a.best_of:  # eighth pass: the first start replaced by the best ski of a --free-mm log
            lines = [json.loads(t) for t in a.best_of.read_text().splitlines() if t.strip()]
            starts[0] = np.array(min(lines, key=lambda r: r["penalty"])["ski_vector"])
        lo, hi = bounds(kind)
        lo = np.minimum(lo, np.min(starts, axis=0))
        hi = np.maximum(hi, np.max(starts, axis=0))
        to_v = lambda w: w  # noqa: E731
        if a.bump:  # the knots of the run, then the 5 mm camber grid for the ski
            base = KNOTS[kind]
            _, gk, _ = feature_knots(kind)
            KNOTS[kind] = (base[0], gk, tuple(int(np.argmin(np.abs(np.array(gk) - base[1][p])))
                                              for p in base[2]))  # fmt: skip
            starts = [np.concatenate([v, a.bump]) for v in starts]
            lo = np.concatenate([lo, [b[0] for b in BUMP_BOUNDS]])
            hi = np.concatenate([hi, [b[1] for b in BUMP_BOUNDS]])
            to_v = lambda w: bump_vector(kind, base, w)  # noqa: E731
        if a.ei_bump:  # EI on the 10 mm grid; the knot (and z0 bump) values before the dip
            ek0, n_e0 = KNOTS[kind][0], len(KNOTS[kind][0])
            KNOTS[kind] = (feature_knots(kind)[0], *KNOTS[kind][1:])
            starts = [np.concatenate([v, a.ei_bump]) for v in starts]
            lo = np.concatenate([lo, [b[0] for b in EI_BUMP_BOUNDS]])
            hi = np.concatenate([hi, [b[1] for b in EI_BUMP_BOUNDS]])
            inner = to_v

            def to_v(w: np.ndarray) -> np.ndarray:
                log_ei = ei_bump_log(kind, ek0, w[:n_e0], w[-3:])
                return np.concatenate([log_ei, inner(w[:-3])[n_e0:]])

        if a.free_mm:  # eighth pass: the knots in the ranges free, the rest the first start's
            if a.bump or a.ei_bump:
                ap.error("--free-mm: not with --bump or --ei-bump")
            ek, zk, pins = KNOTS[kind]
            xs = np.concatenate([ek, [zk[k] for k in range(len(zk)) if k not in pins]])
            mask = np.zeros(xs.size, dtype=bool)
            for x0, x1 in a.free_mm:
                mask |= (xs >= x0 * 1e-3 - 1e-9) & (xs <= x1 * 1e-3 + 1e-9)
            full0 = starts[0].copy()
            starts, lo, hi = [v[mask] for v in starts], lo[mask], hi[mask]
            print(f"--free-mm: {int(mask.sum())} of {mask.size} parameters free")

            def to_v(w: np.ndarray) -> np.ndarray:
                v = full0.copy()
                v[mask] = w
                return v

    state = {"n": 0, "best": math.inf, "v": starts[0]}
    t0 = time.process_time()
    w0 = time.monotonic()

    def f(u: np.ndarray) -> float:
        w = lo + (hi - lo) * np.clip(u, 0.0, 1.0)
        state["n"] += 1
        try:
            v = to_v(w)
            rows = rows_of(kind, v)
        except Exception:  # no wax pocket, the load off the supports, ...
            return BAD
        e_p = errors(rows)
        val = penalty(*e_p, cap=a.cap)
        if a.zone_weight:  # eighth pass: each zone missed costs this much more
            val += a.zone_weight * (len(rows) - tally(rows)[0])
        if val < state["best"]:
            state["best"], state["v"], state["w"] = val, v, w
            zones, n_ok, n = tally(rows)
            rec = {
                "evaluation": state["n"], "cpu_s": round(time.process_time() - t0, 1),
                "penalty": round(val, 4), "penalty_uncapped": round(penalty(*e_p), 4),
                "zones_within": zones, "of": len(rows),
                "numbers_within": n_ok, "numbers": n, "knots": a.knots, "seed": a.seed,
                "param": a.param, "vector": [round(float(x), 6) for x in w],
            }  # fmt: skip
            if a.free_mm:  # the whole ski vector too (the free knots' vector is "vector")
                rec["ski_vector"] = [round(float(x), 6) for x in v]
            if feats:
                rec["features"] = {k: round(x, 6) for k, x in feature_values(w).items()}
            with a.log.open("a") as fh:
                fh.write(json.dumps(rec) + "\n")
            print(f"[{state['n']:6d} {rec['cpu_s']:7.1f} s] {val:9.3f} zones {zones}/"
                  f"{len(rows)} numbers {n_ok}/{n}", flush=True)  # fmt: skip
        return val

    us = [np.clip((v - lo) / (hi - lo), 0.0, 1.0) for v in starts]
    rng = np.random.default_rng(a.seed)
    n_pop = a.popsize * lo.size
    if us:
        centre = np.array([us[i * len(us) // n_pop] for i in range(n_pop)])
        init = np.clip(centre + a.sigma * rng.standard_normal((n_pop, lo.size)), 0.0, 1.0)
        for j, u in enumerate(us):
            init[j * n_pop // len(us)] = u
    else:  # no start: the whole box (a Latin hypercube)
        init = (rng.permuted(np.tile(np.arange(n_pop), (lo.size, 1)), axis=1).T
                + rng.random((n_pop, lo.size))) / n_pop  # fmt: skip
    if a.minutes <= 0:  # --minutes 0: Powell from the (first) start alone
        f(us[0])
    generations = de_then_powell(
        f, init, seed=a.seed, minutes=a.minutes, powell_minutes=a.powell_minutes, clock=w0,
        best=lambda: np.clip((state["w"] - lo) / (hi - lo), 0.0, 1.0),
    )  # fmt: skip
    if generations is not None:
        state["generations"] = generations
    v = state["v"]
    opts = FitOptions(plausibility=False, tolerances=TOL)
    doc = report(kind, v, opts)
    doc |= {
        "reproduction": True, "plausibility_terms": False,
        "knots": "features" if feats else a.knots + ("+bump, camber on 5 mm" if a.bump else "")
                 + ("+EI dip, EI on 10 mm" if a.ei_bump else ""),
        "tolerances": {"length": TOL.length, "pressure": TOL.pressure, "share": TOL.share,
                       "implied_shares": TOL.implied_shares},
        "fit": "benchmarks/fit_k22.py", "penalty": state["best"], "margin": MARGIN,
        "cap": a.cap if math.isfinite(a.cap) else None, "min_patch_frac": a.min_patch_frac,
        "free_mm": a.free_mm, "zone_weight": a.zone_weight, "best_of": str(a.best_of),
        "starts": a.start, "seed": a.seed, "popsize": a.popsize,
        "sigma": a.sigma,
        "evaluations": state["n"], "generations_run": state.get("generations", 0),
        "generations": state.get("generations", 0),
        "cpu_seconds": round(time.process_time() - t0, 1),
    }  # fmt: skip
    if a.bump:
        at = slice(-6, -3) if a.ei_bump else slice(-3, None)
        doc["bump"] = dict(zip(("centre_m", "half_width_m", "height_um"),
                               map(float, state["w"][at]), strict=True))  # fmt: skip
    if a.ei_bump:
        doc["ei_bump"] = dict(zip(("centre_m", "half_width_m", "depth_ln"),
                                  map(float, state["w"][-3:]), strict=True))  # fmt: skip
    if feats:
        doc["parametrisation"] = {
            "name": "features", "fit": "benchmarks/fit_k22.py --param features",
            "features": feature_values(state["w"]),
            "units": {f[0]: f[4] for f in FEATURES},
        }  # fmt: skip
    path = a.out / f"calibration_{kind}_k22{a.tag}.json"
    path.write_text(json.dumps(doc, indent=1))
    print(f"-> {path} (zones within {tally(rows_of(kind, v))[0]})")


if __name__ == "__main__":
    main()
