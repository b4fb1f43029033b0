"""A fleet's ranking across a range of snow moduli (:func:`rank_across_snow`), with the
intervals of skis carrying their posterior and the patch topology of patch-based criteria
(:mod:`skisnow.workflows._topology`).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from skisnow._errors import InputError
from skisnow.workflows._fleet import Criterion, FleetComparison, _criterion
from skisnow.workflows._fleet_intervals import snow_intervals
from skisnow.workflows._solve import choose_route, loaded_profiles, solve_loaded, stations
from skisnow.workflows._ties import competition_ranks
from skisnow.workflows._topology import comparable, patch_zone, ski_topology, topology_warnings

__all__ = ["SnowRanking", "rank_across_snow"]


@dataclass(frozen=True, kw_only=True)
class SnowRanking:
    """A criterion's value and rank per ski across snow moduli.

    Attributes
    ----------
    skis
        Labels, in the fleet's order.
    snow_moduli
        [Pa], increasing.
    values
        Criterion value, shape ``(n_skis, n_moduli)``, in the criterion column's field unit.
    ranks
        1 = best, same shape; tied skis share a rank (standard competition ranking).
    changes
        ``(E_before, E_after, order_before, order_after)`` where the order of the skis changes
        between two neighbouring moduli.
    """

    criterion: Criterion
    skis: tuple[str, ...]
    snow_moduli: np.ndarray
    values: np.ndarray
    ranks: np.ndarray
    changes: tuple[tuple[float, float, tuple[str, ...], tuple[str, ...]], ...]
    #: ``(n_skis, n_moduli, 2)``: the 95 % interval of each value (low = high for a ski
    #: without bands; ``None`` for a ranking made without samples)
    intervals: np.ndarray | None = None
    #: skis not comparable by a patch-based criterion at a modulus (their patch topologies
    #: differ, or their posterior samples straddle two: :mod:`skisnow.workflows._topology`);
    #: they tie there
    warnings: tuple[str, ...] = ()

    def winners(self) -> list[str]:
        """The best ski at each modulus (tied best skis joined by `` = ``)."""
        return [
            " = ".join(s for s, r in zip(self.skis, self.ranks[:, j], strict=True) if r == 1)
            for j in range(self.ranks.shape[1])
        ]

    def order_text(self, j: int) -> str:
        """The order at modulus ``j``, best first: ``a > b = c`` (``=`` a tie)."""
        order = sorted(range(len(self.skis)), key=lambda i: (self.ranks[i, j], i))
        text = self.skis[order[0]]
        for prev, i in itertools.pairwise(order):
            text += (" = " if self.ranks[i, j] == self.ranks[prev, j] else " > ") + self.skis[i]
        return text


def rank_across_snow(
    comparison: FleetComparison,
    criterion: str,
    snow_moduli: Sequence[float],
    *,
    n_points: int = 4096,
    progress: Callable[[int, int], None] | None = None,
    samples: int = 0,
) -> SnowRanking:
    """Rank the compared skis by ``criterion`` on each snow modulus [Pa] of ``snow_moduli``.

    Each (ski, modulus) is the comparison's full-body-weight case on that snow (the loaded
    profile does not depend on the snow and is computed once per ski; the contact along the
    moduli is warm-started from the previous one). With ``samples``, a ski carrying its
    posterior gets the 95 % interval of its value on every modulus (``intervals``), and skis
    whose intervals overlap tie there (a tie within uncertainty). On a patch-based criterion
    (a paper zone: rear, middle, front) skis in different patch topologies at a modulus, or
    whose samples straddle two, tie there as not comparable, named in ``warnings``
    (:mod:`skisnow.workflows._topology`).
    """
    crit = _criterion(criterion)
    moduli = np.asarray(sorted(float(e) for e in snow_moduli))
    if moduli.size < 2 or not np.all(np.isfinite(moduli)) or np.any(moduli <= 0):
        raise InputError("the snow range needs at least two positive, finite moduli")
    entries = comparison.entries
    if not entries:
        raise InputError("no ski of the fleet could be compared")
    values = np.full((len(entries), moduli.size), np.nan)
    zone = patch_zone(crit.column)
    est_tops: list[list[Any]] = [[None] * moduli.size for _ in entries]
    total = len(entries) * moduli.size
    done = 0
    for i, entry in enumerate(entries):
        fs = entry.ski
        if not crit.snow_dependent:
            values[i] = float(entry.record()[crit.column])
            done += moduli.size
            if progress is not None:
                progress(done, total)
            continue
        x = stations(fs, n_points)
        m = comparison.body_mass
        if comparison.ski_model == "flexible":
            route, h = "flexible", None
        else:
            route, _ = choose_route(fs, np.array([m]), np.array([comparison.load_position]), x)
            (h,) = loaded_profiles(
                fs, np.array([m]), np.array([comparison.load_position]), x, route=route
            )
        start = None
        for j, e in enumerate(moduli):
            case = solve_loaded(
                fs,
                x,
                h,
                mass=m,
                load_position=comparison.load_position,
                snow_modulus=float(e),
                route=route,
                start=start,
            )
            start = case.solution.pressure
            values[i, j] = _value(crit, case.zones)
            est_tops[i][j] = case.zones if zone is not None else None
            done += 1
            if progress is not None:
                progress(done, total)
    labels = tuple(e.ski.label for e in entries)

    bounds = np.stack([values, values], axis=-1)  # (skis, moduli, 2); a ski without bands: exact
    sample_tops: list[list[Any]] = [[()] * moduli.size for _ in entries]
    for i, entry in enumerate(entries if crit.snow_dependent else ()):
        c = comparison
        iv = snow_intervals(entry, lambda z: _value(crit, z), values[i], moduli,
                            body_mass=c.body_mass, load_position=c.load_position,
                            ski_model=c.ski_model, samples=samples, n_points=n_points)  # fmt: skip
        if iv is not None:
            bounds[i], sample_tops[i] = iv
    ranks = np.empty_like(values, dtype=np.int64)
    orders, warnings = [], []
    for j in range(moduli.size):
        order = crit.order(values[:, j])
        tops = [None if est_tops[i][j] is None else ski_topology(est_tops[i][j],
                sample_tops[i][j], zone) for i in range(len(entries))]  # fmt: skip
        ok = comparable(tops)
        if zone is not None:
            warnings += topology_warnings(labels, tops, crit.name, zone,
                                          where=f" at {moduli[j] * 1e-6:g} MPa")  # fmt: skip
        ranks[:, j] = competition_ranks(values[:, j], better=crit.better, intervals=bounds[:, j],
                                        comparable=ok)  # fmt: skip
        # the order with its ties: skis sharing a rank form one group (sorted by name)
        groups: dict[int, list[str]] = {}
        for k in order:
            groups.setdefault(int(ranks[k, j]), []).append(labels[k])
        orders.append(tuple(" = ".join(sorted(g)) for _, g in sorted(groups.items())))
    changes = tuple(
        (float(moduli[j]), float(moduli[j + 1]), orders[j], orders[j + 1])
        for j in range(moduli.size - 1)
        if orders[j] != orders[j + 1]
    )
    return SnowRanking(
        criterion=crit,
        skis=labels,
        snow_moduli=moduli,
        values=values,
        ranks=ranks,
        changes=changes,
        intervals=bounds if samples else None,
        warnings=tuple(warnings),
    )


def _value(crit: Criterion, zones: Any) -> float:
    """The criterion's column computed from one full-body-weight contact (field units)."""
    _, zone, *rest = crit.column.split("_")
    quantity = "_".join(rest)
    z = zones[zone]
    return {
        "mean_pressure_kpa": z.mean_pressure * 1e-3,
        "peak_pressure_kpa": z.max_pressure * 1e-3,
        "length_mm": z.length * 1e3,
        "load_share": z.load_share,
    }[quantity]
