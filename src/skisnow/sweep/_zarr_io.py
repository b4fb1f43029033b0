"""Writing a sweep's chunks into its Zarr store: whole Zarr chunks as files, or through Zarr.

:class:`ChunkFiles` writes each whole chunk of a Zarr format-2 array as its file, as the format
specifies it (the key ``NAME/i.j.k``, the C-ordered bytes through the array's compressor, an
all-fill-value chunk stored as no file, as zarr-python's default ``write_empty_chunks=False``
does), each file written beside its place and renamed onto it, as Zarr's ``LocalStore`` does.
It is the sweep's hot write path: Zarr's own path hands every chunk to its I/O event loop and
its codec and file threads, ~3.5 ms of CPU a Figure 8/9 chunk (11 files) against ~0.7 ms for
the same bytes written here (see docs/performance/speed.md, "Fifth pass"). :func:`write_all`
is the fallback through Zarr for arrays this module does not write itself (filters, another
layout or format).
"""

from __future__ import annotations

import json
import os
import uuid
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["ChunkFiles", "write_all"]


class ChunkFiles:
    """Whole-chunk writes into the Zarr format-2 arrays ``names`` of the store at ``root``.

    Use :meth:`open`, which returns ``None`` when an array is not one this class writes
    exactly as Zarr would (format 2, no filters, C order, ``"."`` separator, a numcodecs
    compressor or none, a fixed-size dtype).
    """

    def __init__(self, root: Path, arrays: dict[str, tuple[np.dtype, tuple[int, ...], Any, Any]]):
        self.root = root
        self._arrays = arrays  # name: (dtype, chunk shape, codec or None, fill value)

    @classmethod
    def open(cls, root: str | Path, names: Iterable[str]) -> ChunkFiles | None:
        """The writer of the arrays ``names`` of the store at ``root``, or ``None`` (see the
        class docstring)."""
        import numcodecs

        root = Path(root)
        arrays = {}
        for name in names:
            try:
                meta = json.loads((root / name / ".zarray").read_bytes())
                dtype = np.dtype(meta["dtype"])
            except (OSError, ValueError, TypeError, KeyError):
                return None
            if (
                meta.get("zarr_format") != 2
                or meta.get("filters")
                or meta.get("order") != "C"
                or meta.get("dimension_separator", ".") != "."
                or dtype.hasobject
                or dtype.kind not in "biuf"
            ):
                return None
            compressor = meta.get("compressor")
            codec = None if compressor is None else numcodecs.get_codec(compressor)
            fill = meta.get("fill_value")
            fill = dtype.type(0) if fill is None else np.array(fill).astype(dtype)[()]
            arrays[name] = (dtype, tuple(meta["chunks"]), codec, fill)
        return cls(root, arrays)

    def chunk_shape(self, name: str) -> tuple[int, ...]:
        """The shape of one chunk of ``name``."""
        return self._arrays[name][1]

    def write(self, name: str, index: tuple[int, ...], value: np.ndarray) -> None:
        """Store ``value`` as the whole chunk ``index`` (chunk-grid coordinates) of ``name``."""
        dtype, shape, codec, fill = self._arrays[name]
        chunk = np.ascontiguousarray(np.asarray(value).astype(dtype, copy=False)).reshape(shape)
        path = self.root / name / ".".join(map(str, index))
        if np.array_equal(chunk, np.full_like(chunk, fill), equal_nan=dtype.kind == "f"):
            path.unlink(missing_ok=True)  # Zarr's default: an all-fill-value chunk is no file
            return
        replace_file(path, chunk.tobytes() if codec is None else codec.encode(chunk))


def replace_file(path: Path, data: bytes) -> None:
    """Write ``data`` into a new file beside ``path`` and rename it onto ``path`` (readers see
    the old file or the new one, never a torn one). The array's directory must exist: a store
    deleted meanwhile is never recreated by a late write."""
    tmp = path.with_name(f"{path.name}.{uuid.uuid4().hex}.partial")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
    try:
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view) :]
        finally:
            os.close(fd)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_all(writes: list[tuple[Any, tuple[Any, ...], np.ndarray]]) -> None:
    """``array[index] = value`` for every write, all submitted to Zarr's I/O loop at once (one
    round trip instead of one per variable: 10 ms a chunk against 17 ms, measured on the
    explorer's store), or one by one with a Zarr that does not offer it."""
    try:
        from zarr.core.sync import sync
    except ImportError:  # pragma: no cover - another Zarr
        sync = None
    if sync is None or not all(hasattr(a, "_async_array") for a, _, _ in writes):
        for array, index, value in writes:  # pragma: no cover - another Zarr
            array[index] = value
        return

    async def gather() -> None:
        import asyncio

        # every write ends (done or failed) before this returns: a failed write must leave no
        # other write of the chunk running on Zarr's loop after the error is raised
        results = await asyncio.gather(
            *(a._async_array.setitem(i, v) for a, i, v in writes), return_exceptions=True
        )
        for result in results:
            if isinstance(result, BaseException):
                raise result

    sync(gather())
