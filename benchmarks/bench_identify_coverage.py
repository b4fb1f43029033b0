"""Coverage study and validation of the identification (issue 25): known skis -> independent
benches -> identify_ski -> errors, band coverage, held-out profiles, contact, exit code, time.

Run:  uv run python benchmarks/bench_identify_coverage.py [--skis 1-20] [--plans shop full]
      [--noise-um 5 10] [--jobs 2] [--cache DIR] [--validation]

For each ski × plan × noise:

* the true ski: a plausible synthetic ski, ``skisnow.bench.random_ski(seed)`` (random EI and
  camber shapes: sharp stiffness steps of 10-40 mm, almost flat glide zones of power 2-4, waviness
  up to 15 µm, classic and skate); ``--validation``: the three skis fixed after development
  (seeds 1001-1003, never used while the method was tuned) and issue 25's ski
  (``skisnow.bench.issue25_ski``);
* its bench by an implementation independent of the fit's forward model:
  ``skisnow.bench.reference_bench`` (finite differences in mixed form at ``--dx-mm``, default
  1 mm as in issue 25, contact at every node, a primal-dual active set), noise-free benches
  cached in ``--cache``, seeded Gaussian noise added (seed 1);
* the plans: ``shop`` — 20, 40, ..., 120 kg at -40 and -120 mm, stations every 10 mm; ``full`` —
  10-130 kg in 10 kg steps at -40, -120, -200 mm (39 cases), stations every 2 mm;
* ``identify_ski`` from its default start (BLAS on one thread), then: EI rms [%] over the
  determined stations within -450..+400 mm; z0 rms [µm] over the determined stations, modulo
  the line the bench cannot see (weighted by the bands); the share of determined stations whose
  truth lies inside the 95 % band (±2 sd) for EI and for z0; held-out profiles (35 and 75 kg at
  -160 mm, not in either plan) rms [µm] between identified and true ski (both through
  ``solve_beam``); contact: the largest relative difference of the regions' lengths, mean
  pressures and load shares at 30/60/90 kg, -120 mm, on 30 and 400 MPa snow (rigid route);
  exit code (0 converged, 3 not); CPU time of the identification (``time.process_time``).

Then the coverage table: the shares pooled over skis per plan × noise (target 90-98 %).
Report the load average (``uptime``) with the times.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

PLANS = {
    "shop": dict(masses=(20, 40, 60, 80, 100, 120), load_positions=(-0.04, -0.12),
                 station_step=0.010),
    "full": dict(masses=tuple(range(10, 131, 10)), load_positions=(-0.04, -0.12, -0.2),
                 station_step=0.002),
}  # fmt: skip
VALIDATION_SEEDS = (1001, 1002, 1003)
HELD_OUT = ((35.0, -0.16), (75.0, -0.16))
CONTACT_CASES = ((30.0, 30e6), (60.0, 400e6), (90.0, 100e6))


def true_ski(name: str):
    """The ski named: ``issue25``, a seed of ``random_ski``, or ``shipped:<name>`` (a shipped
    ski, ``skisnow.ski.get_ski``: spline skis calibrated to the paper's captions, not of the
    random generator's family)."""
    from skisnow.bench import issue25_ski, random_ski
    from skisnow.ski import get_ski

    if name.startswith("shipped:"):
        return get_ski(name.split(":", 1)[1])
    return issue25_ski() if name == "issue25" else random_ski(int(name))


def bench_of(name: str, plan: str, noise_um: float, cache: Path, dx_mm: float = 1.0):
    """The noise-free reference bench (cached) plus seeded noise."""
    import pandas as pd

    from skisnow.bench import BenchData, read_bench, reference_bench, write_bench

    cache.mkdir(parents=True, exist_ok=True)
    path = cache / f"ref_{name.replace(':', '-')}_{plan}_{dx_mm:g}mm.csv"
    if path.exists():
        clean = read_bench(path)
    else:
        clean = reference_bench(true_ski(name), **PLANS[plan], dx=dx_mm * 1e-3)
        write_bench(clean, path)
    t = clean.table.copy()
    rng = np.random.default_rng(1)
    t["height_mm"] = t["height_mm"] + rng.normal(0.0, noise_um * 1e-3, len(t))
    md = {**clean.metadata, "noise_mm": noise_um * 1e-3, "seed": 1}
    return BenchData(table=pd.DataFrame(t), metadata=md)


def errors(res, true) -> dict:
    """EI/z0 errors and band coverage over the determined stations (module docstring)."""
    s = res.ski
    ex = np.asarray(s.stiffness_x)
    de = np.asarray(s.stiffness_determined)
    sde = np.asarray(s.stiffness_log_sd)
    le = np.log(np.asarray(s.stiffness_values) / true.stiffness(ex))
    mid = de & (ex >= -0.45) & (ex <= 0.40)
    cx = np.asarray(s.camber_x)
    dz = np.asarray(s.camber_determined)
    sdz = np.asarray(s.camber_sd)
    d = np.asarray(s.camber_values) - true.free_camber(cx)
    w = 1.0 / np.maximum(sdz[dz], 1e-7) ** 2
    a = np.stack([np.ones(int(dz.sum())), cx[dz]], axis=1)
    coef = np.linalg.solve(a.T @ (a * w[:, None]), a.T @ (w * d[dz]))
    dd = d[dz] - a @ coef
    return {
        "ei_rms": float(100 * np.sqrt(np.mean(np.expm1(le[mid]) ** 2))) if mid.any() else np.nan,
        "z0_rms": float(1e6 * np.sqrt(np.mean(dd**2))) if dd.size else np.nan,
        "ei_in": int(np.sum(np.abs(le[de]) <= 2 * sde[de])),
        "ei_n": int(de.sum()),
        "z0_in": int(np.sum(np.abs(dd) <= 2 * sdz[dz])),
        "z0_n": int(dz.sum()),
        "ei_span": f"{ex[de][0] * 1e3:.0f}..{ex[de][-1] * 1e3:.0f}" if de.any() else "none",
        "ei_hw": float(np.median(100 * np.expm1(2 * sde[de]))) if de.any() else np.nan,
        "z0_hw": float(np.median(2e6 * sdz[dz])) if dz.any() else np.nan,
    }


def held_out(ski, true) -> float:
    from skisnow.ski import solve_beam

    xs = np.linspace(true.x_tail + 0.02, true.x_tip - 0.02, 800)
    sq = []
    for m, p in HELD_OUT:
        hi = solve_beam(ski, mass=m, load_position=p, contact="continuous").sample(xs)
        ht = solve_beam(true, mass=m, load_position=p, contact="continuous").sample(xs)
        sq.append(np.mean((hi - ht) ** 2))
    return float(1e6 * np.sqrt(np.mean(sq)))


def contact_error(ski, true) -> float:
    """Largest relative difference [%] of region lengths, mean pressures and load shares."""
    from skisnow.pipeline import solve_case

    worst = 0.0
    for m, e in CONTACT_CASES:
        a = solve_case(ski, mass=m, load_position=-0.12, snow_modulus=e, profile_source="beam")
        b = solve_case(true, mass=m, load_position=-0.12, snow_modulus=e, profile_source="beam")
        for name in ("rear_glide", "kick", "front_glide", "total"):
            za, zb = a.zones[name], b.zones[name]
            for qa, qb in ((za.length, zb.length), (za.mean_pressure, zb.mean_pressure),
                           (za.load_share, zb.load_share)):  # fmt: skip
                if abs(qb) > 0:
                    worst = max(worst, abs(qa / qb - 1.0))
    return 100.0 * worst


def run_one(args: tuple) -> dict:
    name, plan, noise_um, cache, with_contact, dx_mm, n_stiffness, criterion, plain, boot, extra = (
        args
    )
    from skisnow.identify import identify_ski

    kw: dict = {} if n_stiffness is None else {"n_stiffness": n_stiffness}
    kw.update(extra)
    if criterion is not None:
        kw["criterion"] = criterion
    if plain:
        kw["smoothing_bands"] = False
    true = true_ski(name)
    bench = bench_of(name, plan, noise_um, Path(cache), dx_mm)
    t0 = time.process_time()
    w0 = time.perf_counter()
    try:
        res = identify_ski(bench, **kw)
    except Exception as exc:
        return {"ski": name, "plan": plan, "noise": noise_um, "error": repr(exc)[:120]}
    cpu, wall = time.process_time() - t0, time.perf_counter() - w0
    row = {"ski": name, "kind": true.kind, "plan": plan, "noise": noise_um, **errors(res, true),
           "misfit": res.misfit, "exit": 0 if res.converged else 3, "cpu": cpu, "wall": wall,
           "causes": ",".join(res.causes), "mesh_um": res.mesh_error[0] * 1e6,
           "held_out": held_out(res.ski, true), "lam": res.regularisation,
           "criterion": res.criterion, "model_um": res.model_error[0] * 1e6,
           "delta": res.model_error[1], "bound_sigma": float(np.sqrt(res.chi2_bound / res.n_bins)),
           # the exit of the rule before issue 25's sixth pass: χ² within the noise-only bound
           "exit_old": 0 if res.at_noise and res.mesh_error[0] <= res.noise / 5 else 3}  # fmt: skip
    if boot:
        from skisnow.identify import bootstrap_bands

        t1 = time.process_time()
        rb = bootstrap_bands(res, bench, replicates=boot, stiffness=True, **kw)
        eb = errors(rb, true)
        row.update({"boot_cpu": time.process_time() - t1, "boot_n": (rb.bootstrap or (0,))[0],
                    "ei_in_b": eb["ei_in"], "z0_in_b": eb["z0_in"], "ei_hw_b": eb["ei_hw"],
                    "z0_hw_b": eb["z0_hw"]})  # fmt: skip
    if with_contact:
        row["contact"] = contact_error(res.ski, true)
    return row


def _skis(spec: list[str]) -> list[str]:
    out = []
    for item in spec:
        if "-" in item and item.replace("-", "").isdigit():
            a, b = item.split("-")
            out += [str(k) for k in range(int(a), int(b) + 1)]
        else:
            out.append(item)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["1-20"])
    ap.add_argument("--plans", nargs="+", default=["shop", "full"], choices=list(PLANS))
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument(
        "--validation",
        action="store_true",
        help="the skis fixed after development (seeds 1001-1003) and issue 25's ski",
    )
    ap.add_argument("--contact", action="store_true", help="also the contact comparison")
    ap.add_argument("--n-stiffness", type=int, default=None,
                    help="log-EI coefficients (default: identify_ski's)")  # fmt: skip
    ap.add_argument(
        "--out", default=None, help="append every row as a JSON line to this file as it finishes"
    )
    ap.add_argument(
        "--no-smoothing-bands",
        action="store_true",
        help="bands without the estimated smoothing bias (the second pass of issue "
        "25: the 'before' of the coverage tables)",
    )
    ap.add_argument("--criterion", default=None, choices=["evidence", "gcv", "case-cv"],
                    help="how λ is chosen (default: identify_ski's)")  # fmt: skip
    ap.add_argument("--bootstrap", type=int, default=0,
                    help="also the bands with a parametric bootstrap of this many replicates "
                    "(skisnow.identify.bootstrap_bands; z0 and, for the table, EI)")  # fmt: skip
    ap.add_argument("--dx-mm", type=float, default=1.0,
                    help="grid of the reference bench [mm] (issue 25: 1 mm)")  # fmt: skip
    ap.add_argument("--identify-kw", default="{}",
                    help='further keyword arguments of identify_ski as JSON, e.g. '
                    '\'{"stiffness_penalty": "huber"}\'')  # fmt: skip
    a = ap.parse_args()
    skis = [*map(str, VALIDATION_SEEDS), "issue25"] if a.validation else _skis(a.skis)
    jobs = [
        (
            s,
            p,
            n,
            a.cache,
            a.contact,
            a.dx_mm,
            a.n_stiffness,
            a.criterion,
            a.no_smoothing_bands,
            a.bootstrap,
            json.loads(a.identify_kw),
        )
        for s in skis
        for p in a.plans
        for n in a.noise_um
    ]
    print(f"load average at start: {os.getloadavg()}")
    cols = [
        "ski",
        "kind",
        "plan",
        "noise",
        "ei_rms",
        "z0_rms",
        "ei_in",
        "ei_n",
        "z0_in",
        "z0_n",
        "held_out",
        "misfit",
        "exit",
        "exit_old",
        "model_um",
        "bound_sigma",
        "cpu",
        "wall",
        "mesh_um",
        "causes",
        "ei_span",
        "ei_hw",
        "z0_hw",
    ]
    if a.bootstrap:
        cols += ["ei_in_b", "z0_in_b", "ei_hw_b", "z0_hw_b", "boot_n", "boot_cpu"]
    if a.contact:
        cols.insert(11, "contact")
    print(" | ".join(cols))
    rows = []
    with ProcessPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for row in pool.map(run_one, jobs):
            rows.append(row)
            if a.out:
                with open(a.out, "a") as fh:
                    fh.write(json.dumps(row) + "\n")
            print(" | ".join(_fmt(row.get(c, row.get("error", ""))) for c in cols), flush=True)
    print(f"load average at end: {os.getloadavg()}")
    print("\ncoverage of the 95 % bands over determined stations (pooled over skis)")
    print("plan | noise | skis | EI in band | z0 in band | EI rms median | z0 rms median | exit 0")
    for p in a.plans:
        for n in a.noise_um:
            sel = [r for r in rows if r["plan"] == p and r["noise"] == n and "error" not in r]
            if not sel:
                continue
            ce = sum(r["ei_in"] for r in sel) / max(sum(r["ei_n"] for r in sel), 1)
            cz = sum(r["z0_in"] for r in sel) / max(sum(r["z0_n"] for r in sel), 1)
            print(f"{p} | {n:g} µm | {len(sel)} | {100 * ce:.1f} % | {100 * cz:.1f} % | "
                  f"{np.median([r['ei_rms'] for r in sel]):.2f} % | "
                  f"{np.median([r['z0_rms'] for r in sel]):.2f} µm | "
                  f"{sum(r['exit'] == 0 for r in sel)}/{len(sel)} | "
                  f"half-widths EI {np.median([r['ei_hw'] for r in sel]):.1f} %, "
                  f"z0 {np.median([r['z0_hw'] for r in sel]):.1f} µm")  # fmt: skip
            if a.bootstrap:
                be = sum(r["ei_in_b"] for r in sel) / max(sum(r["ei_n"] for r in sel), 1)
                bz = sum(r["z0_in_b"] for r in sel) / max(sum(r["z0_n"] for r in sel), 1)
                print(f"  with the bootstrap: EI {100 * be:.1f} %, z0 {100 * bz:.1f} %; "
                      f"half-widths EI {np.median([r['ei_hw_b'] for r in sel]):.1f} %, "
                      f"z0 {np.median([r['z0_hw_b'] for r in sel]):.1f} µm; CPU "
                      f"{np.median([r['boot_cpu'] for r in sel]):.0f} s median")  # fmt: skip


def _fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


if __name__ == "__main__":
    main()
