"""Files of the apparent contact: rigid profiles in, pressure/gap fields out (field units).

* :func:`read_profile` — a CSV with columns ``x_mm,height_mm`` (a rigid loaded camber profile,
  e.g. a measured one) → (x [m], height [m]) on a uniform grid;
* :func:`fields_table` / :func:`write_fields` — ``x_mm,pressure_kpa,gap_um,snow_displacement_um``
  along the ski, so that anyone can check the balance laws (Σ p·w·dx = m·g); :func:`read_fields`
  reads them back.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from skisnow._errors import FileFormatError
from skisnow.contact._solver import ContactSolution

if TYPE_CHECKING:  # pandas is imported on use: the solver's users (sweep workers) never need it
    import pandas as pd

__all__ = ["fields_table", "read_fields", "read_profile", "write_fields"]

PROFILE_COLUMNS = ("x_mm", "height_mm")
FIELD_COLUMNS = ("x_mm", "pressure_kpa", "gap_um", "snow_displacement_um")


def _read_columns(path: Path, columns: tuple[str, ...], what: str):
    """Read the finite numeric ``columns`` of a CSV (``#`` comments allowed): ``(values, line)``
    where ``line(i)`` names data row ``i`` by its file line, as the user counts."""
    import pandas as pd

    if not path.is_file():
        raise FileFormatError(f"{path}: no such {what} file")
    header = ",".join(columns)
    from skisnow._checks import check_csv_separator

    try:
        text = path.read_text(encoding="utf-8-sig")
    except (ValueError, OSError) as exc:  # a UnicodeDecodeError is a ValueError
        raise FileFormatError(
            f"{path}: cannot be read as a UTF-8 CSV table with columns {header} ({exc})"
        ) from None
    first = next((ln for ln in text.splitlines() if ln.split("#", 1)[0].strip()), "")
    check_csv_separator(first, where=str(path), columns=header, error=FileFormatError)
    try:
        table = pd.read_csv(io.StringIO(text), comment="#")
    except ValueError as exc:  # pandas' parser and empty-data errors are ValueErrors
        raise FileFormatError(
            f"{path}: cannot be read as a UTF-8 CSV table with columns {header} ({exc})"
        ) from None
    # file line (1-based, as the user counts) of each data row: comments and blanks skipped
    data_lines = [
        no for no, line in enumerate(text.splitlines(), start=1) if line.split("#", 1)[0].strip()
    ][1:]

    def line(i: int) -> str:
        return f"line {data_lines[i]}" if i < len(data_lines) else f"data row {i + 1}"

    missing = [c for c in columns if c not in table.columns]
    if missing:
        raise FileFormatError(
            f"{path}: missing column{'s' * (len(missing) != 1)} {', '.join(missing)}; a {what} "
            "file needs columns "
            f"{header} (found: {', '.join(map(str, table.columns)) or 'none'})"
        )
    values = {}
    for col in columns:
        v = pd.to_numeric(table[col], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise FileFormatError(
                f"{path}: {line(int(bad[0]))}, column {col}: {table[col].iloc[bad[0]]!r} is not "
                "a finite number"
            )
        values[col] = v
    return values, line


def read_profile(path: str | Path, *, resample: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Read a rigid profile CSV with columns ``x_mm,height_mm`` → (x [m], height [m]).

    Rows must have finite numbers and strictly increasing ``x_mm`` (at least 8 rows). The
    half-space solver needs a uniform grid: an irregular ``x_mm`` is resampled linearly onto a
    uniform grid with the same number of points when ``resample`` (else an error).

    Raises
    ------
    FileFormatError
        Missing file or columns, non-numeric or non-finite cells (with row and column),
        non-increasing x.
    """
    path = Path(path)
    values, line = _read_columns(path, PROFILE_COLUMNS, "profile")
    from skisnow._checks import check_array, column_swap_hint

    swap = column_swap_hint(values["x_mm"], values["height_mm"])
    for col, quantity in (("x_mm", "x"), ("height_mm", "camber_height")):
        check_array(values[col], quantity, where=f"{path}, column {col}", row_label=line,
                    impossible=FileFormatError, cause=swap)  # fmt: skip
    x, h = values["x_mm"] * 1e-3, values["height_mm"] * 1e-3
    if x.size < 8:
        raise FileFormatError(f"{path}: a profile needs at least 8 rows, found {x.size}")
    if x[-1] - x[0] > 3.0:
        from skisnow._checks import check_value

        check_value((x[-1] - x[0]) * 1e3, "ski_length", where=f"{path}, column x_mm (its span)")
    d = np.diff(x)
    if np.any(d <= 0):
        i = int(np.flatnonzero(d <= 0)[0]) + 1
        raise FileFormatError(
            f"{path}: {line(i)}, column x_mm: x_mm must increase strictly from row to row"
        )
    if np.max(np.abs(d - d.mean())) > 1e-6 * d.mean():
        if not resample:
            raise FileFormatError(f"{path}: x_mm is not uniformly spaced")
        xu = np.linspace(x[0], x[-1], x.size)
        h = np.interp(xu, x, h)
        x = xu
    return x, h


def fields_table(solution: ContactSolution, zones: Any = None) -> pd.DataFrame:
    """The fields along the ski in field units.

    Strip/line: the values at each station. Surface: ``pressure_kpa`` is the width-averaged
    pressure q(x)/w(x) (so that Σ pressure·w·dx = W still holds), ``gap_um`` the smallest gap
    across the width and ``snow_displacement_um`` the width-averaged displacement. With
    ``zones`` (:func:`skisnow.contact.contact_zones` of the solution) two more columns: the
    ``region`` of each station (fixed by the ski) and its contact ``patch`` (1, 2, … tail to tip;
    0 out of contact).
    """
    import pandas as pd

    s = solution
    if s.pressure.ndim == 2:
        fp = s.footprint
        nfp = fp.sum(axis=1)
        p = np.where(fp, s.pressure, 0.0).sum(axis=1) / nfp
        gap = np.where(fp, s.gap, np.inf).min(axis=1)
        u = np.where(fp, s.displacement, 0.0).sum(axis=1) / nfp
    else:
        p, gap, u = s.pressure, s.gap, s.displacement
    table = pd.DataFrame(
        {
            "x_mm": s.x * 1e3,
            "pressure_kpa": p * 1e-3,
            "gap_um": gap * 1e6,
            "snow_displacement_um": u * 1e6,
        }
    )
    if zones is not None:
        from skisnow.contact._regions import region_index

        fp = zones.footprint
        table["region"] = np.asarray(fp.names)[region_index(s.x, fp.marks)]
        patch = np.zeros(s.x.size, dtype=int)
        for k, pt in enumerate(fp.patches, start=1):
            patch[(s.x > pt.start) & (s.x < pt.end)] = k
        table["patch"] = patch
    return table


def write_fields(solution: ContactSolution, path: str | Path, zones: Any = None) -> Path:
    """Write :func:`fields_table` as CSV (full float precision; with ``zones``, the region and
    the patch of each station)."""
    path = Path(path)
    from skisnow._atomic import atomic_write

    table = fields_table(solution, zones)
    return atomic_write(path, table.to_csv(index=False, float_format="%.10g"))


def read_fields(path: str | Path) -> dict[str, np.ndarray]:
    """Read a fields file of :func:`write_fields` back (SI units): ``x`` [m], ``pressure``
    [Pa], ``gap`` [m], ``displacement`` [m] along the ski.

    Raises
    ------
    FileFormatError
        Missing file or columns, a non-numeric or non-finite cell, x not strictly increasing or a
        negative pressure (each naming the file line and column).
    """
    path = Path(path)
    values, line = _read_columns(path, FIELD_COLUMNS, "fields")
    x = values["x_mm"]
    if x.size < 2:
        raise FileFormatError(f"{path}: a fields file needs at least 2 rows, found {x.size}")
    bad = np.flatnonzero(np.diff(x) <= 0)
    if bad.size:
        raise FileFormatError(
            f"{path}: {line(int(bad[0]) + 1)}, column x_mm: x_mm must increase strictly"
        )
    neg = np.flatnonzero(values["pressure_kpa"] < 0)
    if neg.size:
        raise FileFormatError(
            f"{path}: {line(int(neg[0]))}, column pressure_kpa: a contact pressure is >= 0, got "
            f"{values['pressure_kpa'][neg[0]]:g}"
        )
    return {
        "x": x * 1e-3,
        "pressure": values["pressure_kpa"] * 1e3,
        "gap": values["gap_um"] * 1e-6,
        "displacement": values["snow_displacement_um"] * 1e-6,
    }
