"""Calibrated band widths: the conformal factors of the default bands (issue 25, eighth pass).

Run:  uv run python benchmarks/bench_band_conformal.py --store ~/.cache/skisnow-hac
      uv run python benchmarks/bench_band_conformal.py --store ~/.cache/skisnow-hac \\
          --full-store ~/.cache/skisnow-idconf --predict

The fits are those cached by ``bench_band_variants.py --fit`` (identify_ski's defaults on the
independent reference bench of each ski, ``bench_identify_coverage.bench_of``: 1 mm finite
differences, seeded noise; shop plan, or ``--plan full`` in ``--full-store``). For every fit the
default (Laplace) bands are recomputed from its cached linearisation (``band_variants.profiles_of
(g, 'current')``, bitwise the bands ``identify_ski`` writes) and the normalised errors taken at
the determined stations: |log ÊI - log EI| / sd of log EI, and |ẑ0 - z0| / sd of z0 modulo the
line the bench cannot see, weighted by the band (as ``bench_band_variants.coverage``; a common
factor on the band leaves that line unchanged, so the share covered at factor k is the share of
normalised errors <= 2 k).

Calibration (skis ``--calibrate``, default 1-14, both noise levels): the factor by
:func:`skisnow.identify._bands.calibrated_scale` (conformal risk control at ``--alpha``, one
unit per ski: its 5 and 10 µm fits' stations together), per noise level for the check that one
factor serves both, and a ski-block bootstrap (skis drawn with replacement) for its spread.

``--calibrate-plan full``: the same calibration on the full-plan fits of the calibration skis
(``--full-store``), its factors (rounded up to 0.01) predicted on the held-out skis' full plans.

``--predict``: with the factors of the library (``CONFORMAL_SCALE_EI``, ``CONFORMAL_SCALE_Z0``),
nothing refitted to these skis, the coverage before (Laplace) and after (scaled) on skis 15-24,
the held-out skis 1001-1003 and issue 25's ski (shop), and the held-out skis' full plans; the
pooled shares, the median half-widths, and the spread over skis (a pooled 95 % can hide a ski at
30 %), then one row per fit. ``--predict-calibrated``: the same with the factors calibrated in
this run (rounded up to 0.01); ``--no-full``: the shop sets only (tenth pass:
``--calibrate 101-140 --alpha 0.08 --predict --predict-calibrated --no-full``, the calibration
skis fitted at one noise level each, odd seeds 5 µm, even 10 µm).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_band_variants import cached_fits
from bench_identify_coverage import _skis

from skisnow.identify._bands import (
    CONFORMAL_ALPHA,
    CONFORMAL_SCALE_EI,
    CONFORMAL_SCALE_Z0,
    calibrated_scale,
)

VALIDATION = ["1001", "1002", "1003", "issue25"]


def normalised(prof, true) -> dict:
    """The normalised errors of EI and z0 at the determined stations and the bands' sd."""
    de, dz = prof.ei_determined, prof.z_determined
    ee = np.abs(np.log(prof.ei / true.stiffness(prof.ex)))[de] / prof.sd_log_ei[de]
    sdz = prof.sd_z[dz]
    d = (prof.z_rest - true.free_camber(prof.cx))[dz]
    a = np.stack([np.ones(d.size), prof.cx[dz]], axis=1)
    coef = np.linalg.lstsq(a / sdz[:, None], d / sdz, rcond=None)[0]
    dd = d - a @ coef
    return {"ei": ee, "z0": np.abs(dd) / sdz, "sd_ei": prof.sd_log_ei[de], "sd_z0": sdz,
            "z0_rms": float(1e6 * np.sqrt(np.mean(dd**2))) if dd.size else np.nan}  # fmt: skip


def load(store, skis, noise_um, plan) -> list[tuple[str, float, dict]]:
    from band_variants import profiles_of

    return [(s, n, normalised(profiles_of(g, "current"), true))
            for s, n, true, g in cached_fits(store, skis, noise_um, plan)]  # fmt: skip


def _cover(e: np.ndarray, k: float) -> float:
    return float(np.mean(e <= 2 * k)) if e.size else np.nan


def _spread(per: list[float]) -> str:
    return f"{100 * min(per):.0f} / {100 * np.median(per):.0f} / {100 * max(per):.0f} %"


