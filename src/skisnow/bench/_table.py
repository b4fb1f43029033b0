"""The one validation of a camber-bench table (columns, numbers, profiles, plausibility).

A table has the columns :data:`BENCH_COLUMNS` in field units (see :mod:`skisnow.bench._data` for
their meaning). :func:`validate_bench_table` is the one definition of a valid table: the file
readers, :class:`~skisnow.bench.BenchData` and :func:`~skisnow.network.train_network` all call it.
Every defect raises :class:`~skisnow.FileFormatError` (impossible) or
:class:`~skisnow.ImplausibleValueError` (implausible, overridable) naming the file, the row and
the column.
"""

from __future__ import annotations

import difflib
from typing import Any

import numpy as np
import pandas as pd

from skisnow._checks import check_finite_column
from skisnow._errors import FileFormatError

__all__ = ["BENCH_COLUMNS", "LOAD_ORDER_TOLERANCE_MM", "MIN_PROFILE_POINTS", "validate_bench_table"]

#: The columns of a bench table, in order.
BENCH_COLUMNS: tuple[str, ...] = ("ski", "mass_kg", "load_position_mm", "x_mm", "height_mm")
#: The fewest samples a profile may have.
MIN_PROFILE_POINTS: int = 10
_NUMERIC = ("mass_kg", "load_position_mm", "x_mm", "height_mm")


def _row_label(i: int, row_offset: int, csv: bool) -> str:
    return f"line {i + row_offset}" if csv else f"row {i + row_offset}"


def validate_bench_table(
    table: pd.DataFrame, *, where: str = "<table>", row_offset: int = 1, csv: bool = False
) -> pd.DataFrame:
    """Check a bench table and return a clean copy (column order, dtypes); raise on any defect.

    Parameters
    ----------
    table
        the raw table.
    where
        the file name (or ``<table>``) used in messages.
    row_offset
        number added to the 0-based data row index to report rows (CSV: the line
        number of the first data row; Parquet and in-memory tables: 1).
    csv
        report ``line N`` (CSV) instead of ``row N``.

    Raises
    ------
    FileFormatError
        missing, misnamed or unexpected columns; non-numeric values; NaN/inf;
        mass <= 0; duplicated samples; x not strictly increasing within a profile; a
        profile with fewer than :data:`MIN_PROFILE_POINTS` samples; no rows.
    """
    cols = [str(c) for c in table.columns]
    missing = [c for c in BENCH_COLUMNS if c not in cols]
    extra = [c for c in cols if c not in BENCH_COLUMNS]
    if missing or extra:
        parts = []
        for c in missing:
            guess = difflib.get_close_matches(c, extra, n=1, cutoff=0.4)
            if guess:
                parts.append(f"column {guess[0]!r} should be named {c!r}")
            else:
                parts.append(f"missing column {c!r}")
        named = {p.split("'")[1] for p in parts if p.startswith("column ")}
        parts += [f"unexpected column {c!r}" for c in extra if c not in named]
        raise FileFormatError(
            f"{where}: {'; '.join(parts)} (a bench table has exactly the columns "
            f"{', '.join(BENCH_COLUMNS)})"
        )
    if len(table) == 0:
        raise FileFormatError(f"{where}: the table has no rows")
    out = pd.DataFrame({"ski": table["ski"].astype(str).to_numpy()})
    for col in _NUMERIC:
        values = pd.to_numeric(table[col], errors="coerce").to_numpy(dtype=float)
        raw = table[col].to_numpy()
        bad_type = np.isnan(values) & ~pd.isna(raw)
        if bad_type.any():
            i = int(np.flatnonzero(bad_type)[0])
            raise FileFormatError(
                f"{where}: {_row_label(i, row_offset, csv)}, column {col!r}: "
                f"{raw[i]!r} is not a number"
            )
        check_finite_column(
            values, where=where, column=col, raw=raw, error=FileFormatError,
            row_label=lambda i: _row_label(i, row_offset, csv),
        )  # fmt: skip
        out[col] = values
    _check_plausible(out, where, lambda i: _row_label(i, row_offset, csv))
    ski_blank = out["ski"].str.strip() == ""
    if ski_blank.any():
        i = int(np.flatnonzero(ski_blank.to_numpy())[0])
        raise FileFormatError(
            f"{where}: {_row_label(i, row_offset, csv)}, column 'ski': empty name"
        )
    mass = out["mass_kg"].to_numpy()
    if np.any(mass <= 0):
        i = int(np.flatnonzero(mass <= 0)[0])
        raise FileFormatError(
            f"{where}: {_row_label(i, row_offset, csv)}, column 'mass_kg': mass {mass[i]} kg "
            "is not > 0"
        )
    key = ["ski", "mass_kg", "load_position_mm", "x_mm"]
    dup = out.duplicated(subset=key, keep=False).to_numpy()
    if dup.any():
        rows = np.flatnonzero(dup)
        first = out.iloc[rows[0]]
        same = rows[
            (out.iloc[rows][key] == first[key]).all(axis=1).to_numpy()
        ]  # rows equal to the first duplicate
        labels = ", ".join(_row_label(int(i), row_offset, csv) for i in same[:5])
        raise FileFormatError(
            f"{where}: duplicated sample (ski={first['ski']}, mass_kg={first['mass_kg']}, "
            f"load_position_mm={first['load_position_mm']}, x_mm={first['x_mm']}) at {labels}, "
            "column 'x_mm'"
        )
    groups = out.groupby(["ski", "mass_kg", "load_position_mm"], sort=False).indices
    for (ski, m, p), idx in groups.items():
        idx = np.sort(idx)
        if idx.size < MIN_PROFILE_POINTS:
            raise FileFormatError(
                f"{where}: profile (ski={ski}, mass_kg={m}, load_position_mm={p}) starting at "
                f"{_row_label(int(idx[0]), row_offset, csv)} has {idx.size} samples; at least "
                f"{MIN_PROFILE_POINTS} are needed (column 'x_mm')"
            )
        x = out["x_mm"].to_numpy()[idx]
        steps = np.diff(x)
        if np.any(steps <= 0):
            j = int(idx[int(np.flatnonzero(steps <= 0)[0]) + 1])
            raise FileFormatError(
                f"{where}: {_row_label(j, row_offset, csv)}, column 'x_mm': x = {out['x_mm'][j]} "
                f"mm does not increase within the profile (ski={ski}, mass_kg={m}, "
                f"load_position_mm={p}); samples of a profile must be ordered by x"
            )
    _check_load_order(out, groups, where, lambda i: _row_label(i, row_offset, csv))
    return out


