"""The result of an identification: the identified ski and how it was obtained."""

from __future__ import annotations

from dataclasses import dataclass

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
        The identified :class:`Ski` (EI(x), z0(x) resting on the plane, their standard
        deviations ``stiffness_log_sd``/``camber_sd``, provenance).
    regularisation
        The chosen λ (penalty on second differences of log-EI coefficients).
    criterion
        How λ was chosen (``'gcv'`` or ``'given'``).
    gcv
        ``((λ, GCV score, misfit rms / σ, effective degrees of freedom), ...)`` of the search:
        of the Gauss–Newton linearisation around the fit at the middle of the grid, and for the
        chosen λ of its own fit.
    noise
        Bench noise σ [m] used to normalise residuals (estimated from the scatter inside bins,
        or given).
    residual_rms
        RMS of model - data over all samples [m] (from the bins and their scatter).
    n_cases, n_samples, n_parameters
        Load cases, bench samples and fitted parameters.
    n_evaluations, converged, message
        Optimiser evaluations of the final fit, its status and message.
    seconds
        Wall time of the identification.
    misfit
        RMS of the σ-normalised residuals of the bins at the fit (each bin mean weighted by
        the square root of its count): 1 ± (2 n)^-1/2 for a fit at the noise, n bins.
    n_bins
        Bins of the fit (the n of ``misfit``).
    resolution
        ``((n_camber, misfit), ...)`` of each z0 resolution fitted, in turn (the discrepancy
        principle: refined while above the noise); the ski's is the provenance's ``n_camber``
        (a last refinement that does not lower the information criterion is not kept).
    warnings
        Said when the fit is not at the noise (``misfit`` above :data:`AT_NOISE`): the
        identified ski may be a local minimum of the misfit, not the ski on the bench.
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

    @property
    def at_noise(self) -> bool:
        """Whether the fit explains the bench down to its noise (no warning)."""
        return not self.warnings
