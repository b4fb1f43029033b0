"""A fleet side by side: practitioners' metrics and the contact at half and full body weight.

For each ski of a fleet, one athlete (body mass m) and the day's snow (E): the bench metrics a
technician reads (camber under ½ and 1 body weight, wax-pocket length, closing load, stiffness;
:func:`skisnow.bench.ski_metrics`) and the apparent contact at ½ m and m (Kalliorinne et al.
2023: loaded profile, eq. 1, on the elastic half-space with force and moment balance, eq. 2–3):
zone lengths, areas, mean and peak pressures, load shares, and the kick-zone contact. Then a
ranking by a criterion of :data:`CRITERIA` (the same ranking across a range of snow moduli:
:mod:`skisnow.workflows._fleet_snow`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from skisnow._errors import InputError, SkisnowError
from skisnow.workflows._skis import FleetSki, resolve_fleet
from skisnow.workflows._solve import choose_route, loaded_profiles, solve_loaded, stations

__all__ = [
    "CRITERIA",
    "Criterion",
    "FleetComparison",
    "FleetEntry",
    "compare_fleet",
]

#: The reference load position [m]: 120 mm behind the balance point, as in the paper's figures.
DEFAULT_LOAD_POSITION = -0.120
_LOADS = {"half": 0.5, "full": 1.0}
#: The paper's zones, the total, and the regions (``kick`` is the kick-zone region).
_ZONES = ("rear", "middle", "front", "total", "rear_glide", "kick", "front_glide")


@dataclass(frozen=True, kw_only=True)
class FleetEntry:
    """One ski of a comparison: its metrics and its two contact cases (SI units).

    ``cases`` maps ``'half'`` and ``'full'`` (body weight) to :class:`skisnow.pipeline.Case`;
    ``intervals`` the same keys to their :class:`~skisnow.pipeline.Intervals` when the ski
    carries its posterior and samples were asked for (``None``: no uncertainty recorded).
    """

    ski: FleetSki
    route: str
    route_note: str | None
    metrics: Any  # skisnow.bench.SkiMetrics
    cases: dict[str, Any] = field(repr=False)
    intervals: dict[str, Any] | None = field(default=None, repr=False)

    def interval(self, column: str) -> tuple[float, float] | None:
        """The 95 % interval of a record column (field unit), ``None`` where there is none."""
        from skisnow.workflows._fleet_intervals import column_interval

        return column_interval(self.intervals, column)

    def record(self) -> dict[str, Any]:
        """One flat record in field units (mm, cm², kPa, kg, N/mm) — a row of the table.

        Where there is no value it is NaN (JSON null, an empty CSV cell, "—" in a table): the
        pressures of a zone without contact, and every kick-zone column (``kick_contact``:
        ``None``) of a ski without a kick zone.
        """
        m = self.metrics
        rec: dict[str, Any] = {
            "ski": self.ski.label,
            "origin": self.ski.origin,
            "profile_route": self.route,
            "load_position_mm": self.cases["full"].load_position * 1e3,
            "camber_half_mm": m.camber_half * 1e3,
            "camber_full_mm": m.camber_full * 1e3,
            "pocket_0.1mm_half_mm": m.pocket_length_01_half * 1e3,
            "pocket_0.1mm_full_mm": m.pocket_length_01_full * 1e3,
            "closing_load_kg": m.closing_load,
            "stiffness_n_per_mm": m.stiffness * 1e-3,
        }
        nan = float("nan")
        for load in _LOADS:
            z = self.cases[load].zones
            kick = z.kick_zone is not None  # a skate ski has no kick zone: no values there
            for name in _ZONES:
                zone = z[name]
                p = f"{load}_{name}"
                none = name == "kick" and not kick
                rec[f"{p}_length_mm"] = nan if none else zone.length * 1e3
                rec[f"{p}_area_cm2"] = nan if none else zone.area * 1e4
                rec[f"{p}_mean_pressure_kpa"] = zone.mean_pressure * 1e-3
                rec[f"{p}_peak_pressure_kpa"] = zone.max_pressure * 1e-3
                rec[f"{p}_load_share"] = nan if none else zone.load_share
            rec[f"{load}_kick_contact"] = bool(z["kick"].length > 0) if kick else None
        return rec


@dataclass(frozen=True, kw_only=True)
class Criterion:
    """A ranking criterion: a value per ski (from its record) and which way is better."""

    name: str
    description: str
    column: str
    better: Literal["lower", "higher"]
    snow_dependent: bool = True
    label: str = ""

    @property
    def axis_label(self) -> str:
        """The criterion in the field's words, with its unit (figures and tables)."""
        return self.label or self.column

    def order(self, values: Sequence[float]) -> np.ndarray:
        """Indices from best to worst (NaN last; stable for ties).

        An infinite value is a real answer, not a missing one (a closing load of ``inf``: the
        pocket never closes, the stiffest), ranked at its end of the order.
        """
        v = np.asarray(values, dtype=float)
        key = v if self.better == "lower" else -v
        key = np.where(np.isnan(key), np.inf, key)
        return np.argsort(key, kind="stable")


