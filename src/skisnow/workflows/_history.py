"""Load histories: the force on one ski and where it acts, over time (SI inside).

A load history is what force-measuring bindings or pressure insoles record during skiing: at
times t [s] the normal force F [N] the skier puts on ONE ski and the position x_m [m] of its
centre of pressure along the ski (from the balance point, positive toward the tip, as
:func:`skisnow.network.camber_profile` takes it). Each sample is one load case of the paper's
h = f(x, m, x_m) (Kalliorinne et al. 2023, §3.1: following "a whole cycle of the diagonal
stride ... as a sequence of load cases" is what the camber network is for).

Files: CSV with a header ``t_s`` and either ``force_n`` or ``mass_kg`` (F = m·g₀), and
``load_position_mm``; comment lines start with ``#``; row numbers in messages are the lines of
the file as a text editor counts them.
"""

from __future__ import annotations

import io as _io
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from skisnow._checks import (
    OVERRIDE_HINT,
    check_array,
    check_csv_separator,
    check_finite_column,
    check_value,
    implausible_allowed,
)
from skisnow._errors import FileFormatError, ImplausibleValueError, InputError
from skisnow.constants import STANDARD_GRAVITY

__all__ = ["MAX_GAP_FACTOR", "LoadHistory", "check_positions", "read_load_history"]

#: A time step longer than this many times the median step is a gap (a lost stretch of samples).
MAX_GAP_FACTOR: float = 3.0
#: The largest load-history file read (bytes).
MAX_HISTORY_BYTES: int = 256 << 20


@dataclass(frozen=True, kw_only=True, eq=False)
class LoadHistory:
    """Force and centre of pressure on one ski over time (SI units).

    Attributes
    ----------
    time
        Sample times t [s], strictly increasing, shape ``(n,)``.
    force
        Normal force F >= 0 [N] on the ski.
    load_position
        Centre of pressure x_m [m] from the balance point, positive toward the tip.
    name
        A label (template name or file name).
    source
        Where the numbers come from (a citation for the templates, the path of a file).
    lines
        For a history read from a file: the file line of each sample (messages name it).
    """

    time: np.ndarray
    force: np.ndarray
    load_position: np.ndarray
    name: str = "load history"
    source: str = field(default="", compare=False)
    lines: tuple[int, ...] | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        arrays = {}
        for attr in ("time", "force", "load_position"):
            a = np.array(getattr(self, attr), dtype=float)
            if a.ndim != 1:
                raise InputError(f"load history {attr} must be 1-D, got shape {a.shape}")
            a.setflags(write=False)
            arrays[attr] = a
            object.__setattr__(self, attr, a)
        n = arrays["time"].size
        if n < 2 or any(a.size != n for a in arrays.values()):
            raise InputError(
                "a load history needs time, force and load_position of one length >= 2, got "
                + ", ".join(f"{k} {v.size}" for k, v in arrays.items())
            )
        _validate(
            arrays["time"],
            arrays["force"],
            arrays["load_position"],
            where=f"load history {self.name!r}",
            label=lambda i: f"sample {i}",
            columns=("time", "force", "load_position"),
        )

    @property
    def mass(self) -> np.ndarray:
        """The force as a mass m = F/g₀ [kg] (the bench's and the network's load variable)."""
        return self.force / STANDARD_GRAVITY

    @property
    def duration(self) -> float:
        """t_end − t_start [s]."""
        return float(self.time[-1] - self.time[0])

    def resample(self, n_frames: int) -> LoadHistory:
        """The history linearly interpolated on ``n_frames`` equally spaced times (same span)."""
        if int(n_frames) < 2:
            raise InputError(f"n_frames must be at least 2, got {n_frames}")
        t = np.linspace(self.time[0], self.time[-1], int(n_frames))
        return LoadHistory(
            time=t,
            force=np.interp(t, self.time, self.force),
            load_position=np.interp(t, self.time, self.load_position),
            name=self.name,
            source=self.source,
        )


