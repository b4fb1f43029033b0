"""Grids of values as users type them at the edge (CLI options): ``start:stop:step``, a list, one
value. One parser for every command (``bench``, ``sweep``, ``report``, ``bearing``); units are
left as typed — the caller converts to SI."""

from __future__ import annotations

import math

import numpy as np

from skisnow._errors import InputError

__all__ = ["parse_values"]


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
