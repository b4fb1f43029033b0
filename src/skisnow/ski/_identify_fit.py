"""The fit of the ski identification: start, continuation in load, GCV choice of λ, bands.

Nonlinear least squares of the bench model (:mod:`skisnow.ski._identify_model`; Kalliorinne et
al. 2023, §3.1, eq. 1) against every profile of the bench, by SciPy's trust-region reflective
least squares (``scipy.optimize.least_squares``) with the exact Jacobian. The start is z0 from
the two lightest profiles extrapolated to zero load and the best constant EI on it; the load
cases up to a third, then two thirds of the mass range are fitted first (continuation); λ is
chosen by generalised cross-validation (GCV, Craven & Wahba 1979) on the Gauss–Newton
linearisation at each fit; the bands are the Gauss–Newton (sandwich) covariance of the penalised
estimate, (JᵀJ + P)⁻¹ JᵀJ (JᵀJ + P)⁻¹, propagated to log EI and to z0 in the rest-on-the-plane
gauge. Used by :func:`~skisnow.ski.identify_ski`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import solveh_banded
from scipy.optimize import least_squares, minimize_scalar

from skisnow._errors import InputError
from skisnow.ski._fem import boot_load_vector
from skisnow.ski._identify_model import _Case, _design, _Problem
from skisnow.ski._lcp import lower_hull_bracket
from skisnow.ski._skis import Ski

__all__ = ["BenchFit", "fit_bench", "identified_profiles"]


@dataclass(frozen=True, kw_only=True, eq=False)
class BenchFit:
    """The chosen fit of :func:`fit_bench`.

    Attributes
    ----------
    solution
        SciPy's ``OptimizeResult`` of the final least-squares fit at the chosen λ.
    regularisation
        The chosen λ.
    records
        ``((λ, GCV score, misfit rms / σ, effective degrees of freedom), ...)`` of the search.
    covariance
        Gauss–Newton (sandwich) covariance of the parameters (σ-normalised residuals).
    residuals
        σ-normalised residuals of the data at the solution.
    """

    solution: Any
    regularisation: float
    records: tuple[tuple[float, float, float, float], ...]
    covariance: NDArray[np.float64]
    residuals: NDArray[np.float64]


def _zero_load_profile(cases: list[_Case]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A start for z0: the two lightest profiles at the load position with the most profiles,
    extrapolated linearly to zero load station by station (the deflection grows about linearly
    with the load while the contact set changes little; the rigid part is the gauge)."""
    positions = [c.position for c in cases]
    pos = max(set(positions), key=positions.count)
    at = sorted((c for c in cases if c.position == pos), key=lambda c: c.mass)
    if len(at) < 2:
        light = min(cases, key=lambda c: c.mass)
        return light.x, light.h
    a, b = at[0], at[1]
    hb = np.interp(a.x, b.x, b.h)
    return a.x, a.h - a.mass * (hb - a.h) / (b.mass - a.mass)


def _unloaded_camber(
    problem: _Problem, case: _Case, theta_e: NDArray[np.float64]
) -> NDArray[np.float64] | None:
    """z0 at the bins of ``case`` (a light load): its profile minus the deflection of the beam
    with stiffness ``theta_e`` under the boot load and two point reactions at the centroids of
    the measured contact patches behind and in front of the load (lever rule). None if a
    patch is not measured."""
    thr = float(np.min(case.h)) + 3.0 * problem.sigma
    xc = case.m_total / case.f_total
    on = case.h <= thr
    rear, front = on & (case.x < xc), on & (case.x > xc)
    if not rear.any() or not front.any():
        return None
    xr, xf = float(np.mean(case.x[rear])), float(np.mean(case.x[front]))
    rr = case.f_total * (xf - xc) / (xf - xr)
    nodes = problem.nodes
    f = case.f_boot.copy()
    for xp, rp in ((xr, rr), (xf, case.f_total - rr)):
        f -= boot_load_vector(nodes, rp, xp, 0.0, "point")  # upward
    ab, _ = problem._stiffness(theta_e)
    u = solveh_banded(ab, problem._clamp(f), check_finite=False)
    return case.h - case.hermite @ u