def _validate(
    t: np.ndarray,
    force: np.ndarray,
    position: np.ndarray,
    *,
    where: str,
    label,
    columns: tuple[str, str, str],
    max_gap_factor: float = MAX_GAP_FACTOR,
) -> None:
    """Raise an InputError naming the first bad row and column: NaN/inf, non-increasing time,
    a gap in time (a step > ``max_gap_factor`` × the median step), a negative force."""
    for values, col in zip((t, force, position), columns, strict=True):
        check_finite_column(values, where=where, column=col, row_label=label)
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0]) + 1
        raise InputError(
            f"{where}: {label(i)}, column {columns[0]!r}: time {t[i]:g} s does not increase "
            f"(previous {t[i - 1]:g} s); samples must be in strictly increasing time"
        )
    median = float(np.median(steps))
    big = steps > max_gap_factor * median
    if big.any():
        i = int(np.flatnonzero(big)[0]) + 1
        raise InputError(
            f"{where}: {label(i)}, column {columns[0]!r}: gap in time from {t[i - 1]:g} s to "
            f"{t[i]:g} s ({steps[i - 1]:g} s, more than {max_gap_factor:g}x the median step "
            f"{median:g} s); fill the missing samples or cut the history at the gap"
        )
    neg = force < 0
    if neg.any():
        i = int(np.flatnonzero(neg)[0])
        raise InputError(
            f"{where}: {label(i)}, column {columns[1]!r}: negative load {force[i]:g}; the snow "
            "can only push on the ski (use 0 while the ski is unloaded)"
        )
    # the plausibility ranges of skisnow._checks, in the file's units (column names say which)
    mass_column, load = columns[1] == "mass_kg", force  # the load column as given
    check_array(load, "load_mass" if mass_column else "force", where=f"{where}, column "
                f"{columns[1]!r}", row_label=label, check_span=False)  # fmt: skip
    to_mm = 1.0 if columns[2] == "load_position_mm" else 1e3  # a LoadHistory holds metres
    check_array(position * to_mm, "load_position", where=f"{where}, column {columns[2]!r}",
                row_label=label, check_span=False)  # fmt: skip
    check_value(median, "sample_step", where=f"{where}, column {columns[0]!r}: the median time "
                "step between samples")  # fmt: skip
    check_value(float(t[-1] - t[0]), "history_duration", where=f"{where}, column "
                f"{columns[0]!r}: the duration (last - first time)")  # fmt: skip
    span = float(np.ptp(position * to_mm))
    if 0.0 < span < 1.0 and not implausible_allowed():  # a centre of pressure moving 0.1 mm
        raise ImplausibleValueError(
            f"{where}, column {columns[2]!r}: the centre of pressure moves only {span:.3g} mm "
            "over the history (a stride moves it tens of mm); were the positions given in m? "
            f"If you really mean it, pass {OVERRIDE_HINT}."
        )
    # a derived quantity no column shows: the impulse over the duration, the mean load
    impulse = float(np.sum(0.5 * (load[1:] + load[:-1]) * steps))
    mean = impulse / float(t[-1] - t[0])
    check_value(mean, "mean_load" if mass_column else "mean_force",
                where=f"{where}, column {columns[1]!r}: the mean load (impulse / duration = "
                f"{impulse:.4g} {'kg s' if mass_column else 'N s'} over {t[-1] - t[0]:.4g} "
                "s)")  # fmt: skip


