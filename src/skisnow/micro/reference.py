"""Analytic references of the micro contact of a wavy texture (checked in ``tests/micro``).

A texture h(x) = Δ cos(2πx/λ) (constant across), heights toward the ice, pressed against a flat
counter-surface at nominal pressure p̄:

* :func:`westergaard` — elastic contact (Westergaard 1939; Johnson 1985, *Contact Mechanics*
  §13.2): contact half-width a per period with p̄ = p*·sin²(πa/λ), p* = πE*Δ/λ, and the
  pressure p(x) = 2p̄·cos(πx/λ)·√(sin²(πa/λ) − sin²(πx/λ)) / sin²(πa/λ). The mean gap about the
  texture's mean plane is ū = Δ − u(0), u(0) the indentation under the contact centre from the
  periodic line-load Green's function −(2/πE*)·ln|2 sin(πt/λ)| (zero mean), integrated over the
  closed-form pressure by adaptive quadrature (a reference to ~1e-12, independent of any grid).
  E* is Johnson's contact modulus, 1/E* = Σ(1 − ν²)/E — half skisnow's E'.
* :func:`plastic_sinusoid` — the rigid–perfectly-plastic limit (E* → ∞, pressure H on the
  contact): the contact is where cos θ > c, θ = 2πx/λ, with arccos(c)/π = p̄/H; the gap is
  Δ(c − cos θ) elsewhere, so ū = Δ[c(1 − φ/π) + sin φ/π] (φ = arccos c) and the reciprocal
  separation with a film cut-off u_c, ⟨1/max(u, u_c)⟩ over the nominal area, follows from
  ∫dθ/(c − cos θ) = ln|(t − k)/(t + k)|/√(1 − c²), t = tan(θ/2), k = tan(φ/2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from skisnow._errors import InputError

__all__ = ["PlasticSinusoid", "Westergaard", "plastic_sinusoid", "westergaard"]


@dataclass(frozen=True, kw_only=True)
class Westergaard:
    """Elastic wavy contact: half-width a [m], contact fraction 2a/λ, p* [Pa], mean gap [m]."""

    half_width: float
    contact_fraction: float
    full_contact_pressure: float
    mean_gap: float


def westergaard(
    pressure: float, *, amplitude: float, wavelength: float, contact_modulus: float
) -> Westergaard:
    """The elastic contact of Δ cos(2πx/λ) with a flat at mean pressure p̄ < p* (SI units;
    ``contact_modulus`` is Johnson's E*)."""
    from scipy import integrate

    d, lam, e = float(amplitude), float(wavelength), float(contact_modulus)
    if not (d > 0 and lam > 0 and e > 0):
        raise InputError("amplitude, wavelength and contact modulus must be positive")
    pstar = math.pi * e * d / lam
    if not 0 < pressure < pstar:
        raise InputError(f"pressure must lie in (0, p* = {pstar:.4g} Pa), got {pressure}")
    s2 = pressure / pstar
    a = lam / math.pi * math.asin(math.sqrt(s2))

    def p(s: float) -> float:
        inner = max(s2 - math.sin(math.pi * s / lam) ** 2, 0.0)
        return 2 * pressure * math.cos(math.pi * s / lam) * math.sqrt(inner) / s2

    def integrand(s: float) -> float:
        return p(s) * math.log(abs(2 * math.sin(math.pi * s / lam)))

    val, _ = integrate.quad(integrand, -a, a, points=[0.0], limit=400, epsabs=0, epsrel=1e-10)
    u0 = -2.0 / (math.pi * e) * val
    return Westergaard(
        half_width=a, contact_fraction=2 * a / lam, full_contact_pressure=pstar, mean_gap=d - u0
    )


@dataclass(frozen=True, kw_only=True)
class PlasticSinusoid:
    """Rigid–plastic wavy contact: contact fraction p̄/H, mean separation [m] and reciprocal
    separation ⟨1/max(u, u_c)⟩ over the nominal area [1/m]."""

    contact_fraction: float
    mean_separation: float
    reciprocal_separation: float


def plastic_sinusoid(
    pressure_over_hardness: float, *, amplitude: float, film_cutoff: float
) -> PlasticSinusoid:
    """The rigid–perfectly-plastic contact of Δ cos(2πx/λ) with a flat at p̄/H (module
    docstring); independent of λ."""
    ph, d, uc = float(pressure_over_hardness), float(amplitude), float(film_cutoff)
    if not (0 < ph < 1 and d > 0 and 0 < uc < d):
        raise InputError("need 0 < p/H < 1, Δ > 0 and 0 < u_c < Δ")
    phi = math.pi * ph
    c = math.cos(phi)
    ubar = d * (c * (1 - phi / math.pi) + math.sin(phi) / math.pi)
    k = math.tan(phi / 2)
    theta_c = math.acos(max(c - uc / d, -1.0))  # gaps below u_c between φ and θ_c

    def prim(theta: float) -> float:
        t = math.tan(theta / 2)
        return math.log(abs((t - k) / (t + k))) / math.sqrt(1 - c * c)

    above = -prim(theta_c) / d if theta_c < math.pi else 0.0  # prim(π) = 0
    recip = ((theta_c - phi) / uc + above) / math.pi
    return PlasticSinusoid(contact_fraction=ph, mean_separation=ubar, reciprocal_separation=recip)
