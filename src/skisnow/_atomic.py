"""Nothing half-written: every file skisnow writes appears whole or not at all.

One helper for every writer (figures, reports, NetCDF exports, model files, ski files, bench
tables, topographies, fields): the data go to a hidden temporary sibling in the same directory,
are flushed to disk (``fsync``), and the sibling is renamed onto the target (``os.replace``, atomic
on POSIX and Windows within one file system). A process killed at any instant leaves either the
previous file or the complete new one; at most a hidden ``.NAME.tmp-*`` sibling stays behind,
which no reader mistakes for the output.

Writers that choose their format by the file suffix (Matplotlib, xarray, NumPy, Arrow) keep
working: the temporary name ends in the target's suffix.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
from collections.abc import Iterator
from pathlib import Path

__all__ = ["atomic_path", "atomic_write", "fsync_dir", "temporary_sibling"]


def temporary_sibling(path: str | Path, *, tag: str = "tmp") -> Path:
    """A fresh hidden name beside ``path`` that keeps its suffix: ``dir/.STEM.TAG-PID-RAND.SUF``."""
    p = Path(path)
    return p.with_name(f".{p.stem}.{tag}-{os.getpid()}-{secrets.token_hex(4)}{p.suffix}")


def fsync_dir(directory: str | Path) -> None:
    """Flush a directory entry (the rename itself) to disk where the platform allows it."""
    with contextlib.suppress(OSError):  # not every OS/file system supports fsync on directories
        fd = os.open(str(directory), os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _fsync_tree(path: Path) -> None:
    paths = [path] if path.is_file() else [p for p in path.rglob("*") if p.is_file()]
    for p in paths:
        with contextlib.suppress(OSError), open(p, "rb") as fh:
            os.fsync(fh.fileno())


@contextlib.contextmanager
def atomic_path(path: str | Path, *, mkdir: bool = True) -> Iterator[Path]:
    """Yield a temporary sibling of ``path`` to write to; on success rename it onto ``path``.

    If the block raises, the temporary file (or directory) is removed and ``path`` is left as it
    was. Works for a file or a directory written by any library::

        with atomic_path(out) as tmp:
            fig.savefig(tmp)

    Parameters
    ----------
    path
        The final file name.
    mkdir
        Create the parent directory first.
    """
    target = Path(path)
    if mkdir:
        target.parent.mkdir(parents=True, exist_ok=True)
    tmp = temporary_sibling(target)
    try:
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(f"{target}: the writer produced no file")
        _fsync_tree(tmp)
        if tmp.is_dir() and target.is_dir():
            # os.replace cannot replace a non-empty directory: move the old one aside first
            old = temporary_sibling(target, tag="old")
            os.replace(target, old)
            os.replace(tmp, target)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, target)
        fsync_dir(target.parent)
    except BaseException:
        if tmp.is_dir():
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            with contextlib.suppress(OSError):
                tmp.unlink()
        raise


def atomic_write(path: str | Path, data: str | bytes, *, encoding: str = "utf-8") -> Path:
    """Write ``data`` (text or bytes) to ``path`` atomically (see :func:`atomic_path`)."""
    with atomic_path(path) as tmp:
        if isinstance(data, bytes):
            tmp.write_bytes(data)
        else:
            with open(tmp, "w", encoding=encoding, newline="") as fh:
                fh.write(data)
    return Path(path)
