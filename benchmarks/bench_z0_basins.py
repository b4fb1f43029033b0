"""Is the fit's basin the lowest one? Refits of cached fits from other starts (issue 25).

Run:  uv run python benchmarks/bench_band_variants.py --fit --skis validation 18 20 22 23 24
          --noise-um 5 10 --store ~/.cache/skisnow-hac --jobs 2      (the cached fits)
      nice -n 10 uv run python benchmarks/bench_z0_basins.py --store ~/.cache/skisnow-hac
          1001:5 1002:5 1003:5 issue25:5 1001:10 1002:10 1003:10 issue25:10 18:5 20:5 ...

On fits cached by ``bench_band_variants.py --fit`` (shop plan, independent 1 mm reference bench,
seeded noise), each fit is refitted by the fit's own machinery
(:func:`skisnow.identify._fit.fit_bench` at the fit's λ, with its problem: bins, Huber weights,
z0 resolution) from these starts:

* ``fit``: the fit itself (it should stay: the re-polish's own spread);
* ``truth``: the true ski projected on the fit's splines (a diagnostic: no user has it);
* ``mode±k``: the fit plus/minus ``--sd`` standard deviations of the k-th principal mode of the
  fit's Laplace posterior in z0 (the joint mode: the EI correlated with it moves along), the
  weakest-determined z0 directions the fit itself can generate;
* ``mode±1@Xum``: the first mode scaled to X µm rms of z0;
* ``smooth``: a fit at 100 × the z0 smoothness λ_z started at the fit (a stiffer z0 prior: a
  λ_z continuation), then the fit at the default λ_z from there.

Printed first, for each fit: the quadratic part (a bowl) of its z0 error over the determined
stations, its x² coefficient and the fit's λ. Then for each start: the final penalised cost
χ² + |P p - t|² (the fit's own objective) and its
difference from the fit's, misfit σ, EI rms % (determined stations within -450..+400 mm), z0
rms µm over the determined stations modulo the line weighted by the fit's bands (as
``bench_identify_coverage.errors``), CPU s. The question: when a start reaches a lower cost,
is its z0 error smaller?
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import json
import pickle
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_band_variants import STORE
from bench_identify_coverage import true_ski
from bench_z0_linear_error import truth_parameters

from skisnow.identify import _bands as B
from skisnow.identify._bands import _gcv
from skisnow.identify._cv import case_cv
from skisnow.identify._fit import fit_bench


def load(store: Path, name: str, noise: float) -> dict:
    with open(store / f"fit_{name}_shop_{noise:g}.pkl", "rb") as fh:
        g = pickle.load(fh)
    g["problem"].__dict__.setdefault("prior", None)
    g["problem"].__dict__.setdefault("prior_rows", None)
    return g


class Scorer:
    """Cost, misfit and errors of parameters of the cached fit's problem, weighted and masked
    by the fit's own bands (the same stations and weights for every start)."""

    def __init__(self, g: dict, name: str) -> None:
        self.g, self.pr, self.lam = g, g["problem"], g["lam"]
        sol = g["sol"]
        post = B.posterior(sol, g["model_error"], g.get("smoothing"))
        self.post = post
        prof = B.identified_profiles(self.pr, sol.x, post, g["x_tail"], g["x_tip"],
                                     bent=g["bent"], measured=g["measured"])  # fmt: skip
        self.prof = prof
        true = true_ski(name)
        self.cx, self.dz = prof.cx, prof.z_determined
        self.zt = true.free_camber(self.cx[self.dz])
        w = 1.0 / np.maximum(prof.sd_z[self.dz], 1e-7) ** 2
        a = np.stack([np.ones(int(self.dz.sum())), self.cx[self.dz]], axis=1)
        # residual-maker of the weighted line fit
        aw = a * w[:, None]
        self.line = np.eye(a.shape[0]) - a @ np.linalg.solve(a.T @ aw, aw.T)
        ex, de = prof.ex, prof.ei_determined
        self.ex_mid = ex[de & (ex >= -0.45) & (ex <= 0.40)]
        self.ei_t = true.stiffness(self.ex_mid)
        self.at(self.lam)

    def at(self, lam: float) -> Scorer:
        """Score (cost, GCV, case-CV) and refit (:func:`refit`) at ``lam`` from now on."""
        self.lam = lam
        self.p_mat, self.target = self.pr.penalty(lam)
        return self

    def z0_dev(self, p: np.ndarray) -> np.ndarray:
        _, th_z = self.pr.split(p)
        return self.line @ (self.pr.z0_at(th_z, self.cx[self.dz]) - self.zt)

    def row(self, sol) -> dict:
        p, r = sol.x, sol.fun
        rp = self.p_mat @ p - self.target
        th_e, _ = self.pr.split(p)
        ei = self.pr.ei_at(th_e, self.ex_mid)
        pen = (self.p_mat, self.target)
        a = sol.jtj + self.p_mat.T @ self.p_mat
        cost = float(r @ r + rp @ rp)
        sizes = [c.x.size for c in self.pr.cases]
        return {
            "cost": cost,
            # -2 log of the basin's Laplace mass: cost + log det A (MacKay 1992)
            "laplace": cost + float(np.linalg.slogdet(a)[1]),
            "gcv": float(_gcv(sol, pen, self.lam)[1]),
            "case_cv": float(case_cv(sol, pen, self.lam, sizes=sizes)[1]),
            "chi2": float(r @ r),
            "misfit": float(np.sqrt(np.mean(r**2))),
            "ei_rms": float(100 * np.sqrt(np.mean((ei / self.ei_t - 1) ** 2))),
            "z0_rms": float(1e6 * np.sqrt(np.mean(self.z0_dev(p) ** 2))),
        }


