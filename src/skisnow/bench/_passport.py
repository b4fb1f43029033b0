"""The ski passport: EI(x) and z0(x) with their uncertainty bands, and the practitioners' numbers.

What a maker or a service technician reads off a ski: its bending stiffness EI(x) and free camber
z0(x) along the running surface (Euler–Bernoulli beam of Kalliorinne et al. 2023, §3.1), with
95 % bands where the ski was identified from bench data (:func:`skisnow.identify.identify_ski`:
EI·exp(±1.96·sd of log EI), z0 ± 1.96·sd), and the bench metrics of Breitschädel (2012): camber
height at half and full body weight, wax-pocket lengths, closing load, stiffness k, contact
lengths (:func:`skisnow.bench.ski_metrics`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import InputError
from skisnow.ski import Ski

__all__ = ["BAND_Z", "SkiPassport", "ski_passport"]

#: Half-width of the passport bands in standard deviations (two-sided 95 % of a normal law).
BAND_Z: float = 1.96


@dataclass(frozen=True, kw_only=True)
class SkiPassport:
    """EI(x), z0(x) and their bands at stations x, and the practitioners' metrics (SI units).

    Attributes:
        ski: the ski.
        x: stations [m].
        stiffness, stiffness_low, stiffness_high: EI and its 95 % band [N m²] (band = EI where
            the ski carries no uncertainty).
        camber, camber_low, camber_high: z0 and its 95 % band [m].
        metrics: :meth:`skisnow.bench.SkiMetrics.as_field_units` at ``body_mass`` /
            ``load_position`` (field units), or ``None`` if the beam could not carry the load.
    """

    ski: Ski
    x: NDArray[np.float64]
    stiffness: NDArray[np.float64]
    stiffness_low: NDArray[np.float64]
    stiffness_high: NDArray[np.float64]
    camber: NDArray[np.float64]
    camber_low: NDArray[np.float64]
    camber_high: NDArray[np.float64]
    metrics: dict[str, Any] | None

    @property
    def has_bands(self) -> bool:
        """Whether the ski carries uncertainties (an identified ski)."""
        return self.ski.stiffness_log_sd is not None or self.ski.camber_sd is not None

    def table(self) -> dict[str, NDArray[np.float64]]:
        """The station table in field units: x_mm, ei_nm2, ei_low_nm2, ei_high_nm2, z0_mm,
        z0_low_mm, z0_high_mm."""
        return {
            "x_mm": self.x * 1e3,
            "ei_nm2": self.stiffness,
            "ei_low_nm2": self.stiffness_low,
            "ei_high_nm2": self.stiffness_high,
            "z0_mm": self.camber * 1e3,
            "z0_low_mm": self.camber_low * 1e3,
            "z0_high_mm": self.camber_high * 1e3,
        }


def ski_passport(
    ski: Ski,
    *,
    step: float = 0.05,
    body_mass: float = 65.0,
    load_position: float = -0.080,
    metrics: bool = True,
) -> SkiPassport:
    """The passport of ``ski``: EI(x), z0(x) and bands every ``step`` [m], and its metrics.

    Args:
        ski: the ski.
        step: station spacing [m], from the balance point outward (the ends are included).
        body_mass, load_position: skier [kg] and load position x_m [m] of the metrics.
        metrics: compute the practitioners' metrics (a few beam solves).

    The bands interpolate the standard deviations stored at the ski's stations linearly (PCHIP
    for the values themselves, as :class:`Ski` does).
    """
    if not (np.isfinite(step) and step > 0):
        raise InputError(f"step must be > 0 m, got {step}")
    k0 = int(np.ceil(ski.x_tail / step - 1e-9))
    k1 = int(np.floor(ski.x_tip / step + 1e-9))
    x = np.unique(np.concatenate([[ski.x_tail], np.arange(k0, k1 + 1) * step, [ski.x_tip]]))
    ei = ski.stiffness(x)
    z0 = ski.free_camber(x)
    if ski.stiffness_log_sd is not None:
        sd = np.interp(x, ski.stiffness_x, ski.stiffness_log_sd)
        ei_lo, ei_hi = ei * np.exp(-BAND_Z * sd), ei * np.exp(BAND_Z * sd)
    else:
        ei_lo, ei_hi = ei.copy(), ei.copy()
    if ski.camber_sd is not None:
        sd = np.interp(x, ski.camber_x, ski.camber_sd)
        z_lo, z_hi = z0 - BAND_Z * sd, z0 + BAND_Z * sd
    else:
        z_lo, z_hi = z0.copy(), z0.copy()
    doc = None
    if metrics:
        from skisnow._errors import UnsupportedLoadError
        from skisnow.bench._metrics import ski_metrics

        try:
            doc = ski_metrics(ski, body_mass=body_mass, load_position=load_position)
            doc = doc.as_field_units()
        except UnsupportedLoadError:
            doc = None
    return SkiPassport(
        ski=ski,
        x=x,
        stiffness=ei,
        stiffness_low=ei_lo,
        stiffness_high=ei_hi,
        camber=z0,
        camber_low=z_lo,
        camber_high=z_hi,
        metrics=doc,
    )
