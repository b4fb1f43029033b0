"""A smooth model discrepancy of each load case in the fit's likelihood (Kennedy & O'Hagan 2001).

A bench's heights hold, besides white noise, an error smooth along a profile and different from
one load case to the next that no ski explains: the bench's own model error (its stone, its
contact resolution; the independent reference bench at 1 mm differs from the converged beam by
0.2-6.9 µm rms per load case on issue 25's ski). With white noise only, the information a fit
claims grows with the number of stations; on a full plan (39 cases, 16 000 bins) it then follows
such an error along directions of EI that barely change the heights (the glide zones pressed
flat on the stone) — measured: EI 17.6 % off where λ = 100 gave 8 % (docs/validation/
identification-uncertainty.md, fourth pass). A Gaussian-process discrepancy δₖ(x) per case,
standard deviation ``rms`` and squared-exponential correlation ``length``, makes the residuals'
covariance I + Gₖ Gₖᵀ (σ-normalised: Gₖ Gₖᵀ = diag(wₖ) Kₖ diag(wₖ), wₖ the bins' weights
√count / σₖ), so the information a smooth pattern of one case carries saturates at the
discrepancy's size instead of growing with the stations (Brynjarsdóttir & O'Hagan 2014: without
the discrepancy the physical parameters are estimated with confidence and wrongly).

The fit minimises rᵀ (I + G Gᵀ)⁻¹ r: the residuals and their Jacobian are whitened per case by
W = (I + G Gᵀ)^-1/2 = I − U diag(1 − (1 + s)^-1/2) Uᵀ with G Gᵀ = U diag(s) Uᵀ (its few
eigenvalues above 1e-3 of the largest: a smooth kernel is of low rank), two thin products per
case and evaluation.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["whitening"]


def whitening(
    x: NDArray[np.float64], w: NDArray[np.float64], *, rms: float, length: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(U, f)`` of the whitening W = I − U diag(f) Uᵀ of one load case (module docstring):
    bins at ``x`` [m] with residual weights ``w`` [1/m] (σ-normalised residual = w × height
    error), a discrepancy of standard deviation ``rms`` [m] and correlation ``length`` [m]."""
    kern = rms**2 * np.exp(-0.5 * ((x[:, None] - x[None, :]) / length) ** 2)
    m = w[:, None] * kern * w[None, :]
    s, u = np.linalg.eigh(m)
    keep = s > 1e-3 * max(float(s[-1]), 1e-300)
    s, u = s[keep], u[:, keep]
    return u, 1.0 - 1.0 / np.sqrt(1.0 + s)