#: Quantity (skisnow._checks) of each numeric bench column.
_QUANTITY = {"mass_kg": "mass", "load_position_mm": "load_position", "x_mm": "x",
             "height_mm": "camber_height"}  # fmt: skip


def _check_plausible(out: pd.DataFrame, where: str, label: Any) -> None:
    """Every column within what is possible and plausible for a ski on a camber bench (heights
    in metres in ``height_mm``, x in metres, a 20 m ski, masses in grams are refused with the
    unit probably meant; ``--allow-implausible`` accepts them)."""
    from skisnow._checks import check_array, column_swap_hint, implausible_allowed

    profiles = [
        np.sort(i)
        for i in out.groupby(["ski", "mass_kg", "load_position_mm"], sort=False).indices.values()
    ]
    swap = column_swap_hint(out["x_mm"].to_numpy(), out["height_mm"].to_numpy(), profiles)
    for col, quantity in _QUANTITY.items():
        check_array(
            out[col].to_numpy(),
            quantity,
            where=f"{where}, column {col!r}",
            row_label=label,
            impossible=FileFormatError,
            cause=swap if col in ("x_mm", "height_mm") else "",
        )
    if implausible_allowed():
        return
    from skisnow._errors import ImplausibleValueError

    for ski, idx in out.groupby("ski", sort=False).indices.items():
        x = out["x_mm"].to_numpy()[idx]
        if x.max() - x.min() > 3000.0:
            raise ImplausibleValueError(
                f"{where}, column 'x_mm': ski {ski!r} spans {x.max() - x.min():.6g} mm; a "
                "cross-country ski is 1.0 to 2.6 m long (was x given in another unit?). If you "
                "really mean it, pass --allow-implausible."
            )


#: Tolerance [mm] of the load-order check: a heavier load may sit this much higher on average
#: (measurement noise) before the bench is refused.
LOAD_ORDER_TOLERANCE_MM = 0.05


def _check_load_order(out: pd.DataFrame, groups: dict, where: str, label: Any) -> None:
    """A heavier load presses the ski down under the load: at one load position x_m, the camber
    height AT x_m must not grow with the mass (beyond :data:`LOAD_ORDER_TOLERANCE_MM`). The
    displacement under a point force is monotone in the force for an elastic beam on a rigid
    plane, contact included (it is the work-conjugate of a convex energy); elsewhere the ski
    may rise (tips lift as the middle bends), so only x_m is tested. A bench that rises under
    its load has swapped masses or heights of another sign."""
    from skisnow._checks import implausible_allowed
    from skisnow._errors import ImplausibleValueError

    if implausible_allowed():
        return
    x_all, h_all = out["x_mm"].to_numpy(), out["height_mm"].to_numpy()
    by_pos: dict[tuple[str, float], list[tuple[float, np.ndarray]]] = {}
    for (ski, m, p), idx in groups.items():
        by_pos.setdefault((ski, p), []).append((m, np.sort(idx)))
    for (ski, p), profiles in by_pos.items():
        profiles.sort(key=lambda t: t[0])
        inside = all(x_all[i].min() <= p <= x_all[i].max() for _, i in profiles)
        if len(profiles) < 2 or not inside:
            continue
        means = [float(np.interp(p, x_all[i], h_all[i])) for _, i in profiles]
        for k in range(1, len(profiles)):
            rise = means[k] - means[k - 1]
            if rise > LOAD_ORDER_TOLERANCE_MM:
                (m0, i0), (m1, i1) = profiles[k - 1], profiles[k]
                raise ImplausibleValueError(
                    f"{where}: the profile at mass_kg={m1:g} (from {label(int(i1[0]))}) sits "
                    f"{rise:.3g} mm higher under the load than the lighter one at mass_kg={m0:g} "
                    f"(from {label(int(i0[0]))}), ski {ski!r}, load_position_mm={p:g}; a heavier "
                    "load presses the ski down. Are the masses swapped, or the heights of the "
                    "wrong sign (column 'height_mm')? If you really mean it, pass "
                    "--allow-implausible."
                )
