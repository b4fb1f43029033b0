"""λ chosen on each λ's own nonlinear fit: does any data-only criterion pick a better z0?

Run:  nice -n 10 uv run python benchmarks/bench_z0_lambda.py --store ~/.cache/skisnow-hac
          1001:5 1002:5 1003:5 issue25:5 ...

Issue 25, ninth pass (the estimator-side test after ``bench_z0_basins.py``). The default fit
chooses λ by GCV on the Gauss–Newton linearisation at *one* fit (at the grid's middle λ); the z0
errors of the shop fits are mostly a bowl (a quadratic z0 mode) whose sign follows the chosen λ.
Here each cached fit (``bench_band_variants.py --fit``) is refitted
(``bench_z0_basins.refit``) at every λ of the default grid, started at the fit, and
each criterion is evaluated at that λ's *own* fit: GCV (Craven & Wahba 1979), the Laplace
evidence (MacKay 1992), leave-one-load-case-out CV with the one-standard-error rule (Rice &
Silverman 1991); errors as in ``bench_z0_basins.py`` (the fit's determined stations and band
weights). Printed per ski: each λ's misfit, EI rms %, z0 rms µm and scores, then the λ each
criterion picks and its z0 / EI error against the default fit's and the best λ's (the
oracle: knowing the truth).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_band_variants import STORE
from bench_z0_basins import Scorer, load, refit

from skisnow.identify._bands import _evidence
from skisnow.identify._cv import case_cv, choose
from skisnow.identify._result import DEFAULT_LAMBDAS


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("items", nargs="+", help="ski:noise_um")
    ap.add_argument("--store", default=str(STORE))
    ap.add_argument("--out", default=None, help="append rows as JSON lines")
    a = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    summary = []
    for item in a.items:
        name, noise = item.split(":")
        g = load(Path(a.store).expanduser(), name, float(noise))
        sc = Scorer(g, name)
        pr, x0 = sc.pr, g["sol"].x
        sizes = [c.x.size for c in pr.cases]
        rows = []
        for lam in DEFAULT_LAMBDAS:
            t0 = time.process_time()
            sol = refit(sc.at(lam), x0)
            pen = (sc.p_mat, sc.target)
            r = sc.row(sol)
            r.update(lam=lam, evidence=float(_evidence(sol, pen, lam)[1]),
                     cv_record=case_cv(sol, pen, lam, sizes=sizes),
                     cpu=time.process_time() - t0)  # fmt: skip
            rows.append(r)
            print(f"| {name} | {noise} | {lam:g} | {r['misfit']:.4f} | {r['ei_rms']:.2f} | "
                  f"{r['z0_rms']:.1f} | {r['gcv']:.5f} | {r['evidence']:.1f} | "
                  f"{r['case_cv']:.4f} | {r['cpu']:.1f} |", flush=True)  # fmt: skip
        picks = {
            "gcv": int(np.argmin([r["gcv"] for r in rows])),
            "evidence": int(np.argmin([r["evidence"] for r in rows])),
            "case-cv": choose([r["cv_record"] for r in rows]),
            "oracle z0": int(np.argmin([r["z0_rms"] for r in rows])),
        }
        base = sc.row(g["sol"])
        line = {"ski": name, "noise": float(noise), "default_lam": g["lam"],
                "default_z0": base["z0_rms"], "default_ei": base["ei_rms"]}  # fmt: skip
        for k, i in picks.items():
            line[k] = (rows[i]["lam"], rows[i]["z0_rms"], rows[i]["ei_rms"])
        summary.append(line)
        if a.out:
            with open(a.out, "a") as fh:
                fh.write(json.dumps(line) + "\n")
    print("\n| ski | noise | default: λ, z0 µm, EI % | GCV at own fits | evidence | case-CV (1-se) "
          "| oracle (best z0) |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for s in summary:
        cells = " | ".join(f"{s[k][0]:g}: {s[k][1]:.1f} µm, {s[k][2]:.1f} %"
                           for k in ("gcv", "evidence", "case-cv", "oracle z0"))  # fmt: skip
        print(f"| {s['ski']} | {s['noise']:g} | {s['default_lam']:g}: {s['default_z0']:.1f} µm, "
              f"{s['default_ei']:.1f} % | {cells} |")  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
