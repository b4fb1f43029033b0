"""Why the Laplace bands miss z0 (issue 25, fourth pass): the cost between a fit and the truth.

Run:  uv run python benchmarks/bench_band_variants.py --fit --skis 1-4 --noise-um 5 10
      uv run python benchmarks/bench_z0_landscape.py 1:10 2:5 3:10

On fits cached by ``bench_band_variants.py --fit`` (shop plan, independent 1 mm reference bench,
seeded noise), for each ski:noise:

* the linear response of the fit to its own noise, -(JᵀJ + PᵀP)⁻¹ Jᵀ ε (ε: the bench's seeded
  noise, binned like the fit's data), as the rms of z0 modulo a line, against the Laplace
  posterior's z0 standard deviation (median over the stations, line removed): what the bands
  assume the noise does;
* the penalised cost (χ² + penalty, σ-normalised) along the straight line from the fit to the
  truth projected on the fit's splines, at t = 0.25 ... 1, against the Gauss–Newton quadratic
  model at the fit: where the bands assume the cost rises.
"""

from __future__ import annotations

import pickle
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_band_variants import STORE
from bench_z0_linear_error import noise_residual, truth_parameters

from skisnow.identify._model import _design


def linear_response(g: dict, name: str, noise_um: float) -> tuple[float, float]:
    sol, pr = g["sol"], g["problem"]
    r_eps = noise_residual(g, name, noise_um)
    a = sol.jac.T @ sol.jac + sol.pen.T @ sol.pen
    dp = -np.linalg.solve(a, sol.jac.T @ r_eps)
    cx = np.linspace(-0.85, 0.85, 171)
    t = np.zeros((cx.size, dp.size))
    t[:, pr.n_e :] = _design(pr.t_z, cx) @ pr.q_z
    lin = np.stack([np.ones_like(cx), cx], 1)
    t = (np.eye(cx.size) - lin @ np.linalg.pinv(lin)) @ t
    dz = t @ dp
    sd = np.sqrt(np.einsum("ij,jk,ik->i", t, np.linalg.inv(a), t))
    return float(np.sqrt(np.mean(dz**2))), float(np.median(sd))


def scan(g: dict, name: str) -> list[tuple[float, float, float]]:
    sol, pr, lam = g["sol"], g["problem"], g["lam"]
    d = truth_parameters(pr, name) - sol.x
    p_mat, target = pr.penalty(lam)

    def cost(p: np.ndarray) -> float:
        r, _ = pr.evaluate(p, jacobian=False)
        rp = p_mat @ p - target
        return float(r @ r + rp @ rp)

    grad = sol.jac.T @ sol.fun + p_mat.T @ (p_mat @ sol.x - target)
    hess = sol.jac.T @ sol.jac + p_mat.T @ p_mat
    c0 = cost(sol.x)
    return [(t, cost(sol.x + t * d) - c0, 2 * t * grad @ d + t**2 * d @ hess @ d)
            for t in (0.25, 0.5, 0.75, 1.0)]  # fmt: skip


def main() -> None:
    print("| ski | noise µm | linear noise response of z0, rms µm | Laplace z0 sd µm | "
          "Δcost fit → truth at t = 0.25 / 0.5 / 0.75 / 1 (quadratic model) |")  # fmt: skip
    print("| --- | --- | --- | --- | --- |")
    for item in sys.argv[1:]:
        name, noise = item.split(":")
        with open(STORE / f"fit_{name}_shop_{float(noise):g}.pkl", "rb") as fh:
            g = pickle.load(fh)
        lr, sd = linear_response(g, name, float(noise))
        cells = " / ".join(f"{c:+.0f} ({q:+.0f})" for _, c, q in scan(g, name))
        print(f"| {name} | {noise} | {1e6 * lr:.1f} | {1e6 * sd:.1f} | {cells} |", flush=True)


if __name__ == "__main__":
    main()