#: The documented ranking criteria (all at full body weight at the load position, on the snow).
CRITERIA: dict[str, Criterion] = {
    c.name: c
    for c in (
        Criterion(
            name="mean-pressure",
            description="mean contact pressure of the whole footprint at full body weight; lower "
            "first (the ski floats: less compaction and ploughing on soft snow)",
            column="full_total_mean_pressure_kpa",
            label="mean contact pressure at full body weight [kPa]",
            better="lower",
        ),
        Criterion(
            name="peak-pressure",
            description="peak contact pressure at full body weight; lower first (no pressure "
            "spike at a glide-zone end that digs into soft snow)",
            column="full_total_peak_pressure_kpa",
            label="peak contact pressure at full body weight [kPa]",
            better="lower",
        ),
        Criterion(
            name="contact-length",
            description="total contact length at full body weight; shorter first (less base in "
            "contact: the practitioners' choice for hard, cold snow)",
            column="full_total_length_mm",
            label="contact length at full body weight [mm]",
            better="lower",
        ),
        Criterion(
            name="kick-share",
            description="share of the load carried between the kick-zone marks at full body "
            "weight; lower first (the grip wax stays off the snow while gliding)",
            column="full_kick_load_share",
            label="load share of the kick zone at full body weight",
            better="lower",
        ),
        Criterion(
            name="rear-share",
            description="share of the load on the rear glide zone at full body weight; higher "
            "first (the load stays behind the foot and the shovel runs light)",
            column="full_rear_load_share",
            label="load share of the rear zone at full body weight",
            better="higher",
        ),
        Criterion(
            name="closing-load",
            description="load that closes the wax pocket on the bench (from the beam); higher "
            "first (a stiffer pocket); does not depend on the snow",
            column="closing_load_kg",
            label="load closing the wax pocket [kg]",
            better="higher",
            snow_dependent=False,
        ),
    )
}


@dataclass(frozen=True, kw_only=True)
class FleetComparison:
    """The comparison of a fleet: entries, the skis that could not be compared, the inputs."""

    entries: tuple[FleetEntry, ...]
    failures: tuple[tuple[str, str], ...]
    body_mass: float
    snow_modulus: float
    load_position: float
    ski_model: str

    def records(self) -> list[dict[str, Any]]:
        """One record per ski, field units."""
        return [e.record() for e in self.entries]

    def ranking(self, criterion: str) -> list[dict[str, Any]]:
        """The skis from best to worst by ``criterion`` (a key of :data:`CRITERIA`).

        Tied skis (equal values: identical skis; or, for skis carrying their posterior,
        overlapping 95 % intervals: *a tie within uncertainty*, ``within_uncertainty``) share
        a rank (``1, 1, 3``), say so in ``tied`` and name each other in ``tied_with``
        (:mod:`skisnow.workflows._ties`); ``interval`` is ``[low, high]`` or ``None`` (no
        uncertainty recorded: the value counts as exact). On a patch-based zone (rear, middle,
        front) skis in different patch topologies, or whose samples straddle two, tie as *not
        comparable by this criterion* (``not_comparable_with``, ``patch_topology``;
        :mod:`skisnow.workflows._topology`).
        """
        from skisnow.workflows._ties import competition_ranks, tied_with
        from skisnow.workflows._topology import comparable

        crit = _criterion(criterion)
        recs = self.records()
        values = [float(r[crit.column]) for r in recs]
        ivs = [e.interval(crit.column) for e in self.entries]
        bounds = [iv if iv is not None else (v, v) for iv, v in zip(ivs, values, strict=True)]
        tops = self.topologies(criterion)
        ok = comparable(tops)
        ranks = competition_ranks(values, better=crit.better, intervals=bounds, comparable=ok)
        ties = tied_with(values, better=crit.better, intervals=bounds, comparable=ok)
        return [
            {"rank": int(ranks[i]), "tied": bool(ties[i]), "ski": recs[i]["ski"],
             crit.column: values[i], "tied_with": [recs[j]["ski"] for j in ties[i]],
             "interval": None if ivs[i] is None else list(ivs[i]),
             "within_uncertainty": any(values[j] != values[i] for j in ties[i]),
             "not_comparable_with": [recs[j]["ski"] for j in np.flatnonzero(~ok[i])],
             "patch_topology": None if tops[i] is None else tops[i].describe()}
            for i in crit.order(values)
        ]  # fmt: skip

    def topologies(self, criterion: str) -> list[Any]:
        """Each ski's patch topology on a patch-based criterion at full body weight (with its
        posterior samples' shares), ``None`` each for another criterion."""
        from skisnow.workflows._topology import patch_zone, ski_topology

        zone = patch_zone(_criterion(criterion).column)
        if zone is None:
            return [None] * len(self.entries)
        return [
            ski_topology(e.cases["full"].zones,
                         () if e.intervals is None else e.intervals["full"].sample_topologies,
                         zone)
            for e in self.entries
        ]  # fmt: skip

    def topology_warnings(self, criterion: str) -> list[str]:
        """The warnings of a patch-based criterion whose skis are not comparable by it."""
        from skisnow.workflows._topology import patch_zone, topology_warnings

        zone = patch_zone(_criterion(criterion).column)
        labels = [e.ski.label for e in self.entries]
        return [] if zone is None else topology_warnings(labels, self.topologies(criterion),
                                                         criterion, zone)  # fmt: skip


