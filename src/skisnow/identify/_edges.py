"""An edge-preserving smoothness penalty on log EI: a Huber loss on its second differences.

The fit's quadratic penalty λ |D₂ θ_E|² (:meth:`skisnow.identify._model._Problem.penalty_matrix`)
costs a stiffness step ×2.5 over 25 mm (issue 25's ski at -450 and -120 mm: second differences
of its log-EI coefficients up to 2.5, against 0.02-0.2 along the smooth stretches of a ski) as
much as a wide bump of the same area, so at the λ that GCV chooses for the smooth stretches the
steps are smeared (the smoothing bias of the third and fourth passes). Here each row of D₂ θ_E
counts with the Huber loss (Huber 1964) of scale ``c``: quadratic below c, linear above it, so a
few large second differences (an edge) cost little more than their size while the many small
ones keep the quadratic penalty — the edge-preserving regularisation of image restoration
(Charbonnier et al. 1997; for the total-variation limit, Vogel & Oman 1996, §2, "lagged
diffusivity"). It is solved by iteratively reweighted least squares (Holland & Welsch 1977):
from the quadratic fit, the rows' weights w_i = min(1, c / |(D₂ θ_E)_i|) are frozen, the fit
is made again at them (the same Levenberg–Marquardt; the penalty stays linear in p, so the
Laplace bands and GCV read the reweighted penalty as the prior's precision), for at most
:data:`MAX_ROUNDS` rounds or until no weight moves by more than :data:`WEIGHT_TOL`.
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

#: The Huber scale c of the log-EI second differences (module docstring): between the smooth
#: stretches' 0.02-0.2 and the steps' 0.5-2.5 (the true skis' splines, 60 coefficients).
EDGE_SCALE = 0.1


def edge_weights(
    problem: _Problem, theta_e: NDArray[np.float64], scale: float
) -> NDArray[np.float64]:
    """The square roots of the Huber weights min(1, c / |(D₂ θ_E)_i|) of the log-EI smoothness
    rows at the coefficients ``theta_e``."""
    d = np.abs(problem.d2_e @ theta_e)
    return np.sqrt(np.minimum(1.0, scale / np.maximum(d, 1e-300)))


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
        w = edge_weights(problem, theta_e, scale)
        if np.max(np.abs(w - problem.stiffness_weights)) <= WEIGHT_TOL:
            break
        problem.stiffness_weights = w
        say(
            f"edge-preserving penalty: {int(np.sum(w < 1.0))} of {w.size} log-EI second "
            f"differences beyond {scale:g}, reweighted, refitted"
        )
        fit = refit(fit.solution.x, fit.regularisation)
    return fit