def fit_bench(
    problem: _Problem,
    cases: list[_Case],
    nodes: NDArray[np.float64],
    *,
    initial: Ski | None,
    regularisation: float | None,
    lambdas: Sequence[float],
    max_nfev: int,
    continuation: Sequence[float],
    say: Callable[[str], None],
) -> BenchFit:
    """Fit the bench model to all load cases: start, continuation, GCV over ``lambdas`` (or the
    given ``regularisation``); options as in :func:`~skisnow.ski.identify_ski`."""
    n_stiffness, n_camber = problem.n_e, problem.n_z
    # -- start: constant EI, z0 = the lightest profile (least squares on the z0 basis)
    if initial is not None:
        theta_e0 = np.linalg.lstsq(
            _design(problem.t_e, nodes), np.log(initial.stiffness(nodes)), rcond=None
        )[0]
        z_start_x, z_start = nodes, initial.free_camber(nodes)
    else:
        z_start_x, z_start = _zero_load_profile(cases)
    # full-basis fit, then drop its linear part (invisible to the bench): Q is orthonormal
    a_z = _design(problem.t_z, z_start_x)
    c_z = np.linalg.lstsq(a_z, z_start, rcond=None)[0]
    phi0 = problem.q_z.T @ c_z
    if initial is None:
        light = min(cases, key=lambda c: c.mass)
        a_light = problem.q_z.T @ np.linalg.pinv(_design(problem.t_z, light.x))

        def start(log_ei: float) -> NDArray[np.float64]:
            theta = np.full(n_stiffness, log_ei)
            z = _unloaded_camber(problem, light, theta)
            return np.concatenate([theta, phi0 if z is None else a_light @ z])

        # a constant EI: the best on this z0, by a bounded scalar search of log EI
        def misfit(log_ei: float) -> float:
            r, _ = problem.evaluate(start(log_ei), jacobian=False)
            return float(r @ r)

        best_log = minimize_scalar(
            misfit, bounds=(np.log(30.0), np.log(3e4)), method="bounded",
            options={"xatol": 0.02},
        ).x  # fmt: skip
        p = start(float(best_log))
        say(f"start: constant EI {np.exp(best_log):.0f} N m², z0 extrapolated to zero load")
    else:
        p = np.concatenate([theta_e0, phi0])

    # EI between 1 and 1e6 N m² (a ski is 100-10000): keeps the trust region off overflow
    lower = np.concatenate([np.full(n_stiffness, -10.0), np.full(n_camber - 2, -np.inf)])
    upper = np.concatenate([np.full(n_stiffness, 25.0), np.full(n_camber - 2, np.inf)])

    def fit(
        p0: NDArray[np.float64], lam: float, subset: list[int] | None = None, nfev: int = max_nfev
    ):
        pen = problem.penalty_matrix(lam)

        def fun(pp):
            r, _ = problem.evaluate(pp, jacobian=False, cases=subset)
            return np.concatenate([r, pen @ pp])

        def jac(pp):
            _, j = problem.evaluate(pp, jacobian=True, cases=subset)
            return np.concatenate([j, pen], axis=0)

        sol = least_squares(
            fun, p0, jac=jac, method="trf", bounds=(lower, upper), max_nfev=nfev,
            x_scale="jac",
        )  # fmt: skip
        if subset is not None:
            return sol
        r, j = problem.evaluate(sol.x, jacobian=True)
        jtj = j.T @ j
        ptp = pen.T @ pen
        a_inv = np.linalg.pinv(jtj + ptp)
        edf = float(np.trace(a_inv @ jtj))
        rss = float(r @ r)
        gcv = problem.n_data * rss / max(problem.n_data - edf, 1.0) ** 2
        return sol, gcv, rss, edf, a_inv, jtj, r

    records, fits = [], []
    grid = [float(regularisation)] if regularisation is not None else [float(v) for v in lambdas]
    if any(not (np.isfinite(v) and v >= 0) for v in grid) or not grid:
        raise InputError(f"regularisation / lambdas must be finite and >= 0, got {grid}")
    # Continuation in load: the light loads touch the stone at two short zones (the fit is
    # smooth there); heavier loads flatten the glide zones onto the stone, where the contact
    # set reacts to small changes of z0 and the misfit has kinks. Fitting the load cases up to
    # a third, then two thirds of the mass range first brings the contact sets close before
    # the whole sequence is fitted.
    order = sorted({c.mass for c in cases})
    for frac in continuation:
        m_max = order[min(len(order) - 1, int(np.ceil(frac * len(order))) - 1)]
        subset = [k for k, c in enumerate(cases) if c.mass <= m_max]
        if 2 <= len(subset) < len(cases):
            p = fit(p, grid[0], subset).x
            say(f"continuation: load cases up to {m_max:g} kg fitted")
    for lam in grid:  # each further λ starts from the previous fit
        sol, gcv, rss, edf, a_inv, jtj, r = fit(p, lam)
        records.append((lam, gcv, float(np.sqrt(rss / problem.n_data)), edf))
        fits.append((sol, a_inv, jtj, r))
        p = fits[int(np.argmin([rec[1] for rec in records]))][0].x  # next λ from the best
        say(f"λ = {lam:.3g}: GCV {gcv:.4g}, misfit rms {records[-1][2]:.3g} σ, edf {edf:.1f}")
    best = int(np.argmin([rec[1] for rec in records]))
    lam = records[best][0]
    sol, a_inv, jtj, r = fits[best]
    cov = a_inv @ jtj @ a_inv  # σ-normalised residuals: the covariance of p
    return BenchFit(
        solution=sol, regularisation=lam, records=tuple(records), covariance=cov, residuals=r
    )


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
