"""Bench plans: predicted identification uncertainty (Fisher information) against the spread of
identify_ski over noise seeds.

Run:  uv run python benchmarks/bench_bench_plan.py [--ski classic skate stiff]
      [--plan 4x1 4x2 8x1 full] [--noise-um 10] [--observe classic:4x1] [--seed 1 2 3 4 5]
      [--max-nfev 40]

For each ski × plan, ``skisnow.ski.predict_identification_uncertainty`` at the TRUE ski (the
noise-free fit of the plan's bench from the ski's spline projection; the exact Jacobian there):

* CRB: the Cramér–Rao bound (no regularisation) of EI (rms over -450…+400 mm of the standard
  deviation of log EI, %) and z0 (rms over the stations of the standard deviation of z0 modulo
  a line, µm), or "n/i" (not identifiable) with the null-space dimension;
* with the fit's penalty at the λ of the expected GCV: sd, mean error ("bias": penalty and
  spline representation), expected rms √(bias² + sd²).

For the plans in ``--observe`` (``ski:plan``), identify_ski (default start, as
``benchmarks/bench_identify.py``) on the seeded virtual benches of ``--seed``: the observed rms
over seeds of the EI and z0 rms errors (to compare with the expected rms), the rms over stations
of the per-station standard deviation over seeds (to compare with sd) and the rms of the
per-station mean error (bias; with 5 seeds it still carries sd/√5 of noise), and the misfit
range; with ``--from-truth`` also identify_ski started at the true ski on the same bench, and
Δχ² = n_bins (misfit² - misfit_truth²): positive when the default start ended in a worse local
minimum than the one next to the truth (a fault of the fit, not of the data).

Plans (the first three on the user's stations -900…+850 mm, as bench_identify's ``user``):
``4x1`` 20/40/60/80 kg at -120 mm; ``4x2`` the same at -120 and -40 mm; ``8x1`` 10…80 kg in
10 kg steps at -120 mm; ``full`` 10…130 kg in 10 kg steps at -40/-120/-200 mm, whole ski
(bench_identify's ``full``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import time

import numpy as np
from bench_identify import error_profiles, plan_bench, stiff_test_ski

from skisnow.identify import identify_ski, predict_identification_uncertainty
from skisnow.ski import get_ski

USER = (-0.900, 0.850)
PLANS: dict[str, tuple[tuple[float, ...], tuple[float, ...], tuple[float, float] | None]] = {
    "4x1": ((20, 40, 60, 80), (-0.12,), USER),
    "4x2": ((20, 40, 60, 80), (-0.12, -0.04), USER),
    "8x1": (tuple(range(10, 81, 10)), (-0.12,), USER),
    "full": (tuple(range(10, 131, 10)), (-0.04, -0.12, -0.2), None),
}


def ski_of(name: str):
    return stiff_test_ski() if name == "stiff" else get_ski(name)


def observe(true, plan: str, noise: float, seeds: list[int], max_nfev: int, n_bins: int,
            from_truth: bool) -> dict:  # fmt: skip
    masses, positions, window = PLANS[plan]
    ei, z0, misfit, seconds = [], [], [], []
    for seed in seeds:
        bench = plan_bench(true, masses, positions, window, noise, seed)
        t0 = time.perf_counter()
        res = identify_ski(bench, max_nfev=max_nfev)
        seconds.append(time.perf_counter() - t0)
        e, d = error_profiles(res.ski, true, window)
        ei.append(np.log1p(e))  # log EI error (the prediction's measure; ≈ relative)
        z0.append(d)
        misfit.append(res.misfit)
        line = (f"    seed {seed}: EI {100 * np.sqrt(np.mean(e**2)):.2f} %, z0 "
                f"{1e6 * np.sqrt(np.mean(d**2)):.1f} µm, misfit {res.misfit:.3f} σ, "
                f"{seconds[-1]:.1f} s")  # fmt: skip
        if from_truth:
            # the same bench fitted from the true ski: a lower misfit there says the default
            # start ended in a local minimum (a fault of the fit), not at the data's optimum
            tr = identify_ski(bench, initial=true, max_nfev=max_nfev)
            et, dt = error_profiles(tr.ski, true, window)
            chi2 = n_bins * (res.misfit**2 - tr.misfit**2)
            line += (f" | from the truth: EI {100 * np.sqrt(np.mean(et**2)):.2f} %, z0 "
                     f"{1e6 * np.sqrt(np.mean(dt**2)):.1f} µm, misfit {tr.misfit:.3f} σ; "
                     f"Δχ² (default - truth start) {chi2:.0f}")  # fmt: skip
        print(line, flush=True)
    ei_a, z0_a = np.array(ei), np.array(z0)

    def stats(a: np.ndarray, scale: float) -> tuple[float, float, float]:
        rms = scale * np.sqrt(np.mean(a**2))  # over seeds and stations: E[rms²]^½
        sd = scale * np.sqrt(np.mean(np.var(a, axis=0, ddof=1)))
        bias = scale * np.sqrt(np.mean(np.mean(a, axis=0) ** 2))
        return rms, sd, bias

    return {"ei": stats(ei_a, 100.0), "z0": stats(z0_a, 1e6), "misfit": (min(misfit),
            max(misfit)), "seconds": float(np.mean(seconds))}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ski", nargs="+", default=["classic", "skate", "stiff"])
    ap.add_argument("--plan", nargs="+", default=list(PLANS), choices=list(PLANS))
    ap.add_argument("--noise-um", type=float, default=10.0)
    ap.add_argument("--observe", nargs="*", default=["classic:4x1"],
                    help="ski:plan pairs fitted by identify_ski over --seed")  # fmt: skip
    ap.add_argument("--seed", nargs="+", type=int, default=[1, 2, 3, 4, 5])
    ap.add_argument("--max-nfev", type=int, default=40)
    ap.add_argument(
        "--from-truth",
        action="store_true",
        help="also fit each observed bench from the true ski (misfit comparison)",
    )
    args = ap.parse_args()
    noise = args.noise_um * 1e-6
    head = ["ski", "plan", "cases", "null", "CRB EI %", "CRB z0 µm", "λ", "EI sd %", "EI bias %",
            "EI rms %", "z0 sd µm", "z0 bias µm", "z0 rms µm", "pred s"]  # fmt: skip
    print(f"noise {args.noise_um:g} µm; predicted (Fisher information at the true ski)")
    print(" | ".join(head))
    observed = []
    for name in args.ski:
        true = ski_of(name)
        for plan in args.plan:
            masses, positions, window = PLANS[plan]
            t0 = time.perf_counter()
            r = predict_identification_uncertainty(true, masses, positions, noise,
                                                   stations=window)  # fmt: skip
            dt = time.perf_counter() - t0
            crb_e = f"{100 * r.ei_sd_crb:.2f}" if r.ei_identifiable else "n/i"
            crb_z = f"{1e6 * r.z0_sd_crb:.1f}" if r.z0_identifiable else "n/i"
            print(" | ".join([name, plan, str(r.n_cases), str(r.null_dimension), crb_e, crb_z,
                              f"{r.regularisation:g}", f"{100 * r.ei_sd:.2f}",
                              f"{100 * r.ei_bias:.2f}", f"{100 * r.ei_rms:.2f}",
                              f"{1e6 * r.z0_sd:.1f}", f"{1e6 * r.z0_bias:.1f}",
                              f"{1e6 * r.z0_rms:.1f}", f"{dt:.1f}"]), flush=True)  # fmt: skip
            if f"{name}:{plan}" in args.observe:
                observed.append((name, plan, r))
    for name, plan, r in observed:
        print(f"\nobserved: {name} {plan}, identify_ski over seeds {args.seed}")
        o = observe(ski_of(name), plan, noise, args.seed, args.max_nfev, r.n_bins,
                    args.from_truth)  # fmt: skip
        (er, es, eb), (zr, zs, zb) = o["ei"], o["z0"]
        print(f"  EI: observed rms {er:.2f} % (predicted {100 * r.ei_rms:.2f}; CRB "
              f"{100 * r.ei_sd_crb:.2f}), sd {es:.2f} % (pred {100 * r.ei_sd:.2f}), mean error "
              f"{eb:.2f} % (pred {100 * r.ei_bias:.2f})")  # fmt: skip
        print(f"  z0: observed rms {zr:.1f} µm (predicted {1e6 * r.z0_rms:.1f}; CRB "
              f"{1e6 * r.z0_sd_crb:.1f}), sd {zs:.1f} µm (pred {1e6 * r.z0_sd:.1f}), mean "
              f"error {zb:.1f} µm (pred {1e6 * r.z0_bias:.1f})")  # fmt: skip
        print(f"  misfit {o['misfit'][0]:.2f}-{o['misfit'][1]:.2f} σ, {o['seconds']:.1f} s per "
              "fit", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
