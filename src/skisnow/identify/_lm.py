"""The Levenberg–Marquardt loop of the identification and the bounds of its parameters.

Used by every stage of :func:`~skisnow.identify._fit.fit_bench` and by the bench plans
(:mod:`skisnow.identify._bench_plan`); :func:`levenberg_marquardt` says why not SciPy's
``least_squares``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import cho_factor, cho_solve

from skisnow._errors import ConvergenceError
from skisnow.identify._model import _Problem

__all__ = ["LOG_EI_MAX", "LOG_EI_MIN", "levenberg_marquardt", "parameter_bounds"]


@dataclass(frozen=True, kw_only=True, eq=False)
class _LmResult:
    x: NDArray[np.float64]  #: parameters
    fun: NDArray[np.float64]  #: data residuals (σ-normalised) at x
    jac: NDArray[np.float64]  #: their Jacobian at x
    pen: NDArray[np.float64]  #: penalty rows (the penalty residual is P p - t)
    cost: float  #: ½ (|r|² + |P p - t|²)
    nfev: int
    status: int  #: 1 converged (Newton decrement), 0 evaluation limit, -1 no descent
    message: str
    pen_target: NDArray[np.float64] | None = None  #: t (None: zero)
    #: JᵀJ at x if the loop formed it there (else None: :attr:`jtj` forms it when first used)
    jtj_at_x: NDArray[np.float64] | None = None

    @property
    def target(self) -> NDArray[np.float64]:
        """The penalty's target t (zeros when none was given)."""
        return np.zeros(self.pen.shape[0]) if self.pen_target is None else self.pen_target

    @cached_property
    def jtj(self) -> NDArray[np.float64]:
        """JᵀJ of the data residuals at x, computed once per result: every λ of the GCV grid,
        the discrepancy bound, the posterior and the smoothing bias use it (on a 39-case bench
        of 16,000 bins each product is ~2 GFlop; the same numbers as computed afresh)."""
        return self.jac.T @ self.jac if self.jtj_at_x is None else self.jtj_at_x

    @property
    def misfit_rms(self) -> float:
        return float(np.sqrt(np.mean(self.fun**2)))


#: Stop when the Gauss–Newton step would lower the σ-normalised sum of squares by less than
#: this: the step is then below ~0.3 standard deviation of the estimate (Newton decrement;
#: 0.01 before issue 25: its last accepted steps moved χ² by 1-2 units in 10-40 evaluations on
#: the exact contact, whose kinks reject most trial steps near the optimum).
_DECREMENT_TOL = 0.1

#: Growth of the damping (ν of Nielsen's update) after which rejected steps end the fit: five
#: rounds of four trial points (the step and its halves) each, the damping then 2¹⁵ times its
#: value (2²⁰ before issue 25: on the exact contact near the optimum those rounds were up to 80
#: evaluations that lowered χ² by less than the tolerance).
_NU_MAX = 2.0**6

#: The same for the smoothed stages of the homotopy (only a start for the next stage).
_HOMOTOPY_TOL = 0.1

#: Upper bound of the log-EI spline coefficients (EI ≤ 1e7 N m², a thousand times a ski's
#: stiffest). Above it the clamped stiffness of a 5 mm element, 12 EI / l³, exceeds ~1e15 N/m
#: and the equilibrium's roundoff, eps ‖K‖ ‖u‖, reaches the force balance itself: with the
#: former bound 25 (EI 7e10) the fit of the classic's full sequence at 5 µm, seed 2 (the bench
#: made with noise=5e-6) drove the unseen tip overhang's coefficient there, ‖K‖ ~ 1e18, eps
#: ‖K‖ ‖u‖ ≈ 1.4 N against a 98 N load, and the smoothed contact's Newton of its 10 kg case
#: wandered at that floor (force imbalance 0.2 N, steps of 3-140 µm at the tip, no convergence
#: in 100 iterations), so the restart that lowers a stalled fit could not run: 16.0 σ, EI 30 %
#: off. With this bound: 9.9 -> 1.18 σ by the restart, 1.03 σ with the z0 refinement, EI 0.6 %.
LOG_EI_MAX = float(np.log(1e7))

#: Lower bound of the log-EI spline coefficients (EI ≥ 5e-5 N m²): keeps the steps off overflow.
LOG_EI_MIN = -10.0


