"""The practitioners' metrics of one ski, from its beam model or from a bench file.

:func:`ski_metrics` → :class:`SkiMetrics`: camber height, wax pocket, closing load, stiffness
and the 50 µm contact lengths of Breitschädel (2012, Procedia Eng. 34, 391-396) under half and
full body weight, computed with the array metrics of :mod:`skisnow.ski._metrics` on profiles
from :func:`~skisnow.ski.solve_beam` (a :class:`~skisnow.ski.Ski`) or interpolated from a
:class:`~skisnow.bench.BenchData` (its queries :meth:`~skisnow.bench.BenchData.heights_at`,
:meth:`~skisnow.bench.BenchData.profile_at_mass`, :meth:`~skisnow.bench.BenchData.kick_zone_mm`).
:func:`closing_load` bisects the beam; :func:`closing_load_from_bench` reads the bench. SI units;
:meth:`SkiMetrics.as_field_units` converts for tables and JSON.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import InputError
from skisnow.bench._data import BenchData
from skisnow.ski import (
    CLOSED_THRESHOLD,
    DEFAULT_BOOT_LENGTH,
    DEFAULT_METRIC_POSITION,
    DEFAULT_N_ELEMENTS,
    SHIPPED_SKIS,
    Ski,
    camber_height,
    contact_lengths,
    get_ski,
    ski_stiffness,
    solve_beam,
    wax_pocket_length,
)

__all__ = ["SkiMetrics", "closing_load", "closing_load_from_bench", "ski_metrics"]


def _resolve_ski(ski: Ski | str) -> Ski:
    return get_ski(ski) if isinstance(ski, str) else ski


def closing_load(
    ski: Ski | str,
    *,
    load_position: float = DEFAULT_METRIC_POSITION,
    threshold: float = CLOSED_THRESHOLD,
    at: float = 0.0,
    mass_max: float = 300.0,
    tolerance: float = 0.01,
    boot_length: float = DEFAULT_BOOT_LENGTH,
    n_elements: int = DEFAULT_N_ELEMENTS,
) -> float:
    """Mass [kg] at which h(at) first drops below ``threshold`` on the beam, by bisection.

    Returns ``inf`` when the ski is still open at ``mass_max``. Assumes h(at) decreases with
    the mass (true for a beam pressed on a plane).
    """
    sk = _resolve_ski(ski)

    def h(m: float) -> float:
        sol = solve_beam(
            sk, mass=m, load_position=load_position, boot_length=boot_length, n_elements=n_elements
        )
        return float(sol.sample(np.array([at]))[0])

    if h(mass_max) >= threshold:
        return float("inf")
    lo, hi = 0.0, float(mass_max)
    while hi - lo > tolerance:
        mid = 0.5 * (lo + hi)
        if mid > 0 and h(mid) < threshold:
            hi = mid
        else:
            lo = mid
    return hi


def closing_load_from_bench(
    bench: BenchData,
    *,
    load_position: float = DEFAULT_METRIC_POSITION,
    threshold: float = CLOSED_THRESHOLD,
    at: float = 0.0,
    ski: str | None = None,
) -> float:
    """Closing load [kg] read off a bench: first crossing of h(at) below ``threshold``.

    Linear interpolation in mass between the two bench masses around the crossing. ``inf`` if
    the ski never closes within the bench's masses; the smallest mass if already closed there.
    """
    ms, hs_mm = bench.heights_at(load_position_mm=load_position * 1e3, x_mm=at * 1e3, ski=ski)
    hs = hs_mm * 1e-3
    below = np.flatnonzero(hs < threshold)
    if below.size == 0:
        return float("inf")
    j = int(below[0])
    if j == 0:
        return float(ms[0])
    m0, m1, h0, h1 = ms[j - 1], ms[j], hs[j - 1], hs[j]
    return float(m0 + (m1 - m0) * (h0 - threshold) / (h0 - h1))


def _bench_profile_at_mass(
    bench: BenchData, ski: str, mass: float, load_position: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Profile (x [m], h [m]) at ``mass`` [kg] interpolated between the bench's masses."""
    x_mm, h_mm = bench.profile_at_mass(mass_kg=mass, load_position_mm=load_position * 1e3, ski=ski)
    return x_mm * 1e-3, h_mm * 1e-3


def _bench_kick_zone(bench: BenchData, name: str) -> tuple[float, float] | None:
    """Kick zone [m] of ski ``name``: from the metadata if it describes that ski, else from the
    shipped ski of that name, else none."""
    if bench.describes_kick_zone(name):
        kz = bench.kick_zone_mm(name)
        return None if kz is None else (kz[0] * 1e-3, kz[1] * 1e-3)
    if name in SHIPPED_SKIS:
        return get_ski(name).kick_zone
    return None


