"""Friction proxies on the real contact, every parameter stated with its source.

Two terms, as Kalliorinne et al. (2023, Lubricants 11(10) 427) tie them to the contact:

* the dry/adhesive term F_τ = τ·A_r (Bowden & Tabor's law, as Scherge et al. 2021 quote it:
  F = τ·A_r), with τ the shear strength of the real contact;
* the viscous term F_η = η·v·∫ 1/u dA of a meltwater film filling the gap u between base and
  snow (Couette shear), over the non-contact area, gaps below the film cut-off u_c counted as u_c.

Defaults (each overridable; :meth:`FrictionParameters.resolve` states them):

* τ = µ_dry·H_ice(T) with µ_dry = 0.3, the kinetic friction of snow when frictional heat does
  not melt it ("snow is similar to sand", Theile et al. 2009, Tribol. Lett. 36:223, §1): with a
  fully plastic contact, A_r = W/H, τ·A_r = 0.3·W. An unlubricated upper bound, not a glide
  prediction; the lubricated alternative, the same contact spots sheared through a film of
  thickness u_c (τ = η·v/u_c), is reported beside it (:class:`Proxies`).
* η = the viscosity of liquid water at the snow's temperature, Vogel's equation
  η = A·10^(B/(T − C)), A = 2.414·10⁻⁵ Pa·s, B = 247.8 K, C = 140 K (1.75 mPa·s at 0 °C
  against 1.79 measured; at −10 °C 2.48, supercooled water measures ~2.6 mPa·s). Meltwater made
  by frictional heating sits at the melting point (0 °C) — override η to use that.
* v = 10 km/h = 2.78 m/s, the speed of Scherge et al.'s (2021) eq. 1 example.
* u_c = 0.1 µm: the meltwater film is estimated below 1 µm (Colbeck 1988; Bäurle et al. 2007;
  Makkonen & Tikanmäki 2014) and was not seen above 0.05 µm at 0.1 m/s (Strausky et al. 1998).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from skisnow._errors import InputError

__all__ = [
    "DEFAULT_DRY_FRICTION",
    "DEFAULT_FILM_CUTOFF",
    "DEFAULT_SLIDING_SPEED",
    "FrictionParameters",
    "ResolvedFriction",
    "water_viscosity",
]

#: Kinetic friction of snow below melting (Theile et al. 2009, §1).
DEFAULT_DRY_FRICTION: float = 0.3
#: Sliding speed [m/s]: 10 km/h (Scherge et al. 2021, eq. 1).
DEFAULT_SLIDING_SPEED: float = 10.0 / 3.6
#: Film-thickness cut-off [m] (see the module docstring).
DEFAULT_FILM_CUTOFF: float = 1e-7


def water_viscosity(temperature_c: float) -> float:
    """Dynamic viscosity of liquid water [Pa·s] by Vogel's equation (module docstring); below
    0 °C the supercooled liquid (an extrapolation of the fit)."""
    t = float(temperature_c) + 273.15
    if not (math.isfinite(t) and t > 140.0 + 60.0):
        raise InputError(f"temperature {temperature_c} °C is outside Vogel's water viscosity")
    return 2.414e-5 * 10.0 ** (247.8 / (t - 140.0))


@dataclass(frozen=True, kw_only=True)
class ResolvedFriction:
    """The parameters of a friction estimate with the source of each (SI units)."""

    shear_strength: float
    viscosity: float
    sliding_speed: float
    film_cutoff: float
    area_model: str
    sources: dict[str, str]

    def as_dict(self) -> dict[str, Any]:
        """Field units (MPa, mPa·s, m/s, µm) and the sources."""
        return {
            "shear_strength_mpa": self.shear_strength / 1e6,
            "viscosity_mpa_s": self.viscosity * 1e3,
            "sliding_speed_m_s": self.sliding_speed,
            "film_cutoff_nm": self.film_cutoff * 1e9,
            "area_model": self.area_model,
            "sources": dict(self.sources),
        }

    def assumptions(self) -> str:
        """One paragraph for the µ estimate."""
        return (
            f"τ = {self.shear_strength / 1e6:.3g} MPa ({self.sources['shear_strength']}); "
            f"η = {self.viscosity * 1e3:.3g} mPa·s ({self.sources['viscosity']}); "
            f"v = {self.sliding_speed:.3g} m/s ({self.sources['sliding_speed']}); "
            f"film cut-off {self.film_cutoff * 1e9:.3g} nm ({self.sources['film_cutoff']}); "
            f"real area from the {self.area_model} model"
        )


@dataclass(frozen=True, kw_only=True)
class FrictionParameters:
    """What the friction proxies need; ``None`` takes the cited default (module docstring).

    Parameters
    ----------
    shear_strength
        τ [Pa] of the real contact (default µ_dry·H_ice(T), µ_dry = 0.3).
    viscosity
        η [Pa·s] of the meltwater (default: water at the snow's temperature).
    sliding_speed
        v [m/s] (default 10 km/h).
    film_cutoff
        u_c [m] (default 0.1 µm).
    area_model
        Real area of the dry term: ``'grains'`` (default: the bearing model, the base texture
        against the snow's grains, A_r = (p/H)·s) or ``'flat-ice'`` (the elastic–plastic
        contact with a flat ice surface: the same plus the elastic rims of the contact spots,
        but blind to the grains — a smooth base touches flat ice everywhere).
    """

    shear_strength: float | None = None
    viscosity: float | None = None
    sliding_speed: float | None = None
    film_cutoff: float | None = None
    area_model: str = "grains"

    def __post_init__(self) -> None:
        for name in ("shear_strength", "viscosity", "sliding_speed", "film_cutoff"):
            v = getattr(self, name)
            if v is not None and not (math.isfinite(v) and v > 0):
                raise InputError(f"{name} must be positive and finite (SI units), got {v!r}")
        if self.area_model not in ("flat-ice", "grains"):
            raise InputError(f"area_model {self.area_model!r} unknown; valid: 'flat-ice', 'grains'")

    def resolve(self, *, temperature_c: float, hardness: float) -> ResolvedFriction:
        """Concrete values for a snow at ``temperature_c`` [°C] with ice hardness [Pa]."""
        src: dict[str, str] = {}
        if self.shear_strength is None:
            tau = DEFAULT_DRY_FRICTION * hardness
            src["shear_strength"] = (
                f"µ_dry·H_ice, µ_dry = {DEFAULT_DRY_FRICTION} (Theile et al. 2009), "
                f"H_ice = {hardness / 1e6:.3g} MPa (Scherge et al. 2021, eq. 2)"
            )
        else:
            tau, src["shear_strength"] = float(self.shear_strength), "given"
        if self.viscosity is None:
            eta = water_viscosity(temperature_c)
            src["viscosity"] = f"water at {temperature_c:g} °C, Vogel's equation"
        else:
            eta, src["viscosity"] = float(self.viscosity), "given"
        if self.sliding_speed is None:
            v = DEFAULT_SLIDING_SPEED
            src["sliding_speed"] = "10 km/h, Scherge et al. (2021) eq. 1"
        else:
            v, src["sliding_speed"] = float(self.sliding_speed), "given"
        if self.film_cutoff is None:
            uc = DEFAULT_FILM_CUTOFF
            src["film_cutoff"] = "meltwater film < 1 µm (Colbeck 1988; Bäurle et al. 2007)"
        else:
            uc, src["film_cutoff"] = float(self.film_cutoff), "given"
        return ResolvedFriction(
            shear_strength=tau,
            viscosity=eta,
            sliding_speed=v,
            film_cutoff=uc,
            area_model=self.area_model,
            sources=src,
        )
