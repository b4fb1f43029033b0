"""The result of an identification: the identified ski and how it was obtained."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skisnow.ski import Ski

__all__ = ["DEFAULT_LAMBDAS", "IdentificationResult"]

#: Default λ grid of the GCV search (penalty on second differences of log-EI coefficients, in
#: units of the σ-normalised misfit).
DEFAULT_LAMBDAS: tuple[float, ...] = (1e5, 1e4, 1e3, 1e2, 1e1, 1.0, 0.1, 0.01)


@dataclass(frozen=True, kw_only=True)
class IdentificationResult:
    """An identified ski and how it was obtained (SI units).

    Attributes
    ----------
    ski
        The identified :class:`Ski`: EI(x), z0(x) resting on the plane, their standard
        deviations (``stiffness_log_sd``/``camber_sd``: the Laplace posterior, the prior's
        width where the bench does not determine them), which stations the bench determines
        (``stiffness_determined``/``camber_determined``), the posterior's modes, provenance.
    regularisation, criterion
        The chosen λ and how (``'gcv'``, ``'evidence'``, ``'case-cv'``, ``'given'``, or
        ``'prior'``: an opt-in population prior in place of the penalty, λ unused).
    gcv
        ``((λ, score, misfit rms / σ, effective degrees of freedom), ...)`` of the search (score:
        the GCV, or minus the log evidence with ``criterion="evidence"``; the lowest chosen).
    noise
        Bench noise σ [m] (pooled over the load cases; estimated from the scatter of the
        profiles about local cubics, or given).
    noise_cases
        ``((mass [kg], x_m [m], σ [m], misfit rms / σ), ...)`` per load case.
    residual_rms
        RMS of model - data over all bins [m].
    n_cases, n_samples, n_parameters, n_bins
        Load cases, bench samples, fitted parameters and bins of the fit.
    n_evaluations, message
        Evaluations of the final fit, and how it ended.
    converged
        Whether the fit explains the bench down to its noise (χ² within its discrepancy
        bound, widened by the uncertainty of an estimated noise), or to its noise plus a stated
        model error of at most 0.46 σ (``model_error``), with a forward model accurate to a
        fifth of the noise (:mod:`skisnow.identify._diagnosis`).
    seconds
        Wall time of the identification.
    misfit
        RMS of the σ-normalised residuals of the bins at the fit: 1 ± (2 n)^-1/2 at the noise.
    chi2_bound
        The discrepancy bound of the fit's χ² (its residual degrees of freedom + 2 standard
        deviations).
    resolution
        ``((n_camber, misfit), ...)`` of each z0 resolution fitted, in turn.
    mesh_error
        ``(rms [m], max [m], element length [m])``: the discretisation error of the forward
        model at the fit (the change of the bins' model heights on a mesh of half the element
        length, :mod:`skisnow.identify._mesh_error`).
    outliers
        ``((mass [kg], x_m [m], x [m], residual [m], z), ...)``: bins beyond the Huber
        threshold at the end of the fit (:mod:`skisnow.identify._robust`).
    posterior_inflation
        The factor χ²/dof (>= 1) the bands were widened by.
    bootstrap
        ``(replicates, median sd of z0 [m], median sd of log EI)`` of the parametric bootstrap
        added to the bands (:func:`~skisnow.identify.bootstrap_bands`), None without one.
    causes
        Why the result is not better, main cause first (``'mesh'``, ``'noise'``,
        ``'evaluations'``, ``'model'``, ``'model-error'``, ``'information'``;
        :mod:`skisnow.identify._diagnosis`).
    model_error
        ``(rms [m], fraction of the noise)``: the fit's excess over the noise, δ² = (χ² - dof)
        / n in σ² units, and the rms height of a smooth error that would leave it (δ σ on a
        bench of one station per bin; δ σ / √c where the bins average c stations); a fit that
        stopped on its decrement above the noise's bound is converged when δ ≤ 0.46 σ (issue
        25's misfit ≤ 1.1 σ), with δ stated (:mod:`skisnow.identify._diagnosis`). Stated on
        every fit: inside the noise's bound it is chance, not a defect (χ² exceeds its degrees
        of freedom half the time).
    warnings
        The same in words, with what would help.
    """

    ski: Ski
    regularisation: float
    criterion: str
    gcv: tuple[tuple[float, float, float, float], ...]
    noise: float
    residual_rms: float
    n_cases: int
    n_samples: int
    n_parameters: int
    n_evaluations: int
    converged: bool
    message: str
    seconds: float
    misfit: float = float("nan")
    warnings: tuple[str, ...] = ()
    resolution: tuple[tuple[int, float], ...] = ()
    n_bins: int = 0
    chi2_bound: float = float("nan")
    noise_cases: tuple[tuple[float, float, float, float], ...] = ()
    mesh_error: tuple[float, float, float] = (float("nan"), float("nan"), float("nan"))
    outliers: tuple[tuple[float, float, float, float, float], ...] = ()
    posterior_inflation: float = 1.0
    causes: tuple[str, ...] = ()
    bootstrap: tuple[int, float, float] | None = None
    model_error: tuple[float, float] = (float("nan"), float("nan"))

    @property
    def at_noise(self) -> bool:
        """Whether the fit explains the bench down to its noise (χ² within its noise-only
        bound, without the allowance for a stated model error)."""
        return bool(self.n_bins and self.misfit**2 * self.n_bins <= self.chi2_bound)


def _span(x: np.ndarray, flags: np.ndarray) -> str:
    """The determined stations as ``'a..b'`` mm (first to last), or ``'none'``."""
    idx = np.flatnonzero(flags)
    return "none" if idx.size == 0 else f"{x[idx[0]] * 1e3:.0f}..{x[idx[-1]] * 1e3:.0f}"


def _version() -> str:
    from skisnow import __version__

    return __version__