def calibrate(fits, alpha: float, boot: int) -> tuple[float, float]:
    """Print the calibration table; return the pooled factors (EI, z0)."""
    if not fits:
        print("\nno cached fits to calibrate on")
        return float("nan"), float("nan")
    skis = sorted({s for s, _, _ in fits}, key=lambda s: (len(s), s))
    print(f"\ncalibration: {len(skis)} skis ({', '.join(skis)}), alpha {alpha:g}")
    print(
        "| quantity | noise µm | units | Laplace: ski-averaged coverage | factor k "
        "| ski-block bootstrap 5 / 50 / 95 % | scaled: ski-averaged / pooled coverage |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- |")  # fmt: skip
    rng = np.random.default_rng(0)
    pooled_k: dict[str, float] = {}
    for q in ("ei", "z0"):
        for noise in (None, 5.0, 10.0):
            units = _units([f for f in fits if noise is None or f[1] == noise], skis, q)
            k = calibrated_scale(units, alpha=alpha)
            ks = [calibrated_scale([units[i] for i in rng.integers(0, len(units), len(units))],
                                   alpha=alpha) for _ in range(boot)]  # fmt: skip
            lap = np.mean([_cover(u, 1.0) for u in units])
            avg = np.mean([_cover(u, k) for u in units])
            pooled = _cover(np.concatenate(units), k)
            lo, mid, hi = np.quantile(ks, [0.05, 0.5, 0.95])
            if noise is None:
                pooled_k[q] = k
            what = "5 and 10" if noise is None else f"{noise:g}"
            print(f"| {'EI' if q == 'ei' else 'z0'} | {what}"
                  f" | {len(units)} | {100 * lap:.1f} % | {k:.3f} | {lo:.2f} / {mid:.2f} / {hi:.2f}"
                  f" | {100 * avg:.1f} / {100 * pooled:.1f} % |")  # fmt: skip
    return pooled_k["ei"], pooled_k["z0"]


def _units(fits, skis, q: str) -> list[np.ndarray]:
    """One calibration unit per ski of ``skis`` with a fit in ``fits``: the normalised errors of
    ``q`` at the determined stations of all its fits."""
    units = [np.concatenate([f[2][q] for f in fits if f[0] == s])
             for s in skis if any(f[0] == s for f in fits)]  # fmt: skip
    return [u for u in units if u.size]


def _round_up(k: float) -> float:
    """A factor rounded up to 0.01 (as the library's constants are)."""
    return float(np.ceil(100 * k) / 100)


def _plugin_scale(units, alpha: float) -> float:
    """The smallest k whose mean loss over the calibration units is <= alpha (no finite-sample
    term: what the calibration skis alone ask for). The conformal rule (Σ L + 1)/(n + 1) <= α'
    is that rule at α' = (n α + 1)/(n + 1)."""
    n = len(units)
    return calibrated_scale(units, alpha=(n * alpha + 1.0) / (n + 1.0))


def sizes(fits, alphas, sub: int, draws: int) -> None:
    """How much of the factor is the finite-sample term: per quantity and alpha, the conformal
    factor on all units, its median (5 / 95 %) over ``draws`` random subsets of ``sub`` units
    (without replacement), and the plug-in factor (mean loss <= alpha, no +1)."""
    skis = sorted({s for s, _, _ in fits}, key=lambda s: (len(s), s))
    rng = np.random.default_rng(1)
    print(f"\nfactor vs calibration size ({len(skis)} skis; subsets of {sub}, {draws} draws)")
    print("| quantity | alpha | conformal, all skis | conformal, subsets: 5 / 50 / 95 % "
          "| plug-in (no +1), all skis |")  # fmt: skip
    print("| --- | --- | --- | --- | --- |")
    for q in ("ei", "z0"):
        units = _units(fits, skis, q)
        for alpha in alphas:
            k = calibrated_scale(units, alpha=alpha)
            ks = [calibrated_scale([units[i] for i in rng.choice(len(units), sub, replace=False)],
                                   alpha=alpha) for _ in range(draws)]  # fmt: skip
            kp = _plugin_scale(units, alpha)
            if np.all(np.isfinite(ks)):
                lo, mid, hi = np.quantile(ks, [0.05, 0.5, 0.95])
                sub_k = f"{lo:.2f} / {mid:.2f} / {hi:.2f}"
            else:  # 1/(sub + 1) > alpha: no factor can meet the rule
                sub_k = f"inf in {int(np.sum(np.isinf(ks)))} of {len(ks)} draws"
            print(f"| {'EI' if q == 'ei' else 'z0'} | {alpha:g} | {k:.3f} "
                  f"| {sub_k} | {kp:.3f} |")  # fmt: skip


