"""Optional dependencies: imported where they are used, with an error that names the extra.

The default install holds what the main job needs; a dependency that serves one feature only is
an *extra* of ``pyproject.toml`` (``uv sync --extra NAME``, ``pip install 'skisnow[NAME]'``).
:func:`require` imports it or raises :class:`MissingDependencyError`, an
:class:`~skisnow.InputError` (the CLI's exit code 2: nothing was computed) that is also an
:class:`ImportError`.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from skisnow._errors import InputError

__all__ = ["EXTRAS", "MissingDependencyError", "require"]

#: Which extra of ``pyproject.toml`` brings which top-level module.
EXTRAS: dict[str, str] = {
    "pyarrow": "parquet",
    "jax": "network",
    "jaxlib": "network",
    "equinox": "network",
    "optax": "network",
}


class MissingDependencyError(InputError, ImportError):
    """An optional dependency is not installed; the message says which extra brings it."""


def require(module: str, *, feature: str) -> ModuleType:
    """Import ``module`` (e.g. ``'pyarrow.parquet'``) for ``feature`` (what the user asked for,
    e.g. ``'bench.parquet: Parquet bench files'``), or raise :class:`MissingDependencyError`
    naming the extra to install."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        extra = EXTRAS.get(top)
        how = (
            f"install it with `uv sync --extra {extra}` (or pip install 'skisnow[{extra}]')"
            if extra
            else f"install {top}"
        )
        raise MissingDependencyError(
            f"{feature} needs the optional dependency {top!r}, which is not installed: {how}"
        ) from exc
