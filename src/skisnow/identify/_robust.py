"""Outliers of a bench: a Huber loss by iteratively reweighted least squares.

A real bench profile can hold a reading far off the others (dust on the stone, a sensor step):
least squares then bends z0 to it (issue 25: one sample off by 1 mm left an 80 µm bump in z0
under a ±5 µm band). The fit is therefore completed by the Huber loss (Huber 1964): every bin
whose σ-normalised residual r exceeds the threshold c counts with the weight c / |r| (its
contribution to the objective grows linearly, not quadratically), by iteratively reweighted
least squares (Holland & Welsch 1977) started at the least-squares fit, until the set of
downweighted bins no longer changes (at most :data:`MAX_ROUNDS` refits). The threshold is set at
the extreme of the noise, c = max(4.5, √(2 ln n) + 1.5) for n bins (the largest of n standard
normal residuals is about √(2 ln n): 3.9 for 2400 bins, 4.4 for 15000): a bench without
outliers keeps every weight 1 and its least-squares fit, at no cost. The bins left outside the
threshold at the end are the outliers, named by load case and station.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow.identify._model import _Problem

__all__ = ["MAX_ROUNDS", "Outlier", "huber_threshold", "robust_refit"]

#: Refits of the reweighting at most.
MAX_ROUNDS = 3


@dataclass(frozen=True, kw_only=True)
class Outlier:
    """A bin of the bench outside the Huber threshold at the end of the fit: its load case
    (``mass`` [kg], ``load_position`` [m]), station ``x`` [m] (bin centre), the model minus the
    data ``residual`` [m] and in units of the case's noise, ``z``."""

    mass: float
    load_position: float
    x: float
    residual: float
    z: float


def huber_threshold(n_bins: int) -> float:
    """The Huber threshold c of ``n_bins`` σ-normalised residuals (module docstring)."""
    return float(max(4.5, np.sqrt(2.0 * np.log(max(n_bins, 2))) + 1.5))


def robust_refit(
    problem: _Problem,
    fitted: Any,
    refit: Callable[[NDArray[np.float64], float], Any],
    say: Callable[[str], None],
) -> tuple[Any, tuple[Outlier, ...]]:
    """The Huber fit of ``problem`` from its least-squares fit ``fitted`` (a
    :class:`~skisnow.identify._fit.BenchFit`); ``refit(p, λ)`` fits again from ``p`` at λ with
    the problem's current bin weights. Returns the final fit and its outliers."""
    c = huber_threshold(problem.n_data)
    fit = fitted
    previous = np.zeros(problem.n_data, dtype=bool)
    for _ in range(MAX_ROUNDS):
        r = fit.solution.fun
        raw = r / np.concatenate(problem.bin_weights)
        flag = np.abs(raw) > c
        if not flag.any() or np.array_equal(flag, previous):
            break
        weights = np.where(flag, np.sqrt(c / np.maximum(np.abs(raw), c)), 1.0)
        problem.set_bin_weights(weights)
        say(f"{int(flag.sum())} bins beyond the Huber threshold {c:.2g} σ: reweighted, refitted")
        fit = refit(fit.solution.x, fit.regularisation)
        previous = flag
    raw = fit.solution.fun / np.concatenate(problem.bin_weights)
    outliers = []
    start = 0
    for k, case in enumerate(problem.cases):
        z = raw[start : start + case.x.size]
        start += case.x.size
        for i in np.flatnonzero(np.abs(z) > c):
            outliers.append(
                Outlier(
                    mass=case.mass,
                    load_position=case.position,
                    x=float(case.x[i]),
                    residual=float(z[i] * problem.sigma_cases[k] / case.w[i]),
                    z=float(z[i]),
                )
            )
    return fit, tuple(outliers)
