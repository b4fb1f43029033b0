"""The camber bench: bench data and their files, the virtual bench that makes them, its metrics.

The SkiSelector bench of Kalliorinne et al. (2023, §2.1): a ski resting on the flat stone,
loaded through a boot plate by masses m 5–130 kg at positions x_m 40–240 mm behind the balance
point, its camber height h(x) measured along the running surface. :class:`BenchData` is such a
sequence as a tidy table (``ski, mass_kg, load_position_mm, x_mm, height_mm``) with its
metadata, read and written as CSV or Parquet with field units in the column headers and
validated on read (:func:`read_bench`, :func:`write_bench`, :func:`validate_bench_table`);
:func:`run_bench` runs the virtual bench (the beam of :mod:`skisnow.ski`) over a load grid
(:data:`DEFAULT_MASSES`, :data:`DEFAULT_LOAD_POSITIONS`, stations :func:`bench_grid`); the
practitioners' numbers of a ski read off its bench (Breitschädel 2012: camber height at half and
full body weight, wax pocket, closing load, stiffness k, contact lengths): :func:`ski_metrics` →
:class:`SkiMetrics`, :func:`closing_load`, :func:`closing_load_from_bench`; and the passport of a
ski (EI(x), z0(x) with their bands and those metrics): :func:`ski_passport` →
:class:`SkiPassport`; for validation, a bench by an implementation independent of the beam
of :mod:`skisnow.ski` (finite differences, contact at every node: :func:`reference_bench`,
:func:`reference_profile`) and plausible synthetic skis whose truth is known
(:func:`plausible_ski`, :func:`random_ski`, :func:`issue25_ski`).

May import: ski
"""

from __future__ import annotations

from skisnow.bench._data import (
    BENCH_COLUMNS,
    MIN_PROFILE_POINTS,
    BenchData,
    read_bench,
    validate_bench_table,
    write_bench,
)
from skisnow.bench._metrics import SkiMetrics, closing_load, closing_load_from_bench, ski_metrics
from skisnow.bench._passport import BAND_Z, SkiPassport, ski_passport
from skisnow.bench._reference import FiniteDifferenceProfile, reference_bench, reference_profile
from skisnow.bench._synthetic import RANGES, issue25_ski, plausible_ski, random_ski
from skisnow.bench._table import LOAD_ORDER_TOLERANCE_MM
from skisnow.bench._virtual import DEFAULT_LOAD_POSITIONS, DEFAULT_MASSES, bench_grid, run_bench

__all__ = [
    "BAND_Z",
    "BENCH_COLUMNS",
    "DEFAULT_LOAD_POSITIONS",
    "DEFAULT_MASSES",
    "LOAD_ORDER_TOLERANCE_MM",
    "MIN_PROFILE_POINTS",
    "RANGES",
    "BenchData",
    "FiniteDifferenceProfile",
    "SkiMetrics",
    "SkiPassport",
    "bench_grid",
    "closing_load",
    "closing_load_from_bench",
    "issue25_ski",
    "plausible_ski",
    "random_ski",
    "read_bench",
    "reference_bench",
    "reference_profile",
    "run_bench",
    "ski_metrics",
    "ski_passport",
    "validate_bench_table",
    "write_bench",
]
