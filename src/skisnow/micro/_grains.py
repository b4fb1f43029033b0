"""Grain-size distribution of the snow and grain-averaged contact area (Scherge et al. 2021,
eq. 12–13).

Scherge et al. (2021) fit f(D) = a·D^b·e^(−cD) (a gamma-type density, after Nakamura et al.
2001) to the relative frequencies of measured grain diameters by non-linear least squares. Its
printed fit lost digits in the extraction ("(4.65·10'90)·D^?4922·e^−398:84D"); read with D in
metres it is

    a = 4.65·10⁹⁰,  b = 24.922,  c = 39 884 m⁻¹,

whose mode b/c = 625 µm sits inside the 500–750 µm the paper reports (§2.3) — the reason for this
reading. With these numbers ∫f dD ≈ 3.3·10⁻⁴ m and max f ≈ 1, i.e. the printed f is scaled to a
peak of ~1, not to unit area; eq. 13 is therefore evaluated with an explicit normalisation,
⟨A_fr⟩ = ∫A_fr(D) f(D) dD / ∫f(D) dD over the diameters computed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special

from skisnow._errors import ConvergenceError, InputError

__all__ = [
    "PAPER_GRAIN_FIT",
    "GrainFit",
    "fit_grain_distribution",
    "grain_average",
    "sample_grain_diameters",
]


@dataclass(frozen=True)
class GrainFit:
    """f(D) = a·D^b·e^(−cD) with D in metres (a stored as ln a to avoid overflow)."""

    log_a: float
    b: float
    c: float
    residual: float = float("nan")
    converged: bool = True

    @property
    def a(self) -> float:
        """The prefactor a (may be huge: units m^(−b) × those of f)."""
        return math.exp(self.log_a)

    @property
    def mode(self) -> float:
        """Most frequent diameter b/c [m]."""
        return self.b / self.c

    @property
    def mean(self) -> float:
        """Mean diameter (b+1)/c [m] of the normalised density."""
        return (self.b + 1.0) / self.c

    @property
    def integral(self) -> float:
        """∫₀^∞ f dD = a·Γ(b+1)/c^(b+1)."""
        return math.exp(self.log_a + special.gammaln(self.b + 1) - (self.b + 1) * math.log(self.c))

    def __call__(self, diameter: np.ndarray | float) -> np.ndarray:
        """f(D) for D [m] (zero for D <= 0)."""
        d = np.asarray(diameter, dtype=np.float64)
        with np.errstate(divide="ignore"):
            out = np.exp(self.log_a + self.b * np.log(d) - self.c * d)
        return np.where(d > 0, out, 0.0)


#: Scherge et al.'s (2021) fit (eq. 12), reconstructed as described in the module docstring.
PAPER_GRAIN_FIT = GrainFit(log_a=math.log(4.65e90), b=24.922, c=39884.0)


def fit_grain_distribution(
    centres: Sequence[float] | np.ndarray,
    frequencies: Sequence[float] | np.ndarray,
) -> GrainFit:
    """Fit f(D) = a·D^b·e^(−cD) to a histogram (bin centres [m], relative frequencies) by
    non-linear least squares (``scipy.optimize.curve_fit``, trust-region reflective).

    The fit runs in the well-scaled parameters (ln f at the mode, b, c·1 mm) from a
    method-of-moments start (gamma density: c = mean/var, b = mean²/var − 1); it is mapped back
    to (a, b, c) afterwards. Raises :class:`~skisnow.ConvergenceError` if the optimiser fails.
    """
    d = np.asarray(centres, dtype=np.float64).ravel()
    f = np.asarray(frequencies, dtype=np.float64).ravel()
    if d.size != f.size or d.size < 3:
        raise InputError(f"need >= 3 histogram bins with matching sizes, got {d.size}, {f.size}")
    if np.any(d <= 0) or np.any(f < 0) or not np.any(f > 0):
        raise InputError("bin centres must be positive [m] and frequencies non-negative")
    wts = f / f.sum()
    mean = float(np.sum(wts * d))
    var = float(np.sum(wts * (d - mean) ** 2))
    if var <= 0:
        raise InputError("all grains fall into one bin; the distribution cannot be fitted")
    c0 = mean / var
    b0 = max(mean * mean / var - 1.0, 0.5)
    scale = 1e-3

    def model(dd: np.ndarray, log_peak: float, b: float, cs: float) -> np.ndarray:
        c = cs / scale
        mode = b / c
        return np.exp(log_peak + b * np.log(dd / mode) - c * (dd - mode))

    p0 = (math.log(f.max()), b0, c0 * scale)
    try:
        popt, _ = optimize.curve_fit(
            model,
            d,
            f,
            p0=p0,
            bounds=([-50, 0.0, 1e-6], [50, 1e4, 1e6]),
            method="trf",
            max_nfev=10_000,
        )
    except (RuntimeError, ValueError) as exc:
        # curve_fit returns nothing partial when it fails: there is no result to carry
        raise ConvergenceError(f"grain-size fit did not converge: {exc}", result=None) from exc
    log_peak, b, cs = (float(v) for v in popt)
    c = cs / scale
    mode = b / c
    log_a = log_peak - b * math.log(mode) + c * mode
    res = float(np.sqrt(np.mean((model(d, *popt) - f) ** 2)))
    return GrainFit(log_a=log_a, b=b, c=c, residual=res, converged=True)


def sample_grain_diameters(fit: GrainFit, n: int, *, seed: int = 0) -> np.ndarray:
    """Draw ``n`` diameters [m] from the normalised density (a gamma law, shape b+1, rate c)."""
    rng = np.random.default_rng(seed)
    return rng.gamma(fit.b + 1.0, 1.0 / fit.c, size=int(n))


def grain_average(
    diameters: Sequence[float] | np.ndarray,
    values: Sequence[float] | np.ndarray,
    distribution: GrainFit = PAPER_GRAIN_FIT,
) -> float:
    """Grain-averaged value ⟨A_fr⟩ = ∫A_fr(D) f(D) dD / ∫f(D) dD (eq. 13, normalised over the
    given diameter range; trapezoidal rule on the diameters [m] given)."""
    d = np.asarray(diameters, dtype=np.float64).ravel()
    v = np.asarray(values, dtype=np.float64).ravel()
    if d.size != v.size or d.size < 2:
        raise InputError("need >= 2 diameters with one value each")
    if np.any(np.diff(d) <= 0):
        raise InputError("diameters must be strictly increasing")
    wts = distribution(d)
    norm = np.trapezoid(wts, d)
    if not norm > 0:
        raise InputError("the grain-size distribution is zero over the given diameters")
    return float(np.trapezoid(wts * v, d) / norm)
