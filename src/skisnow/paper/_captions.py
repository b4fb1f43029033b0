"""The contact numbers in the captions of Kalliorinne et al. (2023), Figures 4–7, and skisnow's.

The paper states, for a classic and a skate ski of its own (Fischer skis measured on the
SkiSelector), the apparent contact length, mean apparent pressure and — for Figures 5 and 6 —
the load share of each zone, computed with its pipeline: the ski-camber profile of the loaded
ski on the stone (bench), taken as a rigid body, pressed into an elastic half-space with force
and moment balance (eq. 3), E_base = 900 MPa, ν = 0.3 (eq. 2). :data:`CAPTIONS` holds those
numbers; :func:`caption_table` runs the same pipeline on skisnow's skis (the beam on the rigid
plane is the virtual bench, the strip model the half-space) and compares.

These numbers are what the shipped skis are FITTED to (``benchmarks/calibrate_skis.py``); a
caption table within its tolerances is a calibration, not a validation. The paper's Figures 8–9
findings (:mod:`skisnow.paper._findings`) are the validation.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from skisnow._errors import InputError
from skisnow.contact import ZoneMetrics
from skisnow.ski import Ski, get_ski

__all__ = [
    "CAPTIONS",
    "TOLERANCES",
    "CaptionCase",
    "CaptionRow",
    "CaptionZone",
    "Tolerances",
    "caption_table",
    "solve_caption_case",
]

#: Ski-base modulus [Pa] and Poisson ratio of the paper's contact calculations (§3.2).
BASE_MODULUS = 900e6
POISSON = 0.3
#: Stations along the ski of the strip model (the contact CLI's default).
N_POINTS = 2048


@dataclass(frozen=True, kw_only=True)
class CaptionZone:
    """One zone of a caption: length [m], mean pressure [Pa], load share (or None), patches."""

    zone: str
    length: float
    mean_pressure: float
    load_share: float | None = None
    patches: int | None = None


@dataclass(frozen=True, kw_only=True)
class CaptionCase:
    """One load case of a caption: figure, ski, mass [kg], x_m [m], counter modulus [Pa]."""

    figure: str
    ski: str
    mass: float
    load_position: float
    counter_modulus: float
    zones: tuple[CaptionZone, ...]

    @property
    def label(self) -> str:
        """e.g. ``Fig. 5 skate 30 kg -120 mm 100 MPa``."""
        e = self.counter_modulus
        snow = "stone" if e >= 1e10 else f"{e * 1e-6:g} MPa"
        return (
            f"{self.figure} {self.ski} {self.mass:g} kg {self.load_position * 1e3:+.0f} mm {snow}"
        )


def _z(zone: str, mm: float, kpa: float, share: float | None = None, patches: int | None = None):
    return CaptionZone(
        zone=zone, length=mm * 1e-3, mean_pressure=kpa * 1e3, load_share=share, patches=patches
    )


_STONE = 70e9
#: The captions of Figures 4–7 (Kalliorinne et al. 2023). Patch counts where the text states
#: them: the skate's front zone is one patch at 30 kg and two at 60 kg (Fig. 5); the classic at
#: 60 kg, -70 mm has a separate third patch under the foot (Fig. 6, right). Figure 6 (left)
#: reads 50 mm in the text and 51 mm in the caption; 51 mm is used.
CAPTIONS: tuple[CaptionCase, ...] = (
    CaptionCase(figure="Fig. 4", ski="classic", mass=30, load_position=-0.120,
                counter_modulus=_STONE, zones=(_z("rear", 28.1, 169), _z("front", 14.9, 137))),
    CaptionCase(figure="Fig. 7", ski="classic", mass=30, load_position=-0.120,
                counter_modulus=50e6, zones=(_z("rear", 141, 33.3), _z("front", 74, 27.2))),
    CaptionCase(figure="Fig. 7", ski="classic", mass=30, load_position=-0.120,
                counter_modulus=200e6, zones=(_z("rear", 98, 48.2), _z("front", 37, 52.7))),
    CaptionCase(figure="Fig. 6", ski="classic", mass=60, load_position=-0.210,
                counter_modulus=100e6,
                zones=(_z("rear", 200, 56.4, 0.84), _z("front", 51, 40.9, 0.16))),
    CaptionCase(figure="Fig. 6", ski="classic", mass=60, load_position=-0.070,
                counter_modulus=100e6,
                zones=(_z("rear", 146, 41.1, 0.45), _z("middle", 80.9, 46.6, 0.28, 1),
                       _z("front", 105, 34.3, 0.27))),
    CaptionCase(figure="Fig. 4", ski="skate", mass=30, load_position=-0.120,
                counter_modulus=_STONE, zones=(_z("rear", 52.7, 83.7), _z("front", 45.7, 48.1))),
    CaptionCase(figure="Fig. 5", ski="skate", mass=30, load_position=-0.120,
                counter_modulus=100e6,
                zones=(_z("rear", 146, 30.6, 0.67), _z("front", 162, 13.8, 0.33, 1))),
    CaptionCase(figure="Fig. 5", ski="skate", mass=60, load_position=-0.120,
                counter_modulus=100e6,
                zones=(_z("rear", 288, 33.2, 0.71), _z("front", 132, 28.9, 0.29, 2))),
)  # fmt: skip


@dataclass(frozen=True, kw_only=True)
class Tolerances:
    """Caption tolerances: relative length and mean pressure, absolute load share."""

    length: float = 0.20
    pressure: float = 0.25
    share: float = 0.05


#: The tolerances the shipped skis are held to: lengths ±20 %, mean pressures ±25 %, load
#: shares ±5 points, patch counts exact.
TOLERANCES = Tolerances()


@dataclass(frozen=True, kw_only=True)
class CaptionRow:
    """Paper against skisnow for one zone of one case (SI; ``None`` where the paper is silent).

    ``ok`` is True when every stated number is within the tolerances and the patch count (where
    stated) is exact; a zone the paper does not list must be empty in the model.
    """

    case: CaptionCase
    zone: str
    paper: CaptionZone | None
    length: float
    mean_pressure: float
    load_share: float
    patches: int
    length_error: float | None
    pressure_error: float | None
    share_error: float | None
    ok: bool

    def as_dict(self) -> dict:
        """Field units (mm, kPa, %) for tables and JSON."""
        p = self.paper
        return {
            "case": self.case.label,
            "figure": self.case.figure,
            "ski": self.case.ski,
            "mass_kg": self.case.mass,
            "load_position_mm": self.case.load_position * 1e3,
            "counter_modulus_mpa": self.case.counter_modulus * 1e-6,
            "zone": self.zone,
            "paper_length_mm": None if p is None else p.length * 1e3,
            "length_mm": self.length * 1e3,
            "paper_mean_pressure_kpa": None if p is None else p.mean_pressure * 1e-3,
            "mean_pressure_kpa": self.mean_pressure * 1e-3,
            "paper_load_share_pct": None
            if p is None or p.load_share is None
            else p.load_share * 100,
            "load_share_pct": self.load_share * 100,
            "paper_patches": None if p is None else p.patches,
            "patches": self.patches,
            "length_error_pct": None if self.length_error is None else self.length_error * 100,
            "pressure_error_pct": None
            if self.pressure_error is None
            else self.pressure_error * 100,
            "share_error_points": None if self.share_error is None else self.share_error * 100,
            "ok": self.ok,
        }


def solve_caption_case(case: CaptionCase, ski: Ski, *, n_points: int = N_POINTS) -> ZoneMetrics:
    """Run one caption case with the paper's pipeline on ``ski`` and return its zones.

    Through the one door for a case, :func:`skisnow.pipeline.solve_case`: the beam on the rigid
    plane (the virtual SkiSelector bench) gives the loaded camber profile at ``n_points``
    stations, pressed as a rigid body into the half-space of equivalent modulus E' (Kalliorinne
    et al. 2023, eq. 2, E_base = 900 MPa, ν = 0.3) with force and moment balance (eq. 3, strip
    model); the patches are grouped with the ski's kick zone.
    """
    from skisnow.pipeline import solve_case

    result = solve_case(
        ski, mass=case.mass, load_position=case.load_position,
        snow_modulus=case.counter_modulus, profile_source="beam", n_points=n_points,
        base=BASE_MODULUS, poisson=POISSON,
    )  # fmt: skip
    return result.zones


def _rel(model: float, paper: float) -> float:
    return model / paper - 1.0 if math.isfinite(model) else math.inf


def compare_case(
    case: CaptionCase, zones: ZoneMetrics, *, tolerances: Tolerances = TOLERANCES
) -> list[CaptionRow]:
    """Rows paper vs model of one case (every zone the paper lists, and any extra model zone)."""
    stated = {z.zone: z for z in case.zones}
    rows = []
    for name in ("rear", "middle", "front"):
        got = zones[name]
        paper = stated.get(name)
        if paper is None and got.patches == 0:
            continue
        le = pe = se = None
        if paper is None:
            ok = False  # a zone the paper does not have
        else:
            le = _rel(got.length, paper.length)
            pe = _rel(got.mean_pressure, paper.mean_pressure)
            ok = abs(le) <= tolerances.length and abs(pe) <= tolerances.pressure
            if paper.load_share is not None:
                se = got.load_share - paper.load_share
                ok = ok and abs(se) <= tolerances.share
            if paper.patches is not None:
                ok = ok and got.patches == paper.patches
        row = CaptionRow(
            case=case, zone=name, paper=paper, length=got.length,
            mean_pressure=got.mean_pressure, load_share=got.load_share,
            patches=got.patches, length_error=le, pressure_error=pe, share_error=se, ok=ok,
        )  # fmt: skip
        rows.append(row)
    return rows


def caption_table(
    skis: Mapping[str, Ski] | None = None,
    *,
    tolerances: Tolerances = TOLERANCES,
    n_points: int = N_POINTS,
) -> list[CaptionRow]:
    """Paper against skisnow for every caption of Figures 4–7 (Kalliorinne et al. 2023).

    Parameters
    ----------
    skis
        ``{"classic": Ski, "skate": Ski}``; default: the shipped skis. A missing kind skips its
        cases.
    tolerances
        See :data:`TOLERANCES`.
    n_points
        Stations along the ski of the strip model.
    """
    if skis is None:
        skis = {"classic": get_ski("classic"), "skate": get_ski("skate")}
    for kind, ski in skis.items():
        if kind not in ("classic", "skate"):
            raise InputError(f"caption_table: skis keys must be 'classic' or 'skate', not {kind!r}")
        if not isinstance(ski, Ski):
            raise InputError(f"caption_table: skis[{kind!r}] must be a Ski, got {type(ski)}")
    rows: list[CaptionRow] = []
    for case in CAPTIONS:
        ski = skis.get(case.ski)
        if ski is None:
            continue
        zones = solve_caption_case(case, ski, n_points=n_points)
        rows.extend(compare_case(case, zones, tolerances=tolerances))
    return rows