def read_load_history(path: str | Path, *, max_gap_factor: float = MAX_GAP_FACTOR) -> LoadHistory:
    """Read and validate a load-history CSV (``t_s``, ``force_n`` or ``mass_kg``,
    ``load_position_mm``).

    Parameters
    ----------
    path
        The CSV file; ``#`` comment lines are allowed anywhere.
    max_gap_factor
        A time step longer than this × the median step is refused as a gap.

    Returns
    -------
    LoadHistory
        In SI units (s, N, m).

    Raises
    ------
    FileFormatError
        Missing file, wrong or missing columns, a non-numeric or empty cell, NaN, time not
        strictly increasing, a gap in time, a negative force or mass — the message names the
        line of the file and the column.
    """
    import pandas as pd

    path = Path(path)
    if not path.is_file():
        raise FileFormatError(f"{path}: no such file")
    if path.stat().st_size > MAX_HISTORY_BYTES:
        raise FileFormatError(
            f"{path}: {path.stat().st_size / 2**20:.0f} MiB, more than the "
            f"{MAX_HISTORY_BYTES / 2**20:.0f} MiB a load history can be (a day of 1 kHz samples "
            "is less); cut it into cycles"
        )
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise FileFormatError(f"{path}: cannot read as UTF-8 text ({exc})") from None
    # file line numbers (1-based) of the lines pandas sees: not comments, not blank
    kept = [
        (n + 1, line)
        for n, line in enumerate(text.splitlines())
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if len(kept) < 3:
        raise FileFormatError(
            f"{path}: needs a header and at least two data rows (columns t_s, force_n or "
            "mass_kg, load_position_mm)"
        )
    check_csv_separator(kept[0][1], where=f"{path}: line {kept[0][0]}",
                        columns="t_s,force_n,load_position_mm or t_s,mass_kg,load_position_mm",
                        error=FileFormatError)  # fmt: skip
    try:
        table = pd.read_csv(
            _io.StringIO("\n".join(line for _, line in kept)), skipinitialspace=True
        )
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        # pandas counts the lines it was given (comments removed): say the file's line
        why = re.sub(r"line (\d+)", lambda m: f"line {kept[min(int(m[1]), len(kept)) - 1][0]}",
                     str(exc).strip())  # fmt: skip
        raise FileFormatError(f"{path}: not a valid CSV table ({why})") from None
    lines = [n for n, _ in kept[1:]]
    cols = [str(c).strip() for c in table.columns]
    table.columns = cols
    has_force, has_mass = "force_n" in cols, "mass_kg" in cols
    if has_force == has_mass:
        raise FileFormatError(
            f"{path}: give exactly one load column, force_n [N] or mass_kg [kg]; header has "
            f"{', '.join(cols)}"
        )
    load_col = "force_n" if has_force else "mass_kg"
    unknown = [c for c in cols if c not in ("t_s", "force_n", "mass_kg", "load_position_mm")]
    if unknown:
        raise FileFormatError(
            f"{path}: unknown column {unknown[0]!r}; a load history has the columns t_s, "
            "force_n or mass_kg, load_position_mm (a misspelt column would be ignored)"
        )
    missing = [c for c in ("t_s", "load_position_mm") if c not in cols]
    if missing:
        raise FileFormatError(
            f"{path}: missing column{'s' * (len(missing) != 1)} {', '.join(missing)}; a load "
            "history has the columns "
            f"t_s, force_n or mass_kg, load_position_mm (header has {', '.join(cols)})"
        )
    values = {}
    for col in ("t_s", load_col, "load_position_mm"):
        raw = table[col].to_numpy()
        num = pd.to_numeric(table[col], errors="coerce").to_numpy(dtype=float)
        bad = np.isnan(num) & ~pd.isna(raw)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise FileFormatError(
                f"{path}: line {lines[i]}, column {col!r}: {raw[i]!r} is not a number"
            )
        values[col] = num
    try:
        _validate(
            values["t_s"],
            values[load_col],
            values["load_position_mm"],
            where=str(path),
            label=lambda i: f"line {lines[i]}",
            columns=("t_s", load_col, "load_position_mm"),
            max_gap_factor=max_gap_factor,
        )
    except InputError as exc:
        raise FileFormatError(str(exc)) from None
    # every row is a frame of the cycle: as many as --frames may ask for
    check_value(len(lines), "frames", where=f"{path}: {len(lines):,} rows (each a frame: "
                "resample with --frames, or cut the history into cycles)")  # fmt: skip
    force = values[load_col] * (STANDARD_GRAVITY if load_col == "mass_kg" else 1.0)
    return LoadHistory(
        time=values["t_s"],
        force=force,
        load_position=values["load_position_mm"] * 1e-3,
        name=path.name,
        source=str(path),
        lines=tuple(lines),
    )


def check_positions(history: LoadHistory, *, x_tail: float, x_tip: float) -> None:
    """Raise an InputError if a centre of pressure lies off the ski's running surface
    [x_tail, x_tip] [m]; the message names the line of the file (or the sample) and the
    column."""
    pos = history.load_position
    off = (pos < x_tail) | (pos > x_tip)
    if off.any():
        i = int(np.flatnonzero(off)[0])
        where = f"line {history.lines[i]}" if history.lines else f"sample {i}"
        raise InputError(
            f"{history.source or history.name}: {where} (t = {history.time[i]:g} s), column "
            f"'load_position_mm': {history.load_position[i] * 1e3:g} mm is off the ski "
            f"(running surface {x_tail * 1e3:g} to {x_tip * 1e3:g} mm from the balance point)"
        )
