"""The intervals of a fleet's answers: an identified ski's contact at ½ and 1 body weight on its
posterior samples (issue 25, item 4), in the columns of the fleet's records.

Each case of a :class:`~skisnow.workflows.FleetEntry` whose ski carries its posterior gets the
95 % intervals of :func:`skisnow.pipeline.case_intervals` (the case solved on posterior samples
of the ski); a ski without one (a shipped definition, a ski file without bands) has none, and
its values count as exact in a ranking (a zero-width interval) — which the outputs say.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["case_set_intervals", "column_interval", "interval_records", "snow_intervals"]

#: the quantity of a record column's tail -> (attribute of the zone, factor from SI)
_COLUMNS = {
    "length_mm": ("length", 1e3),
    "area_cm2": ("area", 1e4),
    "mean_pressure_kpa": ("mean_pressure", 1e-3),
    "peak_pressure_kpa": ("max_pressure", 1e-3),
    "load_share": ("load_share", 1.0),
}


def case_set_intervals(
    cases: Mapping[str, Any], *, samples: int, seed: int = 0
) -> dict[str, Any] | None:
    """``{load: Intervals}`` for the cases of one ski (``None``: no posterior, or samples 0)."""
    from skisnow.pipeline import case_intervals

    if samples <= 0:
        return None
    out = {}
    for load, case in cases.items():
        iv = case_intervals(case, samples=samples, seed=seed)
        if iv is None:
            return None
        out[load] = iv
    return out


def column_interval(intervals: Mapping[str, Any] | None, column: str) -> tuple[float, float] | None:
    """The interval of a record column (``full_total_mean_pressure_kpa``) in its field unit, or
    ``None`` when the column has none (no posterior, or a column not propagated)."""
    if intervals is None:
        return None
    load, _, rest = column.partition("_")
    for tail, (quantity, factor) in _COLUMNS.items():
        if rest.endswith("_" + tail):
            zone = rest[: -len(tail) - 1]
            iv = intervals.get(load)
            name = f"{zone}.{quantity}"
            if iv is None or name not in iv.low:
                return None
            return iv.low[name] * factor, iv.high[name] * factor
    return None


def interval_records(
    entries: Sequence[Any], columns: Sequence[str], *, notes: Sequence[str]
) -> list[dict[str, Any]]:
    """One record per ski: for each column its 95 % interval (``<column>_low``/``_high``, NaN
    where the ski carries no uncertainty), the samples and what the numbers are worth
    (``notes``: one per entry, said where the ski has no intervals)."""
    out = []
    for e, note in zip(entries, notes, strict=True):
        ivs = e.intervals
        first = None if ivs is None else next(iter(ivs.values()))
        rec: dict[str, Any] = {
            "ski": e.ski.label,
            "uncertainty": note if ivs is None else "95 % intervals from posterior samples",
            "samples": 0 if first is None else first.samples,
            "mc_error_of_ends_max_fraction_of_width": (
                float("nan") if ivs is None else max(iv.worst_mc_error() for iv in ivs.values())
            ),
        }
        for col in columns:
            lo_hi = column_interval(ivs, col)
            lo, hi = (np.nan, np.nan) if lo_hi is None else lo_hi
            rec[f"{col}_low"], rec[f"{col}_high"] = float(lo), float(hi)
        out.append(rec)
    return out


def snow_intervals(
    entry: Any,
    value: Any,
    estimates: np.ndarray,
    moduli: np.ndarray,
    *,
    body_mass: float,
    load_position: float,
    ski_model: str,
    samples: int,
    n_points: int,
    seed: int = 0,
) -> tuple[np.ndarray, list[tuple[Any, ...]]] | None:
    """95 % intervals, shape ``(moduli, 2)``, of a criterion ``value(zones)`` on each snow
    modulus [Pa] for the ski of ``entry`` (``estimates``: its values there), and per modulus
    the patch topologies of the solved samples (:func:`skisnow.pipeline.zone_topology`);
    ``None`` without a posterior or samples. Each posterior sample is solved at full body
    weight on every modulus (warm-started along the moduli, the beam route)."""
    from skisnow.pipeline import sample_intervals, solve_case, zone_topology

    ski = entry.ski.ski
    if samples <= 0 or not ski.has_posterior:
        return None
    route = {} if ski_model == "flexible" else {"profile_source": "beam"}

    tops: list[list[Any]] = []

    def answers(s: Any) -> dict[str, float]:
        out, start, mine = {}, None, []
        for j, e in enumerate(moduli):
            case = solve_case(s, mass=body_mass, load_position=load_position,
                              snow_modulus=float(e), n_points=n_points, ski_model=ski_model,
                              start=start, **route)  # fmt: skip
            start = case.solution.pressure if ski_model == "rigid" else None
            out[str(j)] = value(case.zones)
            mine.append(zone_topology(case.zones))
        tops.append(mine)  # a sample whose load is not supported raised before: not counted
        return out

    est = {str(j): float(v) for j, v in enumerate(estimates)}
    iv = sample_intervals(ski, answers, estimate=est, samples=samples, seed=seed)
    by_modulus = [tuple(t[j] for t in tops) for j in range(len(moduli))]
    return np.array([iv.interval(str(j)) for j in range(len(moduli))]), by_modulus
