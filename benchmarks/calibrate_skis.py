"""Calibrate the shipped skis on the captions of Kalliorinne et al. (2023), Figures 4–7.

Run:  uv run python benchmarks/calibrate_skis.py [--ski skate|classic] [--seed 0]
          [--generations 30] [--popsize 6] [--caption-only] [--out DIR]

A ski is a spline: log EI at 10 knots and the free camber z0 at 13 knots (both PCHIP, as
:class:`skisnow.ski.Ski` interpolates them), the knots denser in the glide zones than in the
middle (the contact lengths on snow come from how the soft glide zones flatten under load). The
shovel and tail rises and the resting on the plane are added as for every shipped ski
(``skisnow.ski._skis._assemble``). For a parameter vector the paper's pipeline runs on the ski
(:func:`skisnow.paper.solve_caption_case`: the beam on the rigid plane → rigid loaded profile →
strip half-space with force and moment balance, E_base = 900 MPa, ν = 0.3). The residuals, in
units of the tolerances of :data:`skisnow.paper.TOLERANCES`, are log(length ratio)/log 1.2,
log(pressure ratio)/log 1.25 and (share difference)/0.05, plus 3 for every wrong patch count
and every zone the paper does not have; plausibility residuals are hinge terms on the
practitioners' numbers (Breitschädel's stiffness k between half and full body weight, camber
at half and full weight, closing load, wax-pocket length; see ``plausibility``).

Fit: a seeded differential evolution (scipy.optimize.differential_evolution, Latin-hypercube
population in a box around the start, the start itself in the population) — derivative-free,
because the patch-count terms jump — then a bounded least-squares polish
(scipy.optimize.least_squares, trust-region reflective, forward differences) of the best
member. ``--caption-only`` drops the plausibility terms: the side-by-side comparison of what
the captions alone want against the shipped (plausible) ski. The fitted knots, the caption table
and the plausibility numbers are written to ``DIR/calibration_<ski>[_caption_only].json``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np
from scipy.optimize import differential_evolution, least_squares

from skisnow.paper import CAPTIONS, TOLERANCES, compare_case, solve_caption_case
from skisnow.ski import Ski, get_ski, solve_beam
from skisnow.ski._metrics import ski_stiffness, wax_pocket, wax_pocket_length
from skisnow.ski._spline import SPLINE_KNOTS, spline_ski

BODY, POS = 65.0, -0.080  # the practitioners' skier [kg] and load position [m]
PATCH_PENALTY = 3.0  # residual of a wrong patch count or an extra zone (in tolerance units)


# --------------------------------------------------------------------------- the ski


#: Starting skis (EI [N m²] at the EI knots, z0 [mm] at the camber knots, before the shovel and
#: tail rises): the classic is the previous shipped classic sampled at the knots; the skate a
#: hand-made ski with soft glide zones (the previous skate's glide zones were too stiff and too
#: curved to give long contacts).
START = {
    "classic": (
        [189, 479, 731, 945, 1184, 1450, 1240, 1095, 878, 137],
        [1.75, 0.59, 0.17, 0.0, -0.02, 0.49, 2.94, 0.30, 0.02, 0.0, 0.18, 0.86, 4.3],
    ),
    "skate": (
        [150, 200, 300, 400, 2000, 6000, 2000, 400, 250, 150],
        [1.0, 0.15, 0.04, 0.0, 0.0, 0.4, 6.0, 0.6, 0.05, 0.0, 0.0, 0.06, 1.0],
    ),
}


def start_vector(kind: str) -> np.ndarray:
    """The starting ski as a parameter vector: log EI [ln N m²] and the free z0 knots [mm]."""
    _, zk, pins = SPLINE_KNOTS[kind]
    ei, z = START[kind]
    free = [k for k in range(len(zk)) if k not in pins]
    return np.concatenate([np.log(ei), np.array(z)[free]])


def shipped_vector(kind: str) -> np.ndarray:
    """The shipped ski as a parameter vector (its tabulated EI and z0 are the knot values)."""
    ski = get_ski(kind)
    _, zk, pins = SPLINE_KNOTS[kind]
    ei = json.loads(ski.provenance.detail("ei_knots_n_m2"))
    z = np.array(json.loads(ski.provenance.detail("camber_knots_mm")))
    free = [k for k in range(len(zk)) if k not in pins]
    return np.concatenate([np.log(ei), z[free]])


def unpack(kind: str, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameter vector → (EI at the EI knots [N m²], z0 at the camber knots [m])."""
    ek, zk, pins = SPLINE_KNOTS[kind]
    n_e = len(ek)
    ei = np.exp(v[:n_e])
    z = np.zeros(len(zk))
    free = [k for k in range(len(zk)) if k not in pins]
    z[free] = v[n_e:] * 1e-3
    return ei, z