@dataclass(frozen=True, kw_only=True)
class SkiMetrics:
    """The practitioners' numbers of one ski for one body mass and load position (SI units).

    Heights [m], lengths [m], masses [kg], stiffness [N/m]. ``*_half`` / ``*_full``: under half
    / full body weight at ``load_position``. Contact lengths use Breitschädel's 50 µm criterion.
    """

    ski: str
    source: str
    body_mass: float
    load_position: float
    camber_half: float
    camber_full: float
    pocket_length_01_half: float
    pocket_length_02_half: float
    pocket_length_01_full: float
    pocket_length_02_full: float
    closing_load: float
    stiffness: float
    rear_contact_half: float
    front_contact_half: float
    rear_contact_full: float
    front_contact_full: float

    def as_field_units(self) -> dict[str, Any]:
        """The metrics with field units in the keys (mm, kg, N/mm), for tables and JSON."""
        mm = 1e3
        return {
            "ski": self.ski,
            "source": self.source,
            "body_mass_kg": self.body_mass,
            "load_position_mm": self.load_position * mm,
            "camber_half_mm": self.camber_half * mm,
            "camber_full_mm": self.camber_full * mm,
            "pocket_length_0.1mm_half_mm": self.pocket_length_01_half * mm,
            "pocket_length_0.2mm_half_mm": self.pocket_length_02_half * mm,
            "pocket_length_0.1mm_full_mm": self.pocket_length_01_full * mm,
            "pocket_length_0.2mm_full_mm": self.pocket_length_02_full * mm,
            "closing_load_kg": self.closing_load,
            "stiffness_n_per_mm": self.stiffness / mm,
            "rear_contact_half_mm": self.rear_contact_half * mm,
            "front_contact_half_mm": self.front_contact_half * mm,
            "rear_contact_full_mm": self.rear_contact_full * mm,
            "front_contact_full_mm": self.front_contact_full * mm,
        }


def _metrics_from_profiles(
    *,
    name: str,
    source: str,
    body_mass: float,
    load_position: float,
    half: tuple[NDArray[np.float64], NDArray[np.float64]],
    full: tuple[NDArray[np.float64], NDArray[np.float64]],
    closing: float,
    kick_zone: tuple[float, float] | None,
) -> SkiMetrics:
    ch, cf = camber_height(*half), camber_height(*full)
    if ch <= CLOSED_THRESHOLD:
        import warnings

        from skisnow._errors import DomainWarning

        warnings.warn(
            DomainWarning(
                f"{name}: the camber pocket is already closed at half the body mass "
                f"({0.5 * body_mass:g} kg at {load_position * 1e3:g} mm: camber "
                f"{ch * 1e3:.2f} mm <= {CLOSED_THRESHOLD * 1e3:g} mm), so Breitschädel's "
                f"stiffness between half and full body weight "
                f"({ski_stiffness(ch, cf, body_mass) * 1e-3:.3g} N/mm) measures the closed ski "
                f"on the stone, not its camber; give a body mass below "
                f"{2 * closing:.0f} kg (twice the closing load) for a camber stiffness"
                if np.isfinite(closing)
                else f"{name}: the camber pocket is already closed at half the body mass; "
                "Breitschädel's stiffness does not measure the camber"
            ),
            stacklevel=3,
        )
    lh = contact_lengths(*half, kick_zone=kick_zone)
    lf = contact_lengths(*full, kick_zone=kick_zone)
    return SkiMetrics(
        ski=name,
        source=source,
        body_mass=body_mass,
        load_position=load_position,
        camber_half=ch,
        camber_full=cf,
        pocket_length_01_half=wax_pocket_length(*half, threshold=0.1e-3),
        pocket_length_02_half=wax_pocket_length(*half, threshold=0.2e-3),
        pocket_length_01_full=wax_pocket_length(*full, threshold=0.1e-3),
        pocket_length_02_full=wax_pocket_length(*full, threshold=0.2e-3),
        closing_load=closing,
        stiffness=ski_stiffness(ch, cf, body_mass),
        rear_contact_half=lh["rear"],
        front_contact_half=lh["front"],
        rear_contact_full=lf["rear"],
        front_contact_full=lf["front"],
    )


def ski_metrics(
    source: Ski | str | BenchData,
    *,
    body_mass: float = 65.0,
    load_position: float = DEFAULT_METRIC_POSITION,
    ski: str | None = None,
) -> SkiMetrics:
    """Practitioners' metrics of a ski from the beam (a :class:`Ski` or a shipped name) or a bench.

    Parameters
    ----------
    source
        a :class:`Ski`, a shipped ski name, or :class:`~skisnow.bench.BenchData`.
    body_mass
        the skier's mass [kg] (half and full body weight are applied).
    load_position
        x_m [m] of both loads (default -0.080 m, the practitioners' position).
    ski
        which ski of a multi-ski bench.

    From a bench, the profiles at ½ and 1 body mass are interpolated linearly between the two
    nearest bench masses at ``load_position`` (which must be one of the bench's positions) and
    the kick zone is taken from the metadata (``kick_zone_mm``) when it describes that ski, else
    from the shipped ski of the same name, else there is none.
    """
    if not (np.isfinite(body_mass) and body_mass > 0):
        raise InputError(f"body_mass must be > 0 kg, got {body_mass}")
    if isinstance(source, BenchData):
        name = source.ski_name(ski)
        kick = _bench_kick_zone(source, name)
        return _metrics_from_profiles(
            name=name,
            source="bench",
            body_mass=body_mass,
            load_position=load_position,
            half=_bench_profile_at_mass(source, name, 0.5 * body_mass, load_position),
            full=_bench_profile_at_mass(source, name, body_mass, load_position),
            closing=closing_load_from_bench(source, load_position=load_position, ski=name),
            kick_zone=kick,
        )
    sk = _resolve_ski(source)  # a shipped name or a ski file
    if not isinstance(sk, Ski):
        raise InputError(f"source must be a Ski, a ski name or BenchData, not {type(source)}")
    from skisnow.bench._virtual import bench_grid

    x = bench_grid(sk)
    profiles = []
    for m in (0.5 * body_mass, body_mass):
        sol = solve_beam(sk, mass=m, load_position=load_position)
        profiles.append((x, sol.sample(x)))
    return _metrics_from_profiles(
        name=sk.name,
        source="beam",
        body_mass=body_mass,
        load_position=load_position,
        half=profiles[0],
        full=profiles[1],
        closing=closing_load(sk, load_position=load_position),
        kick_zone=sk.kick_zone,
    )
