"""The uncertainty of a fit: GCV of its linearisation, the sandwich covariance, the bands.

λ by generalised cross-validation on the Gauss–Newton linearisation at a fit (Craven & Wahba
1979; Wahba 1990, §4.3), the Gauss–Newton (sandwich) covariance of the penalised estimate,
(JᵀJ + P)⁻¹ JᵀJ (JᵀJ + P)⁻¹ with σ-normalised residuals, and its propagation to log EI and to z0
in the rest-on-the-plane gauge (stages 4 and 6 of :mod:`skisnow.identify._fit`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from skisnow.identify._lm import _LmResult
from skisnow.identify._model import _design, _Problem
from skisnow.ski import lower_hull_bracket

__all__ = ["identified_profiles", "sandwich_covariance"]


def _gcv(sol: _LmResult, pen, lam: float):
    """GCV of the Gauss–Newton linearisation at ``sol`` with the penalty rows ``pen`` of λ
    (or ``(rows, target)``): ``(λ, GCV, misfit rms / σ, edf, step)`` (Craven & Wahba 1979;
    Wahba 1990, §4.3)."""
    pen, target = pen if isinstance(pen, tuple) else (pen, np.zeros(pen.shape[0]))
    j, r, p = sol.jac, sol.fun, sol.x
    jtj = j.T @ j
    ptp = pen.T @ pen
    a = jtj + ptp
    a_inv = np.linalg.pinv(a)
    step = -a_inv @ (j.T @ r + ptp @ p - pen.T @ target)
    rl = r + j @ step
    rss = float(rl @ rl)
    edf = float(np.trace(a_inv @ jtj))
    n = r.size
    gcv = n * rss / max(n - edf, 1.0) ** 2
    return lam, gcv, float(np.sqrt(rss / n)), edf, step


def sandwich_covariance(sol: _LmResult) -> NDArray[np.float64]:
    """The Gauss–Newton (sandwich) covariance of the parameters of the penalised fit ``sol``,
    (JᵀJ + PᵀP)⁻¹ JᵀJ (JᵀJ + PᵀP)⁻¹ (σ-normalised residuals: the covariance of p)."""
    jtj = sol.jac.T @ sol.jac
    a_inv = np.linalg.pinv(jtj + sol.pen.T @ sol.pen)
    return a_inv @ jtj @ a_inv


def identified_profiles(
    problem: _Problem,
    parameters: NDArray[np.float64],
    cov: NDArray[np.float64],
    x_tail: float,
    x_tip: float,
) -> tuple[NDArray[np.float64], ...]:
    """EI and z0 of the fitted parameters with their standard deviations.

    Returns
    -------
    tuple
        ``(ex, ei, sd_log_ei, cx, z_rest, sd_z)``: EI [N m²] and the standard deviation of
        log EI at stations ``ex`` 20 mm apart, z0 [m] resting on the plane (zero at the two
        support points of its lower convex hull) and its standard deviation at stations ``cx``
        5 mm apart.
    """
    n_stiffness = problem.n_e
    theta_e, theta_z = problem.split(parameters)
    ex = np.unique(np.concatenate([np.arange(x_tail, x_tip, 0.02), [x_tip]]))
    ei = problem.ei_at(theta_e, ex)
    be = _design(problem.t_e, ex)
    cov_e = cov[:n_stiffness, :n_stiffness]
    sd_log_ei = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", be, cov_e, be), 0.0))
    cx = np.unique(np.concatenate([np.arange(x_tail, x_tip, 0.005), [x_tip]]))
    zc = problem.z0_at(theta_z, cx)
    i, j = lower_hull_bracket(cx, zc, 0.0)
    s1, s2 = cx[i], cx[j]
    line = zc[i] + (zc[j] - zc[i]) * (cx - s1) / (s2 - s1)
    z_rest = np.maximum(zc - line, 0.0)
    bz = _design(problem.t_z, cx)
    bz_g = bz - (np.outer((s2 - cx) / (s2 - s1), bz[i]) + np.outer((cx - s1) / (s2 - s1), bz[j]))
    tz = bz_g @ problem.q_z
    cov_z = cov[n_stiffness:, n_stiffness:]
    sd_z = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", tz, cov_z, tz), 0.0))
    return ex, ei, sd_log_ei, cx, z_rest, sd_z