def kick_zone_of(ski: Ski) -> tuple[float, float] | None:
    """Kick zone: the 0.2 mm mark at the rear to the 0.1 mm mark in front (½ BODY, -80 mm)."""
    sol = solve_beam(ski, mass=0.5 * BODY, load_position=POS)
    x = np.linspace(ski.x_tail, ski.x_tip, 4001)
    h = sol.sample(x)
    p2, p1 = wax_pocket(x, h, threshold=0.2e-3), wax_pocket(x, h, threshold=0.1e-3)
    if p2 is None or p1 is None:
        return None
    return (p2[0], p1[1])


def make_ski(kind: str, v: np.ndarray) -> Ski:
    ei, z = unpack(kind, v)
    ski = spline_ski(kind, ei, z, kick_zone=None, description="calibration candidate")
    if kind == "classic":
        kz = kick_zone_of(ski)
        if kz is None:
            raise ValueError("no wax pocket at half body weight")
        ski = spline_ski(kind, ei, z, kick_zone=kz, description="calibration candidate")
    return ski


# --------------------------------------------------------------------------- residuals


def plausibility(ski: Ski) -> dict[str, float]:
    """The practitioners' numbers of the ski on the virtual bench (65 kg skier, -80 mm)."""
    x = np.linspace(ski.x_tail, ski.x_tip, 4001)
    half = solve_beam(ski, mass=0.5 * BODY, load_position=POS)
    full = solve_beam(ski, mass=BODY, load_position=POS)
    hh, hf = float(half.sample(0.0)), float(full.sample(0.0))
    out = {
        "free_camber_mm": float(ski.free_camber(0.0)) * 1e3,
        "camber_half_mm": hh * 1e3,
        "camber_full_mm": hf * 1e3,
        "k_n_per_mm": ski_stiffness(hh, hf, BODY) * 1e-3,
        "ei_max_n_m2": float(np.max(ski.stiffness(x))),
        "ei_min_n_m2": float(np.min(ski.stiffness(x))),
    }
    if ski.kind == "classic":
        h50 = solve_beam(ski, mass=50.0, load_position=POS).sample(0.0)
        out["h_50kg_mm"] = float(h50) * 1e3
        out["pocket_01_half_mm"] = wax_pocket_length(x, half.sample(x), threshold=0.1e-3) * 1e3
    else:
        out["h_130kg_mm"] = float(solve_beam(ski, mass=130.0, load_position=POS).sample(0.0)) * 1e3
    return out


def _hinge(value: float, lo: float | None, hi: float | None, scale: float) -> float:
    if lo is not None and value < lo:
        return (lo - value) / scale
    if hi is not None and value > hi:
        return (value - hi) / scale
    return 0.0


def plausibility_residuals(kind: str, prac: dict[str, float]) -> list[float]:
    """Hinge residuals (0 inside the practitioners' ranges; sources in ``_skis.py``)."""
    if kind == "classic":
        return [
            _hinge(prac["camber_half_mm"], 0.6, 1.2, 0.05),
            _hinge(prac["camber_full_mm"], None, 0.07, 0.01),
            _hinge(prac["h_50kg_mm"], 0.12, None, 0.01),
            _hinge(prac["pocket_01_half_mm"], 450, 560, 15),
            _hinge(prac["free_camber_mm"], None, 15.0, 1.0),
        ]
    return [
        _hinge(prac["k_n_per_mm"], 225, 251, 5),
        _hinge(prac["camber_full_mm"], 1.2, None, 0.05),
        _hinge(prac["h_130kg_mm"], 0.15, None, 0.02),
        _hinge(prac["free_camber_mm"], None, 15.0, 1.0),
    ]


