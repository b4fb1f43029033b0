"""The operators of the flexible ski on elastic snow: snow compliance plus beam compliance.

The gap of the flexible ski (:mod:`skisnow.contact._flexible`) responds to the pressure through
K_snow + K_beam: the half-space's (Kalliorinne et al. 2023, eq. 2, applied by FFT,
:class:`~skisnow.contact.Convolution`) or a local Winkler foundation's (for the checks against
Hetényi's (1946) free beam on an elastic foundation), plus the cantilever compliance of the two
halves of the ski clamped at the binding (:mod:`skisnow.contact._beam_operator`). Both duck-type
:class:`~skisnow.contact.Convolution` (call, ``add_columns``, ``shape``, ``self_influence``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from skisnow.contact._beam_operator import CantileverCompliance
from skisnow.contact._kernels import Convolution

__all__ = ["CoupledOperator", "WinklerOperator"]


@dataclass(frozen=True, eq=False)
class WinklerOperator:
    """u = p/k on every cell (a local foundation of modulus k [Pa/m]); duck-types Convolution."""

    shape: tuple[int, ...]
    foundation: float

    def __call__(self, p: np.ndarray) -> np.ndarray:
        return np.asarray(p, dtype=np.float64) / self.foundation

    def add_columns(self, out: np.ndarray, index: np.ndarray, values: np.ndarray) -> None:
        out.reshape(-1)[index] += values / self.foundation

    @property
    def self_influence(self) -> float:
        return 1.0 / self.foundation

    def inverse(self) -> WinklerOperator:
        return WinklerOperator(shape=self.shape, foundation=1.0 / self.foundation)


@dataclass(frozen=True, eq=False)
class CoupledOperator:
    """K_snow + K_beam acting on a pressure field (strip: (n,), surface: (nx, ny)) [Pa → m].

    The beam sees the force of each station (pressure × cell area, summed across the width) and
    its deflection is the same across the width. Duck-types :class:`Convolution` for the
    Polonsky–Keer iteration (call, ``add_columns``, ``shape``, ``self_influence``).
    """

    snow: Convolution | WinklerOperator
    beam: CantileverCompliance
    cell_area: float

    @property
    def shape(self) -> tuple[int, ...]:
        return self.snow.shape

    @property
    def self_influence(self) -> float:
        return self.snow.self_influence

    def beam_part(self, p: np.ndarray) -> np.ndarray:
        f = p.sum(axis=-1) if len(self.shape) == 2 else p
        w = self.beam(f * self.cell_area)
        return w[:, None] if len(self.shape) == 2 else w

    def __call__(self, p: np.ndarray) -> np.ndarray:
        p = np.asarray(p, dtype=np.float64)
        return self.snow(p) + self.beam_part(p)

    def add_columns(self, out: np.ndarray, index: np.ndarray, values: np.ndarray) -> None:
        self.snow.add_columns(out, index, values)
        f = np.zeros(self.beam.x.size)
        rows = index // self.shape[1] if len(self.shape) == 2 else index
        np.add.at(f, rows, values * self.cell_area)
        w = self.beam(f)
        out += w[:, None] if len(self.shape) == 2 else w