def posterior_modes(sc: Scorer, k: int) -> list[tuple[np.ndarray, float]]:
    """The first ``k`` principal modes of the fit's Laplace posterior in z0 (line removed, at
    the determined stations), as joint parameter steps of one standard deviation, with the z0
    rms [m] of that step."""
    pr, cov = sc.pr, sc.post.covariance
    cov = 0.5 * (cov + cov.T)
    w, v = np.linalg.eigh(cov)
    ell = v * np.sqrt(np.clip(w, 0, None))[None, :]  # cov = L Lᵀ
    from skisnow.identify._model import _design

    tz = sc.line @ (_design(pr.t_z, sc.cx[sc.dz]) @ pr.q_z)
    t_full = np.zeros((tz.shape[0], cov.shape[0]))
    t_full[:, pr.n_e :] = tz
    _, _, vt = np.linalg.svd(t_full @ ell, full_matrices=False)
    out = []
    for i in range(k):
        dp = ell @ vt[i]
        out.append((dp, float(np.sqrt(np.mean((t_full @ dp) ** 2)))))
    return out


def refit(sc: Scorer, p0: np.ndarray, lam_z: float | None = None) -> tuple:
    """The fit's own refit (its problem, at ``sc.lam``; z0's smoothness ``lam_z`` if given)
    started at ``p0``."""
    pr = sc.pr
    if lam_z is not None:
        pr.penalty = lambda lam: (pr.penalty_matrix(lam, lam_z), pr.penalty_target(lam, lam_z))
    try:
        f = fit_bench(pr, pr.cases, pr.nodes, initial=None, start_parameters=p0,
                      regularisation=sc.lam, lambdas=(sc.lam,), max_nfev=60,
                      continuation=(1 / 3, 2 / 3), say=lambda _m: None)  # fmt: skip
    finally:
        if lam_z is not None:
            del pr.penalty
    return f.solution


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("items", nargs="+", help="ski:noise_um")
    ap.add_argument("--store", default=str(STORE))
    ap.add_argument("--sd", type=float, default=3.0)
    ap.add_argument("--modes", type=int, default=2)
    ap.add_argument("--fixed-um", type=float, default=30.0)
    ap.add_argument("--out", default=None, help="append rows as JSON lines")
    a = ap.parse_args()
    print(f"load average at start: {os.getloadavg()}")
    print(
        "| ski | noise | start | cost | Δcost vs fit | Δ(−2 log Laplace mass) | GCV | "
        "case-CV | misfit σ | EI rms % | z0 rms µm | CPU s |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for item in a.items:
        name, noise = item.split(":")
        g = load(Path(a.store).expanduser(), name, float(noise))
        sc = Scorer(g, name)
        sol = g["sol"]
        base = sc.row(sol)
        d, xd = sc.z0_dev(sol.x), sc.cx[sc.dz]
        c = np.polyfit(xd, d, 2)
        q = np.polyval(c, xd)
        q = q - np.polyval(np.polyfit(xd, q, 1), xd)
        print(f"| {name} | {noise} | the fit's z0 error: its bowl (quadratic part) "
              f"{1e6 * np.sqrt(np.mean(q**2)):.1f} of {base['z0_rms']:.1f} µm rms, x² coefficient "
              f"{1e6 * c[0]:+.1f} µm/m², λ {sc.lam:g} | | | | | | | | |")  # fmt: skip
        rows = [("cached fit", base, 0.0)]
        starts = [("fit", sol.x), ("truth", truth_parameters(sc.pr, name))]
        modes = posterior_modes(sc, a.modes)
        for i, (dp, zr) in enumerate(modes, 1):
            starts += [(f"mode+{i} ({a.sd:g} sd, {a.sd * zr * 1e6:.0f} µm)", sol.x + a.sd * dp),
                       (f"mode-{i}", sol.x - a.sd * dp)]  # fmt: skip
        dp, zr = modes[0]
        s = a.fixed_um * 1e-6 / max(zr, 1e-12)
        starts += [(f"mode+1@{a.fixed_um:g}µm", sol.x + s * dp),
                   (f"mode-1@{a.fixed_um:g}µm", sol.x - s * dp)]  # fmt: skip
        for label, p0 in starts:
            t0 = time.process_time()
            try:
                s1 = refit(sc, p0)
                rows.append((label, sc.row(s1), time.process_time() - t0))
            except Exception as exc:  # a diagnostic: report, go on
                rows.append((label, {"error": repr(exc)[:80]}, time.process_time() - t0))
        t0 = time.process_time()
        try:
            s_smooth = refit(sc, sol.x, lam_z=100.0)
            s1 = refit(sc, s_smooth.x)
            rows.append(("smooth (λ_z×100, then λ_z)", sc.row(s1),
                         time.process_time() - t0))  # fmt: skip
        except Exception as exc:
            rows.append(("smooth", {"error": repr(exc)[:80]}, time.process_time() - t0))
        for label, r, cpu in rows:
            if "error" in r:
                print(f"| {name} | {noise} | {label} | {r['error']} | | | | | | | | {cpu:.1f} |")
                continue
            print(f"| {name} | {noise} | {label} | {r['cost']:.1f} | "
                  f"{r['cost'] - base['cost']:+.1f} | {r['laplace'] - base['laplace']:+.1f} | "
                  f"{r['gcv']:.5f} | {r['case_cv']:.5f} | {r['misfit']:.4f} | "
                  f"{r['ei_rms']:.2f} | {r['z0_rms']:.1f} | {cpu:.1f} |", flush=True)  # fmt: skip
            if a.out:
                with open(a.out, "a") as fh:
                    fh.write(json.dumps({"ski": name, "noise": float(noise), "start": label,
                                         **r, "cpu": cpu}) + "\n")  # fmt: skip
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
