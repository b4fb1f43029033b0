"""Where the z0 error of a fit comes from, linearly (issue 25, seventh pass: the default bands).

Run:  uv run python benchmarks/bench_band_variants.py --fit --skis validation --noise-um 5
          --store DIR
      uv run python benchmarks/bench_z0_linear_error.py --store DIR 1002:5 issue25:5

On fits cached by ``bench_band_variants.py --fit`` (shop plan, independent 1 mm reference bench,
seeded noise): the truth projected on the fit's splines, p_t, and the penalised Gauss–Newton
step from it on the noisy bench, p_lin = p_t - A_t⁻¹ (J_tᵀ r(p_t) + Pᵀ(P p_t - t)), split into
the parts of the seeded noise (r_ε), of the model error at the truth (r_clean(p_t): the
reference bench against the fit's beam at the projected truth, basis error included) and of the
prior (the penalty's pull). Printed: z0 rms (µm, modulo the weighted line, over the determined
stations) of the fit's error, of the linear prediction's error and of each part, the Laplace z0
sd (median), the rms of the model error at the truth (µm) and the share of it common to all load
cases at the same station (what z0 absorbs: invisible in the fit's residuals, whose cross-case
correlation at a station is about -1/(K-1)), and the penalised cost χ² + |P p - t|² at the
projected truth and at the linear prediction minus the fit's: negative means the fit is a
local minimum above one near the truth.
"""

from __future__ import annotations

import argparse
import pickle
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_band_variants import STORE
from bench_identify_coverage import bench_of, true_ski

from skisnow.bench import read_bench
from skisnow.identify import _bands as B
from skisnow.identify._cases import _bench_cases
from skisnow.identify._model import _design

CACHE = Path.home() / ".cache" / "skisnow-identify-bench"


def truth_parameters(pr, name: str) -> np.ndarray:
    """The true ski in the fit's own basis: log EI and z0 (modulo a line, which the bench
    cannot see) projected by least squares on 2000 points between the fit's outer nodes."""
    true = true_ski(name)
    x = np.linspace(pr.nodes[0], pr.nodes[-1], 2000)
    th_e = np.linalg.lstsq(_design(pr.t_e, x), np.log(true.stiffness(x)), rcond=None)[0]
    bz = _design(pr.t_z, x) @ pr.q_z
    lin = np.stack([np.ones_like(x), x], 1)
    th_z = np.linalg.lstsq(np.hstack([bz, lin]), true.free_camber(x), rcond=None)[0]
    return np.concatenate([th_e, th_z[: bz.shape[1]]])


