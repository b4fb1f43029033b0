"""The wavy-texture references, checked on their own by independent evaluations."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from skisnow.micro.reference import plastic_sinusoid, westergaard


def test_westergaard_mean_gap_against_a_spectral_evaluation() -> None:
    # u(0) from the Fourier series of the closed-form pressure (u_k = 2 p_k/(E* q_k)) on a fine
    # periodic grid: another route than the log-kernel quadrature of the reference
    d, lam, e = 1e-6, 200e-6, 5e8
    for frac in (0.05, 0.3, 0.8):
        ref = westergaard(frac * math.pi * e * d / lam, amplitude=d, wavelength=lam,
                          contact_modulus=e)  # fmt: skip
        n = 2**18
        x = (np.arange(n) - n // 2) * lam / n
        s2 = math.sin(math.pi * ref.half_width / lam) ** 2
        inner = np.clip(s2 - np.sin(np.pi * x / lam) ** 2, 0.0, None)
        pbar = frac * ref.full_contact_pressure
        p = 2 * pbar * np.cos(np.pi * x / lam) * np.sqrt(inner) / s2
        assert p.mean() == pytest.approx(pbar, rel=1e-4)  # the pressure carries the load
        pk = np.fft.rfft(p) / n
        q = 2 * np.pi * np.arange(pk.size) / lam
        uk = np.zeros_like(pk)
        uk[1:] = 2 * pk[1:] / (e * q[1:])
        # u at sample n/2 (x = 0): the DFT's own phase e^{2πik(n/2)/n} = (−1)^k
        sign = np.where(np.arange(pk.size) % 2 == 0, 1.0, -1.0)
        u0 = float(2 * np.sum(np.real(uk[1:]) * sign[1:]))
        assert d - u0 == pytest.approx(ref.mean_gap, rel=2e-4)
    # full contact closes every gap
    near = westergaard(0.999 * ref.full_contact_pressure, amplitude=d, wavelength=lam,
                       contact_modulus=e)  # fmt: skip
    assert near.mean_gap < 1e-3 * d


def test_plastic_sinusoid_against_quadrature() -> None:
    d, uc = 2e-6, 3e-8
    for ph in (0.05, 0.4, 0.9):
        ref = plastic_sinusoid(ph, amplitude=d, film_cutoff=uc)
        c = math.cos(math.pi * ph)
        gap = lambda t, c=c: max(d * (c - math.cos(t)), 0.0)  # noqa: E731
        ubar, _ = integrate.quad(gap, 0, math.pi, points=[math.pi * ph], limit=400)
        assert ref.mean_separation == pytest.approx(ubar / math.pi, rel=1e-10)
        recip, _ = integrate.quad(
            lambda t, c=c: 1.0 / max(d * (c - math.cos(t)), uc), math.pi * ph, math.pi,
            points=[math.acos(c - uc / d)], limit=400, epsrel=1e-11,
        )  # fmt: skip
        assert ref.reciprocal_separation == pytest.approx(recip / math.pi, rel=1e-8)
        assert ref.contact_fraction == ph
