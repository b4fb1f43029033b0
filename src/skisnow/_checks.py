"""Plausibility at the boundary: every quantity a user types or a file holds, stated once.

Each :class:`Quantity` names its field unit (the unit of the CLI option or file column), the
values that are physically impossible (always an error: a negative mass, a pixel of 0 µm, a
temperature below absolute zero) and the range that is plausible for a cross-country ski and its
snow (outside it: an :class:`~skisnow.ImplausibleValueError` that says which unit was probably
meant, e.g. heights in metres in a ``height_mm`` column). A researcher who really means an
implausible value passes ``--allow-implausible`` (CLI) or runs inside :func:`allow_implausible`
(library); impossible values have no override.

:func:`check_memory` refuses, before allocating, grids that would not fit in the memory this
machine has available.

The ranges come from the skis and snows of Kalliorinne et al. (Lubricants 2023: skis of
1.8–2.1 m, camber heights up to ~40 mm at the tips, snow 20–400 MPa on a 70 GPa stone bench) and
Scherge et al. (Front. Mech. Eng. 2021: grinds of µm depth, pixels of 0.1–10 µm, grains of
100–2000 µm, snow from −30 °C to 0 °C), widened generously: they catch unit slips, not
unusual skis.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from skisnow._errors import ImplausibleValueError, InputError

__all__ = [
    "QUANTITIES",
    "Quantity",
    "allow_implausible",
    "available_memory",
    "check_array",
    "check_finite_column",
    "check_grid_points",
    "check_memory",
    "check_option_values",
    "check_value",
    "implausible_allowed",
    "positive_finite",
]

_ALLOW: contextvars.ContextVar[bool | None] = contextvars.ContextVar("skisnow_allow_implausible")

#: The option that lifts the plausibility ranges (named in every message).
OVERRIDE_HINT = "--allow-implausible (library: skisnow.allow_implausible())"


def implausible_allowed() -> bool:
    """Whether implausible (but possible) values are accepted: inside :func:`allow_implausible`
    or with the environment variable ``SKISNOW_ALLOW_IMPLAUSIBLE=1``."""
    value = _ALLOW.get(None)
    if value is not None:
        return value
    return os.environ.get("SKISNOW_ALLOW_IMPLAUSIBLE", "").strip() in ("1", "true", "yes")


@contextlib.contextmanager
def allow_implausible(allow: bool = True) -> Iterator[None]:
    """Accept values outside the plausible ranges (never impossible ones) within the block."""
    token = _ALLOW.set(allow)
    try:
        yield
    finally:
        _ALLOW.reset(token)


@dataclass(frozen=True, kw_only=True)
class Quantity:
    """One physical quantity at the edge of skisnow, in its field unit.

    Attributes
    ----------
    name
        What it is ("camber height").
    unit
        The field unit the value is given in ("mm").
    low, high
        Physically impossible beyond these bounds; ``low_open``/``high_open`` make the bound
        itself impossible too (a mass of 0 kg).
    plausible
        The range plausible for a ski; outside it the value is refused unless overridden.
    alternatives
        Units a user may have typed by mistake, as ``(unit, factor, offset)`` with
        ``value_in_field_unit = value_in_alternative · factor + offset``: used to say which unit
        was probably meant.
    min_span
        For a column of values: the smallest plausible spread (max − min); a smaller one means
        a unit slip (heights in metres in a millimetre column). ``0`` disables the check.
    """

    name: str
    unit: str
    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False
    plausible: tuple[float, float] = (-math.inf, math.inf)
    alternatives: tuple[tuple[str, float, float], ...] = ()
    min_span: float = 0.0

    def possible(self, v: np.ndarray) -> np.ndarray:
        ok = np.isfinite(v)
        ok &= (v > self.low) if self.low_open else (v >= self.low)
        ok &= (v < self.high) if self.high_open else (v <= self.high)
        return ok

    def describe_possible(self) -> str:
        lo = "" if self.low == -math.inf else f"{'>' if self.low_open else '>='} {self.low:g}"
        hi = "" if self.high == math.inf else f"{'<' if self.high_open else '<='} {self.high:g}"
        bounds = " and ".join(b for b in (lo, hi) if b)
        return f"a finite number {bounds} {self.unit}".replace("  ", " ").strip()

    def describe_plausible(self) -> str:
        lo, hi = self.plausible
        return f"{lo:g} to {hi:g} {self.unit}"

    def guess_unit(self, value: float, *, span: bool = False) -> str | None:
        """The alternative unit in which ``value`` would be plausible, if exactly one is."""
        lo, hi = self.plausible
        hits = []
        for unit, factor, offset in self.alternatives:
            if not span and value < lo <= 0.0 and offset == 0.0:
                continue  # a negative value of a (nearly) positive quantity: the sign is wrong

            if span:
                v = abs(value) * factor
                if v >= self.min_span and v <= hi - lo:
                    hits.append(unit)
            else:
                v = value * factor + offset
                if lo <= v <= hi:
                    hits.append(unit)
        return hits[0] if len(hits) >= 1 else None


_M = ("m", 1e3, 0.0)
_CM = ("cm", 10.0, 0.0)
_UM_IN_MM = ("µm", 1e-3, 0.0)

#: Every quantity skisnow reads at its edge, keyed by the name used in code.
QUANTITIES: dict[str, Quantity] = {
    "mass": Quantity(
        name="mass", unit="kg", low=0.0, low_open=True, plausible=(0.1, 300.0),
        alternatives=(("g", 1e-3, 0.0), ("lb", 0.45359237, 0.0)),
    ),
    "load_position": Quantity(
        name="load position x_m from the balance point", unit="mm", plausible=(-700.0, 700.0),
        alternatives=(_M, _CM),
    ),
    "x": Quantity(
        name="position along the ski", unit="mm", plausible=(-1600.0, 1600.0),
        alternatives=(_M, _CM), min_span=100.0,
    ),
    "ski_length": Quantity(
        name="ski length", unit="mm", low=0.0, low_open=True, plausible=(800.0, 2600.0),
        alternatives=(_M, _CM),
    ),
    "camber_height": Quantity(
        name="camber height above the bench", unit="mm", plausible=(-0.5, 250.0),
        alternatives=(_M, _UM_IN_MM), min_span=0.2,
    ),
    "width": Quantity(
        name="ski width", unit="mm", low=0.0, low_open=True, plausible=(20.0, 150.0),
        alternatives=(_M, _CM),
    ),
    "snow_modulus": Quantity(
        name="snow (counter-surface) modulus", unit="MPa", low=0.0, low_open=True,
        plausible=(0.01, 2.5e5), alternatives=(("Pa", 1e-6, 0.0), ("kPa", 1e-3, 0.0)),
    ),
    "base_modulus": Quantity(
        name="ski base modulus", unit="MPa", low=0.0, low_open=True, plausible=(10.0, 2.0e4),
        alternatives=(("Pa", 1e-6, 0.0), ("GPa", 1e3, 0.0), ("kPa", 1e-3, 0.0)),
    ),
    "temperature": Quantity(
        name="snow temperature", unit="°C", low=-273.15, low_open=False, plausible=(-60.0, 0.0),
        alternatives=(("K", 1.0, -273.15),),
    ),
    "pixel": Quantity(
        name="pixel size", unit="µm", low=0.0, low_open=True, plausible=(0.005, 2000.0),
        alternatives=(("m", 1e6, 0.0), ("mm", 1e3, 0.0), ("nm", 1e-3, 0.0)),
    ),
    "map_size": Quantity(
        name="side of a topography map", unit="µm", low=0.0, low_open=True,
        plausible=(5.0, 2.0e5), alternatives=(("mm", 1e3, 0.0), ("m", 1e6, 0.0)),
    ),
    "topography_height": Quantity(
        name="peak-to-valley height of a ski-base topography", unit="m", low=0.0,
        plausible=(0.0, 5e-3), alternatives=(("µm", 1e-6, 0.0), ("nm", 1e-9, 0.0),
                                             ("mm", 1e-3, 0.0)),
    ),
    "grain": Quantity(
        name="snow grain diameter", unit="µm", low=0.0, low_open=True, plausible=(5.0, 1.0e4),
        alternatives=(("mm", 1e3, 0.0), ("m", 1e6, 0.0)),
    ),
    "pressure": Quantity(
        name="macroscopic pressure", unit="kPa", low=0.0, low_open=True,
        plausible=(0.01, 2.0e4), alternatives=(("Pa", 1e-3, 0.0), ("MPa", 1e3, 0.0)),
    ),
    "cutoff": Quantity(
        name="low-pass cut-off wavelength (0 = none)", unit="µm", low=0.0,
        plausible=(0.0, 1.0e5), alternatives=(("m", 1e6, 0.0), ("mm", 1e3, 0.0)),
    ),
    "step_along_ski": Quantity(
        name="sampling step along the ski", unit="mm", low=0.0, low_open=True,
        plausible=(0.005, 200.0), alternatives=(_M, _UM_IN_MM),
    ),
    "noise": Quantity(
        name="height noise (standard deviation)", unit="mm", low=0.0, plausible=(0.0, 5.0),
        alternatives=(_UM_IN_MM,),
    ),
    "alpha": Quantity(
        name="significance level", unit="(probability)", low=0.0, high=1.0, low_open=True,
        high_open=True, plausible=(1e-9, 0.2),
    ),
    "glide_time": Quantity(
        name="glide time", unit="s", low=0.0, low_open=True, plausible=(0.01, 36000.0),
    ),
    "grid_points": Quantity(
        name="grid points", unit="(count)", low=16.0, plausible=(16.0, 2.0**21),
    ),
    "sliding_speed": Quantity(
        name="sliding speed", unit="m/s", low=0.0, low_open=True, plausible=(0.05, 40.0),
        alternatives=(("km/h", 1 / 3.6, 0.0),),
    ),
    "film_cutoff": Quantity(
        name="film-thickness cut-off", unit="nm", low=0.0, low_open=True,
        plausible=(0.1, 1.0e5), alternatives=(("µm", 1e3, 0.0), ("m", 1e9, 0.0)),
    ),
    "shear_strength": Quantity(
        name="shear strength of the real contact", unit="MPa", low=0.0, low_open=True,
        plausible=(1e-4, 100.0), alternatives=(("Pa", 1e-6, 0.0), ("kPa", 1e-3, 0.0)),
    ),
    "viscosity": Quantity(
        name="meltwater viscosity", unit="mPa·s", low=0.0, low_open=True,
        plausible=(0.1, 100.0), alternatives=(("Pa·s", 1e3, 0.0),),
    ),
    "cells_across": Quantity(
        name="cells across the width", unit="(count)", low=1.0, plausible=(1.0, 1024.0),
    ),
}  # fmt: skip


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def check_value(
    value: float,
    quantity: str | Quantity,
    *,
    where: str,
    allow: bool | None = None,
) -> float:
    """Check one value given in the field unit of ``quantity``; return it as a float.

    Parameters
    ----------
    value
        The value as typed or read (field unit).
    quantity
        A key of :data:`QUANTITIES` or a :class:`Quantity`.
    where
        What to name in messages: an option (``"--mass-kg"``) or ``"FILE: line 7, column x_mm"``.
    allow
        Accept implausible values; default :func:`implausible_allowed`.

    Raises
    ------
    InputError
        The value is not a number or physically impossible.
    ImplausibleValueError
        The value is possible but implausible for a ski; the message names the unit probably
        meant and the override.
    """
    q = QUANTITIES[quantity] if isinstance(quantity, str) else quantity
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(
            f"{where}: {value!r} is not a number; need {q.describe_possible()}"
        ) from None
    if not q.possible(np.array([v]))[0]:
        raise InputError(
            f"{where}: {_fmt(v)} {q.unit} is not a possible {q.name}; need {q.describe_possible()}"
        )
    lo, hi = q.plausible
    if not (lo <= v <= hi) and not (implausible_allowed() if allow is None else allow):
        guess = q.guess_unit(v)
        hint = f"; was it given in {guess}" if guess else ""
        raise ImplausibleValueError(
            f"{where}: {_fmt(v)} {q.unit} is implausible for a {q.name} of a ski (expected "
            f"{q.describe_plausible()}){hint}. If you really mean it, pass {OVERRIDE_HINT}."
        )
    return v


def check_array(
    values: np.ndarray,
    quantity: str | Quantity,
    *,
    where: str,
    row_label: Callable[[int], str] | None = None,
    allow: bool | None = None,
    check_span: bool = True,
    impossible: type[InputError] = InputError,
) -> np.ndarray:
    """Check a column of values in the field unit of ``quantity`` (see :func:`check_value`).

    The first offending entry is named with ``row_label(i)`` (e.g. ``"line 12"``). With
    ``check_span`` a column whose spread is below the quantity's ``min_span`` is refused as a
    probable unit slip (heights in metres in a millimetre column). ``impossible`` is the error
    raised for impossible values (readers pass :class:`~skisnow.FileFormatError`).
    """
    q = QUANTITIES[quantity] if isinstance(quantity, str) else quantity
    v = np.asarray(values, dtype=np.float64)
    label = row_label or (lambda i: f"entry {i + 1}")
    bad = np.flatnonzero(~q.possible(v))
    if bad.size:
        i = int(bad[0])
        raise impossible(
            f"{where}, {label(i)}: {_fmt(v[i])} {q.unit} is not a possible {q.name}; need "
            f"{q.describe_possible()}"
        )
    if implausible_allowed() if allow is None else allow:
        return v
    lo, hi = q.plausible
    out = np.flatnonzero((v < lo) | (v > hi))
    if out.size:
        i = int(out[0])
        guess = q.guess_unit(float(v[i]))
        hint = f"; was the column given in {guess}" if guess else ""
        raise ImplausibleValueError(
            f"{where}, {label(i)}: {_fmt(v[i])} {q.unit} is implausible for a {q.name} of a ski "
            f"(expected {q.describe_plausible()}){hint}. If you really mean it, pass "
            f"{OVERRIDE_HINT}."
        )
    if check_span and q.min_span > 0 and v.size >= 2:
        span = float(v.max() - v.min())
        if span < q.min_span:
            guess = q.guess_unit(span, span=True)
            hint = f"; the values look like {guess}, not {q.unit}" if guess else ""
            raise ImplausibleValueError(
                f"{where}: the {q.name} spans only {_fmt(span)} {q.unit} over {v.size} rows "
                f"(a ski's spans at least {q.min_span:g} {q.unit}){hint}. If you really mean "
                f"it, pass {OVERRIDE_HINT}."
            )
    return v


def check_option_values(values: np.ndarray, quantity: str | Quantity, option: str) -> np.ndarray:
    """Check the values of a grid option (``--mass-kg 5:130:5``) in its field unit."""
    return check_array(
        values, quantity, where=option, row_label=lambda i: f"value {i + 1}", check_span=False
    )


#: Bytes a contact solve or a sampled profile needs per grid point (a generous bound: the FFT
#: solver keeps ~40 float64 work arrays of the grid size).
BYTES_PER_POINT = 8 * 64


def check_grid_points(n: int, *, where: str) -> int:
    """Check a number of grid points (an integer >= 16, plausible, and fitting in memory)."""
    if isinstance(n, float) and not float(n).is_integer():
        raise InputError(f"{where}: need a whole number of grid points >= 16, got {n}")
    n = int(check_value(n, "grid_points", where=where))
    check_memory(
        n * BYTES_PER_POINT,
        where=f"{where} {n}",
        what=f"a grid of {n} points",
        hint="use fewer points",
    )
    return n


def positive_finite(name: str, value: float, unit: str = "") -> float:
    """``value`` as a float if it is finite and > 0, else :class:`InputError` naming ``name``.

    The library's own argument check (SI units); values typed by users go through
    :func:`check_value` with their :class:`Quantity` instead.
    """
    need = f"{name} must be a finite number > 0{' ' + unit if unit else ''}, got {value!r}"
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(need) from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(need)
    return v


def check_finite_column(
    values: np.ndarray,
    *,
    where: str,
    column: str,
    row_label: Callable[[int], str],
    raw: np.ndarray | None = None,
    error: type[InputError] = InputError,
) -> None:
    """Raise ``error`` naming the first row of a table column whose value is NaN, inf or empty
    (the one rule for a column of numbers read from a file): ``where``, the row
    (``row_label(i)``), the column, the value as read (``raw``, if given) and what is valid."""
    bad = ~np.isfinite(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        value = "value" if raw is None else f"value {raw[i]!r}"
        raise error(
            f"{where}: {row_label(i)}, column {column!r}: {value} is NaN, inf or empty; every "
            "value must be a finite number"
        )


def available_memory() -> int:
    """Bytes of memory available to a new allocation on this machine (``MemAvailable`` on
    Linux; physical memory elsewhere; 8 GiB when neither is known)."""
    with contextlib.suppress(OSError, ValueError), open("/proc/meminfo", encoding="ascii") as fh:
        for line in fh:
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    with contextlib.suppress(AttributeError, ValueError, OSError):
        return int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    return 8 << 30


#: The share of the available memory one allocation may take.
MEMORY_FRACTION = 0.5


def check_memory(n_bytes: float, *, where: str, what: str, hint: str = "") -> None:
    """Refuse, before allocating, an allocation of ``n_bytes`` that would not fit.

    The limit is :data:`MEMORY_FRACTION` of :func:`available_memory` (the environment variable
    ``SKISNOW_MEMORY_LIMIT_GIB`` sets it explicitly). ``where`` names the option or file and
    ``hint`` what would be valid.
    """
    env = os.environ.get("SKISNOW_MEMORY_LIMIT_GIB", "").strip()
    limit = float(env) * (1 << 30) if env else MEMORY_FRACTION * available_memory()
    if not math.isfinite(n_bytes) or n_bytes > limit:
        raise InputError(
            f"{where}: {what} would need {n_bytes / (1 << 30):.3g} GiB of memory; this machine "
            f"allows {limit / (1 << 30):.3g} GiB{'; ' + hint if hint else ''}"
        )
