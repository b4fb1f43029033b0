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
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from skisnow._errors import InputError
from skisnow.contact import ZoneMetrics
from skisnow.ski import Ski, get_ski

__all__ = [
    "CAPTIONS",
    "REPRODUCTION_TOLERANCES",
    "ROUTES",
    "TOLERANCES",
    "CaptionCase",
    "CaptionRow",
    "CaptionZone",
    "Tolerances",
    "caption_table",
    "compare_case",
    "solve_caption_case",
    "tolerances_of",
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

    def shares(self) -> dict[str, tuple[float, bool]]:
        """The paper's load share of every zone: ``{zone: (share, implied)}``.

        Stated where the caption states them (Figures 5 and 6); otherwise implied by the
        caption's own numbers, length × mean pressure over the sum over the zones (the force
        per unit width, the strip being the same width for every zone; Figures 4 and 7: the
        classic 70/30 on the stone, on 50 and on 200 MPa, the skate 67/33 on the stone).
        """
        if all(z.load_share is not None for z in self.zones):
            return {z.zone: (float(z.load_share), False) for z in self.zones}  # type: ignore[arg-type]
        forces = {z.zone: z.length * z.mean_pressure for z in self.zones}
        total = sum(forces.values())
        return {name: (f / total, True) for name, f in forces.items()}

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
    """Caption tolerances: relative length and mean pressure, absolute load share.

    ``implied_shares``: also hold the load shares the captions of Figures 4 and 7 imply but do
    not state (each zone's length × mean pressure over the sum, :meth:`CaptionCase.shares`).
    """

    length: float = 0.20
    pressure: float = 0.25
    share: float = 0.05
    implied_shares: bool = False


#: The tolerances the plausible skis (``classic``, ``skate``) were fitted to: lengths ±20 %,
#: mean pressures ±25 %, stated load shares ±5 points, patch counts exact.
TOLERANCES = Tolerances()
#: The tolerances of the reproduction skis (``classic-k22``, ``skate-k22``, issue 30): every
#: length and mean pressure within ±10 %, every load share within ±3 points including the
#: shares Figures 4 and 7 imply (length × pressure), patch counts exact.
REPRODUCTION_TOLERANCES = Tolerances(length=0.10, pressure=0.10, share=0.03, implied_shares=True)


@dataclass(frozen=True, kw_only=True)
class CaptionRow:
    """Paper against skisnow for one zone of one case (SI; ``None`` where the paper is silent).

    ``ok`` is True when every held number is within the tolerances (the stated load shares,
    and the implied ones when the tolerances ask for them) and the patch count, where stated,
    is exact; a zone the paper does not list must be empty in the model. ``paper_share`` is the
    paper's share of the zone, stated or implied (``share_implied``); ``share_error`` is
    measured against it either way.
    """

    case: CaptionCase
    ski: str
    route: str
    zone: str
    paper: CaptionZone | None
    length: float
    mean_pressure: float
    load_share: float
    patches: int
    length_error: float | None
    pressure_error: float | None
    paper_share: float | None
    share_implied: bool
    share_error: float | None
    ok: bool

    def as_dict(self) -> dict:
        """Field units (mm, kPa, %) for tables and JSON."""
        p = self.paper
        return {
            "case": self.case.label,
            "figure": self.case.figure,
            "ski": self.ski,
            "kind": self.case.ski,
            "route": self.route,
            "mass_kg": self.case.mass,
            "load_position_mm": self.case.load_position * 1e3,
            "counter_modulus_mpa": self.case.counter_modulus * 1e-6,
            "zone": self.zone,
            "paper_length_mm": None if p is None else p.length * 1e3,
            "length_mm": self.length * 1e3,
            "paper_mean_pressure_kpa": None if p is None else p.mean_pressure * 1e-3,
            "mean_pressure_kpa": self.mean_pressure * 1e-3,
            "paper_load_share_pct": None if self.paper_share is None else self.paper_share * 100,
            "paper_share_implied": self.share_implied,
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


#: The profile routes of a caption case: ``'network'`` (the paper's: the camber network
#: trained on the ski's bench) and ``'beam'`` (the beam on the rigid plane, which a perfect
#: network would emulate).
ROUTES: tuple[str, ...] = ("network", "beam")


def solve_caption_case(
    case: CaptionCase, ski: Ski, *, route: str = "beam", n_points: int = N_POINTS
) -> ZoneMetrics:
    """Run one caption case with the paper's pipeline on ``ski`` and return its zones.

    Through the one door for a case, :func:`skisnow.pipeline.solve_case`: the loaded camber
    profile at ``n_points`` stations — ``route='network'``, the paper's route, from the ski's
    camber network trained on its bench on the stone (a shipped ski's); ``'beam'``, from the
    beam on the rigid plane (the virtual SkiSelector bench) that the network emulates —
    pressed as a rigid body into the half-space of equivalent modulus E' (Kalliorinne et al.
    2023, eq. 2, E_base = 900 MPa, ν = 0.3) with force and moment balance (eq. 3, strip
    model); the patches are grouped into the paper's zones (:func:`skisnow.contact.paper_zones`)
    with the ski's kick zone.
    """
    from skisnow.pipeline import solve_case

    if route not in ROUTES:
        raise InputError(f"route: {route!r} is not one of {ROUTES}")
    result = solve_case(
        ski, mass=case.mass, load_position=case.load_position,
        snow_modulus=case.counter_modulus, profile_source=route, n_points=n_points,
        base=BASE_MODULUS, poisson=POISSON,
    )  # fmt: skip
    return result.zones


def _rel(model: float, paper: float) -> float:
    return model / paper - 1.0 if math.isfinite(model) else math.inf


def compare_case(
    case: CaptionCase,
    zones: ZoneMetrics,
    *,
    tolerances: Tolerances = TOLERANCES,
    ski: str | None = None,
    route: str = "beam",
) -> list[CaptionRow]:
    """Rows paper vs model of one case (every zone the paper lists, and any extra model zone).

    ``ski`` (the ski's name, default the case's kind) and ``route`` label the rows.
    """
    stated = {z.zone: z for z in case.zones}
    shares = case.shares()
    rows = []
    for name in ("rear", "middle", "front"):
        got = zones[name]
        paper = stated.get(name)
        if paper is None and got.patches == 0:
            continue
        le = pe = se = ps = None
        implied = False
        if paper is None:
            ok = False  # a zone the paper does not have
        else:
            le = _rel(got.length, paper.length)
            pe = _rel(got.mean_pressure, paper.mean_pressure)
            ok = abs(le) <= tolerances.length and abs(pe) <= tolerances.pressure
            ps, implied = shares[name]
            se = got.load_share - ps
            if not implied or tolerances.implied_shares:
                ok = ok and abs(se) <= tolerances.share
            if paper.patches is not None:
                ok = ok and got.patches == paper.patches
        row = CaptionRow(
            case=case, ski=ski or case.ski, route=route, zone=name, paper=paper,
            length=got.length, mean_pressure=got.mean_pressure, load_share=got.load_share,
            patches=got.patches, length_error=le, pressure_error=pe, paper_share=ps,
            share_implied=implied, share_error=se, ok=ok,
        )  # fmt: skip
        rows.append(row)
    return rows


def tolerances_of(ski: Ski) -> Tolerances:
    """The tolerances a ski is held to: :data:`REPRODUCTION_TOLERANCES` for a reproduction ski
    (its name in :data:`skisnow.ski.REPRODUCTION_SKIS`), :data:`TOLERANCES` otherwise."""
    from skisnow.ski import REPRODUCTION_SKIS

    return REPRODUCTION_TOLERANCES if ski.name in REPRODUCTION_SKIS else TOLERANCES


def _resolve_skis(skis: Mapping[str, Ski] | Sequence[Ski | str] | None) -> list[Ski]:
    from skisnow.ski import SHIPPED_SKIS

    if skis is None:
        return [get_ski(name) for name in SHIPPED_SKIS]
    items = list(skis.items()) if isinstance(skis, Mapping) else [(None, s) for s in skis]
    out = []
    for key, ski in items:
        if isinstance(ski, str) and key is None:
            ski = get_ski(ski)
        if not isinstance(ski, Ski):
            raise InputError(f"caption_table: skis[{key!r}] must be a Ski, got {type(ski)}")
        if key is not None and key != ski.kind:
            raise InputError(
                f"caption_table: skis keys must be 'classic' or 'skate' (the ski's kind), "
                f"not {key!r}"
            )
        out.append(ski)
    return out


def caption_table(
    skis: Mapping[str, Ski] | Sequence[Ski | str] | None = None,
    *,
    route: str = "beam",
    tolerances: Tolerances | None = None,
    n_points: int = N_POINTS,
) -> list[CaptionRow]:
    """Paper against skisnow for every caption of Figures 4–7 (Kalliorinne et al. 2023).

    Parameters
    ----------
    skis
        Skis (or shipped names) whose captions to run, the cases of each ski's kind; or
        ``{"classic": Ski, "skate": Ski}``. Default: every shipped ski
        (:data:`skisnow.ski.SHIPPED_SKIS`: the plausible and the reproduction skis).
    route
        ``'beam'`` or ``'network'`` (:data:`ROUTES`, :func:`solve_caption_case`).
    tolerances
        See :data:`TOLERANCES`; default: each ski's own (:func:`tolerances_of`).
    n_points
        Stations along the ski of the strip model.
    """
    rows: list[CaptionRow] = []
    for ski in _resolve_skis(skis):
        tol = tolerances_of(ski) if tolerances is None else tolerances
        for case in CAPTIONS:
            if case.ski != ski.kind:
                continue
            zones = solve_caption_case(case, ski, route=route, n_points=n_points)
            rows.extend(compare_case(case, zones, tolerances=tol, ski=ski.name, route=route))
    return rows
