"""File formats: bench data tables, profiles, model files. Field units in column headers.

* :class:`BenchData`, :func:`read_bench`, :func:`write_bench` — camber-bench tables (CSV with a
  commented JSON metadata line, or Parquet with schema metadata), validated on read.
* :func:`save_network`, :func:`load_network`, :func:`shipped_network` — the camber network's
  model files (``PATH.npz`` weights + ``PATH.json`` metadata; JAX is imported only when a
  network is built); :func:`read_model_files` and friends move the arrays and the JSON safely.
"""

from __future__ import annotations

from skisnow.io._bench import (
    BENCH_COLUMNS,
    MIN_PROFILE_POINTS,
    BenchData,
    read_bench,
    validate_bench_table,
    write_bench,
)
from skisnow.io._model import (
    MODEL_FORMAT,
    MODEL_FORMAT_VERSION,
    load_network,
    metadata_checksum,
    model_paths,
    network_arrays,
    network_from_files,
    parse_model_bytes,
    read_model_files,
    save_network,
    shipped_network,
    write_model_files,
)

__all__ = [
    "BENCH_COLUMNS",
    "MIN_PROFILE_POINTS",
    "MODEL_FORMAT",
    "MODEL_FORMAT_VERSION",
    "BenchData",
    "load_network",
    "metadata_checksum",
    "model_paths",
    "network_arrays",
    "network_from_files",
    "parse_model_bytes",
    "read_bench",
    "read_model_files",
    "save_network",
    "shipped_network",
    "validate_bench_table",
    "write_bench",
    "write_model_files",
]
