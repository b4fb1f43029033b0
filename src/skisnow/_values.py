"""Grids of values: as users type them at the edge (CLI options: ``start:stop:step``, a list, one
value; one parser for every command, units left as typed — the caller converts to SI), and the
one check that a grid is a non-empty set of distinct finite values, sorted (:func:`sorted_unique`),
used by the bench, the sweep and the CLI."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError

__all__ = ["MAX_VALUES", "parse_values", "sorted_unique"]

#: The most values one grid option may hold (each is at least one contact solve).
MAX_VALUES = 1_000_000


def parse_values(text: str, *, name: str = "values") -> np.ndarray:
    """Parse a grid given in field units: ``"5:130:1"`` (start:stop:step, stop included when it
    lies on the grid), ``"-120"`` (one value) or ``"30,60,90"`` (a list).

    Returns the values as float64 (unchanged units). Raises :class:`InputError` naming ``name``.
    """
    text = text.strip()
    try:
        if ":" in text:
            parts = [float(p) for p in text.split(":")]
            if len(parts) != 3:
                raise ValueError
            start, stop, step = parts
            if not (math.isfinite(start) and math.isfinite(stop) and math.isfinite(step)):
                raise ValueError
            if step <= 0 or stop < start:
                raise InputError(
                    f"{name}: range {text!r} needs step > 0 and stop >= start (start:stop:step)"
                )
            n = math.floor((stop - start) / step + 1e-9) + 1
            if n > MAX_VALUES:  # counted before anything is allocated
                raise InputError(
                    f"{name}: range {text!r} holds {n:,} values, more than the {MAX_VALUES:,} "
                    "a grid may have; use a larger step"
                )
            # Rounded so that 20:400:20 gives exactly 20.0, 40.0, ... (no accumulated float noise).
            return np.round(start + step * np.arange(n), 9)
        values = np.array([float(p) for p in text.split(",") if p.strip() != ""])
    except InputError:
        raise
    except ValueError:
        raise InputError(
            f"{name}: cannot read {text!r}; expected start:stop:step, one number, or a "
            "comma-separated list"
        ) from None
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise InputError(f"{name}: {text!r} holds no finite values")
    return values


def sorted_unique(
    values: ArrayLike, *, name: str, unit: str = "", positive: bool = False
) -> NDArray[np.float64]:
    """A grid axis checked once: a non-empty 1-D set of distinct finite values, sorted ascending.

    Parameters
    ----------
    values : array_like
        One value or a 1-D sequence.
    name : str
        The argument or option named in messages (``masses``, ``--grain-um``).
    unit : str
        The unit of ``values`` shown in messages (``kg``, ``m``, ``Pa``).
    positive : bool
        Also require every value > 0.

    Returns
    -------
    ndarray of float64
        The values sorted ascending.

    Raises
    ------
    InputError
        Empty, not 1-D, NaN/inf, a value <= 0 with ``positive``, or a value given twice (a grid
        that names a point twice is a typo more often than an intent).
    """
    where = f"{name} [{unit}]" if unit else name
    try:
        arr = np.atleast_1d(np.asarray(values, dtype=float))
    except (TypeError, ValueError):
        raise InputError(f"{where}: need numbers, got {values!r}") from None
    if arr.ndim != 1 or arr.size == 0:
        raise InputError(f"{where}: need a non-empty 1-D list of values, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{where}: all values must be finite, got {arr.tolist()}")
    if positive and np.any(arr <= 0):
        raise InputError(f"{where}: all values must be > 0, got min {arr.min()}")
    uniq = np.unique(arr)
    if uniq.size != arr.size:
        twice = sorted({float(v) for v in arr if np.count_nonzero(arr == v) > 1})
        raise InputError(f"{where}: values must be distinct; given more than once: {twice}")
    return uniq