def noise_residual(g, name, noise_um):
    """The seeded noise as σ-normalised residuals of the fit's bins (r = r_clean + r_ε)."""
    pr = g["problem"]
    noisy = bench_of(name, "shop", noise_um, CACHE)
    clean = read_bench(CACHE / f"ref_{name}_shop_1mm.csv")
    lab = noisy.ski_name(None)
    res = []
    for k, (rn, rc) in enumerate(zip(_bench_cases(noisy, lab), _bench_cases(clean, lab),
                                     strict=True)):  # fmt: skip
        c, x, e = pr.cases[k], rn[2], rn[3] - rc[3]
        idx = np.abs(x[:, None] - c.x[None, :]).argmin(1)
        eb = np.bincount(idx, e, c.x.size) / np.maximum(np.bincount(idx, None, c.x.size), 1)
        res.append(-c.w * pr.bin_weights[k] * eb / pr.sigma_cases[k])
    return np.concatenate(res)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("items", nargs="+", help="ski:noise_um")
    ap.add_argument("--store", default=str(STORE))
    a = ap.parse_args()
    print(
        "| ski | noise µm | fit z0 err | linear pred. err | noise part | model-error part | "
        "prior part | Laplace z0 sd | model error at truth µm rms | common to all cases | "
        "Δcost truth / linear pred. − fit | of the truth's: Δχ² / Δpenalty |"
    )
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for item in a.items:
        name, noise = item.split(":")
        with open(Path(a.store) / f"fit_{name}_shop_{float(noise):g}.pkl", "rb") as fh:
            g = pickle.load(fh)
        g["problem"].__dict__.setdefault("prior", None)
        g["problem"].__dict__.setdefault("prior_rows", None)
        sol, pr, lam = g["sol"], g["problem"], g["lam"]
        p_t = truth_parameters(pr, name)
        r_t, j_t = pr.evaluate(p_t, jacobian=True)
        r_eps = noise_residual(g, name, float(noise))
        r_clean = r_t - r_eps
        p_mat, target = pr.penalty(lam)
        a_t = j_t.T @ j_t + p_mat.T @ p_mat
        parts = {
            "noise": -np.linalg.solve(a_t, j_t.T @ r_eps),
            "model": -np.linalg.solve(a_t, j_t.T @ r_clean),
            "prior": -np.linalg.solve(a_t, p_mat.T @ (p_mat @ p_t - target)),
        }
        # z0 at the stations, modulo the line weighted by the Laplace band, determined only
        post = B.posterior(sol, g["model_error"])
        prof = B.identified_profiles(pr, sol.x, post, g["x_tail"], g["x_tip"],
                                     bent=g["bent"], measured=g["measured"])  # fmt: skip
        cx, dz = prof.cx, prof.z_determined
        tz = _design(pr.t_z, cx[dz]) @ pr.q_z
        w = 1 / np.maximum(prof.sd_z[dz], 1e-9)
        lz = np.stack([np.ones(int(dz.sum())), cx[dz]], 1)
        proj = np.eye(lz.shape[0]) - lz @ np.linalg.pinv(lz * w[:, None]) * w[None, :]

        def z_rms(dp, proj=proj, tz=tz, n_e=pr.n_e):
            return 1e6 * float(np.sqrt(np.mean((proj @ (tz @ dp[n_e:])) ** 2)))

        dfit = sol.x - p_t
        dlin = sum(parts.values())

        def cost(p, pr=pr, p_mat=p_mat, target=target):
            r, _ = pr.evaluate(p, jacobian=False)
            rp = p_mat @ p - target
            return float(r @ r + rp @ rp)

        c_fit = cost(sol.x)
        dc_lin, dc_true = cost(p_t + dlin) - c_fit, cost(p_t) - c_fit
        # the truth's excess split: the data's χ² and the penalty's
        pen_t, pen_f = (float(np.sum((p_mat @ q - target) ** 2)) for q in (p_t, sol.x))
        dpen = pen_t - pen_f
        # the model error in heights, and its part common to all cases at a station
        sizes = [c.x.size for c in pr.cases]
        hs = np.split(r_clean, np.cumsum(sizes)[:-1])
        hs = [h * pr.sigma_cases[k] / np.maximum(c.w * pr.bin_weights[k], 1e-12)
              for k, (h, c) in enumerate(zip(hs, pr.cases, strict=True))]  # fmt: skip
        keys = np.concatenate([np.round(c.x * 1e4).astype(int) for c in pr.cases])
        allh = np.concatenate(hs)
        _, inv = np.unique(keys, return_inverse=True)
        mean_at = np.bincount(inv, allh) / np.bincount(inv)
        common = mean_at[inv]
        share = float(np.sum(common**2) / max(np.sum(allh**2), 1e-30))
        print(
            f"| {name} | {noise} | {z_rms(dfit):.1f} | {z_rms(dlin):.1f} | "
            f"{z_rms(parts['noise']):.1f} | {z_rms(parts['model']):.1f} | "
            f"{z_rms(parts['prior']):.1f} | {1e6 * np.median(prof.sd_z[dz]):.1f} | "
            f"{1e6 * np.sqrt(np.mean(allh**2)):.2f} | {100 * share:.0f} % | "
            f"{dc_true:+.0f} / {dc_lin:+.0f} | {dc_true - dpen:+.0f} / {dpen:+.0f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
