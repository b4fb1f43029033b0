"""File formats: bench data tables, profiles, model files. Field units in column headers.

* :class:`BenchData`, :func:`read_bench`, :func:`write_bench` — camber-bench tables (CSV with a
  commented JSON metadata line, or Parquet with schema metadata), validated on read.
* The network's model files (issue 4, ``skisnow.io._model``) are re-exported lazily.
"""

from __future__ import annotations

from skisnow._lazy import lazy_getattr
from skisnow.io._bench import (
    BENCH_COLUMNS,
    MIN_PROFILE_POINTS,
    BenchData,
    read_bench,
    validate_bench_table,
    write_bench,
)

_LAZY = {
    "model_paths": "skisnow.io._model",
    "parse_model_bytes": "skisnow.io._model",
    "read_model_files": "skisnow.io._model",
    "write_model_files": "skisnow.io._model",
}


__getattr__ = lazy_getattr(__name__, _LAZY)


__all__ = [
    "BENCH_COLUMNS",
    "MIN_PROFILE_POINTS",
    "BenchData",
    "model_paths",
    "parse_model_bytes",
    "read_bench",
    "read_model_files",
    "validate_bench_table",
    "write_bench",
]