def caption_residuals(ski: Ski) -> tuple[list[float], list]:
    """Residuals in tolerance units, a fixed number per ski (for the least-squares polish)."""
    res: list[float] = []
    rows = []
    for case in CAPTIONS:
        if case.ski != ski.kind:
            continue
        zones = solve_caption_case(case, ski)
        rows.extend(compare_case(case, zones))
        stated = {z.zone: z for z in case.zones}
        for name in ("rear", "middle", "front"):
            got, paper = zones[name], stated.get(name)
            if paper is None:  # a zone the paper does not have must stay empty
                res.append(PATCH_PENALTY if got.patches else 0.0)
                continue
            g_len = max(got.length, 1e-3)
            g_p = got.mean_pressure if math.isfinite(got.mean_pressure) else 1e6
            res.append(math.log(g_len / paper.length) / math.log(1 + TOLERANCES.length))
            res.append(math.log(g_p / paper.mean_pressure) / math.log(1 + TOLERANCES.pressure))
            if paper.load_share is not None:
                res.append((got.load_share - paper.load_share) / TOLERANCES.share)
            want = paper.patches if paper.patches is not None else 1
            if paper.patches is not None or got.patches == 0:
                res.append(PATCH_PENALTY * min(abs(got.patches - want), 2))
            else:
                res.append(0.0)
    return res, rows


BAD = 1e3
N_RES: dict[str, int] = {}  # residuals per ski (fixed by the captions)


def residuals(kind: str, v: np.ndarray, use_plausibility: bool) -> np.ndarray:
    try:
        ski = make_ski(kind, v)
        res, _ = caption_residuals(ski)
        if use_plausibility:
            res += [2.0 * r for r in plausibility_residuals(kind, plausibility(ski))]
        else:
            res += [0.0] * (5 if kind == "classic" else 4)
    except Exception:  # an infeasible shape: no wax pocket, the load off the supports, ...
        n = N_RES.get(kind, 1)
        return np.full(n, BAD / math.sqrt(n))
    N_RES[kind] = len(res)
    return np.nan_to_num(np.asarray(res, dtype=float), nan=BAD, posinf=BAD, neginf=-BAD)


# --------------------------------------------------------------------------- the fit


def bounds(kind: str) -> tuple[np.ndarray, np.ndarray]:
    """The box: EI 40..30000 N m²; z0 knots [mm]: ends 0..8, glide zones -0.5..2, middle 0..20."""
    ek, zk, pins = SPLINE_KNOTS[kind]
    n_e = len(ek)
    free = [k for k in range(len(zk)) if k not in pins]
    lo = np.empty(n_e + len(free))
    hi = np.empty_like(lo)
    lo[:n_e], hi[:n_e] = math.log(40.0), math.log(30000.0)
    for m, k in enumerate(free):
        if k in (0, len(zk) - 1):
            lo[n_e + m], hi[n_e + m] = 0.0, 8.0
        elif abs(zk[k]) >= 0.42:
            lo[n_e + m], hi[n_e + m] = -0.5, 2.0
        else:
            lo[n_e + m], hi[n_e + m] = 0.0, 20.0
    return lo, hi


