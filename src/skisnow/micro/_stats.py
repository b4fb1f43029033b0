"""Correlation of surface descriptors with glide times (Scherge et al. 2021, eq. 10–11, Table 4).

Pearson's r (eq. 10) and its two-sided p-value come from ``scipy.stats.pearsonr`` (exact for
normal data: t = r√(n−2)/√(1−r²) with n−2 degrees of freedom). With n = 5 structures a
correlation is significant at α = 0.05 only for |r| > 0.878 (:func:`critical_r`; the paper
rounds to 0.88).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import stats

from skisnow._errors import FileFormatError, InputError
from skisnow.micro import _scherge2021 as scherge2021

__all__ = [
    "Correlation",
    "RankTable",
    "correlate",
    "critical_r",
    "pearson",
    "rank",
    "rank_table",
    "read_rank_table",
    "table4_comparison",
]


@dataclass(frozen=True)
class Correlation:
    """Pearson correlation of one descriptor with the glide times."""

    name: str
    r: float
    p_value: float
    n: int
    alpha: float

    @property
    def significant(self) -> bool:
        """|r| beyond the critical value at ``alpha`` (two-sided)."""
        return bool(self.p_value < self.alpha)


def pearson(
    x: Sequence[float] | np.ndarray, y: Sequence[float] | np.ndarray
) -> tuple[float, float]:
    """Pearson r (eq. 10) and two-sided p-value of paired samples."""
    xa = np.asarray(x, dtype=np.float64).ravel()
    ya = np.asarray(y, dtype=np.float64).ravel()
    if xa.size != ya.size or xa.size < 3:
        raise InputError(f"need >= 3 paired values of equal length, got {xa.size} and {ya.size}")
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ya))):
        raise InputError("values must be finite")
    if np.ptp(xa) == 0 or np.ptp(ya) == 0:
        raise InputError("a constant column has no correlation (zero variance)")
    res = stats.pearsonr(xa, ya)
    return float(res.statistic), float(res.pvalue)


def critical_r(n: int, *, alpha: float = 0.05) -> float:
    """Smallest |r| significant at ``alpha`` (two-sided) for n pairs: t/√(n−2+t²)."""
    if n < 3:
        raise InputError(f"need n >= 3, got {n}")
    t = stats.t.ppf(1.0 - alpha / 2.0, n - 2)
    return float(t / math.sqrt(n - 2 + t * t))


def rank(values: Sequence[float] | np.ndarray) -> np.ndarray:
    """Ranks 1..n in increasing order (1 = smallest glide time = fastest; ties share the mean
    rank)."""
    return stats.rankdata(np.asarray(values, dtype=np.float64), method="average")


def correlate(
    name: str, values: Sequence[float], glide_times: Sequence[float], *, alpha: float = 0.05
) -> Correlation:
    """:class:`Correlation` of one descriptor with the glide times."""
    r, p = pearson(values, glide_times)
    return Correlation(name=name, r=r, p_value=p, n=len(values), alpha=alpha)


@dataclass(frozen=True, eq=False)
class RankTable:
    """Structures, glide times, their ranking and the correlation of every descriptor."""

    structures: tuple[str, ...]
    glide_times: np.ndarray
    ranks: np.ndarray
    descriptors: dict[str, np.ndarray]
    correlations: tuple[Correlation, ...]
    critical_r: float


def rank_table(
    structures: Sequence[str],
    glide_times: Sequence[float],
    descriptors: Mapping[str, Sequence[float]],
    *,
    alpha: float = 0.05,
) -> RankTable:
    """Rank the structures by glide time and correlate every descriptor with it."""
    t = np.asarray(glide_times, dtype=np.float64)
    if len(structures) != t.size:
        raise InputError("one glide time per structure is needed")
    corr = tuple(correlate(k, v, t, alpha=alpha) for k, v in descriptors.items())
    return RankTable(
        structures=tuple(structures),
        glide_times=t,
        ranks=rank(t),
        descriptors={k: np.asarray(v, dtype=np.float64) for k, v in descriptors.items()},
        correlations=corr,
        critical_r=critical_r(t.size, alpha=alpha),
    )


def read_rank_table(path: str | Path, *, alpha: float = 0.05) -> RankTable:
    """Read a CSV with columns ``structure``, ``glide_time_s`` and any numeric descriptor
    columns (e.g. ``A_fr``, ``Sa_um``) and build the :class:`RankTable`."""
    import pandas as pd

    path = Path(path)
    try:
        df = pd.read_csv(path)
    except FileNotFoundError as exc:
        raise FileFormatError(f"{path}: no such file") from exc
    except (ValueError, OSError) as exc:  # pandas' parser and empty-data errors are ValueErrors
        raise FileFormatError(f"{path}: not a readable CSV table ({exc})") from exc
    if len(df.columns) == 1:  # one column: perhaps another separator
        from skisnow._checks import check_csv_separator

        check_csv_separator(str(df.columns[0]), where=str(path), error=FileFormatError,
                            columns="structure,glide_time_s,<descriptors>")  # fmt: skip
    missing = [c for c in ("structure", "glide_time_s") if c not in df.columns]
    if missing:
        raise FileFormatError(
            f"{path}: missing column{'s' * (len(missing) != 1)} {missing}; need 'structure', "
            "'glide_time_s' and "
            f"descriptor columns; found {list(df.columns)}"
        )
    if len(df) < 3:
        raise FileFormatError(
            f"{path}: need at least 3 structures, found {len(df)} row{'s' * (len(df) != 1)}"
        )
    descriptors: dict[str, np.ndarray] = {}
    for col in df.columns:
        if col in ("structure", "glide_time_s"):
            continue
        values = pd.to_numeric(df[col], errors="coerce")
        if values.isna().any():
            row = int(values.isna().to_numpy().argmax()) + 2
            raise FileFormatError(f"{path}: row {row}, column {col!r}: not a number")
        descriptors[col] = values.to_numpy(dtype=np.float64)
    times = pd.to_numeric(df["glide_time_s"], errors="coerce")
    if times.isna().any():
        row = int(times.isna().to_numpy().argmax()) + 2
        raise FileFormatError(f"{path}: row {row}, column 'glide_time_s': not a number")
    if not descriptors:
        raise FileFormatError(f"{path}: no descriptor column beside structure and glide_time_s")
    from skisnow._checks import check_array, check_value

    check_value(alpha, "alpha", where="alpha (CLI: --alpha)")
    check_array(
        times.to_numpy(dtype=np.float64),
        "glide_time",
        where=f"{path}, column 'glide_time_s'",
        row_label=lambda i: f"line {i + 2}",
        impossible=FileFormatError,
    )
    names = [str(s) for s in df["structure"]]
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        if name in seen:
            raise FileFormatError(
                f"{path}: line {i + 2}, column 'structure': {name!r} already on line "
                f"{seen[name] + 2}; each structure needs one row (average repeated runs first)"
            )
        seen[name] = i
    for col, values in [("glide_time_s", times.to_numpy(dtype=np.float64)), *descriptors.items()]:
        if np.ptp(values) == 0.0:
            raise FileFormatError(
                f"{path}: column {col!r} is constant ({values[0]:g}); Pearson's r with it is "
                "undefined: give a column that varies between structures"
            )
    return rank_table(
        [str(s) for s in df["structure"]],
        times.to_numpy(dtype=np.float64),
        descriptors,
        alpha=alpha,
    )


def table4_comparison() -> list[dict[str, float | str | bool]]:
    """Recompute Table 4's r column from Table 3's glide times.

    For each roughness parameter: r (and p) against the published averages (r is invariant to
    the scaling of eq. 11, so the dimensionless time gives the same r), r against the mean of
    the three runs recomputed from Table 3, and the published r.
    """
    names = scherge2021.STRUCTURES
    t_pub = [scherge2021.TABLE3_AVERAGE_S[s] for s in names]
    t_runs = [float(np.mean(scherge2021.TABLE3_RUNS_S[s])) for s in names]
    rows: list[dict[str, float | str | bool]] = []
    for param, values in scherge2021.TABLE4.items():
        x = [values[s] for s in names]
        r1, p1 = pearson(x, t_pub)
        r2, _ = pearson(x, t_runs)
        pub = scherge2021.TABLE4_R_PUBLISHED[param]
        rows.append(
            {
                "parameter": param,
                "r_published": pub,
                "r_from_averages": r1,
                "p_value": p1,
                "r_from_runs": r2,
                "difference": r1 - pub,
                "agrees_to_rounding": abs(round(r1, 2) - pub) <= 0.01,
            }
        )
    return rows