def predict(sets, k_ei: float, k_z0: float) -> None:
    print(f"\nprediction with k_EI = {k_ei:g}, k_z0 = {k_z0:g} (nothing refitted to these skis)")
    print(
        "| set | plan | noise µm | fits | EI in band: Laplace → scaled | z0 in band: Laplace → "
        "scaled | EI half-width %: Laplace → scaled | z0 half-width µm: Laplace → scaled "
        "| z0 per ski, min / median / max: Laplace → scaled | skis < 90 % (z0) |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")  # fmt: skip
    rows = []
    for name, plan, fits in sets:
        for noise in sorted({f[1] for f in fits}):
            sel = [f for f in fits if f[1] == noise]
            if not sel:
                continue
            ee = np.concatenate([f[2]["ei"] for f in sel])
            ez = np.concatenate([f[2]["z0"] for f in sel])
            hw_e = np.median([np.median(100 * np.expm1(2 * f[2]["sd_ei"])) for f in sel])
            hw_e2 = np.median([np.median(100 * np.expm1(2 * k_ei * f[2]["sd_ei"])) for f in sel])
            hw_z = np.median([np.median(2e6 * f[2]["sd_z0"]) for f in sel])
            per = [_cover(f[2]["z0"], k_z0) for f in sel]
            per0 = [_cover(f[2]["z0"], 1.0) for f in sel]
            n_e, n_z = ee.size, ez.size
            print(f"| {name} | {plan} | {noise:g} | {len(sel)} "
                  f"| {np.sum(ee <= 2)}/{n_e} {100 * _cover(ee, 1):.1f} % → "
                  f"**{np.sum(ee <= 2 * k_ei)}/{n_e} {100 * _cover(ee, k_ei):.1f} %** "
                  f"| {np.sum(ez <= 2)}/{n_z} {100 * _cover(ez, 1):.1f} % → "
                  f"**{np.sum(ez <= 2 * k_z0)}/{n_z} {100 * _cover(ez, k_z0):.1f} %** "
                  f"| {hw_e:.1f} → {hw_e2:.1f} | {hw_z:.1f} → {k_z0 * hw_z:.1f} "
                  f"| {_spread(per0)} → {_spread(per)} "
                  f"| {sum(p < 0.9 for p in per0)} → {sum(p < 0.9 for p in per)} of {len(per)} |",
                  flush=True)  # fmt: skip
            rows += [(name, plan, f) for f in sel]
    print(
        "\n| set | plan | ski | noise µm | z0 error rms µm | EI in band: Laplace → scaled "
        "| z0 in band: Laplace → scaled | z0 half-width µm: Laplace → scaled "
        "| z0 error / scaled half-width: median, max |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")  # fmt: skip
    for name, plan, (s, n, c) in rows:
        e, z = c["ei"], c["z0"]
        hz = float(np.median(2e6 * c["sd_z0"]))
        print(f"| {name} | {plan} | {s} | {n:g} | {c['z0_rms']:.1f} | {np.sum(e <= 2)}/{e.size} → "
              f"{np.sum(e <= 2 * k_ei)}/{e.size} | {np.sum(z <= 2)}/{z.size} → "
              f"{np.sum(z <= 2 * k_z0)}/{z.size} | {hz:.1f} → {k_z0 * hz:.1f} "
              f"| {np.median(z) / (2 * k_z0):.2f}, {np.max(z) / (2 * k_z0):.2f} |")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--store", default=str(Path.home() / ".cache" / "skisnow-hac"))
    ap.add_argument("--full-store", default=str(Path.home() / ".cache" / "skisnow-idconf"))
    ap.add_argument("--calibrate", nargs="+", default=["1-14"])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--alpha", type=float, default=CONFORMAL_ALPHA)
    ap.add_argument("--boot", type=int, default=1000, help="ski-block bootstrap draws")
    ap.add_argument("--predict", action="store_true")
    ap.add_argument(
        "--predict-calibrated",
        action="store_true",
        help="also predict with the factors calibrated here (rounded up to 0.01)",
    )
    ap.add_argument("--no-full", action="store_true", help="shop prediction sets only")
    ap.add_argument("--sizes", type=int, default=0, metavar="N",
                    help="also the factor on random subsets of N calibration skis and the "
                    "plug-in factor, at alpha 0.05, 0.08, 0.10")  # fmt: skip
    ap.add_argument("--calibrate-plan", default="shop", choices=["shop", "full"],
                    help="full: the full plan's own factors")  # fmt: skip
    a = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    if a.calibrate_plan == "full":
        # the full plan's own factors (calibrated on the full-plan fits of the calibration
        # skis in --full-store), predicted on the held-out skis' full plans
        k_ei, k_z0 = calibrate(load(a.full_store, _skis(a.calibrate), a.noise_um, "full"),
                               a.alpha, a.boot)  # fmt: skip
        k_ei, k_z0 = _round_up(k_ei), _round_up(k_z0)
        full = load(a.full_store, VALIDATION, a.noise_um, "full")
        predict([("held out", "full", full)], k_ei, k_z0)
        print(f"load average at end: {os.getloadavg()}")
        return
    cal = load(a.store, _skis(a.calibrate), a.noise_um, "shop")
    k_ei, k_z0 = calibrate(cal, a.alpha, a.boot)
    if a.sizes:
        sizes(cal, (0.05, 0.08, 0.10), a.sizes, a.boot)
    if a.predict or a.predict_calibrated:
        sets = [
            ("seeded skis 15-24", "shop", load(a.store, _skis(["15-24"]), a.noise_um, "shop")),
            ("held out", "shop", load(a.store, VALIDATION, a.noise_um, "shop")),
        ]
        if not a.no_full:
            sets.append(("held out", "full", load(a.full_store, VALIDATION, a.noise_um, "full")))
        if a.predict:
            predict(sets, CONFORMAL_SCALE_EI, CONFORMAL_SCALE_Z0)
        if a.predict_calibrated:
            predict(sets, _round_up(k_ei), _round_up(k_z0))
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
