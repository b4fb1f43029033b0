"""The ski at the macro scale: beam model, shipped virtual skis, virtual bench, metrics, network.

* :class:`Ski`, :func:`get_ski`, :data:`SHIPPED_SKIS` — virtual skis (EI(x), z0(x), kick zone).
* :func:`solve_beam` → :class:`BeamSolution`, :func:`loaded_profile` — the free-floating
  Euler–Bernoulli beam on the rigid bench stone (seed paper 000, §3.1, eq. 1 h = f(x, m, x_m)).
* The camber network (issue 4) is re-exported lazily (``CamberNetwork``, ``train_network``,
  ``load_network``, ``save_network``, ``shipped_network``) so that ``import skisnow.ski`` does
  not import JAX.
"""

from __future__ import annotations

import importlib
from typing import Any

from skisnow.ski._beam import (
    BeamSolution,
    beam_stiffness_matrix,
    cantilever_tip_deflection,
    hermite_interpolate,
    loaded_profile,
    solve_beam,
    three_point_bending_deflection,
)
from skisnow.ski._skis import SHIPPED_SKIS, Ski, get_ski

_LAZY = {
    "CamberNetwork": "skisnow.ski._network",
    "load_network": "skisnow.ski._network",
    "save_network": "skisnow.ski._network",
    "shipped_network": "skisnow.ski._network",
    "train_network": "skisnow.ski._training",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'skisnow.ski' has no attribute {name!r}")


__all__ = [
    "SHIPPED_SKIS",
    "BeamSolution",
    "CamberNetwork",
    "Ski",
    "beam_stiffness_matrix",
    "cantilever_tip_deflection",
    "get_ski",
    "hermite_interpolate",
    "load_network",
    "loaded_profile",
    "save_network",
    "shipped_network",
    "solve_beam",
    "three_point_bending_deflection",
    "train_network",
]
