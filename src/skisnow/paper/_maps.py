"""The maps of Kalliorinne et al. (2023), Figures 8–9: zones over load × snow modulus.

Figure 8 plots the apparent contact area of the rear and the front zone of the paper's skate ski
against the load m at x_m = -120 mm, one line per snow modulus (20–400 MPa in 20 MPa steps),
with the Breitschädel (50 µm) estimate; Figure 9 the mean apparent pressure of the same zones.
:func:`zone_maps` computes them for any ski, on any mass grid, through either profile route
(the paper's camber network, or the beam it emulates), every case through the one door
:func:`skisnow.pipeline.solve_case` (the profile of each mass computed once,
:func:`skisnow.pipeline.loaded_profiles`, then pressed into every snow). The zones are the
paper's (:func:`skisnow.contact.paper_zones`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError
from skisnow.ski import Ski, get_ski

__all__ = [
    "FIGURE89_MASS_RANGE_KG",
    "FIGURE89_MODULI_MPA",
    "ZoneMaps",
    "figure89_masses",
    "zone_maps",
]

#: The snow moduli of Figures 8–9 [MPa]: 20 to 400 MPa in 20 MPa steps (their captions).
FIGURE89_MODULI_MPA: tuple[float, ...] = tuple(float(e) for e in range(20, 401, 20))
#: The load range of the maps [kg]: the paper's load range, 5–130 kg (its bench, §3.1, and the
#: domain of its network). The extracted text does not give the axis of Figures 8–9; every
#: load their text names (20–60 kg) lies inside.
FIGURE89_MASS_RANGE_KG: tuple[float, float] = (5.0, 130.0)


def figure89_masses(step_kg: float) -> NDArray[np.float64]:
    """The mass grid of the maps: :data:`FIGURE89_MASS_RANGE_KG` in steps of ``step_kg``."""
    lo, hi = FIGURE89_MASS_RANGE_KG
    if not (np.isfinite(step_kg) and 0 < step_kg <= (hi - lo) / 4):
        raise InputError(f"step_kg: need a step in (0, {(hi - lo) / 4:g}] kg, got {step_kg!r}")
    return np.arange(lo, hi + 1e-9, step_kg)


@dataclass(frozen=True, kw_only=True)
class ZoneMaps:
    """Rear and front maps over load (rows) × snow modulus (columns), field units.

    ``area_cm2``, ``pressure_kpa`` and ``patches`` map ``"rear"``/``"front"`` to arrays of shape
    ``(n_mass, n_modulus)``; ``breitschaedel_cm2`` to arrays of shape ``(n_mass,)`` (a property
    of the profile alone). ``ski``, ``route``, ``load_position_mm`` and ``n_points`` say what
    was computed.
    """

    masses_kg: NDArray[np.float64]
    moduli_mpa: NDArray[np.float64]
    area_cm2: dict[str, NDArray[np.float64]]
    pressure_kpa: dict[str, NDArray[np.float64]]
    patches: dict[str, NDArray[np.int64]]
    breitschaedel_cm2: dict[str, NDArray[np.float64]]
    ski: str = ""
    route: str = ""
    load_position_mm: float = -120.0
    n_points: int = 0

    @property
    def step_kg(self) -> float:
        """The mass step of the grid [kg] (its smallest)."""
        return float(np.min(np.diff(self.masses_kg)))

    def every(self, k: int) -> ZoneMaps:
        """The maps on every ``k``-th mass (the 2 kg grid of a 1 kg map: ``every(2)``)."""
        if int(k) != k or k < 1:
            raise InputError(f"every: need a positive integer, got {k!r}")
        k = int(k)

        def cut(d: dict[str, NDArray]) -> dict[str, NDArray]:
            return {z: a[::k] for z, a in d.items()}

        return ZoneMaps(
            masses_kg=self.masses_kg[::k], moduli_mpa=self.moduli_mpa,
            area_cm2=cut(self.area_cm2), pressure_kpa=cut(self.pressure_kpa),
            patches=cut(self.patches), breitschaedel_cm2=cut(self.breitschaedel_cm2),
            ski=self.ski, route=self.route, load_position_mm=self.load_position_mm,
            n_points=self.n_points,
        )  # fmt: skip

    def arrays(self) -> dict[str, NDArray]:
        """Every array by a flat name (``area_cm2_rear``, …), for storing the maps."""
        out: dict[str, NDArray] = {"masses_kg": self.masses_kg, "moduli_mpa": self.moduli_mpa}
        for field in ("area_cm2", "pressure_kpa", "patches", "breitschaedel_cm2"):
            for zone, arr in getattr(self, field).items():
                out[f"{field}_{zone}"] = arr
        return out

    @classmethod
    def from_arrays(cls, arrays: dict[str, NDArray], **meta: object) -> ZoneMaps:
        """The inverse of :meth:`arrays` (``meta``: ``ski``, ``route``, … as stored)."""

        def pair(field: str) -> dict[str, NDArray]:
            return {z: np.asarray(arrays[f"{field}_{z}"]) for z in ("rear", "front")}

        return cls(
            masses_kg=np.asarray(arrays["masses_kg"], dtype=float),
            moduli_mpa=np.asarray(arrays["moduli_mpa"], dtype=float),
            area_cm2=pair("area_cm2"),
            pressure_kpa=pair("pressure_kpa"),
            patches={z: a.astype(np.int64) for z, a in pair("patches").items()},
            breitschaedel_cm2=pair("breitschaedel_cm2"),
            **meta,  # type: ignore[arg-type]
        )


def zone_maps(
    ski: Ski | str,
    masses_kg: ArrayLike,
    moduli_mpa: ArrayLike = FIGURE89_MODULI_MPA,
    *,
    load_position: float = -0.120,
    route: str = "network",
    n_points: int = 2048,
) -> ZoneMaps:
    """Rear/front area, mean pressure, patches and Breitschädel area over load × snow.

    The paper's pipeline (Kalliorinne et al. 2023, §3): the loaded camber profile of every mass
    (``route='network'``, the paper's: the ski's camber network; ``'beam'``: the beam on the
    rigid plane it emulates), pressed as a rigid body into the half-space of E' from
    E_base = 900 MPa, ν = 0.3 (eq. 2) with force and moment balance (eq. 3), strip model,
    ``n_points`` stations; the paper's zones (:func:`skisnow.contact.paper_zones`).

    Parameters
    ----------
    ski
        A :class:`~skisnow.ski.Ski` or a shipped name (the network route needs a shipped ski).
    masses_kg, moduli_mpa
        The grid: loads m [kg] (1-D, at least 3) and snow moduli E_counter [MPa].
    load_position
        x_m [m] (the paper's -120 mm).
    route
        ``'network'`` or ``'beam'``.
    n_points
        Stations along the ski.
    """
    from skisnow.paper._captions import BASE_MODULUS, POISSON
    from skisnow.pipeline import loaded_profiles, solve_case

    masses = np.asarray(masses_kg, dtype=float)
    moduli = np.asarray(moduli_mpa, dtype=float)
    if masses.ndim != 1 or moduli.ndim != 1 or masses.size < 3 or moduli.size < 1:
        raise InputError("zone_maps: need 1-D masses (>= 3) and moduli (>= 1)")
    if route not in ("network", "beam"):
        raise InputError(f"zone_maps: route must be 'network' or 'beam', not {route!r}")
    s = get_ski(ski)
    shape = (masses.size, moduli.size)
    area = {z: np.zeros(shape) for z in ("rear", "front")}
    press = {z: np.full(shape, np.nan) for z in ("rear", "front")}
    npatch = {z: np.zeros(shape, dtype=np.int64) for z in ("rear", "front")}
    breit = {z: np.zeros(masses.size) for z in ("rear", "front")}
    x, heights = loaded_profiles(
        s, masses, load_position, profile_source=route, n_points=n_points, missing="raise"
    )
    for i, m in enumerate(masses):
        start = None
        for j, e in enumerate(moduli):
            case = solve_case(
                s, mass=float(m), load_position=load_position, snow_modulus=float(e) * 1e6,
                profile_source=route, profile=(x, heights[i]), base=BASE_MODULUS,
                poisson=POISSON, start=start,
            )  # fmt: skip
            start = case.solution.pressure  # warm start: the next snow is a little stiffer
            zones = case.zones
            for z in ("rear", "front"):
                area[z][i, j] = zones[z].area * 1e4
                press[z][i, j] = zones[z].mean_pressure * 1e-3
                npatch[z][i, j] = zones[z].patches
            if j == 0:
                for z in ("rear", "front"):
                    breit[z][i] = zones.breitschaedel[z].area * 1e4
    return ZoneMaps(
        masses_kg=masses, moduli_mpa=moduli, area_cm2=area, pressure_kpa=press,
        patches=npatch, breitschaedel_cm2=breit, ski=s.name, route=route,
        load_position_mm=load_position * 1e3, n_points=int(x.size),
    )  # fmt: skip