def fit(
    kind: str,
    *,
    seed: int,
    generations: int,
    popsize: int,
    use_plausibility: bool,
    start: np.ndarray | None = None,
    sigma: float = 0.08,
) -> dict:
    """Differential evolution in the unit box around the start, then a least-squares polish."""
    v0 = start_vector(kind) if start is None else start
    lo, hi = bounds(kind)
    u0 = np.clip((v0 - lo) / (hi - lo), 0.0, 1.0)

    def vec(u: np.ndarray) -> np.ndarray:
        return lo + (hi - lo) * np.clip(u, 0.0, 1.0)

    residuals(kind, vec(u0), use_plausibility)  # fixes N_RES[kind]
    count = [0]
    best = [math.inf]
    t0 = time.perf_counter()

    def objective(u: np.ndarray) -> float:
        count[0] += 1
        f = float(np.sum(residuals(kind, vec(u), use_plausibility) ** 2))
        if f < best[0]:
            best[0] = f
            print(
                f"  [{kind} {count[0]:5d} {time.perf_counter() - t0:5.0f} s] {f:10.3f}", flush=True
            )
        return f

    # the population: a seeded cloud around the start (sigma of the box), the start itself
    rng = np.random.default_rng(seed)
    init = np.clip(u0 + sigma * rng.standard_normal((popsize * u0.size, u0.size)), 0.0, 1.0)
    init[0] = u0
    de = differential_evolution(
        objective, [(0.0, 1.0)] * u0.size, init=init, maxiter=generations, seed=seed,
        polish=False, tol=0.0, mutation=(0.4, 0.9), recombination=0.7,
    )  # fmt: skip
    print(f"  DE: {de.nfev} evaluations, misfit {de.fun:.3f}", flush=True)
    ls = least_squares(
        lambda u: residuals(kind, vec(u), use_plausibility),
        de.x, bounds=(0.0, 1.0), method="trf", diff_step=0.01, max_nfev=20 * u0.size,
    )  # fmt: skip
    u = ls.x if 2 * ls.cost < de.fun else de.x
    print(f"  polish: {ls.nfev} evaluations, misfit {2 * ls.cost:.3f}", flush=True)
    return {"vector": vec(u).tolist(), "evaluations": count[0], "seconds": time.perf_counter() - t0}


def report(kind: str, v: np.ndarray) -> dict:
    ski = make_ski(kind, v)
    _, rows = caption_residuals(ski)
    prac = plausibility(ski)
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
    caption_misfit = float(np.sum(np.square(caption_residuals(ski)[0])))
    print(f"caption misfit {caption_misfit:.3f}, all within tolerance: {all(r.ok for r in rows)}")
    return {
        "ski": kind,
        "ei_knots_m": list(SPLINE_KNOTS[kind][0]),
        "ei_n_m2": [round(float(e), 2) for e in ei],
        "camber_knots_m": list(SPLINE_KNOTS[kind][1]),
        "camber_mm": [round(float(c) * 1e3, 4) for c in z],
        "kick_zone_m": None if ski.kick_zone is None else [round(k, 4) for k in ski.kick_zone],
        "plausibility": prac,
        "caption_misfit": caption_misfit,
        "captions_within_tolerance": all(r.ok for r in rows),
        "captions": [r.as_dict() for r in rows],
    }


SHIPPED = Path(__file__).resolve().parents[1] / "src" / "skisnow" / "ski" / "data"


