"""Band variants on cached fits (issue 25, fourth pass: the z0 coverage).

Run:  uv run python benchmarks/bench_band_variants.py --fit --skis 1-4 --noise-um 5 10 --jobs 2
      uv run python benchmarks/bench_band_variants.py --skis 1-4 --noise-um 5 10

``--fit`` runs ``identify_ski`` (default options, shop plan or ``--plan full``) on the independent
reference bench
(``bench_identify_coverage.bench_of``: 1 mm finite differences, seeded noise) and pickles the
fit's linearisation (parameters, residuals, Jacobian, penalty, the problem, λ, the mesh error)
in ``--store``. Without ``--fit`` it recomputes the bands of every cached fit under each
variant of :func:`skisnow.identify._bands` and prints the shares of determined stations whose
truth lies inside ±2 sd (EI, z0 modulo the weighted line, as in the coverage bench) and the
median band half-widths (2 sd: % of EI, µm of z0). Band variants only: the point estimate is
the cached fit's, so a variant costs seconds where a refit costs minutes.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import pickle
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_identify_coverage import _skis, bench_of, true_ski

STORE = Path.home() / ".cache" / "skisnow-band-variants"


def cached_fits(store, skis, noise_um, plan):
    """``(ski, noise µm, true ski, cached fit)`` for every fit of ``skis`` × ``noise_um`` on
    ``plan`` in the store (``--fit`` writes them; missing ones are skipped)."""
    for s in skis:
        true = true_ski(s)
        for n in noise_um:
            path = Path(store) / f"fit_{s}_{plan}_{n:g}.pkl"
            if not path.exists():
                continue
            with open(path, "rb") as fh:
                g = pickle.load(fh)
            # fits cached before the opt-in population prior (main, 2026-11-26) have none
            g["problem"].__dict__.setdefault("prior", None)
            g["problem"].__dict__.setdefault("prior_rows", None)
            yield s, n, true, g


def fit_one(args: tuple) -> str:
    name, noise_um, cache, store, plan = args
    import skisnow.identify._identify as ident

    grabbed: dict = {}
    post0, prof0 = ident.posterior, ident.identified_profiles

    def post_spy(sol, model_error=None, smoothing=None, discrepancy=None):
        grabbed.update(sol=sol, model_error=model_error, smoothing=smoothing)
        return post0(sol, model_error, smoothing, discrepancy)

    def prof_spy(problem, parameters, post, x_tail, x_tip, *, bent, measured, **kw):
        grabbed.update(problem=problem, x_tail=x_tail, x_tip=x_tip, bent=bent, measured=measured)
        return prof0(problem, parameters, post, x_tail, x_tip, bent=bent, measured=measured, **kw)

    ident.posterior, ident.identified_profiles = post_spy, prof_spy
    bench = bench_of(name, plan, noise_um, Path(cache))
    t0 = time.process_time()
    res = ident.identify_ski(bench)
    grabbed["cpu"] = time.process_time() - t0
    grabbed["lam"] = res.regularisation
    grabbed["problem"]._beam_cache = []
    out = Path(store) / f"fit_{name}_{plan}_{noise_um:g}.pkl"
    with open(out, "wb") as fh:
        pickle.dump(grabbed, fh)
    return (
        f"{out.name}: λ {res.regularisation:g}, misfit {res.misfit:.3f}, cpu {grabbed['cpu']:.1f} s"
    )


def coverage(prof, true) -> dict:
    """EI and z0 coverage and median half-widths (module docstring)."""
    ex, de = prof.ex, prof.ei_determined
    le = np.log(prof.ei / true.stiffness(ex))
    cx, dz = prof.cx, prof.z_determined
    sdz = prof.sd_z[dz]
    d = (prof.z_rest - true.free_camber(cx))[dz]
    a = np.stack([np.ones(d.size), cx[dz]], axis=1)
    coef = np.linalg.lstsq(a / sdz[:, None], d / sdz, rcond=None)[0]
    dd = d - a @ coef
    return {
        "ei_in": int(np.sum(np.abs(le[de]) <= 2 * prof.sd_log_ei[de])), "ei_n": int(de.sum()),
        "z0_in": int(np.sum(np.abs(dd) <= 2 * sdz)), "z0_n": int(dz.sum()),
        "ei_hw": float(np.median(100 * np.expm1(2 * prof.sd_log_ei[de]))) if de.any() else np.nan,
        "z0_hw": float(np.median(2e6 * sdz)) if dz.any() else np.nan,
        "z0_rms": float(1e6 * np.sqrt(np.mean(dd**2))) if dd.size else np.nan,
    }  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["1-4"])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[5.0, 10.0])
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--fit", action="store_true")
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument("--store", default=str(STORE))
    ap.add_argument("--variants", nargs="+", default=None)
    ap.add_argument("--plan", default="shop", choices=["shop", "full"])
    a = ap.parse_args()
    Path(a.store).mkdir(parents=True, exist_ok=True)
    skis = [*("1001", "1002", "1003", "issue25")] if a.skis == ["validation"] else _skis(a.skis)
    print(f"load average at start: {os.getloadavg()}")
    if a.fit:
        jobs = [(s, n, a.cache, a.store, a.plan) for s in skis for n in a.noise_um]
        with ProcessPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            for line in pool.map(fit_one, jobs):
                print(line, flush=True)
        print(f"load average at end: {os.getloadavg()}")
        return
    from band_variants import VARIANTS, profiles_of

    names = a.variants or list(VARIANTS)
    pooled: dict = {}
    print("| ski | noise µm | λ | variant | EI in band | z0 in band | EI 2sd % | z0 2sd µm "
          "| z0 rms µm |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for s, n, true, g in cached_fits(a.store, skis, a.noise_um, a.plan):
        for v in names:
            c = coverage(profiles_of(g, v), true)
            pooled.setdefault((n, v), []).append(c)
            print(f"| {s} | {n:g} | {g['lam']:g} | {v} | {c['ei_in']}/{c['ei_n']} | "
                  f"{c['z0_in']}/{c['z0_n']} | {c['ei_hw']:.1f} | {c['z0_hw']:.1f} | "
                  f"{c['z0_rms']:.1f} |", flush=True)  # fmt: skip
    print("\n| noise µm | variant | skis | EI in band | z0 in band | median EI 2sd % "
          "| median z0 2sd µm |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for (n, v), cs in sorted(pooled.items()):
        ce = sum(c["ei_in"] for c in cs) / max(sum(c["ei_n"] for c in cs), 1)
        cz = sum(c["z0_in"] for c in cs) / max(sum(c["z0_n"] for c in cs), 1)
        print(f"| {n:g} | {v} | {len(cs)} | {100 * ce:.1f} % | {100 * cz:.1f} % | "
              f"{np.median([c['ei_hw'] for c in cs]):.1f} | "
              f"{np.median([c['z0_hw'] for c in cs]):.1f} |")  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
