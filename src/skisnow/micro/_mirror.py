"""The half-space under a map that stands for a piece of a large contact: mirror boundaries.

A topography map (1 mm² of a ski base) is a sample of a surface that continues far beyond it,
pressed everywhere with the same nominal pressure. The zero-padded (free-boundary) half-space of
:func:`skisnow.contact.surface_convolution` loads only the map: the half-space then bends like
under a finite punch, u rises by ~p·L/E' from the edges to the centre (1 µm at 1 MPa on 1 mm,
the size of the roughness itself). The standard remedy is a periodic half-space (Stanley & Kato
1997; Campañá & Müser 2006); a measured map is not periodic, so skisnow continues it by its
mirror images (even extension, period 2L per axis) — the extension the 33 µm low-pass already
uses (:func:`skisnow.micro.lowpass`, a type-II DCT). An even field stays even under the even
half-space kernel, so the periodic problem on the 2L × 2L extension is solved on the map itself
with an operator that is diagonal in the type-II DCT basis:

    û(q) = 4 p̂(q) / (E' |q|),    q = (π i/(N_x Δx), π j/(N_y Δy)),    û(0) = 0,

E' the contact package's equivalent modulus (2/E' = Σ(1 − ν²)/E, so 4/E' = 2/E* of Johnson's
1/E* = Σ(1 − ν²)/E: a periodic pressure p cos(qx) indents a half-space by 2p/(E* q)). The mean
displacement is zero (the mean load is carried "at infinity", as in every periodic
formulation), so the rigid approach alone sets the mean gap: ū = d − mean(h) + 0.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft

from skisnow._errors import InputError

__all__ = ["MirrorOperator"]


@dataclass(frozen=True, eq=False)
class MirrorOperator:
    """u = K p on a map with mirror-symmetric (even) continuation, as a flat-vector operator.

    Implements :class:`skisnow.contact.ComplianceOperator` (``__call__`` on flat vectors and
    ``self_influence``), so the contact package's Polonsky–Keer core runs on it unchanged.

    Parameters
    ----------
    shape
        Grid ``(nx, ny)`` of the map.
    dx, dy
        Pixel sizes [m].
    modulus
        Equivalent modulus E' [Pa] (contact-package convention, E' = 2E*).
    workers
        Threads of ``scipy.fft``.
    """

    shape: tuple[int, int]
    dx: float
    dy: float
    modulus: float
    workers: int = 1
    spectrum: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        nx, ny = (int(s) for s in self.shape)
        if nx < 2 or ny < 2:
            raise InputError(f"a map needs at least 2 × 2 pixels, got {self.shape}")
        if not (self.dx > 0 and self.dy > 0 and self.modulus > 0):
            raise InputError("pixel sizes [m] and the modulus [Pa] must be positive")
        qx = np.pi * np.arange(nx) / (nx * self.dx)
        qy = np.pi * np.arange(ny) / (ny * self.dy)
        q = np.hypot(qx[:, None], qy[None, :])
        k = np.zeros((nx, ny))
        k[q > 0] = 4.0 / (self.modulus * q[q > 0])
        object.__setattr__(self, "shape", (nx, ny))
        object.__setattr__(self, "spectrum", k)

    @property
    def self_influence(self) -> float:
        """The mean diagonal of K [m/Pa] (the diagonal of a DCT-diagonal operator varies a
        little near the map's edges; the core uses it only to size a cell's first pressure)."""
        return float(self.spectrum.mean())

    def __call__(self, v: np.ndarray) -> np.ndarray:
        """``K v`` for a flat pressure vector [Pa] → displacements [m] (flat, zero mean)."""
        s = sfft.dctn(
            np.asarray(v, dtype=np.float64).reshape(self.shape),
            type=2,
            norm="ortho",
            workers=self.workers,
        )
        s *= self.spectrum
        return sfft.idctn(s, type=2, norm="ortho", workers=self.workers).ravel()
