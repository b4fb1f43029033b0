"""Is a missed identification the estimator or the fit's path? The skate's full sequence.

Run:  uv run python benchmarks/bench_identify_path.py [--noise-um 5 10] [--seed 1 2]
      [--max-nfev 40]

For the shipped skate's full bench sequence of ``benchmarks/bench_identify.py`` (10-130 kg at
-40/-120/-200 mm, seeded noise) it compares, with the public ``identify_ski`` only:

* ``default``: the default identification (start, homotopy/restart, z0 refinement 100 -> 197);
* ``default@100``: the same with ``n_camber_max=100`` (the coarse fit the refinement starts from);
* ``truth@100`` / ``truth@197``: started at the TRUE ski with 100 / 197 z0 coefficients (no
  refinement), λ by GCV: what the estimator gives from the data's optimum near the ski;
* ``truth@197 λ=…``: the same with λ fixed (the GCV choice against the EI error);
* ``fine<-default@100`` / ``fine<-truth@100``: a fit with 197 z0 coefficients started at the
  coarse identified ski of the default path / of the fit from the truth (the refinement's step
  from each coarse basin; the start is the identified ski resampled, not knot insertion).

Columns: EI rms error [%] between the glide zones (-450…+400 mm), the Gauss–Newton band of the
fit (rms over the same stations of the standard deviation of log EI, noise only), z0 rms [µm]
modulo a line, misfit [σ], χ² = n misfit², λ, n_camber. A fit whose EI error is many band
widths off while a fit from the truth reaches a lower χ² with the error inside the target is a
local minimum of the fit's path, not the estimator.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse

import numpy as np
from bench_identify import bench_of, error_profiles

from skisnow.identify import identify_ski
from skisnow.ski import get_ski


def line(tag: str, res, true) -> str:
    ei_err, d = error_profiles(res.ski, true, None)
    x = np.linspace(-0.45, 0.40, 86)
    sd = np.interp(x, res.ski.stiffness_x, res.ski.stiffness_log_sd)
    ei, band = 100 * np.sqrt(np.mean(ei_err**2)), 100 * np.sqrt(np.mean(sd**2))
    z0, chi2 = 1e6 * np.sqrt(np.mean(d**2)), res.n_bins * res.misfit**2
    return (
        f"{tag:24s} | {ei:.2f} | {band:.2f} | {z0:.1f} | {res.misfit:.3f} | {chi2:.0f}"
        f" | {res.regularisation:g} | {res.ski.provenance.detail('n_camber')}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--noise-um", nargs="+", type=float, default=[10.0])
    ap.add_argument("--seed", nargs="+", type=int, default=[1])
    ap.add_argument("--max-nfev", type=int, default=40)
    ap.add_argument("--lambdas", nargs="*", type=float, default=[0.1, 1.0, 10.0, 100.0, 1000.0])
    args = ap.parse_args()
    true = get_ski("skate")
    kw = {"max_nfev": args.max_nfev}
    print("fit | EI rms % | EI band % | z0 rms µm | misfit σ | χ² | λ | n_camber")
    for noise in args.noise_um:
        for seed in args.seed:
            print(f"# skate, full, {noise:g} µm, seed {seed}", flush=True)
            bench = bench_of(true, "full", noise * 1e-6, seed)
            fits = {
                "default": identify_ski(bench, **kw),
                "default@100": identify_ski(bench, n_camber_max=100, **kw),
                "truth@100": identify_ski(bench, initial=true, n_camber=100, n_camber_max=100,
                                          **kw),
                "truth@197": identify_ski(bench, initial=true, n_camber=197, n_camber_max=197,
                                          **kw),
            }  # fmt: skip
            for tag, res in fits.items():
                print(line(tag, res, true), flush=True)
            for lam in args.lambdas:
                res = identify_ski(bench, initial=true, n_camber=197, n_camber_max=197,
                                   regularisation=lam, **kw)  # fmt: skip
                print(line(f"truth@197 λ={lam:g}", res, true), flush=True)
            for tag in ("default@100", "truth@100"):
                res = identify_ski(bench, initial=fits[tag].ski, n_camber=197, n_camber_max=197,
                                   **kw)  # fmt: skip
                print(line(f"fine<-{tag}", res, true), flush=True)


if __name__ == "__main__":
    main()
