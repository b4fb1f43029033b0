"""A derived quantity checked where it is computed: the apparent pressure of a case.

No single input shows it. A width typed in metres into a millimetre field passes every field
check with ``--allow-implausible`` and then presses the ski onto the snow with a thousand times
the pressure; a snow given the modulus of the stone bench carries the stone's pressure spikes.
:func:`pressure_notes` looks at what came out of the contact solve and returns, as texts for
:attr:`skisnow.pipeline.Case.warnings` (a :class:`~skisnow.DomainWarning`: exit code 4 at the
CLI, listed in ``--json``), each of these:

* **more than the snow can bear**: on a snow counter surface the apparent pressure cannot
  exceed the hardness of the ice the grains are made of (Scherge et al. 2021, eq. 2, Poirier's
  H(T) = −0.6·T + 14.7 MPa): in the bearing model the grains deform plastically at H, so the
  real contact area is load / H and at p ≥ H it would be the whole apparent area — the snow
  would be crushed to ice. The peak and the mean of the zone that carries it are named.
* **not a small strain**: the equivalent elastic half-space of Kalliorinne et al. (2023, eq. 2)
  is linear; a peak pressure above :data:`SMALL_STRAIN` of E' means a surface strain of that
  order, outside linear elasticity. On the shipped skis loaded 120 mm behind the balance point
  the largest p/E' over the paper's range (5–130 kg, 20–400 MPa) is 0.26 %, and 0.36 % at
  300 kg (``docs/validation/robustness.md``).
* **a snow as stiff as stone**: a :class:`~skisnow.snow.Snow` whose modulus is at least that of
  ice (:data:`skisnow.materials.ICE`, 9.5 GPa, Scherge et al. 2021, Table 2) — snow is porous
  ice and cannot be stiffer; the stone bench's 70 GPa given for a snow is the usual slip.

A counter surface given only by its modulus is snow (or ice) when that modulus is below the
ice's, else a bench (stone, 70 GPa in Kalliorinne et al. 2023, §3.1), to which only the strain
check applies; its temperature is then the default of :class:`~skisnow.snow.Snow` (−2 °C).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

__all__ = ["SMALL_STRAIN", "pressure_notes", "snow_pressure_limit"]

#: Largest peak apparent pressure over E' taken as a small strain (linear elasticity, eq. 2).
SMALL_STRAIN: float = 0.05

#: Poirier's H(T) (Scherge et al. 2021, eq. 2) is fitted below −1 °C; warmer snow is bounded by
#: its value there (15.3 MPa, 4 % above the fit's 14.7 MPa at 0 °C: a ceiling, not an estimate).
_WARMEST_FIT_C: float = -1.0 - 1e-9


def _default_temperature() -> float:
    from skisnow.snow import Snow

    return float(next(f.default for f in dataclasses.fields(Snow) if f.name == "temperature_c"))


def snow_pressure_limit(temperature_c: float | None = None) -> tuple[float, float]:
    """The largest apparent pressure [Pa] a snow at ``temperature_c`` [°C] can bear, and that
    temperature: the ice hardness of Scherge et al. (2021, eq. 2, Poirier) at it (default: the
    temperature of a :class:`~skisnow.snow.Snow` given only a modulus)."""
    from skisnow.micro import ice_hardness

    t = _default_temperature() if temperature_c is None else float(temperature_c)
    return ice_hardness(min(t, _WARMEST_FIT_C), model="poirier"), t


def _where(zones: Any, peak: float) -> str:
    for name in ("rear", "middle", "front"):
        z = zones[name]
        if z.length > 0 and np.isfinite(z.max_pressure) and z.max_pressure >= peak:
            return f" in the {name} zone (its mean {z.mean_pressure / 1e6:.3g} MPa)"
    return ""


def pressure_notes(pressure: np.ndarray, zones: Any, *, modulus: float, snow: Any) -> list[str]:
    """What is implausible about the apparent pressure of one solved case (see the module).

    Parameters
    ----------
    pressure
        The apparent contact pressure [Pa] (any shape).
    zones
        The case's :class:`~skisnow.contact.ZoneMetrics` (names the zone of the peak).
    modulus
        E' of eq. 2 [Pa] (Kalliorinne et al. 2023).
    snow
        The :class:`~skisnow.snow.Snow` of the case (its temperature sets H), or E_counter [Pa]
        when the case was given only a modulus.

    Returns
    -------
    list of str
        One text per finding (empty: nothing implausible).
    """
    from skisnow.materials import ICE

    notes: list[str] = []
    p = np.asarray(pressure, dtype=float)
    peak = float(np.nanmax(p, initial=0.0))
    if isinstance(snow, int | float):
        on_snow, snow = float(snow) < ICE.modulus, None
    else:
        on_snow = True
    if snow is not None and snow.modulus >= ICE.modulus:
        notes.append(
            f"the snow {snow.name!r} has a modulus of {snow.modulus / 1e6:g} MPa, as stiff as "
            f"ice or stiffer ({ICE.modulus / 1e6:g} MPa): snow is porous ice and cannot be; "
            "was a bench's modulus (stone: 70000 MPa) given for the snow?"
        )
    if on_snow:
        limit, t = snow_pressure_limit(None if snow is None else snow.temperature_c)
        if peak > limit:
            notes.append(
                f"a peak apparent pressure of {peak / 1e6:.3g} MPa{_where(zones, peak)} is more "
                f"than snow can bear: the hardness of ice at {t:g} °C is {limit / 1e6:.3g} MPa "
                "(Scherge et al. 2021, eq. 2), where the grains would be crushed into one "
                "block of ice; check the load, the ski's width and the snow modulus"
            )
    if peak > SMALL_STRAIN * modulus:
        notes.append(
            f"a peak apparent pressure of {peak / 1e6:.3g} MPa is {peak / modulus:.3g} of the "
            f"equivalent modulus E' = {modulus / 1e6:.4g} MPa: not a small strain (above "
            f"{SMALL_STRAIN:g}), so the linear elastic half-space (Kalliorinne et al. 2023, "
            "eq. 2) does not hold; check the load, the ski's width and the snow modulus"
        )
    return notes
