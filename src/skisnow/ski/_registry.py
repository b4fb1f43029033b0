"""The skis by name or file: the shipped skis' names and files, :func:`get_ski`.

The shipped skis are ski files, ``skisnow/ski/data/<name>.json`` (:mod:`skisnow.ski._skifile`):
the plausible skis ``classic`` and ``skate`` (:data:`PLAUSIBLE_SKIS`: fitted to the captions of
Kalliorinne et al. (2023) under the practitioners' limits, what a technician should use) and the
reproduction skis ``classic-k22`` and ``skate-k22`` (:data:`REPRODUCTION_SKIS`: fitted to the
captions alone, to reproduce the paper's Figures 4-9; their provenance says where they leave
what is reported for real skis). :func:`get_ski` returns one of them by name, or a ski read from
any ski file, cached per (path, modification time, size).
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

from skisnow._errors import InputError
from skisnow.ski._skifile import read_ski
from skisnow.ski._skis import Ski

__all__ = ["PLAUSIBLE_SKIS", "REPRODUCTION_SKIS", "SHIPPED_SKIS", "get_ski", "shipped_ski_path"]

#: The plausible skis: fitted to the paper's captions under the practitioners' limits.
PLAUSIBLE_SKIS: tuple[str, ...] = ("classic", "skate")
#: The reproduction skis of the paper (Kalliorinne et al. 2023, Lubricants; "k22" is a short
#: name for "the paper's skis", not a citation): fitted to the captions of its Figures 4-7 alone,
#: NOT plausible skis (issue 30).
REPRODUCTION_SKIS: tuple[str, ...] = ("classic-k22", "skate-k22")
#: Names of the skis shipped with skisnow (see :func:`get_ski`).
SHIPPED_SKIS: tuple[str, ...] = PLAUSIBLE_SKIS + REPRODUCTION_SKIS


def shipped_ski_path(name: str) -> Path:
    """Path of the file of the shipped ski ``name`` (``skisnow/ski/data/<name>.json``)."""
    if name not in SHIPPED_SKIS:
        raise InputError(f"unknown ski {name!r}; shipped skis are: {', '.join(SHIPPED_SKIS)}")
    return Path(__file__).with_name("data") / f"{name}.json"


def get_ski(name_or_path: str | os.PathLike[str] | Ski) -> Ski:
    """Return a ski: a shipped one by name (:data:`SHIPPED_SKIS`) or one read from a ski file.

    Args:
        name_or_path: ``'classic'`` / ``'skate'``, the path of a ski file (``.json``, see
            :mod:`skisnow.ski._skifile`), or a :class:`Ski` (returned as is).

    A file is read once per (path, modification time, size) and cached; the shipped skis are
    files too (``skisnow/ski/data``).

    Raises:
        InputError: neither a shipped ski nor an existing file (the message lists the valid
            names); FileFormatError: the file is not a valid ski file (the message names the
            field and what would be valid).
    """
    if isinstance(name_or_path, Ski):
        return name_or_path
    if isinstance(name_or_path, str) and name_or_path in SHIPPED_SKIS:
        path = shipped_ski_path(name_or_path)
    else:
        path = Path(name_or_path)
        if not path.is_file():
            raise InputError(
                f"unknown ski {str(name_or_path)!r}: neither a shipped ski "
                f"({', '.join(SHIPPED_SKIS)}) nor an existing ski file (.json)"
            )
    stat = path.stat()
    return _read_cached(str(path.resolve()), stat.st_mtime_ns, stat.st_size)


@functools.lru_cache(maxsize=64)
def _read_cached(path: str, mtime_ns: int, size: int) -> Ski:
    return read_ski(path)
