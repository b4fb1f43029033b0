"""Materials of the ski–snow micro contact (Scherge et al. 2021, eq. 1–4 and Table 2).

Temperatures are in °C here — the paper's fits are linear in the Celsius temperature, and a
Kelvin argument would invite silent errors — and every function says so in its argument name.
Hardness and moduli are returned in Pa (SI). The elastic constants of ice and UHMWPE (Table 2)
are the presets :data:`ICE` and :data:`UHMWPE` of :mod:`skisnow.materials` (one
:class:`Material` for every scale), re-exported here.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from skisnow._errors import DomainWarning, InputError
from skisnow.materials import ICE, UHMWPE, Material

__all__ = [
    "ICE",
    "UHMWPE",
    "Material",
    "Regime",
    "contact_time",
    "deformation_regime",
    "ice_hardness",
    "uhmwpe_hardness",
]


def _temperature(temperature_c: float) -> float:
    t = float(temperature_c)
    if not np.isfinite(t):
        raise InputError(f"temperature must be finite [°C], got {temperature_c}")
    if t > 0:
        raise InputError(f"temperature {t} °C is above the melting point; ice needs T <= 0 °C")
    return t


def ice_hardness(temperature_c: float, *, model: str = "poirier") -> float:
    """Hardness of ice H(T) [Pa] at a contact time of ~10⁻⁴ s.

    * ``'poirier'`` (eq. 2, Poirier et al. 2011): H = −0.6·T + 14.7 MPa (±0.4, ±2.1), valid for
      T < −1 °C. At −2 °C: 15.9 MPa (Table 2; the paper's §5 prints "159 MPa", a lost decimal
      point).
    * ``'makkonen'`` (eq. 3, Makkonen & Tikanmäki 2014): H = −5.08·T − 15.19 MPa, valid for
      −10 ≤ T ≤ −3 °C. Taken as printed: 0.05 MPa at −3 °C, 35.6 MPa at −10 °C, negative
      above −2.99 °C, as the paper remarks.

    A :class:`~skisnow.DomainWarning` is issued outside the model's range; a non-positive
    result raises :class:`~skisnow.InputError`.
    """
    t = _temperature(temperature_c)
    if model == "poirier":
        if not t < -1.0:
            warnings.warn(
                f"Poirier's ice hardness (eq. 2) is valid below -1 °C; T = {t} °C",
                DomainWarning,
                stacklevel=2,
            )
        h = -0.6 * t + 14.7
    elif model == "makkonen":
        if not -10.0 <= t <= -3.0:
            warnings.warn(
                f"Makkonen–Tikanmäki's ice hardness (eq. 3) is valid from -10 to -3 °C; T = {t} °C",
                DomainWarning,
                stacklevel=2,
            )
        h = -5.08 * t - 15.19
    else:
        raise InputError(f"ice hardness model {model!r} unknown; valid: 'poirier', 'makkonen'")
    if h <= 0:
        raise InputError(f"ice hardness model {model!r} gives {h:.3g} MPa <= 0 at {t} °C")
    return h * 1e6


def uhmwpe_hardness(temperature_c: float) -> float:
    """Hardness of the UHMWPE ski base [Pa] (eq. 4): H = 41.66 − 0.33·T MPa (42.3 MPa at −2 °C,
    Table 2)."""
    t = _temperature(temperature_c)
    return (41.66 - 0.33 * t) * 1e6


def contact_time(grain_diameter: float, speed: float) -> float:
    """Contact time t = d/v [s] of a base asperity sliding over a grain (eq. 1): 500 µm at
    10 km/h gives 1.8·10⁻⁴ s."""
    if not (grain_diameter > 0 and speed > 0):
        raise InputError(
            f"grain diameter [m] and speed [m/s] must be positive, got {grain_diameter}, {speed}"
        )
    return float(grain_diameter) / float(speed)


@dataclass(frozen=True)
class Regime:
    """Which body yields (Scherge et al. 2021, §3.5): the softer one deforms plastically."""

    temperature_c: float
    ice_hardness: float
    base_hardness: float
    yielding: str
    hardness_ratio: float
    ice_stiffness_to_hardness: float

    @property
    def bearing_model_applies(self) -> bool:
        """True when the ice yields (the premise of the bearing model, eq. 5–9)."""
        return self.yielding == "ice"


def deformation_regime(temperature_c: float, *, model: str = "poirier") -> Regime:
    """Compare ice and UHMWPE hardness at ``temperature_c`` [°C]: the softer body yields.

    ``ice_stiffness_to_hardness`` = E_ice/H_ice (≈ 600 at −2 °C): a large value means the ice
    grain is stiff but yields early, so elastic deformation is small against plastic (§3.5).
    """
    hi = ice_hardness(temperature_c, model=model)
    hb = uhmwpe_hardness(temperature_c)
    return Regime(
        temperature_c=float(temperature_c),
        ice_hardness=hi,
        base_hardness=hb,
        yielding="ice" if hi < hb else "base",
        hardness_ratio=hb / hi,
        ice_stiffness_to_hardness=ICE.modulus / hi,
    )