def _criterion(name: str) -> Criterion:
    if name not in CRITERIA:
        raise InputError(f"unknown ranking criterion {name!r}; choose one of {', '.join(CRITERIA)}")
    return CRITERIA[name]


def _check_inputs(body_mass: float, snow_modulus: float, ski_model: str) -> None:
    if not (np.isfinite(body_mass) and 20.0 <= body_mass <= 150.0):
        raise InputError(f"body mass must be within 20..150 kg, got {body_mass:g} kg")
    if not (np.isfinite(snow_modulus) and snow_modulus > 0):
        raise InputError(f"snow modulus must be a positive number of Pa, got {snow_modulus!r}")
    if ski_model not in ("rigid", "flexible"):
        raise InputError(f"ski model must be rigid or flexible, got {ski_model!r}")


def _entry(
    fs: FleetSki,
    *,
    body_mass: float,
    snow_modulus: float,
    load_position: float,
    n_points: int,
    ski_model: str,
    samples: int = 0,
) -> FleetEntry:
    from skisnow.bench import ski_metrics

    x = stations(fs, n_points)
    masses = np.array([_LOADS[k] * body_mass for k in _LOADS])
    positions = np.full(masses.size, load_position)
    if ski_model == "flexible":
        route, note = "flexible", None
        heights = [None] * masses.size
    else:
        route, note = choose_route(fs, masses, positions, x)
        heights = loaded_profiles(fs, masses, positions, x, route=route)
    cases = {
        key: solve_loaded(
            fs,
            x,
            h,
            mass=m,
            load_position=load_position,
            snow_modulus=snow_modulus,
            route=route,
        )
        for key, m, h in zip(_LOADS, masses, heights, strict=True)
    }
    metrics = ski_metrics(fs.ski, body_mass=body_mass, load_position=load_position)
    from skisnow.workflows._fleet_intervals import case_set_intervals

    intervals = case_set_intervals(cases, samples=samples)
    return FleetEntry(
        ski=fs, route=route, route_note=note, metrics=metrics, cases=cases, intervals=intervals
    )


def compare_fleet(
    skis: Sequence[str | FleetSki],
    *,
    body_mass: float,
    snow_modulus: float,
    load_position: float = DEFAULT_LOAD_POSITION,
    ski_model: Literal["rigid", "flexible"] = "rigid",
    n_points: int = 4096,
    progress: Callable[[int, int], None] | None = None,
    samples: int = 0,
) -> FleetComparison:
    """Compare the skis of a fleet for one athlete on one snow.

    Parameters
    ----------
    skis
        Shipped names, ski files, bench files (or resolved :class:`FleetSki`).
    body_mass
        The athlete's mass [kg]; contact is solved at ½ and 1 body weight on one ski.
    snow_modulus
        Young's modulus of the snow [Pa].
    load_position
        x_m [m] of the load (default 120 mm behind the balance point, the paper's reference).
    ski_model
        ``'rigid'`` (the paper's rigid loaded profile) or ``'flexible'`` (the ski's beam and the
        snow solved together, :func:`skisnow.contact.solve_flexible`).
    n_points
        Stations along each ski.
    progress
        ``progress(done, total)`` after each ski.
    samples
        Posterior samples for the 95 % intervals of the contact answers of a ski that carries
        its posterior (an identified ski; :func:`skisnow.pipeline.case_intervals`); 0: none.

    Returns
    -------
    FleetComparison
        A ski that cannot be read or solved is listed in ``failures`` with its message; the
        others are compared.
    """
    _check_inputs(body_mass, snow_modulus, ski_model)
    resolved, failures = resolve_fleet(list(skis))
    entries = []
    for done, fs in enumerate(resolved, start=1):
        try:
            entries.append(
                _entry(
                    fs,
                    body_mass=body_mass,
                    snow_modulus=snow_modulus,
                    load_position=load_position,
                    n_points=n_points,
                    ski_model=ski_model,
                    samples=samples,
                )
            )
        except SkisnowError as exc:
            failures.append((fs.label, str(exc)))
        if progress is not None:
            progress(done, len(resolved))
    return FleetComparison(
        entries=tuple(entries),
        failures=tuple(failures),
        body_mass=float(body_mass),
        snow_modulus=float(snow_modulus),
        load_position=float(load_position),
        ski_model=ski_model,
    )
