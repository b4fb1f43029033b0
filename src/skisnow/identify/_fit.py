"""The fit of the ski identification: start, homotopy, Levenberg–Marquardt, GCV choice of λ, bands.

Nonlinear least squares of the bench model (:mod:`skisnow.identify._model`; Kalliorinne et
al. 2023, §3.1, eq. 1) against every profile of the bench, with the exact Jacobian:

1. Start: z0 from the lightest profile unloaded by the beam (its heights minus the deflection under
   the boot load and lever-rule reactions at the measured contact patches: all of them, or the
   outermost run on each side), at each trial constant EI, or the two lightest profiles extrapolated
   to zero load if that fits better, and the constant EI that fits all profiles best on it (grid of
   log EI, then a scalar search). Then the shape of EI(x) from the differences between load cases,
   in which z0 cancels (:func:`~skisnow.identify._start._stiffness_from_differences`: the bending
   moments of the model's contact reactions, w'' = M / EI), re-made with the new z0 and contact
   while the misfit falls, in three sequences (the lightest third, half, all of the masses); the
   best start by misfit. Its cost (the classic's full sequence, 39 load cases: 42 of 48 s before):
   the difference fit works on its normal matrices (O(n_el²) per step) and the level of log EI is
   walked from the shape's own (4-6 contact solves of every case instead of a 21-point grid): the
   same starts, 57.5 -> 17.3 s all told (10 µm, seed 4). A constant EI cannot start a ski whose EI
   varies by a factor 100 (the classic of version 2: 57-6200 N m² with a stiff spot behind the
   foot): from it every later stage stalled at 30 σ.
2. Homotopy (default start, only when the EI shape did not improve on the constant start;
   from a start near the solution it pulls the fit away: at the largest λ of the grid and with
   the smoothed stone, the classic of version 2 ended at 1.6 σ from the true EI shape, against
   1.0 σ on the exact contact directly): the load cases up to a third, then two thirds of the mass
   range, then all of them, on the smoothed stone of width ε = 10 µm, then ε = 3, 1, 0.3,
   0.1 µm (:mod:`skisnow.identify._smooth`), at the largest λ of the grid.
3. The exact contact (the LCP): a fit at the geometric middle of the λ grid.
4. λ by generalised cross-validation (GCV, Craven & Wahba 1979; Wahba 1990, §4.3) on the
   Gauss–Newton linearisation around that one fit: for every λ the penalised linear step from
   the fit, its residual sum of squares and the trace of its influence matrix; then one fit at
   the chosen λ, warm-started from that step (or from the fit if the step raises the misfit).
   Five full nonlinear fits, one per λ, cost 3-4 times more for the same choice.
5. Globalisation, only for a fit that ends above the noise: its χ² above the discrepancy bound of
   the fit's own residual degrees of freedom, dof + 2 (2 dof)^1/2 with dof = n − tr(2H − H²)
   (:func:`~skisnow.identify._homotopy.restart_bound`; a statistical stopping test: a fit at the
   data's optimum passes it with probability 97.7 %). Until 9444867 the bound was
   :func:`~skisnow.identify._resolution.at_noise_bound`, 1 + 2 (2 n)^-1/2 in the misfit, which
   leaves the ~100 parameters of the fit out (on a four-mass bench dof ≈ 1300 of n = 1400: χ² up to
   ≈ 1500, 200 above the optimum, passed); until 8427f18
   :data:`~skisnow.identify._resolution.AT_NOISE`, 1.2 (χ² ≈ 1.44 n passed): the classic's full
   sequence at 10 µm, seed 1, ended at 1.09 σ with EI 4.2 % and z0 10.6 µm off, polished 1.03 σ, the
   misfit the true ski reaches, and after the z0 refinement 0.99 σ, EI 2.1 %, z0 1.9 µm; the
   four-mass stiff ski at 10 µm 1.18 -> 0.99 σ, EI 5.6 -> 1.8 %. Why the fit stalls (measured on the
   four-mass user benches of ``benchmarks/bench_identify.py`` that ended above the noise: classic of
   version 2 at 5 µm, seed 1, 2.05 σ and 10 µm, seeds 4 and 5, 1.31 / 1.24 σ; the stiff test ski at
   5 µm, seed 1, 2.39 σ): at the heaviest load (80 kg) the ski touches the stone under the foot,
   where the measured profile lies within the noise of the stone over 45-70 mm (classic), and the
   stalled fit has that contact at the wrong node (classic: -125 mm or none, true -150 mm; stiff:
   -248 mm, true -195 mm); the Gauss–Newton decrement is below the noise there (a local minimum of
   the exact-contact misfit: classic 5 µm with 600 evaluations allowed stopped at 1.69 σ, and fits
   from the other start candidates, from random changes of log EI or by alternating z0 / EI steps
   ended at 1.68 σ or above). The remedy: the smoothed contact (:mod:`skisnow.identify._smooth`)
   restarted at the stalled fit, ε = 3, 1, 0.3, 0.1 µm at λ = 1 (15 evaluations each) and on to 30,
   10, 3, 1 nm while the smoothed stone differs from the exact contact at the polished point by more
   than the noise (:func:`~skisnow.identify._homotopy.smoothing_gap`, since 26cbb2c: where heavy
   loads press a glide zone flat, 0.1 µm is not yet the exact contact; the skate's full sequences,
   1.06-1.47 σ and EI up to 5.4 % off, then reached 0.99-1.06 σ, EI 0.95-1.55 %), then stages 3-4
   again, the lower misfit kept: a smoothing method for the complementarity (Chen & Mangasarian
   1996) started near the solution instead of at the far start of stage 2. Within the width ε the
   reaction spreads over the nodes whose gap is within ε of the stone, so the contact under the foot
   moves continuously instead of node by node. It reached the noise on all four stalled benches
   (1.00-1.07 σ; EI 2.5-9.0 % off; 1-3 s for four load cases; at λ = 0.1 or 10 instead of 1 also at
   the noise but with EI up to 7.5 % off; measured with 40 evaluations per stage), and every user
   bench of the identification table reached the noise with it (30 benches: three skis, the skate of
   version 1, 5 and 10 µm, seeds 1-5: 0.96-1.18 σ; 10 of them needed it, and reached it again with
   15 evaluations per stage). On the full sequence of the skate of version 2 at 10 µm it lowered
   1.94 to 1.15 σ (EI 4.7 % off; 1.09 σ started at the true ski); on the classic's full sequence at
   5 µm, seed 2 and 10 µm, seed 4, 9.9 and 1.6 σ to 1.17 and 1.05 σ (EI 0.8 / 0.9 % off), where it
   had not run while the smoothed Newton's stopping test ignored its roundoff floor (the 10 kg case,
   balanced to 1e-10 N, reported as not converging). Measured and not kept: coarse-to-fine in the
   number of log-EI coefficients (multiscale inversion, Bunks et al. 1995: the whole fit with 10 or
   7 coefficients, then the fine one from it) — 1.06-1.36 σ on the three stalled benches of issue
   12, needed on none of the 30 after the smoothed restart, and on a 39-case bench each route
   repeats the start (25-30 s). Where the misfit above the noise is the model's (the full sequence
   of the skate of version 1 at 5 µm: 1.93 σ, and 1.57 σ started at the true ski: the z0 spline
   cannot follow its glide hump), the restart does not lower it.
6. Bands: the Laplace posterior of the penalised estimate (:mod:`skisnow.identify._bands`,
   computed by :func:`~skisnow.identify.identify_ski` after the discretisation error).

Each stage is a Levenberg–Marquardt fit on the normal equations
(:func:`~skisnow.identify._lm.levenberg_marquardt`).
A contact solve that fails at a trial point or at an accepted one rejects that step; a smoothed
contact that fails ends the homotopy, and the fit goes on from its last point on the exact
contact (measured with the EI shape switched off, on the full bench of the classic of version 2:
misfit 2.8 σ, EI 8.8 % off, where it raised ConvergenceError before).
Used by :func:`~skisnow.identify.identify_ski`. The stages live in their own modules: the start
in :mod:`skisnow.identify._start` (1), the homotopy and the restart in
:mod:`skisnow.identify._homotopy` (2, 5), the Levenberg–Marquardt loop in
:mod:`skisnow.identify._lm`, GCV and the bands in :mod:`skisnow.identify._bands` (4, 6); here
they are put together (:func:`fit_bench`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import ConvergenceError, InputError
from skisnow.identify._bands import _evidence, _gcv
from skisnow.identify._cv import case_cv, choose
from skisnow.identify._homotopy import homotopy, polish, restart_bound
from skisnow.identify._lm import (
    _DECREMENT_TOL,
    _HOMOTOPY_TOL,
    _LmResult,
    levenberg_marquardt,
    parameter_bounds,
)
from skisnow.identify._model import _Case, _design, _Problem
from skisnow.identify._smooth import SmoothedBench
from skisnow.identify._start import _camber_fit, _zero_load_profile, default_start
from skisnow.ski import Ski

__all__ = ["BenchFit", "fit_bench"]


@dataclass(frozen=True, kw_only=True, eq=False)
class BenchFit:
    """The chosen fit of :func:`fit_bench`.

    Attributes
    ----------
    solution
        The final Levenberg–Marquardt fit at the chosen λ (parameters ``x``, residuals, Jacobian,
        ``nfev``, ``status`` > 0 when converged, ``message``).
    regularisation
        The chosen λ.
    records
        ``((λ, GCV score, misfit rms / σ, effective degrees of freedom), ...)`` of the search.
    residuals
        σ-normalised residuals of the data at the solution.
    chi2_bound
        The discrepancy bound of the solution's χ²
        (:func:`~skisnow.identify._homotopy.restart_bound`): above it the fit is
        not at the noise.
    chi2_dof
        The residual degrees of freedom behind that bound (the mean χ² at the noise).
    """

    solution: Any
    regularisation: float
    records: tuple[tuple[float, float, float, float], ...]
    residuals: NDArray[np.float64]
    chi2_bound: float
    chi2_dof: float = float("nan")


def _lowest(records: Sequence[tuple]) -> int:
    """The record of the lowest score (GCV, minus the log evidence)."""
    return int(np.argmin([rec[1] for rec in records]))


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
    start_parameters: NDArray[np.float64] | None = None,
    criterion: str = "gcv",
) -> BenchFit:
    """Fit the bench model to all load cases: start, continuation, GCV over ``lambdas`` (or the
    given ``regularisation``), the globalisation of a fit above the noise; options as in
    :func:`~skisnow.identify.identify_ski`. ``start_parameters`` (parameters of ``problem``, e.g. a
    coarser fit carried to a refined z0 basis by
    :func:`~skisnow.identify._resolution.refined_parameters`) start the fit on
    the exact contact directly, like ``initial``."""
    if criterion == "case-cv":
        score: Callable = partial(case_cv, sizes=[c.x.size for c in problem.cases])
        pick: Callable = choose
    else:
        score = _evidence if criterion == "evidence" else _gcv
        pick = _lowest
    # -- start: constant EI, z0 = the lightest profile (least squares on the z0 basis)
    if start_parameters is not None:
        z_start_x, z_start = nodes, np.zeros(nodes.size)  # unused: the start is given
    elif initial is not None:
        theta_e0 = np.linalg.lstsq(
            _design(problem.t_e, nodes), np.log(initial.stiffness(nodes)), rcond=None
        )[0]
        z_start_x, z_start = nodes, initial.free_camber(nodes)
    else:
        z_start_x, z_start = _zero_load_profile(cases)
    # full-basis fit, then drop its linear part (invisible to the bench): Q is orthonormal
    phi0 = _camber_fit(problem, z_start_x) @ z_start
    physics = False
    if start_parameters is not None:
        p = np.asarray(start_parameters, dtype=float).copy()
    elif initial is None:
        p, physics = default_start(problem, cases, phi0, say)
    else:
        p = np.concatenate([theta_e0, phi0])

    lower, upper = parameter_bounds(problem)

    smooth = SmoothedBench(problem)

    def residuals_of(lam: float, subset: list[int] | None, eps: float | None):
        pen = problem.penalty(lam)

        def residuals(pp: NDArray[np.float64], jacobian: bool):
            if eps is None:
                r, j = problem.evaluate(pp, jacobian=jacobian, cases=subset)
            else:
                r, j = smooth.evaluate(pp, eps, jacobian=jacobian, cases=subset)
            return r, j, pen

        return residuals

    def fit(
        p0: NDArray[np.float64],
        lam: float,
        subset: list[int] | None = None,
        eps: float | None = None,
        nfev: int | None = None,
    ) -> _LmResult:
        tol = _DECREMENT_TOL if eps is None else _HOMOTOPY_TOL
        return levenberg_marquardt(
            residuals_of(lam, subset, eps), p0, lower, upper, max_nfev=nfev or max_nfev, tol=tol
        )

    grid = [float(regularisation)] if regularisation is not None else [float(v) for v in lambdas]
    if any(not (np.isfinite(v) and v >= 0) for v in grid) or not grid:
        raise InputError(f"regularisation / lambdas must be finite and >= 0, got {grid}")
    lam_smooth = max(grid)
    lam0 = float(np.sqrt(max(grid) * max(min(grid), 1e-12))) if len(grid) > 1 else grid[0]

    def exact(
        p: NDArray[np.float64], lam_first: float | None = None
    ) -> tuple[_LmResult, float, tuple, int]:
        """The exact contact from ``p``: the fit at λ0 (or ``lam_first``, a λ chosen by GCV on
        the smoothed path's last fit), GCV, the fit at the chosen λ if it differs."""
        lam_a = lam0 if lam_first is None else lam_first
        sol = fit(p, lam_a)
        say(f"fit at λ = {lam_a:.3g}: misfit rms {sol.misfit_rms:.3g} σ, {sol.nfev} evaluations")
        # GCV (Craven & Wahba 1979) of the Gauss–Newton linearisation at this fit: for every λ
        # the penalised linear least-squares step from the fit, its residual sum of squares and
        # the trace of its influence matrix; then one fit at the chosen λ from that step (or
        # from the fit itself if the step raises the misfit: the linearisation does not hold
        # that far).
        records = [score(sol, problem.penalty(v), v) for v in grid]
        best = pick(records)
        lam = grid[best]
        if lam != lam_a:
            p_refit = sol.x + records[best][4]
            residuals = residuals_of(lam, None, None)

            def cost_at(pp: NDArray[np.float64]) -> float:
                try:
                    rr, _, pen = residuals(pp, False)
                except (ConvergenceError, np.linalg.LinAlgError):
                    return np.inf
                rp = pen[0] @ pp - pen[1]
                return float(rr @ rr + rp @ rp)

            if not cost_at(p_refit) <= cost_at(sol.x):
                p_refit = sol.x
            sol = fit(p_refit, lam)
            say(f"fit at λ = {lam:.3g}: misfit rms {sol.misfit_rms:.3g} σ, {sol.nfev} evaluations")
        return sol, lam, tuple(records), best

    lam_first: float | None = None
    if initial is None and start_parameters is None and not physics:
        p = homotopy(p, fit, cases, continuation, lam_smooth, say)
    else:
        # a start far above the noise (χ² above twice the bins) takes the smoothed path first:
        # on the exact contact such a start ends in a local minimum where a contact point sits
        # at the wrong wave of a flat glide zone (issue 25's ski, shop bench at 5 µm, from the
        # load-difference start at 3.7 σ: 1.05 σ after 112 evaluations, then the smoothed
        # restart and 0.93 σ; along the smoothed path first, 0.93 σ with 100 fewer)
        try:
            r0, _ = problem.evaluate(p, jacobian=False)
            far = float(r0 @ r0) > 2.0 * problem.n_data
        except (ConvergenceError, np.linalg.LinAlgError):
            far = True
        if far and start_parameters is None:
            say("start above the noise: the smoothed contact from the start")
            p, last = polish(p, fit, problem, max_nfev, say)
            if last is not None and len(grid) > 1:
                # λ by GCV on the smoothed path's last fit (its stone the exact one within
                # the noise): the exact fit then starts at the λ it will most likely keep
                lam_first = grid[pick([score(last, problem.penalty(v), v) for v in grid])]
    sol, lam, records, best = exact(p, lam_first)
    bound, dof = restart_bound(sol.jac, problem.penalty_matrix(lam), jtj=sol.jtj)
    if float(sol.fun @ sol.fun) > bound:
        # Globalisation of a fit that ends above the noise (module docstring, stage 5): the
        # smoothed contact restarted at the stalled fit, then the exact contact again; the
        # lower misfit is kept.
        p = sol.x
        say(
            f"χ² {float(sol.fun @ sol.fun):.0f} above the discrepancy bound {bound:.0f} "
            f"({dof:.0f} residual degrees of freedom): the smoothed contact from the fit"
        )
        p, _ = polish(p, fit, problem, max_nfev, say)
        trial = exact(p, lam)
        if trial[0].misfit_rms < sol.misfit_rms:
            sol, lam, records, best = trial
            bound, dof = restart_bound(sol.jac, problem.penalty_matrix(lam), jtj=sol.jtj)
    final = score(sol, problem.penalty(lam), lam)
    table = tuple(
        (rec[0], rec[1], rec[2], rec[3]) if k != best else final[:4]
        for k, rec in enumerate(records)
    )
    return BenchFit(
        solution=sol, regularisation=lam, records=table, residuals=sol.fun, chi2_bound=bound,
        chi2_dof=dof,
    )  # fmt: skip
