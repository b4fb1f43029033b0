"""Camber-bench data: one tidy table, one row per sample, and its metadata.

Columns (field units, named in the header): ``ski`` (str), ``mass_kg`` (load m),
``load_position_mm`` (x_m from the balance point, positive toward the tip; the paper's "120 mm
behind the balance point" is -120), ``x_mm`` (position along the ski from the balance point),
``height_mm`` (camber height h above the bench plane). A *profile* is the set of rows sharing
(ski, mass_kg, load_position_mm); within a profile x_mm strictly increases.

Files (chosen by suffix):

* ``.csv`` — comment lines starting with ``#`` before the header. One of them is
  ``# skisnow-bench-metadata: {...}`` holding the metadata as one JSON object; the others are
  human-readable. Floats are written with 17 significant digits (exact round trip).
* ``.parquet`` — the same columns; the metadata JSON is stored in the Arrow schema metadata
  under the key ``skisnow.bench``.

Every file is validated before anything is returned; a failing file loads nothing and raises
:class:`~skisnow.FileFormatError` naming the file, the row (CSV: the line number in the file;
Parquet: the 1-based data row) and the column.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from skisnow._errors import FileFormatError, InputError
from skisnow._json import load_json
from skisnow.bench._table import BENCH_COLUMNS, MIN_PROFILE_POINTS, validate_bench_table

_META_TAG = "# skisnow-bench-metadata:"
_PARQUET_KEY = b"skisnow.bench"

__all__ = [
    "BENCH_COLUMNS",
    "MIN_PROFILE_POINTS",
    "BenchData",
    "read_bench",
    "validate_bench_table",
    "write_bench",
]


@dataclass(frozen=True, eq=False)
class BenchData:
    """A camber-bench data set: the tidy ``table`` and its ``metadata``.

    ``table`` has the columns :data:`BENCH_COLUMNS` (field units) and is validated on
    construction; ``metadata`` is a JSON-serialisable dict (ski name, length_mm, width_mm,
    balance point convention, source/device, units, ...).
    """

    table: pd.DataFrame
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.table, pd.DataFrame):
            raise InputError(f"BenchData.table must be a pandas DataFrame, got {type(self.table)}")
        if not isinstance(self.metadata, Mapping):
            raise InputError("BenchData.metadata must be a mapping")
        try:
            json.dumps(dict(self.metadata), allow_nan=False)
        except (TypeError, ValueError) as exc:
            raise InputError(f"BenchData.metadata must be JSON-serialisable: {exc}") from None
        object.__setattr__(self, "table", validate_bench_table(self.table))
        object.__setattr__(self, "metadata", dict(self.metadata))

    @classmethod
    def _from_validated(cls, table: pd.DataFrame, metadata: dict[str, Any]) -> BenchData:
        """Wrap a table that :func:`validate_bench_table` just returned (no second check)."""
        obj = object.__new__(cls)
        object.__setattr__(obj, "table", table)
        object.__setattr__(obj, "metadata", dict(metadata))
        return obj

    @property
    def skis(self) -> tuple[str, ...]:
        """Ski names in the table (in order of appearance)."""
        return tuple(pd.unique(self.table["ski"]))

    @property
    def conditions(self) -> pd.DataFrame:
        """The load conditions (ski, mass_kg, load_position_mm), one row per profile."""
        cols = ["ski", "mass_kg", "load_position_mm"]
        return self.table[cols].drop_duplicates().reset_index(drop=True)

    def ski_name(self, ski: str | None = None) -> str:
        """The ski a query is about: ``ski`` if the table holds it, else the only ski.

        Raises
        ------
        InputError
            ``ski`` is not in the table, or it is ``None`` and the table holds several skis.
        """
        names = self.skis
        if ski is None:
            if len(names) != 1:
                raise InputError(f"the bench holds several skis {names}; choose one with ski=")
            return names[0]
        if ski not in names:
            raise InputError(f"ski {ski!r} is not in the bench (it holds {names})")
        return ski

    def _at_position(self, ski: str, load_position_mm: float) -> pd.DataFrame:
        """Rows of ``ski`` at one load position; InputError lists the positions if none."""
        t = self.table[self.table["ski"] == ski]
        sub = t[np.isclose(t["load_position_mm"].to_numpy(), load_position_mm, atol=1e-6)]
        if sub.empty:
            raise InputError(
                f"the bench has no profiles at load_position_mm = {load_position_mm:g}; it has "
                f"{sorted(float(v) for v in np.unique(t['load_position_mm']))}"
            )
        return sub

    def heights_at(
        self, *, load_position_mm: float, x_mm: float = 0.0, ski: str | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """Camber height at one station over the bench's masses at one load position.

        Parameters
        ----------
        load_position_mm : float
            The load position x_m [mm]; must be one of the bench's positions.
        x_mm : float
            The station [mm] (default the balance point), interpolated linearly in each profile.
        ski : str, optional
            Which ski (see :meth:`ski_name`).

        Returns
        -------
        mass_kg, height_mm : ndarray
            The masses in increasing order and h(x_mm) of each profile.
        """
        sub = self._at_position(self.ski_name(ski), load_position_mm)
        masses, heights = [], []
        for m, grp in sub.groupby("mass_kg", sort=True):
            masses.append(float(m))
            heights.append(np.interp(x_mm, grp["x_mm"].to_numpy(), grp["height_mm"].to_numpy()))
        return np.array(masses), np.array(heights)

    def profile_at_mass(
        self, *, mass_kg: float, load_position_mm: float, ski: str | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """(x_mm, height_mm) at ``mass_kg``, linear in mass between the two nearest profiles.

        The stations are those of the lighter profile; the heavier one is interpolated onto
        them. ``mass_kg`` must lie within the bench's masses at ``load_position_mm``.
        """
        sub = self._at_position(self.ski_name(ski), load_position_mm)
        masses = np.unique(sub["mass_kg"].to_numpy())
        if not (masses[0] - 1e-9 <= mass_kg <= masses[-1] + 1e-9):
            raise InputError(
                f"mass {mass_kg} kg is outside the bench's masses [{masses[0]}, {masses[-1]}] "
                f"kg at load_position_mm = {load_position_mm:g}"
            )
        j = (
            int(np.clip(np.searchsorted(masses, mass_kg), 1, masses.size - 1))
            if masses.size > 1
            else 0
        )
        lo_m, hi_m = masses[max(j - 1, 0)], masses[j]
        g_lo = sub[sub["mass_kg"] == lo_m]
        g_hi = sub[sub["mass_kg"] == hi_m]
        x = g_lo["x_mm"].to_numpy()
        h_lo = g_lo["height_mm"].to_numpy()
        h_hi = np.interp(x, g_hi["x_mm"].to_numpy(), g_hi["height_mm"].to_numpy())
        wgt = 0.0 if hi_m == lo_m else (mass_kg - lo_m) / (hi_m - lo_m)
        return x, (1 - wgt) * h_lo + wgt * h_hi

    def kick_zone_mm(self, ski: str | None = None) -> tuple[float, float] | None:
        """The kick zone (start, end) [mm] the metadata gives for ``ski``, else ``None``.

        The metadata describes a ski when its ``ski`` entry names it; ``kick_zone_mm`` is
        ``[start, end]`` in mm or ``null`` (no kick zone, a skate ski).
        """
        name = self.ski_name(ski)
        md = self.metadata
        if md.get("ski") != name or md.get("kick_zone_mm") is None:
            return None
        kz = md["kick_zone_mm"]
        try:
            a, b = (float(v) for v in kz)
        except (TypeError, ValueError):
            raise InputError(
                f"bench metadata kick_zone_mm must be [start, end] in mm or null, got {kz!r}"
            ) from None
        return a, b

    def describes_kick_zone(self, ski: str | None = None) -> bool:
        """Whether the metadata says anything (a zone or ``null``) about ``ski``'s kick zone."""
        md = self.metadata
        return md.get("ski") == self.ski_name(ski) and "kick_zone_mm" in md

    def profile(
        self, *, mass_kg: float, load_position_mm: float, ski: str | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """(x_mm, height_mm) of one measured profile; InputError lists what exists if absent."""
        t = self.table
        sel = np.isclose(t["mass_kg"], mass_kg) & np.isclose(
            t["load_position_mm"], load_position_mm
        )
        if ski is not None:
            sel &= t["ski"] == ski
        elif len(self.skis) > 1:
            raise InputError(f"the bench holds several skis {self.skis}; name one with ski=")
        if not sel.any():
            raise InputError(
                f"no profile at mass_kg={mass_kg}, load_position_mm={load_position_mm}; masses: "
                f"{sorted(pd.unique(t['mass_kg']))}, positions: "
                f"{sorted(pd.unique(t['load_position_mm']))}"
            )
        sub = t[sel]
        return sub["x_mm"].to_numpy(), sub["height_mm"].to_numpy()

    def equals(self, other: BenchData) -> bool:
        """Same table values (exactly) and same metadata."""
        return self.table.equals(other.table) and self.metadata == other.metadata


def _suffix(path: Path) -> str:
    suf = path.suffix.lower()
    if suf not in (".csv", ".parquet"):
        raise FileFormatError(
            f"{path}: unknown bench file type {path.suffix!r}; use .csv or .parquet"
        )
    return suf


def write_bench(data: BenchData, path: str | Path) -> Path:
    """Write ``data`` to ``path`` (.csv or .parquet by suffix); return the path."""
    if not isinstance(data, BenchData):
        raise InputError(f"write_bench needs a BenchData, got {type(data).__name__}")
    path = Path(path)
    suf = _suffix(path)
    meta = json.dumps(data.metadata, allow_nan=False, sort_keys=True)
    if suf == ".csv":
        lines = [
            "# skisnow camber-bench data: one row per sample; columns carry their unit.",
            "# load_position_mm and x_mm are measured from the balance point, + toward the tip.",
            f"{_META_TAG} {meta}",
        ]
        body = data.table.to_csv(index=False, float_format="%.17g", lineterminator="\n")
        from skisnow._atomic import atomic_write

        atomic_write(path, "\n".join(lines) + "\n" + body)
    else:
        from skisnow._optional import require

        pa = require("pyarrow", feature=f"{path}: Parquet bench files")
        pq = require("pyarrow.parquet", feature=f"{path}: Parquet bench files")
        tbl = pa.Table.from_pandas(data.table, preserve_index=False)
        md = dict(tbl.schema.metadata or {})
        md[_PARQUET_KEY] = meta.encode("utf-8")
        from skisnow._atomic import atomic_path

        with atomic_path(path) as tmp:
            pq.write_table(tbl.replace_schema_metadata(md), tmp)
    return path


def read_bench(path: str | Path) -> BenchData:
    """Read and validate a bench file (.csv or .parquet); see the module docs for the format.

    Raises
    ------
    FileFormatError
        the file is missing, unreadable or fails validation (nothing loaded).
    """
    path = Path(path)
    suf = _suffix(path)
    if not path.is_file():
        raise FileFormatError(f"{path}: no such file")
    metadata: dict[str, Any] = {}
    if suf == ".csv":
        try:
            text = path.read_text(encoding="utf-8-sig")
        except (OSError, UnicodeDecodeError) as exc:
            raise FileFormatError(f"{path}: cannot read as UTF-8 text ({exc})") from None
        lines = text.splitlines()
        n_comment = 0
        for n_comment, line in enumerate(lines):
            if not line.startswith("#"):
                break
            if line.startswith(_META_TAG):
                metadata = load_json(line[len(_META_TAG) :],
                                     where=f"{path}: line {n_comment + 1}: metadata")  # fmt: skip
                if not isinstance(metadata, dict):
                    raise FileFormatError(
                        f"{path}: line {n_comment + 1}: metadata must be an object"
                    )
        else:
            n_comment = len(lines)
        import io as _io

        from skisnow._checks import check_csv_separator

        if n_comment < len(lines):
            check_csv_separator(lines[n_comment], where=f"{path}: line {n_comment + 1}",
                                columns=",".join(BENCH_COLUMNS), error=FileFormatError)  # fmt: skip
        try:
            table = pd.read_csv(
                _io.StringIO("\n".join(lines[n_comment:])),
                dtype={"ski": str},
                keep_default_na=True,
            )
        except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
            raise FileFormatError(f"{path}: not a valid CSV table ({exc})") from None
        # data row i (0-based) sits on file line n_comment + 2 + i (1-based; header first)
        clean = validate_bench_table(table, where=str(path), row_offset=n_comment + 2, csv=True)
    else:
        from skisnow._optional import require

        pa = require("pyarrow", feature=f"{path}: Parquet bench files")
        pq = require("pyarrow.parquet", feature=f"{path}: Parquet bench files")
        try:
            tbl = pq.read_table(path)
        except (OSError, pa.ArrowException) as exc:
            raise FileFormatError(f"{path}: not a readable Parquet file ({exc})") from None
        raw = (tbl.schema.metadata or {}).get(_PARQUET_KEY)
        if raw is not None:
            try:
                text = raw.decode("utf-8")
            except UnicodeDecodeError as exc:
                raise FileFormatError(f"{path}: schema metadata is not UTF-8 ({exc})") from None
            metadata = load_json(text, where=f"{path}: schema metadata")
        clean = validate_bench_table(tbl.to_pandas(), where=str(path), row_offset=1)
    try:
        json.dumps(metadata, allow_nan=False)
    except ValueError as exc:
        raise FileFormatError(f"{path}: metadata is not strict JSON ({exc})") from None
    return BenchData._from_validated(clean, metadata)
