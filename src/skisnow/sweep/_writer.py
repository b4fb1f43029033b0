"""Writing a sweep's chunks into its store: each chunk's data, THEN its completion marker.

Written by the client (results gathered from the workers, or computed in process), or by the
workers themselves into their own chunks of the store (a local cluster: the same file system,
no result sent back, see :func:`skisnow.sweep.run_sweep`). Either way each Zarr chunk is a file
replaced whole (:class:`skisnow.sweep._zarr_io.ChunkFiles`), and a chunk's marker is written
only once all its data are: a process killed at any instant leaves a chunk with its data and
marker, or a chunk without marker that the next run computes again.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from skisnow._errors import InputError, SkisnowError
from skisnow.sweep._grid import SweepSpec
from skisnow.sweep._store import CHUNK_DIMS, chunk_shapes, lock_path, variables
from skisnow.sweep._zarr_io import ChunkFiles, write_all


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two arrays hold the same values (NaN equal to NaN)."""
    return bool(np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"))


class ChunkWriter:
    """Writes chunks into an existing store: each chunk's data, THEN its completion marker.

    Each variable's Zarr chunk is written whole as its file (:class:`ChunkFiles`: ~0.7 ms of
    CPU a Figure 8/9 chunk), or through Zarr for a store whose arrays that class does not write
    (~3.5 ms; ``Dataset.to_zarr(region=...)`` took 65 ms).

    ``token``: the run's token (:class:`skisnow.sweep._store.StoreLock`); the writer of a
    worker checks it in the store's lock file before a chunk's data and before its marker, so a
    task that outlives its run (a Ctrl-C'ed sweep on a cluster the user keeps) writes nothing
    into a store a later run has taken over.
    """

    def __init__(self, path: str | Path, spec: SweepSpec, *, token: str | None = None) -> None:
        self.path = Path(path)
        self.spec = spec
        self.token = token
        self._variables = variables(spec)
        self._shapes = chunk_shapes(spec)
        self._files = ChunkFiles.open(self.path, [*self._variables, "chunk_done"])
        if self._files is not None and not self._files_fit():
            self._files = None
        if self._files is None:
            import zarr  # only here: ~0.3 s to import in a worker that writes its own chunks

            group = zarr.open_group(str(self.path), mode="r+")
            self._arrays = {name: group[name] for name in self._variables}
            self._marker = group["chunk_done"]
        # profile-only variables this writer has written completely, by (ski, position)
        self._profiles_written: dict[tuple[int, int], dict[str, np.ndarray]] = {}

    def _files_fit(self) -> bool:
        """Whether every array is chunked as the tasks are (one chunk a task)."""
        assert self._files is not None
        for name, var in (*self._variables.items(), ("chunk_done", None)):
            dims = CHUNK_DIMS if var is None else var.dims
            want = iter(self._shapes.get(name, ()))
            shape = tuple(1 if d in CHUNK_DIMS else next(want) for d in dims)
            if self._files.chunk_shape(name) != shape:
                return False
        return True

    def _check_token(self) -> None:
        if self.token is None:
            return
        try:
            held = lock_path(self.path).read_text(encoding="ascii").split()
        except FileNotFoundError:  # no lock file: a platform without flock (StoreLock)
            return
        except OSError:
            held = []
        if held[1:2] != [self.token]:
            raise SkisnowError(
                f"{self.path} is no longer held by the sweep run this chunk belongs to; the "
                "chunk was not written (run the sweep again to complete the store)"
            )

    def write(self, key: tuple[int, int, int], values: Mapping[str, np.ndarray]) -> None:
        """Write the chunk ``key`` = (ski, position, modulus) indices from a chunk function's
        result (validated first: nothing is written if any variable is missing or misshapen)."""
        i, j, k = key
        data = {}
        for name, var in self._variables.items():
            if name not in values:
                raise InputError(
                    f"chunk function returned no {name!r} (needs {sorted(self._variables)})"
                )
            want = self._shapes[name]
            arr = np.asarray(values[name]).astype(var.dtype)
            if arr.shape != want:
                raise InputError(
                    f"chunk function returned {name!r} of shape {arr.shape}, need {want}"
                )
            data[name] = arr
        where = {"ski": i, "load_position_mm": j, "snow_modulus_mpa": k}
        # The profile-only variables (no snow_modulus_mpa dim) are the same for every modulus
        # of this (ski, position): each chunk writes them (idempotent; each chunk file is
        # replaced whole, so a kill never leaves a torn file), except where this writer has
        # already written the very same values for an earlier chunk of the (ski, position):
        # that write ended before the earlier chunk's marker, so every chunk with a marker has
        # them on disk (2 of the 11 files of a Figure 8/9 chunk).
        written = self._profiles_written.get((i, j), {})
        names = [
            name
            for name, var in self._variables.items()
            if "snow_modulus_mpa" in var.dims
            or not (name in written and _same(written[name], data[name]))
        ]
        self._check_token()
        if self._files is not None:
            for name in names:
                dims = self._variables[name].dims
                self._files.write(name, tuple(where.get(d, 0) for d in dims), data[name])
        else:
            write_all([
                (self._arrays[name],
                 tuple(where.get(d, slice(None)) for d in self._variables[name].dims),
                 data[name])
                for name in names
            ])  # fmt: skip
        self._profiles_written[(i, j)] = {
            name: data[name] for name, var in self._variables.items()
            if "snow_modulus_mpa" not in var.dims
        }  # fmt: skip
        self._check_token()
        # only once every variable is written
        if self._files is not None:
            self._files.write("chunk_done", (i, j, k), np.ones((1, 1, 1), dtype=np.int8))
        else:
            self._marker[i, j, k] = 1


def write_chunk(
    path: Path, spec: SweepSpec, key: tuple[int, int, int], values: Mapping[str, np.ndarray]
) -> None:
    """Write one chunk's data, THEN its completion marker (see :class:`ChunkWriter`)."""
    ChunkWriter(path, spec).write(key, values)


#: The writer of this process's current run, per thread (a cluster of threads shares it).
_WRITERS: dict[tuple[str, int], ChunkWriter] = {}
_WRITERS_LOCK = threading.Lock()


def run_writer(path: str, spec: SweepSpec, token: str) -> ChunkWriter:
    """The writer a worker uses for the chunks of the run ``token`` (one per run and thread:
    it remembers the profile-only variables it wrote, which only hold within its run)."""
    ident = threading.get_ident()
    with _WRITERS_LOCK:
        writer = _WRITERS.get((token, ident))
        if writer is None:
            for stale in [k for k in _WRITERS if k[1] == ident]:
                del _WRITERS[stale]
            writer = _WRITERS[(token, ident)] = ChunkWriter(path, spec, token=token)
    return writer
