"""Rankings that show ties (issue 26; issue 25 plugs uncertainty intervals into the same rule).

Two skis *tie* on a criterion when neither is better: with plain values, when the values are
equal (two identical skis give bit-identical numbers through the one-case pipeline); with
intervals ``(low, high)`` around the values, when the intervals overlap ("tie within
uncertainty"). A ski's rank is 1 + the number of skis strictly better than it (standard
competition ranking, "1 = 1 3"): tied skis share a rank, and the rule needs no transitivity,
so it holds unchanged for overlapping intervals. Skis whose values are not comparable by a
criterion (``comparable[i, j]`` False: a patch-based zone in two different patch topologies,
:mod:`skisnow.workflows._topology`) are never ranked apart: they tie.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

__all__ = ["better_than", "competition_ranks", "tied_with"]


def _intervals(values: Sequence[float], intervals: Sequence[tuple[float, float]] | None):
    v = np.asarray(values, dtype=float)
    if intervals is None:
        return v, v
    iv = np.asarray(intervals, dtype=float).reshape(v.size, 2)
    return iv[:, 0], iv[:, 1]


def better_than(
    values: Sequence[float],
    *,
    better: Literal["lower", "higher"],
    intervals: Sequence[tuple[float, float]] | None = None,
    comparable: np.ndarray | None = None,
) -> np.ndarray:
    """``B[i, j]``: ski i is strictly better than ski j (values, or whole intervals, apart,
    and comparable: ``comparable[i, j]``, default all).

    A NaN value (no answer) is worse than every number and ties with another NaN; an infinite
    value is a real answer at its end of the order.
    """
    lo, hi = _intervals(values, intervals)
    nan = np.isnan(lo) | np.isnan(hi)
    b = hi[:, None] < lo[None, :] if better == "lower" else lo[:, None] > hi[None, :]
    b = np.where(nan[:, None] | nan[None, :], ~nan[:, None] & nan[None, :], b)
    return b if comparable is None else b & np.asarray(comparable, dtype=bool)


def competition_ranks(
    values: Sequence[float],
    *,
    better: Literal["lower", "higher"],
    intervals: Sequence[tuple[float, float]] | None = None,
    comparable: np.ndarray | None = None,
) -> np.ndarray:
    """Rank of each ski (1 = best): 1 + the number of skis strictly better; ties share a rank."""
    b = better_than(values, better=better, intervals=intervals, comparable=comparable)
    return 1 + b.sum(axis=0)


def tied_with(
    values: Sequence[float],
    *,
    better: Literal["lower", "higher"],
    intervals: Sequence[tuple[float, float]] | None = None,
    comparable: np.ndarray | None = None,
) -> list[list[int]]:
    """For each ski, the other skis it ties with (neither strictly better)."""
    b = better_than(values, better=better, intervals=intervals, comparable=comparable)
    tie = ~b & ~b.T
    return [[j for j in np.flatnonzero(tie[i]).tolist() if j != i] for i in range(len(tie))]
