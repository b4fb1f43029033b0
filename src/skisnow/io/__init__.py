"""File formats, kept for compatibility: bench tables and the camber network's model files.

This package holds no code of its own any more. Kept for compatibility; the home of the bench
data and their files (BENCH_COLUMNS, MIN_PROFILE_POINTS, BenchData, read_bench,
validate_bench_table, write_bench) is :mod:`skisnow.bench`, the home of the network's model
files (MODEL_FORMAT, MODEL_FORMAT_VERSION, load_network, metadata_checksum, model_paths,
network_arrays, network_from_files, parse_model_bytes, read_model_files, save_network,
shipped_network, write_model_files) is :mod:`skisnow.network`: these names are imported from
there on first use. Nothing inside skisnow imports from here.

May import: core only
"""

from __future__ import annotations

from skisnow._lazy import lazy_getattr

# The names repeat those of their homes on purpose: a compatibility map names each old name and
# its home, statically (read by tools/import_graph.py and tests/test_compat.py).
_LAZY = {
    **dict.fromkeys(
        (
            "BENCH_COLUMNS",
            "MIN_PROFILE_POINTS",
            "BenchData",
            "read_bench",
            "validate_bench_table",
            "write_bench",
        ),
        "skisnow.bench",
    ),
    **dict.fromkeys(
        (
            "MODEL_FORMAT",
            "MODEL_FORMAT_VERSION",
            "load_network",
            "metadata_checksum",
            "model_paths",
            "network_arrays",
            "network_from_files",
            "parse_model_bytes",
            "read_model_files",
            "save_network",
            "shipped_network",
            "write_model_files",
        ),
        "skisnow.network",
    ),
}

__getattr__ = lazy_getattr(__name__, _LAZY)

__all__ = sorted(_LAZY)
