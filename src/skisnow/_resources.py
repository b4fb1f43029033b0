"""Resources counted before they are spent: the number of solves a run asks for, and the memory
an array file will take, read from its header before a byte of data is read.

* :func:`check_solves`: a run of more contact solves than any machine finishes (a grid of
  100 000 masses, ``--frames 1e9``) is refused with the number;
* :func:`check_npy_header`, :func:`check_npz`: a ``.npy`` header declares the array's shape and
  type; a ``.npz`` is a zip archive whose directory declares each member's uncompressed size.
  Both are read (the ``.npz`` members' ``.npy`` headers through the decompressor, a few hundred
  bytes) and checked against the memory this machine allows (:func:`skisnow._checks.
  check_memory`) and against the file itself (a header declaring more data than the file
  holds is a truncated file or a forgery), so an archive bomb is refused before it inflates;
* :func:`load_npz`: an ``.npz`` read only after these checks, never with pickle.
"""

from __future__ import annotations

import io
import math
import os
import zipfile
from collections.abc import Iterable
from pathlib import Path
from typing import IO, Any

import numpy as np

from skisnow._checks import check_memory
from skisnow._errors import FileFormatError, InputError

__all__ = ["MAX_NPZ_MEMBERS", "MAX_SOLVES", "check_npy_header", "check_npz", "check_solves",
           "load_npz"]  # fmt: skip

#: More contact solves than this in one run (days on any machine) are refused: split the grid.
MAX_SOLVES = 5_000_000
#: An ``.npz`` of skisnow holds a few dozen arrays; more members than this is not one of them.
MAX_NPZ_MEMBERS = 10_000


def check_solves(n: float, *, where: str, what: str, hint: str = "") -> int:
    """Refuse a run of more than :data:`MAX_SOLVES` solves (``n``), naming ``where`` and the
    number; returns ``n`` as an int."""
    if not math.isfinite(n) or n > MAX_SOLVES:
        raise InputError(
            f"{where}: {what} means {n:.4g} contact solves, more than the {MAX_SOLVES:,} one run "
            f"may ask for (days of computation){'; ' + hint if hint else ''}"
        )
    return int(n)


def _header(fh: IO[bytes], where: str) -> tuple[tuple[int, ...], np.dtype, int]:
    """(shape, dtype, header length) of the ``.npy`` stream ``fh`` (positioned at its start)."""
    fmt = np.lib.format
    try:
        version = fmt.read_magic(fh)
        reader = {(1, 0): fmt.read_array_header_1_0, (2, 0): fmt.read_array_header_2_0}.get(version)
        if reader is None:
            raise ValueError(f"unsupported .npy version {version}")
        shape, _, dtype = reader(fh, max_header_size=100_000)
    except (ValueError, EOFError, OSError, SyntaxError, zipfile.BadZipFile) as exc:
        raise FileFormatError(f"{where}: not a readable .npy array header ({exc})") from None
    return tuple(int(n) for n in shape), np.dtype(dtype), fh.tell()


def _check_array(shape: tuple[int, ...], dtype: np.dtype, data_bytes: int | None,
                 where: str) -> int:  # fmt: skip
    if dtype.hasobject:
        raise FileFormatError(f"{where}: holds Python objects (pickle), which skisnow never loads")
    n_bytes = math.prod(shape) * dtype.itemsize
    check_memory(
        n_bytes,
        where=where,
        what=f"its header's array of shape {shape} ({dtype})",
        hint="is this the right file?",
    )
    if data_bytes is not None and data_bytes < n_bytes:
        raise FileFormatError(
            f"{where}: the header declares {n_bytes:,} bytes of data (shape {shape}, {dtype}) "
            f"but the file holds {data_bytes:,}: truncated or not a .npy array"
        )
    return n_bytes


def check_npy_header(path: str | os.PathLike[str], *, where: str | None = None) -> int:
    """Check the header of a ``.npy`` file before reading it; return the data's bytes."""
    p = Path(path)
    where = where or str(p)
    with open(p, "rb") as fh:
        shape, dtype, offset = _header(fh, where)
    return _check_array(shape, dtype, p.stat().st_size - offset, where)


def check_npz(source: str | os.PathLike[str] | bytes, *, where: str) -> dict[str, int]:
    """Check a ``.npz`` archive before reading it: member count, every member's declared size
    and ``.npy`` header, the total against the memory allowed. Returns ``{member: bytes}``."""
    raw: Any = io.BytesIO(source) if isinstance(source, bytes) else source
    sizes: dict[str, int] = {}
    try:
        with zipfile.ZipFile(raw) as zf:
            infos = zf.infolist()
            if len(infos) > MAX_NPZ_MEMBERS:
                raise FileFormatError(
                    f"{where}: {len(infos):,} members, more than the {MAX_NPZ_MEMBERS:,} of any "
                    ".npz skisnow reads"
                )
            declared = sum(i.file_size for i in infos)
            check_memory(declared, where=where, what=f"its {len(infos)} arrays once decompressed",
                         hint="is this the right file?")  # fmt: skip
            for info in infos:
                member = f"{where}, member {info.filename!r}"
                with zf.open(info) as fh:
                    shape, dtype, offset = _header(fh, member)
                sizes[info.filename] = _check_array(shape, dtype, info.file_size - offset, member)
            check_memory(sum(sizes.values()), where=where, what="its arrays",
                         hint="is this the right file?")  # fmt: skip
    except zipfile.BadZipFile as exc:
        raise FileFormatError(f"{where}: not a readable .npz archive ({exc})") from None
    except (OSError, EOFError) as exc:
        raise FileFormatError(f"{where}: cannot read the archive ({exc})") from None
    return sizes


def load_npz(source: str | os.PathLike[str] | bytes, *, where: str,
             keys: Iterable[str] | None = None) -> dict[str, np.ndarray]:  # fmt: skip
    """The arrays of a ``.npz`` (all, or ``keys``), read after :func:`check_npz`; never pickle."""
    check_npz(source, where=where)
    raw: Any = io.BytesIO(source) if isinstance(source, bytes) else source
    try:
        with np.load(raw, allow_pickle=False) as f:
            names = f.files if keys is None else list(keys)
            return {k: f[k] for k in names}
    except KeyError:
        raise
    except (ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
        raise FileFormatError(f"{where}: cannot read the arrays ({exc})") from None
