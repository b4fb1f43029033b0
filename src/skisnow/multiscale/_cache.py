"""Where the micro curves are kept between runs: a user cache directory, atomic writes.

The directory is, in this order: the ``cache_dir`` argument; the environment variable
``SKISNOW_CACHE_DIR``; ``$XDG_CACHE_HOME/skisnow``; ``~/.cache/skisnow``. Curves live in its
``micro-curves/`` folder as one ``.npz`` per key (arrays plus a JSON ``meta`` entry that repeats
the full key, checked on reading). A file is written to a hidden sibling and renamed
(:mod:`skisnow._atomic`), so a reader never sees half a file; a corrupt or foreign file is
ignored (and recomputed), never trusted.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["cache_dir", "load_arrays", "save_arrays"]

#: Environment variable that overrides the cache directory.
CACHE_ENV = "SKISNOW_CACHE_DIR"


def cache_dir(override: str | Path | None = None) -> Path:
    """The cache directory (see the module docstring); not created here."""
    if override is not None:
        return Path(override)
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env)
    xdg = os.environ.get("XDG_CACHE_HOME")
    root = Path(xdg) if xdg else Path.home() / ".cache"
    return root / "skisnow"


def _path(key: str, directory: str | Path | None) -> Path:
    return cache_dir(directory) / "micro-curves" / f"{key[:40]}.npz"


def load_arrays(key: str, directory: str | Path | None = None) -> tuple[dict, dict] | None:
    """The arrays and meta stored under ``key``, or ``None`` (absent, unreadable, other key)."""
    path = _path(key, directory)
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            if meta.get("key") != key:
                return None
            arrays = {k: np.asarray(f[k]) for k in f.files if k != "meta"}
    except (OSError, ValueError, KeyError, json.JSONDecodeError, EOFError):
        return None
    return arrays, meta


def save_arrays(
    key: str, arrays: dict[str, np.ndarray], meta: dict[str, Any], directory: str | Path | None
) -> Path | None:
    """Store ``arrays`` and ``meta`` under ``key`` atomically; ``None`` if the directory is not
    writable (the curves are then simply not cached)."""
    from skisnow._atomic import atomic_path

    path = _path(key, directory)
    doc = json.dumps(meta | {"key": key}, sort_keys=True)
    try:
        with atomic_path(path) as tmp:
            np.savez(tmp, meta=np.array(doc), **arrays)
    except OSError:
        return None
    return path