def parameter_bounds(problem: _Problem) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Bounds of the fit's parameters: the log-EI spline coefficients within
    :data:`LOG_EI_MIN`…:data:`LOG_EI_MAX` (EI within about 5e-5…1e7 N m², a ski is 100–10000),
    the z0 coefficients free. They keep the numerics in range and do not make the fit plausible
    (a tighter box, 0…13.8, was tried on the stalled seed-2 bench)."""
    n_e, n_par = problem.n_e, problem.n_params
    lower = np.concatenate([np.full(n_e, LOG_EI_MIN), np.full(n_par - n_e, -np.inf)])
    upper = np.concatenate([np.full(n_e, LOG_EI_MAX), np.full(n_par - n_e, np.inf)])
    return lower, upper


def levenberg_marquardt(
    residuals: Callable[[NDArray[np.float64], bool], tuple[Any, Any, NDArray[np.float64]]],
    p0: NDArray[np.float64],
    lower: NDArray[np.float64],
    upper: NDArray[np.float64],
    *,
    max_nfev: int,
    tol: float = 1e-2,
) -> _LmResult:
    """Levenberg–Marquardt on the normal equations (Marquardt 1963; Nielsen's damping update,
    Madsen, Nielsen & Tingleff 2004, §3.2), steps projected onto the bounds.

    ``residuals(p, jacobian)`` returns the σ-normalised data residuals, their Jacobian (or
    None) and the penalty rows P (the penalty residual is P p), or ``(P, t)`` (the penalty
    residual is P p - t: a prior with a mean). The Jacobian is evaluated only
    at accepted points; trial points cost one residual evaluation.

    Why not ``scipy.optimize.least_squares``: its trust-region solvers factor the m × n
    Jacobian (SVD for ``trf``, QR for ``lm``) at every iteration; with tens of thousands of
    bench residuals and ~110 parameters that factorisation took 40 % of a full-bench fit
    (cProfile), while JᵀJ (n × n) is one product and each damped step a small solve. Its
    stopping tests are also relative, while here the natural scale is known: residuals are in
    units of the noise, so the fit stops when the Gauss–Newton step would lower the sum of
    squares by less than ``tol`` (the step is then a small fraction of the estimate's standard
    deviation), or after two accepted steps that lowered it by less than ``tol``. And on the
    exact contact a rejected step is often one that crossed a kink of the contact set: it is
    halved along its direction (down to 1/8) before the damping grows: on the full bench of
    the first-release classic (``benchmarks/bench_identify.py``, 40 evaluations per stage) the
    fit then reached 0.90 σ misfit and EI within 0.5 % rms, where raising the damping alone
    stalled at 0.94 σ with EI 8.8 % off.
    """
    p = np.clip(p0, lower, upper)
    r, j, pen = residuals(p, True)
    pen, target = pen if isinstance(pen, tuple) else (pen, np.zeros(pen.shape[0]))
    nfev = 1

    def cost_of(rr: NDArray[np.float64], pp: NDArray[np.float64]) -> float:
        rp = pen @ pp - target
        return 0.5 * float(rr @ rr + rp @ rp)

    cost = cost_of(r, p)
    ptp = pen.T @ pen
    pt = pen.T @ target
    mu, nu = -1.0, 2.0
    small_steps = 0  # consecutive accepted steps that lowered the sum of squares by < tol
    status, message = 0, "evaluation limit reached"
    jtj_at: tuple[Any, Any] = (None, None)  # (J, JᵀJ) of the last normal matrix formed
    while nfev < max_nfev:
        jtj = j.T @ j
        jtj_at = (j, jtj)
        a = jtj + ptp
        g = j.T @ r + ptp @ p - pt
        dscale = np.maximum(np.diag(a), 1e-12 * max(float(np.max(np.diag(a))), 1e-300))
        if mu < 0:
            mu = 1e-3 * float(np.max(np.diag(a) / dscale))
        # Newton decrement of the undamped step: predicted decrease of the sum of squares
        gn = _solve_spd(a, -g)
        if float(-g @ gn) < tol or small_steps >= 2:
            status, message = 1, "converged: Gauss–Newton step below the noise"
            break
        accepted = False
        while nfev < max_nfev:
            full = _solve_spd(a + mu * np.diag(dscale), -g)
            # the damped step, then (on a kink of the contact set) halves of it along the same
            # direction, before the damping grows
            for alpha in (1.0, 0.5, 0.25, 0.125):
                p_new = np.clip(p + alpha * full, lower, upper)
                step = p_new - p
                predicted = -(g @ step) - 0.5 * step @ a @ step
                nfev += 1
                try:
                    r_new, _, _ = residuals(p_new, False)
                    cost_new = cost_of(r_new, p_new)
                except (ConvergenceError, np.linalg.LinAlgError):  # a failed solve: reject
                    cost_new = np.inf
                rho = (cost - cost_new) / max(predicted, 1e-300)
                if (predicted > 0 and rho > 1e-4) or nfev >= max_nfev:
                    break
            if predicted > 0 and rho > 1e-4:
                try:  # the Jacobian at the accepted point (a failed solve: reject the step)
                    r_acc, j_acc, _ = residuals(p_new, True)
                except (ConvergenceError, np.linalg.LinAlgError):
                    r_acc = None
                if r_acc is not None:
                    if alpha == 1.0:
                        mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
                        nu = 2.0
                    small_steps = small_steps + 1 if 2.0 * (cost - cost_new) < tol else 0
                    p, r, j = p_new, r_acc, j_acc
                    cost = cost_of(r, p)
                    accepted = True
                    break
            if predicted < tol:  # the damped step can no longer lower the misfit
                nu = 2.0**21  # by a meaningful amount: at the optimum within the model's noise
                break
            mu *= nu
            nu *= 2.0
            if nu > _NU_MAX:
                break
        if not accepted:
            if nu > _NU_MAX:
                status, message = 1, "converged: no damped step lowers the misfit"
            break
    return _LmResult(
        x=p, fun=r, jac=j, pen=pen, cost=cost, nfev=nfev, status=status, message=message,
        pen_target=target, jtj_at_x=jtj_at[1] if jtj_at[0] is j else None,
    )  # fmt: skip


def _solve_spd(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    try:
        return cho_solve(cho_factor(a, check_finite=False), b, check_finite=False)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(a, b, rcond=None)[0]
