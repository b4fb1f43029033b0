"""Is the contact miss of an identified ski within the identification's own uncertainty?

Run:  uv run python benchmarks/bench_identify_uncertainty.py [--ski classic skate stiff]
      [--coverage user full] [--noise-um 10] [--seed 1 2 3 4 5] [--samples 20] [--max-nfev 40]

The contact column of ``benchmarks/bench_identify.py`` (rear/front zone length and mean pressure
at 30 and 60 kg, x_m = -120 mm, 100 MPa snow, rigid route; identified ski against the true one)
measured two ways for each ski × coverage × noise:

* over noise seeds: the signed difference [%] of each of the 8 quantities for every seed, then
  per quantity the mean over the seeds (the bias of the identification) and the standard
  deviation (its noise); a miss (> 5 %) that the seeds' spread explains is the noise of the
  bench, a mean beyond it is a systematic error;
* Gauss–Newton band (first seed): ``--samples`` parameter vectors drawn from the normal
  distribution of the fit's sandwich covariance (the one the identified ski's bands come from:
  noise only, linearised), each made into a ski and solved: the standard deviation [%] of each
  quantity. ``|difference| / sd`` above 2 says the band does not cover the error (n/a: every
  sample gave the same value, a zone length within one step of the contact grid).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import dataclasses

import numpy as np
from bench_identify import bench_of, stiff_test_ski
from bench_identify_contact import QUANTITIES, contact, differences

from skisnow import SkisnowError
from skisnow.identify import _identify as ident
from skisnow.identify import _resolution
from skisnow.identify._bands import identified_profiles
from skisnow.ski import get_ski


def identify(bench, max_nfev: int):
    """identify_ski, keeping the fit's problem and BenchFit (parameters and covariance)."""
    box: dict = {}
    orig = ident.fit_bench

    def keep(problem, cases, nodes, **kw):
        box["problem"] = problem
        box["fit"] = orig(problem, cases, nodes, **kw)
        return box["fit"]

    # the first fit is made by identify_ski, the z0 refinements by _resolution
    ident.fit_bench = _resolution.fit_bench = keep
    try:
        res = ident.identify_ski(bench, max_nfev=max_nfev)
    finally:
        ident.fit_bench = _resolution.fit_bench = orig
    return res, box["problem"], box["fit"]


def band(res, problem, fit, n: int, rng: np.random.Generator) -> list[dict]:
    ski = res.ski
    p, cov = fit.solution.x, fit.covariance
    w, v = np.linalg.eigh(0.5 * (cov + cov.T))
    root = v * np.sqrt(np.maximum(w, 0.0))
    out = []
    for _ in range(n):
        q = p + root @ rng.standard_normal(p.size)
        _, ei, _, _, z, _ = identified_profiles(problem, q, cov, ski.x_tail, ski.x_tip)
        s = dataclasses.replace(ski, stiffness_values=tuple(ei), camber_values=tuple(z),
                                stiffness_log_sd=None, camber_sd=None)  # fmt: skip
        try:
            out.append(contact(s))
        except SkisnowError as exc:  # a sample whose contact fails: said, skipped
            print(f"    sample skipped: {exc}")
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ski", nargs="+", default=["classic", "skate", "stiff"])
    ap.add_argument("--coverage", nargs="+", default=["user", "full"])
    ap.add_argument("--noise-um", type=float, default=10.0)
    ap.add_argument("--seed", nargs="+", type=int, default=[1, 2, 3, 4, 5])
    ap.add_argument("--samples", type=int, default=20)
    ap.add_argument("--max-nfev", type=int, default=40)
    args = ap.parse_args()
    names = [f"{int(m)}{z[0]}{'L' if q == 'length' else 'p'}" for m, z, q in QUANTITIES]
    print("quantities: " + " ".join(names) + " (mass kg, rear/front, length/mean pressure), %")
    for name in args.ski:
        true = stiff_test_ski() if name == "stiff" else get_ski(name)
        ref = contact(true)
        for cov in args.coverage:
            print(f"\n{name} {cov} {args.noise_um:g} µm")
            rows = []
            for k, seed in enumerate(args.seed):
                res, problem, fit = identify(bench_of(true, cov, args.noise_um * 1e-6, seed),
                                             args.max_nfev)  # fmt: skip
                d = np.array(differences(contact(res.ski), ref))
                rows.append(d)
                print(f"  seed {seed}: " + " ".join(f"{v:6.2f}" for v in d)
                      + f" | max {np.nanmax(np.abs(d)):.2f} (misfit {res.misfit:.2f} σ)",
                      flush=True)  # fmt: skip
                if k == 0 and args.samples > 0:
                    samples = band(res, problem, fit, args.samples, np.random.default_rng(seed))
                    sd = np.array([np.std([100 * (s[q] / ref[q] - 1) for s in samples], ddof=1)
                                   for q in QUANTITIES])  # fmt: skip
                    print("  GN sd  : " + " ".join(f"{v:6.2f}" for v in sd)
                          + f" | ({len(samples)} samples)")  # fmt: skip
                    # sd 0: every sample gave the same length (the contact grid's step)
                    ratio = [f"{abs(u) / v:6.2f}" if v > 0 else "   n/a"
                             for u, v in zip(d, sd, strict=True)]  # fmt: skip
                    print("  |d|/sd : " + " ".join(ratio))
            arr = np.array(rows)
            mean, sd = arr.mean(axis=0), arr.std(axis=0, ddof=1)
            print("  mean   : " + " ".join(f"{v:6.2f}" for v in mean))
            print("  sd     : " + " ".join(f"{v:6.2f}" for v in sd))
            worst = np.nanmax(np.abs(arr), axis=1)
            print(f"  worst per seed: {' '.join(f'{v:.2f}' for v in worst)}; largest |mean| "
                  f"{np.nanmax(np.abs(mean)):.2f} %", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
