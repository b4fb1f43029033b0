"""An edge-preserving smoothness penalty on log EI: a Huber loss on its second differences.

The fit's quadratic penalty λ |D₂ θ_E|² (:meth:`skisnow.identify._model._Problem.penalty_matrix`)
costs a stiffness step ×2.5 over 25 mm (issue 25's ski at -450 and -120 mm: second differences
of its log-EI coefficients up to 2.5, against 0.02-0.2 along the smooth stretches of a ski) as
much as a wide bump of the same area, so at the λ that GCV chooses for the smooth stretches the
steps are smeared (the smoothing bias of the third and fourth passes). Here each penalty row
e_i = √λ (D₂ θ_E)_i — read as a prior, the standardised increment of log EI's curvature —
counts with the Huber loss (Huber 1964) of scale ``c``: quadratic below c, linear above it, so a
few large rows (an edge, a heavy-tailed prior's outlier) cost little more than their size while
the many small ones keep the quadratic penalty — the edge-preserving regularisation of image
restoration (Charbonnier et al. 1997; for the total-variation limit, Vogel & Oman 1996, §2,
"lagged diffusivity"). The scale is in the prior's standard deviations, so it means the same at
every λ (a scale on D₂ θ_E itself: where GCV chose a large λ the quadratic fit's second
differences all lie below it, and the Huber fit is the quadratic one). It is solved by
iteratively reweighted least squares (Holland & Welsch 1977): from the quadratic fit, the rows'
weights w_i = min(1, c / |e_i|) are frozen, the fit is made again at them (the same
Levenberg–Marquardt; the penalty stays linear in p, so the Laplace bands and GCV read the
reweighted penalty as the prior's precision), for at most :data:`MAX_ROUNDS` rounds or until no
weight moves by more than :data:`WEIGHT_TOL`. Measured on a linear stand-in (the coefficients
observed directly, a ×2.5 step, ``tests/identify/test_edges.py``): the error next to the step
0.095 → 0.044 at λ = 100, 0.157 → 0.083 at 10³, 0.217 → 0.157 at 10⁴ with c = 1, iterated to
convergence (0.155 → 0.106 at 10³ in the three rounds used here); a smooth stiffness unchanged.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow.identify._model import _Problem

__all__ = ["EDGE_SCALE", "MAX_ROUNDS", "edge_refit", "edge_weights"]

#: Refits of the reweighting at most.
MAX_ROUNDS = 3

#: Stop when no square-root weight moves by more than this.
WEIGHT_TOL = 0.05

#: The Huber scale c of the log-EI smoothness rows √λ D₂ θ_E, in the prior's standard
#: deviations (module docstring).
EDGE_SCALE = 1.0


def edge_weights(
    problem: _Problem, theta_e: NDArray[np.float64], lam: float, scale: float
) -> NDArray[np.float64]:
    """The square roots of the Huber weights min(1, c / |√λ (D₂ θ_E)_i|) of the log-EI
    smoothness rows at the coefficients ``theta_e`` and λ."""
    e = np.sqrt(lam) * np.abs(problem.d2_e @ theta_e)
    return np.sqrt(np.minimum(1.0, scale / np.maximum(e, 1e-300)))


def edge_refit(
    problem: _Problem,
    fitted: Any,
    refit: Callable[[NDArray[np.float64], float], Any],
    say: Callable[[str], None],
    scale: float = EDGE_SCALE,
) -> Any:
    """The fit with the edge-preserving penalty from the quadratic fit ``fitted`` (a
    :class:`~skisnow.identify._fit.BenchFit`); ``refit(p, λ)`` fits again from ``p`` with the
    problem's current weights. Leaves the weights of the returned fit in ``problem``."""
    fit = fitted
    for _ in range(MAX_ROUNDS):
        theta_e = problem.split(fit.solution.x)[0]
        w = edge_weights(problem, theta_e, fit.regularisation, scale)
        if np.max(np.abs(w - problem.stiffness_weights)) <= WEIGHT_TOL:
            break
        problem.stiffness_weights = w
        say(
            f"edge-preserving penalty: {int(np.sum(w < 1.0))} of {w.size} log-EI smoothness "
            f"rows beyond {scale:g} prior sd, reweighted, refitted"
        )
        fit = refit(fit.solution.x, fit.regularisation)
    return fit
