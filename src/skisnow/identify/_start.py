"""The start of the identification's fit: z0 unloaded from the lightest profile, EI from the
load differences (stage 1 of :mod:`skisnow.identify._fit`).

z0 from the lightest profile unloaded by the beam (its heights minus the deflection under the
boot load and lever-rule reactions at the measured contact patches: all of them, or the
outermost run on each side), at each trial constant EI, or the two lightest profiles
extrapolated to zero load if that fits better, and the constant EI that fits all profiles best
on it (grid of log EI, then a scalar search); then the shape of EI(x) from the differences
between load cases, in which z0 cancels (:func:`_stiffness_from_differences`), re-made with the
new z0 and contact while the misfit falls (:func:`default_start`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import solveh_banded
from scipy.optimize import minimize_scalar

from skisnow._errors import ConvergenceError
from skisnow.identify._lm import LOG_EI_MIN
from skisnow.identify._model import _Case, _design, _Problem
from skisnow.ski import boot_load_vector

__all__ = ["default_start"]


#: At most this many re-estimates of the EI shape from the load differences at the start.
_SHAPE_ITERATIONS = 12

#: Fractions of the bench's masses whose load differences give the EI shape, in turn.
_SHAPE_FRACTIONS = (1 / 3, 1 / 2, 1.0)


def _zero_load_profile(cases: list[_Case]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The fallback start for z0 (when a contact patch of the lightest profile is not
    measured): the two lightest profiles at the load position with the most profiles,
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


def _camber_fit(problem: _Problem, x: NDArray[np.float64]) -> NDArray[np.float64]:
    """The matrix from z0 at stations ``x`` to the z0 parameters: least squares on the spline
    basis with a weak penalty on second differences of the coefficients, which continues z0
    along a straight line beyond the stations (a minimum-norm solution would pull the
    coefficients the stations do not see to zero: an unmeasured tip then drops onto the stone
    and carries the ski), then without its linear part (invisible to the bench)."""
    a = _design(problem.t_z, x)
    d2 = np.diff(np.eye(problem.n_z), 2, axis=0)
    w = 0.1  # [-]: curvature rows of weight 0.1 against z0 rows: a start, not an estimate
    m = np.linalg.solve(a.T @ a + w**2 * d2.T @ d2, a.T)
    return problem.q_z.T @ m


def _outer_run(on: NDArray[np.bool_], x: NDArray[np.float64], first: bool) -> NDArray[np.bool_]:
    """The first (``first``) or last run of consecutive True bins of ``on`` (gaps of more than
    20 mm between the bins end a run)."""
    idx = np.flatnonzero(on)
    breaks = np.flatnonzero(np.diff(x[idx]) > 0.02)
    runs = np.split(idx, breaks + 1)
    keep = np.zeros_like(on)
    keep[runs[0] if first else runs[-1]] = True
    return keep


def _unloaded_camber(
    problem: _Problem, case: _Case, theta_e: NDArray[np.float64], outer: bool = False
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
    if outer:  # the run of contact bins farthest from the load on each side
        rear, front = _outer_run(rear, case.x, first=True), _outer_run(front, case.x, first=False)
    xr, xf = float(np.mean(case.x[rear])), float(np.mean(case.x[front]))
    rr = case.f_total * (xf - xc) / (xf - xr)
    nodes = problem.nodes
    f = case.f_boot.copy()
    for xp, rp in ((xr, rr), (xf, case.f_total - rr)):
        f -= boot_load_vector(nodes, rp, xp, 0.0, "point")  # upward
    ab, _ = problem._stiffness(theta_e)
    u = solveh_banded(ab, problem._clamp(f), check_finite=False)
    return case.h - case.hermite @ u


def _stiffness_from_differences(
    problem: _Problem,
    cases: list[_Case],
    p: NDArray[np.float64],
    fraction: float,
    lam: float = 100.0,
) -> NDArray[np.float64] | None:
    """log-EI spline coefficients from the differences between load cases (z0 cancels).

    With the contact reactions r_k of the model at ``p`` (the exact LCP of every load case),
    the bending moment M_k(x) of each case is statics (boot load and reactions, Euler–Bernoulli
    w'' = M / EI), and the difference of a case's profile and the lightest one's is

        h_k - h_1 = ∫ (x - s)₊ (M_k - M_1)(s) / EI(s) ds + α_k + β_k x,

    free of z0. It is fitted by damped Gauss–Newton in log EI (its spline, penalty λ on second
    differences of the coefficients as in the fit), the rigid terms α_k, β_k eliminated
    (variable projection). The load cases up to the ``fraction`` of the masses (all at 1): the
    light ones' contact patches are short, so the reactions of a start model are nearly
    right, while the heavy loads flatten the glide zones, where the reaction distribution
    follows µm of z0 (the caller keeps whichever fits better). Beyond the region where the
    moment differences are carried (the overhangs) log EI is continued as a constant. None if
    no contact could be solved."""
    try:
        problem.evaluate(p, jacobian=False)
    except (ConvergenceError, np.linalg.LinAlgError):
        return None
    nodes = problem.nodes
    xe = 0.5 * (nodes[1:] + nodes[:-1])
    le = np.diff(nodes)
    be = _design(problem.t_e, xe)  # (n_el, nE)
    lever = np.maximum(xe[:, None] - nodes[None, :], 0.0)  # (n_el, n)

    def moment(k: int) -> NDArray[np.float64]:
        force = cases[k].f_boot[0::2] + problem.warm[k]  # nodal forces, upward positive
        return lever @ force

    k1 = min(range(len(cases)), key=lambda k: cases[k].mass)
    m1, c1 = moment(k1), cases[k1]
    masses = sorted({c.mass for c in cases})
    m_cut = masses[min(len(masses) - 1, int(fraction * len(masses)))]
    others = [k for k in range(len(cases)) if k != k1 and cases[k].mass <= m_cut]
    if not others:
        return None
    # The rigid terms of each case are eliminated case by case (variable projection: its
    # kernel rows and data projected off the span of 1 and x at its bins); the projected
    # problem is then carried by its normal matrices alone, G = KᵀK and c = Kᵀd over the
    # elements, so every Gauss–Newton step costs O(n_el²) instead of O(n_data n_el).
    n_el = xe.size
    gram, cross, d0, info = np.zeros((n_el, n_el)), np.zeros(n_el), 0.0, np.zeros(n_el)
    for k in others:
        c = cases[k]
        inside = (c.x > c1.x.min()) & (c.x < c1.x.max())
        x, w = c.x[inside], c.w[inside] / problem.sigma_cases[k]
        dm = moment(k) - m1
        info += np.abs(dm)
        kern = w[:, None] * np.maximum(x[:, None] - xe[None, :], 0.0) * (dm * le)
        data = w * (c.h[inside] - np.interp(x, c1.x, c1.h))
        q_rig, _ = np.linalg.qr(np.stack([w, w * x], axis=1))
        kern -= q_rig @ (q_rig.T @ kern)  # the best rigid terms of this case for any EI
        data -= q_rig @ (q_rig.T @ data)
        gram += kern.T @ kern
        cross += kern.T @ data
        d0 += float(data @ data)
    pen = np.sqrt(lam) * problem.d2_e

    def cost_of(th: NDArray[np.float64]) -> float:
        wv = np.exp(-be @ th)
        return float(wv @ (gram @ wv - 2.0 * cross) + d0 + np.sum((pen @ th) ** 2))

    theta = problem.split(p)[0].copy()
    cost = cost_of(theta)
    mu = 1e-3
    for _ in range(30):
        wv = np.exp(-be @ theta)
        bw = be * wv[:, None]  # (n_el, nE): d(kernel weights)/d(-θ)
        g = -bw.T @ (gram @ wv - cross) + pen.T @ (pen @ theta)
        h = bw.T @ gram @ bw + pen.T @ pen
        improved = False
        while mu < 1e8:
            step = np.linalg.solve(h + mu * np.diag(np.diag(h)), -g)
            # an overflow guard of the start only (wider than parameter_bounds, to which the
            # fit clips its start; measured: the start at these bounds changes the fits)
            th_new = np.clip(theta + step, LOG_EI_MIN, 25.0)
            cost_new = cost_of(th_new)
            if cost_new < cost:
                theta, cost, mu, improved = th_new, cost_new, max(mu / 3, 1e-6), True
                break
            mu *= 4
        if not improved or float(-g @ step) < 1e-3:
            break
    informed = np.flatnonzero(info > 0.2 * float(info.max()))
    log_ei = be @ theta
    log_ei[: informed[0]] = log_ei[informed[0]]
    log_ei[informed[-1] + 1 :] = log_ei[informed[-1]]
    return np.linalg.lstsq(be, log_ei, rcond=None)[0]


def default_start(
    problem: _Problem,
    cases: list[_Case],
    phi0: NDArray[np.float64],
    say: Callable[[str], None],
) -> tuple[NDArray[np.float64], bool]:
    """The default start of the fit (no starting ski or parameters given): ``(parameters,
    physics)``, ``physics`` telling whether the EI shape from the load differences improved on
    the best constant EI (the fit then goes to the exact contact without the homotopy).
    ``phi0``: the z0 parameters of the zero-load profile (the fallback of the unloading)."""
    k_light = min(range(len(cases)), key=lambda k: cases[k].mass)
    light = cases[k_light]
    a_light = _camber_fit(problem, light.x)

    shape = np.zeros(problem.n_e)  # log EI about its mean (set below)

    def start(log_ei: float, unload: int, shp: NDArray | None = None) -> NDArray[np.float64]:
        theta = log_ei + (shape if shp is None else shp)
        z = _unloaded_camber(problem, light, theta, outer=unload == 2) if unload else None
        return np.concatenate([theta, phi0 if z is None else a_light @ z])

    def cost_of(pp: NDArray[np.float64]) -> float:
        try:
            r, _ = problem.evaluate(pp, jacobian=False)
        except (ConvergenceError, np.linalg.LinAlgError):
            return np.inf
        return float(r @ r)

    def misfit(log_ei: float, unload: int, shp: NDArray | None = None) -> float:
        return cost_of(start(log_ei, unload, shp))

    def unloadings(log_ei: float, shp: NDArray | None = None) -> list[float]:
        # the misfits of the three z0 unloadings (2, 1, 0) at one level; the outermost
        # runs are often all the patches: an identical start is solved once
        seen: list[tuple[NDArray[np.float64], float]] = []
        for u in (2, 1, 0):
            pu = start(log_ei, u, shp)
            same = [c for q, c in seen if np.array_equal(q, pu)]
            seen.append((pu, same[0] if same else cost_of(pu)))
        return [c for _, c in seen]

    # A constant EI: the best on its z0 (the lightest profile unloaded by the beam at that
    # EI, or, as a fallback when the unloading picks wrong contact patches, the zero-load
    # extrapolation), on a grid of log EI first (the misfit can have several minima), then
    # refined around the best grid point by a bounded scalar search.
    grid_log = np.linspace(np.log(30.0), np.log(3e4), 13)
    table = [
        (c, k, u)
        for k, v in enumerate(grid_log)
        for u, c in zip((2, 1, 0), unloadings(float(v)), strict=True)
    ]
    _, k, unload = min(table, key=lambda item: item[0])
    lo, hi = grid_log[max(k - 1, 0)], grid_log[min(k + 1, grid_log.size - 1)]
    best_log = minimize_scalar(
        lambda v: misfit(v, unload), bounds=(lo, hi), method="bounded",
        options={"xatol": 0.02},
    ).x  # fmt: skip
    p = start(float(best_log), unload)
    how = "the lightest profile unloaded" if unload else "extrapolated to zero load"
    say(f"start: constant EI {np.exp(best_log):.0f} N m², z0 {how}")
    # The shape of log EI from the differences between load cases (z0 cancels), with the
    # contact reactions of the model at the current start; the start is then re-made
    # (z0 unloaded at the new EI, the level of log EI by a walk) and the contact re-solved,
    # while the misfit falls (by more than 1 %).
    cost0 = misfit(float(best_log), unload)

    def level_search(shp: NDArray[np.float64], centre: float) -> tuple[float, float, int]:
        # The level of log EI for the shape ``shp`` and the z0 unloading: the three
        # unloadings at the shape's own level (the outermost runs are often all the
        # patches: the same start, solved once), then a walk in steps of 0.2 (up to ±0.6)
        # from the best of them while the misfit falls. Measured on the classic's full
        # sequence: the minimum over a 7-level x 3-unloading grid lay at the centre in 20
        # of 22 re-estimates, and the grid was 21 contact solves of every load case.
        costs = {(centre, u): c for u, c in zip((2, 1, 0), unloadings(centre, shp), strict=True)}
        (lvl, u_best), c_best = min(costs.items(), key=lambda item: item[1])
        for direction in (1.0, -1.0):
            moved = False
            for step in (1, 2, 3):
                v = centre + direction * 0.2 * step
                c = misfit(v, u_best, shp)
                if not c < c_best:
                    break
                lvl, c_best, moved = v, c, True
            if moved:
                break
        return c_best, lvl, u_best

    p0, best = p, (cost0, p, shape)
    for frac in _SHAPE_FRACTIONS:  # sequences on the light cases, or all of them
        p, best_cost = p0, cost0
        for _ in range(_SHAPE_ITERATIONS):
            theta = _stiffness_from_differences(problem, cases, p, frac)
            if theta is None:
                break
            shp = theta - theta.mean()
            cost, level, how_ = level_search(shp, float(theta.mean()))
            if not cost < best_cost:
                break
            p = start(level, how_, shp)
            if cost < best[0]:
                best = (cost, p, shp)
            improved, best_cost = cost < 0.99 * best_cost, cost
            if not improved:
                break
        if best_cost < cost0:
            say(
                f"start: EI from the load differences of "
                f"masses up to a fraction {frac:.2g}, misfit rms "
                f"{np.sqrt(best_cost / problem.n_data):.3g} σ"
            )
    physics = best[0] < cost0
    _, p, shape = best
    return p, physics