def write_shipped(doc: dict, path: Path) -> Path:
    """Write the fitted ski of a calibration record as a ski file with its provenance."""
    import datetime

    from skisnow import __version__
    from skisnow.ski import Provenance
    from skisnow.ski._shipped import _SOURCE_LIST
    from skisnow.ski._skifile import write_ski

    kind = doc["ski"]
    pr = doc["plausibility"]
    rows = doc["captions"]
    n_ok = sum(r["ok"] for r in rows)
    text = (
        f"Virtual {kind} ski, a spline ski (log EI at 10 knots, free camber at 13 knots, PCHIP; "
        f"skisnow.ski._spline), 44 mm wide, fitted to the captions of Kalliorinne et al. (2023), "
        f"Figs. 4-7 under the practitioners' limits: {n_ok}/{len(rows)} zones within all "
        f"tolerances (`skisnow captions`). Free camber at the balance point "
        f"{pr['free_camber_mm']:.1f} mm; EI {pr['ei_min_n_m2']:.0f}-{pr['ei_max_n_m2']:.0f} N m². "
        f"Virtual bench (65 kg skier, -80 mm): camber {pr['camber_half_mm']:.2f} mm at half and "
        f"{pr['camber_full_mm']:.2f} mm at full body weight, Breitschädel stiffness k "
        f"{pr['k_n_per_mm']:.0f} N/mm."
    )
    if doc["kick_zone_m"]:
        a, b = doc["kick_zone_m"]
        text += (
            f" Kick zone {a * 1e3:.0f} .. {b * 1e3:.0f} mm (0.2 mm rear and 0.1 mm front marks "
            "at half body weight)."
        )
    text += " CHOSEN by a fit, not measured: no public EI(x) or camber table of a XC ski."
    provenance = Provenance(
        method="calibrated: spline ski fitted to the captions of Kalliorinne et al. (2023), "
        "Figs. 4-7 (benchmarks/calibrate_skis.py: differential evolution, then least squares)",
        data="the caption numbers of Figs. 4-7 (skisnow.paper.CAPTIONS) through the paper's "
        "pipeline (beam on the rigid plane, rigid profile, strip half-space, E_base 900 MPa, "
        "nu 0.3); hinge limits on the practitioners' numbers",
        sources=_SOURCE_LIST,
        created=datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        software=f"skisnow {__version__}",
        details=(
            ("seed", int(doc["seed"])),
            ("generations", int(doc["generations"])),
            ("popsize", int(doc["popsize"])),
            ("evaluations", int(doc["evaluations"])),
            ("caption_misfit", round(float(doc["caption_misfit"]), 3)),
            ("caption_zones_within_tolerance", f"{n_ok}/{len(rows)}"),
            ("k_n_per_mm", round(float(pr["k_n_per_mm"]), 1)),
            ("ei_knots_n_m2", json.dumps(doc["ei_n_m2"])),
            ("camber_knots_mm", json.dumps(doc["camber_mm"])),
            ("boot_plate", "chosen: a boot from the balance point 300 mm back"),
        ),
    )
    kick = tuple(doc["kick_zone_m"]) if doc["kick_zone_m"] else None
    ski = spline_ski(
        kind, np.array(doc["ei_n_m2"]), np.array(doc["camber_mm"]) * 1e-3, kick_zone=kick,
        description=text, provenance=provenance,
    )  # fmt: skip
    return write_ski(ski, path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ski", choices=("classic", "skate"), action="append")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--generations", type=int, default=30)
    ap.add_argument("--popsize", type=int, default=6)
    ap.add_argument("--caption-only", action="store_true", help="no plausibility terms")
    ap.add_argument("--shipped", action="store_true", help="only the table of the shipped skis")
    ap.add_argument("--out", type=Path, default=Path("calibration"))
    ap.add_argument(
        "--start", type=Path, default=None, help="start from a calibration JSON (a restart)"
    )
    ap.add_argument("--sigma", type=float, default=0.08, help="population spread (unit box)")
    ap.add_argument(
        "--write-shipped", type=Path, default=None,
        help="write the ski of this calibration record as the shipped ski file",
    )  # fmt: skip
    args = ap.parse_args()
    if args.write_shipped is not None:
        doc = json.loads(args.write_shipped.read_text())
        print(write_shipped(doc, SHIPPED / f"{doc['ski']}.json"))
        return
    args.out.mkdir(parents=True, exist_ok=True)
    for kind in args.ski or ["classic", "skate"]:
        if args.shipped:
            report(kind, shipped_vector(kind))
            continue
        start = None
        if args.start is not None:
            prev = json.loads(args.start.read_text())
            _, zk, pins = SPLINE_KNOTS[kind]
            free = [k for k in range(len(zk)) if k not in pins]
            start = np.concatenate([np.log(prev["ei_n_m2"]), np.array(prev["camber_mm"])[free]])
        result = fit(
            kind, seed=args.seed, generations=args.generations, popsize=args.popsize,
            use_plausibility=not args.caption_only, start=start, sigma=args.sigma,
        )  # fmt: skip
        doc = report(kind, np.array(result["vector"]))
        doc |= {
            "seed": args.seed,
            "generations": args.generations,
            "popsize": args.popsize,
            "plausibility_terms": not args.caption_only,
            "evaluations": result["evaluations"],
            "seconds": round(result["seconds"], 1),
        }
        tag = "_caption_only" if args.caption_only else ""
        path = args.out / f"calibration_{kind}{tag}.json"
        path.write_text(json.dumps(doc, indent=1))
        print(f"({kind}: {result['seconds']:.0f} s, {result['evaluations']} evaluations) → {path}")


if __name__ == "__main__":
    main()
