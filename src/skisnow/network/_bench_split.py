"""The training data of a camber network: one ski's bench table, its hash, its held-out split.

Kalliorinne et al. (2023, section 3.1) train the network on one ski's bench measurements;
:func:`bench_sha256` identifies that bench in a model file, :func:`split_conditions` holds out
whole load conditions for the early stopping of :func:`skisnow.network.train_network`.
"""

from __future__ import annotations

import contextlib
import hashlib

import numpy as np
import pandas as pd

from skisnow._errors import InputError
from skisnow.bench import BENCH_COLUMNS, BenchData

__all__ = ["bench_sha256", "split_conditions"]


def _bench_table(bench: BenchData | pd.DataFrame) -> pd.DataFrame:
    """The validated table of one ski: :class:`~skisnow.bench.BenchData`'s validation (the one
    definition of a valid bench table) plus the training's own rule, one ski per network."""
    if isinstance(bench, pd.DataFrame):
        bench = BenchData(bench)  # validates (FileFormatError naming the row and column)
    elif not isinstance(bench, BenchData):
        raise InputError(
            "bench must be a skisnow.bench.BenchData or a pandas DataFrame, "
            f"got {type(bench).__name__}"
        )
    if len(bench.skis) != 1:
        raise InputError(
            "bench table must hold one ski (a network is trained per ski), "
            f"found {list(bench.skis)}"
        )
    return bench.table


def bench_sha256(bench: BenchData | pd.DataFrame) -> str:
    """sha256 of the bench data's content (ski name + rows sorted, float64), order-independent.

    A DataFrame is put in bench order (by mass, position, x) before it is validated, so that
    the same samples in any row order give the same hash.
    """
    if isinstance(bench, pd.DataFrame) and set(BENCH_COLUMNS) <= set(bench.columns):
        # mixed types in a column cannot be sorted: the validation below names the bad value
        with contextlib.suppress(TypeError):
            bench = bench.sort_values(list(BENCH_COLUMNS[1:]), kind="stable")
    table = _bench_table(bench)
    cols = list(BENCH_COLUMNS[1:])
    values = table[cols].to_numpy(dtype=np.float64)
    order = np.lexsort(values.T[::-1])
    h = hashlib.sha256(str(table["ski"].iloc[0]).encode())
    h.update(np.ascontiguousarray(values[order]).astype("<f8").tobytes())
    return h.hexdigest()


def split_conditions(
    masses: np.ndarray, positions: np.ndarray, *, validation_fraction: float, seed: int
) -> np.ndarray:
    """Boolean mask over load conditions: True = held out for validation.

    Conditions are drawn (seeded) among the interior ones -- not at the extreme mass or
    position of the bench -- so that validation measures interpolation, the network's job, and
    the trained domain stays the bench's domain. At least one condition is held out.
    """
    n = len(masses)
    interior = (
        (masses > masses.min())
        & (masses < masses.max())
        & (positions > positions.min())
        & (positions < positions.max())
    )
    candidates = np.flatnonzero(interior)
    if candidates.size == 0:
        candidates = np.arange(n)
    n_val = max(1, round(validation_fraction * n))
    n_val = min(n_val, candidates.size, n - 2)
    if n_val < 1:
        raise InputError(f"bench has {n} load conditions; at least 3 are needed to train")
    rng = np.random.default_rng(seed)
    chosen = rng.choice(candidates, size=n_val, replace=False)
    mask = np.zeros(n, dtype=bool)
    mask[chosen] = True
    return mask
