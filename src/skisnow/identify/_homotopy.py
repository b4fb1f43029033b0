"""The smoothed contact's paths: the homotopy from a far start and the restart of a stalled fit.

Stages 2 and 5 of :mod:`skisnow.identify._fit`: from the default start the fit runs first on
the smoothed stone (:mod:`skisnow.identify._smooth`), the light load cases, then all of them with
ε shrinking (:func:`homotopy`); a fit on the exact contact that ends above the noise
(:func:`restart_bound`) is restarted on the smoothed stone from where it stalled, ε shrinking
while the smoothed stone differs from the exact contact by more than the noise
(:func:`polish`, :func:`smoothing_gap`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import ConvergenceError
from skisnow.identify._lm import _LmResult
from skisnow.identify._model import _Case, _Problem

__all__ = ["RESTART_SIGMAS", "homotopy", "polish", "restart_bound", "smoothing_gap"]


#: Widths ε [m] of the smoothed contact (:mod:`skisnow.identify._smooth`), in turn.
_HOMOTOPY = (1e-5, 3e-6, 1e-6, 3e-7, 1e-7)

#: Widths ε [m] of the smoothed contact that polishes a fit ending above the noise, in turn.
_POLISH = (3e-6, 1e-6, 3e-7, 1e-7)

#: Further widths ε [m] of the polish, taken in turn while the smoothed stone still differs from
#: the exact contact by more than the noise at the polished point (:func:`smoothing_gap`). Where
#: a glide zone lies flat on the stone, a 0.1 µm smoothing still redistributes its reactions
#: (module docstring of :mod:`skisnow.identify._smooth`): on the skate's full sequence at 10
#: µm (seed 1) at the fit from the true ski, χ² 31675 at ε = 0.1 µm, 16343 at 10 nm, 14315 at 3
#: nm, 14037 at 1 nm against 13977 on the exact contact; a polish that ended at 0.1 µm ended
#: where the exact contact was at χ² 35671 (EI 2.5 % off), and its exact fit in a worse local
#: minimum than the one it started from (25693 after 186 evaluations, against 16397); carried
#: on to 3 nm, 14210 there, and the exact fit 14031 (EI 1.1 % off).
_POLISH_FINE = (3e-8, 1e-8, 3e-9, 1e-9)

#: λ of the smoothed polish (the exact fit after it chooses λ again by GCV; measured 0.1, 1, 10).
_POLISH_LAMBDA = 1.0

#: Evaluations per stage of the smoothed polish (a path, not an estimate): measured on the full
#: sequence of the skate of version 2 at 10 µm, seed 1, 40 per stage cost 34 s and ended at
#: 1.40 σ, 15 per stage ended at 1.15 σ in 49.5 s all told; the ten user benches that need the
#: polish ended within 0.03 σ of their misfit with 40.
_POLISH_NFEV = 15

#: Standard deviations of χ² above its mean at the optimum beyond which a fit gets the
#: smoothed-contact restart (:func:`restart_bound`): a fit at the data's optimum is restarted
#: with the probability of two standard deviations of a normal variable (2.3 %).
RESTART_SIGMAS = 2.0


def restart_bound(
    jac: NDArray[np.float64],
    pen: NDArray[np.float64],
    sigmas: float = RESTART_SIGMAS,
    *,
    jtj: NDArray[np.float64] | None = None,
) -> tuple[float, float]:
    """The discrepancy bound of the χ² of a penalised fit at its optimum (Morozov 1966, with the
    fit's own degrees of freedom): ``(bound, dof)``.

    With σ-normalised residuals r of n bins, the Jacobian J and the penalty rows P of a fit,
    the penalised Gauss–Newton linearisation is a linear smoother with influence matrix
    H = J (JᵀJ + PᵀP)⁻¹ Jᵀ, and the residual sum of squares of a fit at the data's optimum has
    the mean dof = n − tr(2H − H²) (the residual degrees of freedom, Buja, Hastie & Tibshirani
    1989; Hastie & Tibshirani 1990, §3.5; the penalty's bias left out) and the standard
    deviation (2 dof)^1/2. The bound is dof + ``sigmas`` (2 dof)^1/2. Against the bound of
    :func:`at_noise_bound` (n + 2 (2 n)^1/2 in χ²) it counts the ~100 parameters a four-mass
    bench's fit spends at λ = 0.1 (dof ≈ 1300 of 1400 bins): a local minimum of the
    exact-contact misfit with χ² 60-180 above the data's optimum sits below that bound and
    above this one (measured: the four-mass skate at 10 µm, seed 2, 1.021 σ, restarted 0.979
    σ, where the fit from the true ski ends at 1.012 σ)."""
    jtj = jac.T @ jac if jtj is None else jtj  # JᵀJ given: the fit's own (_LmResult.jtj)
    b = np.linalg.lstsq(jtj + pen.T @ pen, jtj, rcond=None)[0]  # (JᵀJ + PᵀP)⁻¹ JᵀJ
    dof = float(jac.shape[0] - 2.0 * np.trace(b) + np.sum(b * b.T))
    return dof + sigmas * np.sqrt(2.0 * max(dof, 1.0)), dof


def smoothing_gap(problem: _Problem, smoothed: _LmResult) -> float:
    """|χ²| difference between the smoothed stone and the exact contact at a smoothed fit
    (σ-normalised residuals; inf if the exact contact fails there). The smoothed model is the
    exact one within the noise when the gap is below the standard deviation of χ² at the noise,
    (2 n)^1/2 for n bins: the data cannot tell the two apart at that point."""
    try:
        r, _ = problem.evaluate(smoothed.x, jacobian=False)
    except (ConvergenceError, np.linalg.LinAlgError):
        return float("inf")
    return abs(float(r @ r) - float(smoothed.fun @ smoothed.fun))


def homotopy(
    p: NDArray[np.float64],
    fit: Callable[..., _LmResult],
    cases: list[_Case],
    continuation: Sequence[float],
    lam_smooth: float,
    say: Callable[[str], None],
) -> NDArray[np.float64]:
    """The homotopy from a far start ``p`` (stage 2 of :mod:`skisnow.identify._fit`): the
    smoothed stone's fits ``fit(p, λ, subset, eps=ε)`` at ``lam_smooth``, the light load cases
    first (``continuation``), then all of them with ε shrinking; returns the last point."""
    # Homotopy from the default start (far from the solution): the load cases up to a
    # third, then two thirds of the mass range, then all of them, with the smoothed stone
    # of width ε = 10 µm, then ε shrinking to 0.1 µm, all at the largest λ of the grid (the
    # smoothest EI). The light loads touch the stone at two short zones; heavier loads
    # flatten the glide zones onto it, where the exact contact set switches with µm
    # changes of z0 and the misfit has a kink at every switch (module docstring of
    # skisnow.identify._smooth).
    # A smoothed contact that does not converge (Newton on a far start) ends the homotopy:
    # the fit goes on from its last point on the exact contact instead of stopping.
    order = sorted({c.mass for c in cases})
    try:
        for frac in continuation:
            m_max = order[min(len(order) - 1, int(np.ceil(frac * len(order))) - 1)]
            subset = [k for k, c in enumerate(cases) if c.mass <= m_max]
            if 2 <= len(subset) < len(cases):
                p = fit(p, lam_smooth, subset, eps=_HOMOTOPY[0]).x
                say(f"continuation: load cases up to {m_max:g} kg fitted (ε = 10 µm)")
        for eps in _HOMOTOPY:
            sol = fit(p, lam_smooth, eps=eps)
            p = sol.x
            say(
                f"smoothed contact ε = {eps * 1e6:g} µm: misfit rms {sol.misfit_rms:.3g} "
                f"σ, {sol.nfev} evaluations"
            )
    except ConvergenceError as exc:
        say(f"homotopy stopped ({exc}); on to the exact contact")
    return p


def polish(
    p: NDArray[np.float64],
    fit: Callable[..., _LmResult],
    problem: _Problem,
    max_nfev: int,
    say: Callable[[str], None],
) -> tuple[NDArray[np.float64], _LmResult | None]:
    """The smoothed contact restarted at the stalled fit ``p`` (stage 5 of
    :mod:`skisnow.identify._fit`): ε = 3, 1, 0.3, 0.1 µm at λ = :data:`_POLISH_LAMBDA`, then on
    to 1 nm while the smoothed stone differs from the exact contact by more than the noise
    (:func:`smoothing_gap`); a smoothed contact that fails ends the path. Returns its last
    point and its last fit (None if none ran)."""
    smoothed = None
    try:
        for eps in _POLISH + _POLISH_FINE:
            smoothed = fit(p, _POLISH_LAMBDA, eps=eps, nfev=min(max_nfev, _POLISH_NFEV))
            p = smoothed.x
            if eps <= _POLISH[-1]:
                # the path ends where the smoothed stone is the exact one within the noise
                gap = smoothing_gap(problem, smoothed)
                if gap <= np.sqrt(2.0 * problem.n_data):
                    break
                say(f"smoothed contact ε = {eps * 1e6:g} µm: χ² {gap:.0f} off the exact")
    except ConvergenceError as exc:
        say(f"smoothed contact stopped ({exc}); on to the exact contact")
    return p, smoothed
