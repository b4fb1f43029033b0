"""The parametric bootstrap's z0 bands (issue 25, sixth pass): scale rule, cold vs warm starts,
coverage and cost, from replicates saved once.

Run:  nice -n 10 uv run python benchmarks/bench_z0_bootstrap_rules.py run --skis 1-4
          --noise-um 5 10 --replicates 8 --modes cold warm --jobs 2 --out DIR
      uv run python benchmarks/bench_z0_bootstrap_rules.py table --out DIR --skis 1-4
          [--scales rms mad trimmed] [--mode cold]

``run``: for each ski × noise (shop plan; the independent 1 mm reference bench with seeded noise,
``bench_identify_coverage.bench_of``; ``--validation``: 1001-1003 and issue 25's ski),
``identify_ski`` once (default options, one BLAS thread), then the replicates of
:func:`skisnow.identify.run_replicates` for each ``--modes`` (``cold``: each replicate from the
default start, as the real fit; ``warm``: from the identified ski; ``fast``: from the identified
ski at its λ, no GCV search), seeds 101, 102, ...; saves
``DIR/<ski>_<noise>.npz`` with the truth's deviation from the fit, the Laplace sd, each mode's
replicate deviations, misfits and CPU seconds. ``table``: per row and pooled, the share of the
determined stations whose truth (z0 modulo the line, weighted by the final band) lies inside
±2 sd, for the Laplace band and each scale of :func:`skisnow.identify.replicate_scale` combined
in quadrature; the median z0 half-width; the replicates excluded; CPU. Report the load average.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import VALIDATION_SEEDS, _skis, bench_of, true_ski


def run_one(args: tuple) -> str:
    name, noise, replicates, modes, cache, out = args
    from skisnow.identify import identify_ski, run_replicates

    true = true_ski(name)
    bench = bench_of(name, "shop", noise, Path(cache))
    t0 = time.process_time()
    res = identify_ski(bench)
    fit_cpu = time.process_time() - t0
    s = res.ski
    cx, dz = np.asarray(s.camber_x), np.asarray(s.camber_determined, dtype=bool)
    ex, de = np.asarray(s.stiffness_x), np.asarray(s.stiffness_determined, dtype=bool)
    data = {
        "x": cx[dz],
        "d": (np.asarray(s.camber_values) - true.free_camber(cx))[dz],
        "sd": np.asarray(s.camber_sd)[dz],
        "le": np.log(np.asarray(s.stiffness_values) / true.stiffness(ex))[de],
        "sde": np.asarray(s.stiffness_log_sd)[de],
        "fit_cpu": fit_cpu,
        "fit_misfit": res.misfit,
        "fit_exit": 0 if res.converged else 3,
        "noise": res.noise,
    }
    for mode in modes:
        w0 = time.perf_counter()
        # fast: from the identified ski at its λ (no GCV search)
        extra = {"regularisation": res.regularisation} if mode == "fast" else {}
        reps = run_replicates(res, bench, replicates=replicates, warm=mode != "cold", **extra)
        data[f"{mode}_wall"] = time.perf_counter() - w0
        data[f"{mode}_z"] = reps.camber
        data[f"{mode}_e"] = reps.stiffness
        data[f"{mode}_misfit"] = reps.misfit
        data[f"{mode}_conv"] = reps.converged
        data[f"{mode}_cpu"] = reps.cpu
        data[f"{mode}_failed"] = reps.failed
    path = Path(out) / f"{name}_{noise:g}.npz"
    if path.exists():  # another run's modes of the same row: keep them (the same fit)
        old = dict(np.load(path))
        data = {**{k: v for k, v in old.items() if k not in data}, **data}
    np.savez(path, **data)
    return f"{name} {noise:g} µm: fit {fit_cpu:.1f} s " + " ".join(
        f"{m} {np.sum(data[f'{m}_cpu']):.0f} s CPU" for m in modes
    )


def _line_free(d, x, sd):
    a = np.stack([np.ones(x.size), x], axis=1) / sd[:, None]
    coef = np.linalg.lstsq(a, d / sd, rcond=None)[0]
    return d - np.stack([np.ones(x.size), x], axis=1) @ coef


def row_stats(f, mode: str, scale: str) -> dict:
    from skisnow.identify import replicate_scale

    x, d, sd = f["x"], f["d"], f["sd"]
    out = {"n": d.size}
    lap = _line_free(d, x, sd)
    out["lap_in"] = int(np.sum(np.abs(lap) <= 2 * sd))
    out["lap_hw"] = float(np.median(2e6 * sd))
    out["z0_rms"] = float(1e6 * np.sqrt(np.mean(lap**2)))
    if f"{mode}_z" in f and f[f"{mode}_z"].shape[0] >= 2:
        boot, kept = replicate_scale(f[f"{mode}_z"], scale=scale)
        tot = np.hypot(sd, boot)
        dd = _line_free(d, x, tot)
        out.update(in_=int(np.sum(np.abs(dd) <= 2 * tot)), hw=float(np.median(2e6 * tot)),
                   excl=int((~kept).sum()), cpu=float(np.sum(f[f"{mode}_cpu"])),
                   rep_rms=float(1e6 * np.median(np.sqrt(np.mean(f[f"{mode}_z"] ** 2, 1)))),
                   reps=int(f[f"{mode}_z"].shape[0]))  # fmt: skip
    return out


def table(a) -> None:
    names = [*map(str, VALIDATION_SEEDS), "issue25"] if a.validation else _skis(a.skis)
    for mode in a.modes:
        for noise in a.noise_um:
            files = [(n, Path(a.out) / f"{n}_{noise:g}.npz") for n in names]
            files = [(n, p) for n, p in files if p.exists()]
            if not files:
                continue
            print(f"\n### mode {mode}, {noise:g} µm ({len(files)} skis)")
            hdr = "| ski | z0 rms µm | median replicate dev µm | Laplace in | "
            hdr += " | ".join(f"{s} in | {s} hw µm | {s} excl" for s in a.scales)
            print(hdr + " | CPU s |")
            print("|" + " --- |" * (hdr.count("|") + 1))
            tot = {s: [0, 0] for s in ["lap", *a.scales]}
            hws = {s: [] for s in ["lap", *a.scales]}
            cpus = []
            for n, p in files:
                f = dict(np.load(p))
                st = {s: row_stats(f, mode, s) for s in a.scales}
                b = st[a.scales[0]]
                if "in_" not in b:
                    continue
                line = f"| {n} | {b['z0_rms']:.1f} | {b['rep_rms']:.1f} | "
                line += f"{b['lap_in']}/{b['n']} ({100 * b['lap_in'] / b['n']:.0f} %) | "
                tot["lap"][0] += b["lap_in"]
                tot["lap"][1] += b["n"]
                hws["lap"].append(b["lap_hw"])
                for s in a.scales:
                    r = st[s]
                    tot[s][0] += r["in_"]
                    tot[s][1] += r["n"]
                    hws[s].append(r["hw"])
                    line += f"{r['in_']}/{r['n']} ({100 * r['in_'] / r['n']:.0f} %) | "
                    line += f"{r['hw']:.1f} | {r['excl']} | "
                cpus.append(b["cpu"])
                print(line + f"{b['cpu']:.0f} |")
            summ = " ; ".join(f"{s} {100 * tot[s][0] / max(tot[s][1], 1):.1f} % "
                              f"(hw median {np.median(hws[s]):.1f} µm)" for s in tot)  # fmt: skip
            print(f"pooled: {summ}; replicate CPU median {np.median(cpus):.0f} s per row")


def why(a) -> None:
    """Per row and mode: the fit's z0 error, the replicates' spread about the fit (median of
    their rms), the rms of their mean deviation (the bootstrap's estimate of the fit's bias)
    and its correlation with the fit's actual error (all line-free, µm)."""
    names = [*map(str, VALIDATION_SEEDS), "issue25"] if a.validation else _skis(a.skis)
    print("| ski | noise µm | mode | z0 error rms | replicate rms (median, range) | "
          "rms of the replicates' mean | corr(mean, error) | replicates' misfit |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for noise in a.noise_um:
        for n in names:
            p = Path(a.out) / f"{n}_{noise:g}.npz"
            if not p.exists():
                continue
            f = dict(np.load(p))
            err = _line_free(f["d"], f["x"], f["sd"])
            for mode in a.modes:
                if f"{mode}_z" not in f:
                    continue
                z = f[f"{mode}_z"]
                r = 1e6 * np.sqrt(np.mean(z**2, axis=1))
                mean = z.mean(axis=0)
                c = float(np.corrcoef(mean, err)[0, 1])
                mf = f[f"{mode}_misfit"]
                print(f"| {n} | {noise:g} | {mode} | {1e6 * np.sqrt(np.mean(err**2)):.1f} | "
                      f"{np.median(r):.1f} ({r.min():.1f}-{r.max():.1f}) | "
                      f"{1e6 * np.sqrt(np.mean(mean**2)):.1f} | {c:+.2f} | "
                      f"{mf.min():.2f}-{mf.max():.2f} |")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=["run", "table", "why"])
    ap.add_argument("--skis", nargs="+", default=["1-4"])
    ap.add_argument("--validation", action="store_true")
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--replicates", type=int, default=8)
    ap.add_argument(
        "--modes", nargs="+", default=["cold", "warm"], choices=["cold", "warm", "fast"]
    )
    ap.add_argument("--scales", nargs="+", default=["rms", "mad", "trimmed"])
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    if a.what in ("table", "why"):
        (table if a.what == "table" else why)(a)
        return
    Path(a.out).mkdir(parents=True, exist_ok=True)
    names = [*map(str, VALIDATION_SEEDS), "issue25"] if a.validation else _skis(a.skis)
    jobs = [(n, noise, a.replicates, a.modes, a.cache, a.out)
            for n in names for noise in a.noise_um]  # fmt: skip
    print(f"load average at start: {os.getloadavg()}", flush=True)
    with ProcessPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for msg in pool.map(run_one, jobs):
            print(msg, f"(load {os.getloadavg()[0]:.1f})", flush=True)
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
