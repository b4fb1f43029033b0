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

import numpy as np

from skisnow._errors import ImplausibleValueError, InputError
from skisnow._quantities import QUANTITIES, Quantity

__all__ = [
    "QUANTITIES",
    "Quantity",
    "allow_implausible",
    "available_memory",
    "check_array",
    "check_csv_separator",
    "check_finite_column",
    "check_grid_points",
    "check_memory",
    "check_option_values",
    "check_value",
    "column_swap_hint",
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


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def _value(v: float, q: Quantity) -> str:
    """``v`` with its unit (a count or a factor, whose "unit" is a note in brackets, bare)."""
    return _fmt(v) if q.unit.startswith("(") else f"{_fmt(v)} {q.unit}"


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
    if not q.possible(np.array([v]))[0] or (q.integer and not float(v).is_integer()):
        raise InputError(
            f"{where}: {_value(v, q)} is not a possible {q.name}; need {q.describe_possible()}"
        )
    lo, hi = q.plausible
    if not (lo <= v <= hi) and not (implausible_allowed() if allow is None else allow):
        guess = q.guess_unit(v)
        hint = f"; was it given in {guess}?" if guess else ""
        raise ImplausibleValueError(
            f"{where}: {_value(v, q)} is an implausible {q.name} (plausible: "
            f"{q.describe_plausible()}{hint}). If you really mean it, pass {OVERRIDE_HINT}."
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
    cause: str = "",
) -> np.ndarray:
    """Check a column of values in the field unit of ``quantity`` (see :func:`check_value`).

    The first offending entry is named with ``row_label(i)`` (e.g. ``"line 12"``). With
    ``check_span`` a column whose spread is below the quantity's ``min_span`` is refused as a
    probable unit slip (heights in metres in a millimetre column). ``impossible`` is the error
    raised for impossible values (readers pass :class:`~skisnow.FileFormatError`). ``cause``
    (e.g. from :func:`column_swap_hint`) is named first in an implausibility message, before
    the unit probably meant.
    """
    q = QUANTITIES[quantity] if isinstance(quantity, str) else quantity
    v = np.asarray(values, dtype=np.float64)
    label = row_label or (lambda i: f"entry {i + 1}")
    bad = np.flatnonzero(~q.possible(v))
    if bad.size:
        i = int(bad[0])
        raise impossible(
            f"{where}, {label(i)}: {_value(v[i], q)} is not a possible {q.name}; need "
            f"{q.describe_possible()}"
        )
    if implausible_allowed() if allow is None else allow:
        return v
    lo, hi = q.plausible
    out = np.flatnonzero((v < lo) | (v > hi))
    if out.size:
        i = int(out[0])
        guess = q.guess_unit(float(v[i]))
        hint = cause + (f"; was the column given in {guess}?" if guess else "")
        raise ImplausibleValueError(
            f"{where}, {label(i)}: {_value(v[i], q)} is an implausible {q.name} (plausible: "
            f"{q.describe_plausible()}{hint}). If you really mean it, pass {OVERRIDE_HINT}."
        )
    if check_span and q.min_span > 0 and v.size >= 2:
        span = float(v.max() - v.min())
        if span < q.min_span:
            guess = q.guess_unit(span, span=True)
            hint = cause + (f"; the values look like {guess}, not {q.unit}" if guess else "")
            raise ImplausibleValueError(
                f"{where}: the {q.name} spans only {_fmt(span)} {q.unit} over {v.size} rows "
                f"(on a ski it spans at least {q.min_span:g} {q.unit}{hint}). If you really "
                f"mean it, pass {OVERRIDE_HINT}."
            )
    return v


def column_swap_hint(
    x_mm: np.ndarray,
    height_mm: np.ndarray,
    profiles: list[np.ndarray] | None = None,
    *,
    x_name: str = "x_mm",
    height_name: str = "height_mm",
) -> str:
    """A hint that the position and height columns of a profile table were swapped, or ``""``.

    The data fit a swap when the height column looks like positions along a ski (it increases
    strictly within every profile and spans at least the ``x`` quantity's ``min_span``) and the
    position column looks like camber heights (every value within the ``camber_height``
    plausible range, spread below ``x``'s ``min_span``).

    Parameters
    ----------
    x_mm, height_mm
        the columns as read (field unit mm).
    profiles
        row indices of each profile (each must be ordered by x); ``None``: one profile.
    x_name, height_name
        the column names used in the hint.

    Returns
    -------
    str
        ``"; the columns may be swapped: ..."`` (to pass as ``cause`` to :func:`check_array`),
        or ``""`` when the data do not fit that explanation.
    """
    x = np.asarray(x_mm, dtype=np.float64)
    h = np.asarray(height_mm, dtype=np.float64)
    if x.size < 2 or x.shape != h.shape or not (np.all(np.isfinite(x)) and np.all(np.isfinite(h))):
        return ""
    qx, qh = QUANTITIES["x"], QUANTITIES["camber_height"]
    lo, hi = qh.plausible
    if not (np.all((x >= lo) & (x <= hi)) and np.ptp(x) < qx.min_span):
        return ""
    groups = [np.arange(x.size)] if profiles is None else profiles
    for idx in groups:
        hp = h[np.asarray(idx)]
        if hp.size < 2 or not np.all(np.diff(hp) > 0) or np.ptp(hp) < qx.min_span:
            return ""
    return (
        f"; the columns may be swapped: {height_name!r} increases along every profile over "
        f"{_fmt(float(np.ptp(h)))} mm like positions on a ski, and {x_name!r} stays within "
        f"{_fmt(float(x.min()))}..{_fmt(float(x.max()))} mm like camber heights (check the "
        "header's column order)"
    )


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
        r = None if raw is None else raw[i]
        r = r.item() if isinstance(r, np.generic) else r  # 'nan', not 'np.float64(nan)'
        value = "value" if raw is None else f"value {r!r}"
        raise error(
            f"{where}: {row_label(i)}, column {column!r}: {value} is NaN, inf or empty; every "
            "value must be a finite number"
        )


def check_csv_separator(
    header: str, *, where: str, columns: str, error: type[InputError] = InputError
) -> None:
    """Refuse a CSV whose header line is separated by ``;`` or tabs instead of commas (a
    spreadsheet saved in a locale with decimal commas): naming the separator, not a parse error
    or a "missing column" that would blame the columns. ``columns`` names the expected header."""
    if "," in header:
        return
    for sep, name in ((";", "semicolons"), ("\t", "tabs")):
        if sep in header:
            raise error(
                f"{where}: the header {header.strip()!r} is separated by {name}, not commas (a "
                "spreadsheet saved with decimal commas?); skisnow reads comma-separated values "
                f"with decimal points: {columns}"
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
