"""Half-space influence coefficients and the non-periodic FFT convolution that applies them.

Convention (used by every kernel here and by the whole contact package): the *equivalent
modulus* ``modulus`` is the paper's E' of eq. 2 (Kalliorinne et al. 2023),

    2/E' = (1 − ν_base²)/E_base + (1 − ν_counter²)/E_counter,

which is **twice** the contact modulus E* of Hertz/Johnson (1/E* = Σ (1 − ν²)/E). The normal
surface displacement of the equivalent half-space under a pressure p [Pa] is then

    u(x, y) = 2/(π E') ∬ p(ξ, η) / √((x − ξ)² + (y − η)²) dξ dη          (Boussinesq)

and, in plane strain (per unit width, up to a rigid constant),

    u(x) = −4/(π E') ∫ p(ξ) ln(|x − ξ| / L_ref) dξ.

Influence coefficients are exact for a *uniform* pressure on each cell (Love 1929 for the
rectangle; the strip and line versions are integrated in closed form below) and are collocated
at the cell centres. They are returned for every offset ``-(n-1) .. n-1`` so that the
displacement is a linear (aperiodic) convolution; :class:`Convolution` evaluates it with a
zero-padded real FFT (circulant embedding of size ≥ 2n − 1), so nothing wraps around.

Public names (stable; the micro area builds on them): :func:`surface_kernel`,
:func:`strip_kernel`, :func:`line_kernel`, :class:`Convolution` and the shortcuts
:func:`surface_convolution`, :func:`strip_convolution`, :func:`line_convolution`.
"""

from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft

from skisnow._checks import positive_finite
from skisnow._errors import InputError
from skisnow._parallel import default_workers

__all__ = [
    "Convolution",
    "default_workers",
    "line_convolution",
    "line_kernel",
    "strip_convolution",
    "strip_kernel",
    "surface_convolution",
    "surface_kernel",
]


def _count(name: str, value: int) -> int:
    if int(value) != value or int(value) < 1:
        raise InputError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def _offsets(n: int, dx: float) -> np.ndarray:
    """Centre-to-centre offsets -(n-1)·dx .. (n-1)·dx."""
    return np.arange(-(n - 1), n, dtype=np.float64) * dx


def _love_primitive(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """F(u, v) with ∂²F/∂u∂v = 1/√(u² + v²): F = u·asinh(v/|u|) + v·asinh(u/|v|).

    Terms in u or v alone are dropped (they cancel in the four-corner sum); F(0, ·) and
    F(·, 0) are the limits (0·asinh(∞) → 0).
    """
    au, av = np.abs(u), np.abs(v)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(au > 0.0, u * np.arcsinh(v / np.where(au > 0.0, au, 1.0)), 0.0)
        t2 = np.where(av > 0.0, v * np.arcsinh(u / np.where(av > 0.0, av, 1.0)), 0.0)
    return t1 + t2


def surface_kernel(shape: tuple[int, int], dx: float, dy: float, *, modulus: float) -> np.ndarray:
    """Boussinesq–Love influence coefficients of a grid of rectangular cells (3D half-space).

    Parameters
    ----------
    shape
        ``(nx, ny)`` cells of the pressure grid (x along the first axis).
    dx, dy
        Cell sizes [m].
    modulus
        Equivalent modulus E' of eq. 2 [Pa] (= 2·E* of Hertz/Johnson).

    Returns
    -------
    ndarray, shape ``(2nx − 1, 2ny − 1)``
        ``K[i + nx − 1, j + ny − 1]`` is the displacement [m] at the centre of the cell offset
        by ``(i·dx, j·dy)`` from a cell carrying a uniform pressure of 1 Pa (Love 1929):
        u = 2/(π E') Σ_corners ±F(x ± dx/2, y ± dy/2), F(u, v) = u·asinh(v/|u|) + v·asinh(u/|v|).
    """
    nx, ny = (_count("shape[0]", shape[0]), _count("shape[1]", shape[1]))
    dx, dy = positive_finite("dx", dx, "m"), positive_finite("dy", dy, "m")
    modulus = positive_finite("modulus", modulus, "Pa")
    # F on the (2nx) × (2ny) grid of cell corners, then the four-corner differences: each corner
    # value is shared by four cells (4× fewer transcendental evaluations than cell by cell)
    xc = (np.arange(2 * nx, dtype=np.float64) - nx + 0.5) * dx
    yc = (np.arange(2 * ny, dtype=np.float64) - ny + 0.5) * dy
    f = _love_primitive(xc[:, None], yc[None, :])
    integral = f[1:, 1:] - f[:-1, 1:] - f[1:, :-1] + f[:-1, :-1]
    return 2.0 / (np.pi * modulus) * integral


def _strip_primitive(u: np.ndarray, w: float) -> np.ndarray:
    """h(u) = (2/w)·∫₀ʷ (w − s)·asinh(u/s) ds in closed form (odd in u).

    With A = ∫₀ʷ asinh(u/s) ds = w·asinh(u/w) + u·asinh(w/|u|) and
    B = ∫₀ʷ s·asinh(u/s) ds = (w²/2)·asinh(u/w) + (u/2)(√(w² + u²) − |u|), h = (2/w)(w·A − B).
    """
    au = np.abs(u)
    with np.errstate(divide="ignore", invalid="ignore"):
        ua = np.where(au > 0.0, u * np.arcsinh(w / np.where(au > 0.0, au, 1.0)), 0.0)
    asw = np.arcsinh(u / w)
    a_int = w * asw + ua
    b_int = 0.5 * w * w * asw + 0.5 * u * (np.hypot(w, u) - au)
    return (2.0 / w) * (w * a_int - b_int)


def strip_kernel(n: int, dx: float, width: float, *, modulus: float) -> np.ndarray:
    """Influence coefficients of a 1D strip of cells along a ski of constant width (3D half-space).

    Each cell ``[x − dx/2, x + dx/2] × [−w/2, w/2]`` carries a pressure that is uniform across the
    width; the displacement is the *width average* of the Boussinesq displacement at the cell's
    centre station (a Galerkin reduction across the width, exact in closed form):

        K(x) = 2/(π E') · (1/w) ∫∫_{[−w/2, w/2]²} ∫_{x−dx/2}^{x+dx/2} dξ / √(ξ² + (y − η)²) dη dy.

    Parameters
    ----------
    n
        Number of cells along the ski.
    dx
        Cell length [m].
    width
        Ski width w [m].
    modulus
        Equivalent modulus E' of eq. 2 [Pa].

    Returns
    -------
    ndarray, shape ``(2n − 1,)``
        Displacement [m] per unit pressure [Pa] at offsets ``-(n-1)·dx .. (n-1)·dx``.
    """
    n = _count("n", n)
    dx, width = positive_finite("dx", dx, "m"), positive_finite("width", width, "m")
    modulus = positive_finite("modulus", modulus, "Pa")
    x = _offsets(n, dx)
    integral = _strip_primitive(x + dx / 2.0, width) - _strip_primitive(x - dx / 2.0, width)
    return 2.0 / (np.pi * modulus) * integral


def line_kernel(n: int, dx: float, *, modulus: float, reference_length: float = 1.0) -> np.ndarray:
    """Plane-strain influence coefficients (per unit width), logarithmic kernel.

    u(x) = −4/(π E') ∫_{cell} ln(|x − ξ| / L_ref) dξ per unit pressure (the 2D Boussinesq–
    Flamant solution; 4/(π E') = 2/(π E*)). The displacement of a 2D half-space is defined only
    up to a rigid constant: ``reference_length`` L_ref [m] fixes it (the depth at which the
    displacement is zero); load control does not depend on it.

    Returns
    -------
    ndarray, shape ``(2n − 1,)``
        Displacement [m] per unit pressure [Pa] at offsets ``-(n-1)·dx .. (n-1)·dx``.
    """
    n = _count("n", n)
    dx = positive_finite("dx", dx, "m")
    modulus = positive_finite("modulus", modulus, "Pa")
    ref = positive_finite("reference_length", reference_length, "m")
    x = _offsets(n, dx)

    def phi(t: np.ndarray) -> np.ndarray:  # ∫ ln(|t|/L) dt = t·ln(|t|/L) − t
        at = np.abs(t)
        with np.errstate(divide="ignore", invalid="ignore"):
            tl = np.where(at > 0.0, t * np.log(np.where(at > 0.0, at, 1.0) / ref), 0.0)
        return tl - t

    return -4.0 / (np.pi * modulus) * (phi(x + dx / 2.0) - phi(x - dx / 2.0))


@dataclass(frozen=True, eq=False)
class Convolution:
    """Aperiodic convolution ``u = K * p`` by a zero-padded real FFT, kernel spectrum precomputed.

    Build it with :meth:`from_kernel` (or the ``*_convolution`` shortcuts). Calling it maps a
    pressure field of :attr:`shape` [Pa] to the displacement field [m] of the same shape.
    Batches are allowed: extra *leading* axes are convolved independently.

    Attributes
    ----------
    shape
        Shape of the pressure grid (1 or 2 axes).
    fft_shape
        Padded transform shape (each axis ≥ 2n − 1, a fast length for ``scipy.fft``).
    spectrum
        ``rfftn`` of the circulant-embedded kernel; real when the kernel is even (the half-space
        kernels are), which halves the cost of the product.
    workers
        Threads used by ``scipy.fft``.
    """

    shape: tuple[int, ...]
    fft_shape: tuple[int, ...]
    spectrum: np.ndarray = field(repr=False)
    workers: int = 1
    kernel: np.ndarray | None = field(default=None, repr=False)

    @classmethod
    def from_kernel(
        cls,
        kernel: np.ndarray,
        shape: tuple[int, ...] | int,
        *,
        workers: int | None = None,
        even: bool | None = None,
    ) -> Convolution:
        """Precompute the spectrum of a kernel given at offsets ``-(n-1) .. n-1`` per axis.

        ``even``: whether the kernel is even on every axis (its spectrum then real); checked
        when not given (a window of an even kernel, centred, is even)."""
        shape = (int(shape),) if np.isscalar(shape) else tuple(int(s) for s in shape)
        kernel = np.asarray(kernel, dtype=np.float64)
        expected = tuple(2 * n - 1 for n in shape)
        if kernel.shape != expected:
            raise InputError(
                f"kernel has shape {kernel.shape}; for a grid of shape {shape} it must have "
                f"shape {expected} (offsets -(n-1)..n-1 on every axis)"
            )
        fft_shape = tuple(sfft.next_fast_len(2 * n - 1, real=True) for n in shape)
        # circulant embedding: offset k goes to index k mod L (kernel index i is offset i − (n−1));
        # on each axis the offsets 0..n−1 fill the start, −(n−1)..−1 the end: block copies
        embedded = np.zeros(fft_shape)
        parts = [
            ((slice(0, n), slice(n - 1, None)), (slice(size - (n - 1), size), slice(0, n - 1)))
            for n, size in zip(shape, fft_shape, strict=True)
        ]
        for blocks in itertools.product(*parts):
            dst = tuple(b[0] for b in blocks)
            src = tuple(b[1] for b in blocks)
            embedded[dst] = kernel[src]
        workers = default_workers() if workers is None else max(1, int(workers))
        real_axis = _real_axis(shape)
        spectrum = _forward(embedded, fft_shape, real_axis, workers)
        if even is None:
            even = all(np.allclose(kernel, np.flip(kernel, axis=a)) for a in range(kernel.ndim))
        if even:
            spectrum = np.ascontiguousarray(spectrum.real)
        return cls(
            shape=shape, fft_shape=fft_shape, spectrum=spectrum, workers=workers, kernel=kernel
        )

    @property
    def ndim(self) -> int:
        """Number of grid axes."""
        return len(self.shape)

    def __call__(self, pressure: np.ndarray) -> np.ndarray:
        """Displacement [m] at the cell centres due to ``pressure`` [Pa] (same shape)."""
        p = np.asarray(pressure, dtype=self.spectrum.dtype)
        if p.shape[p.ndim - self.ndim :] != self.shape:
            raise InputError(
                f"pressure has shape {p.shape}; the operator was built for grids of shape "
                f"{self.shape}"
            )
        if self.ndim == 1 and p.ndim == 1 and p.dtype == np.float64:
            # one transform (threads cannot split it): NumPy's pocketfft gives the same bits as
            # SciPy's with half the call overhead (~20 µs a pair: most of a small window's cost)
            spec = np.fft.rfft(p, n=self.fft_shape[0])
            spec *= self.spectrum
            return np.fft.irfft(spec, n=self.fft_shape[0])[: self.shape[0]]
        if self.ndim == 1:
            spec = sfft.rfft(p, n=self.fft_shape[0], axis=-1, workers=self.workers)
            spec *= self.spectrum
            return sfft.irfft(spec, n=self.fft_shape[0], axis=-1, workers=self.workers)[
                ..., : self.shape[0]
            ]
        if self.ndim == 2:
            # axis by axis, skipping the transforms of rows that are known to be zero (padding);
            # the real transform runs along the longer axis, the complex one along the shorter
            (nx, ny), (lx, ly) = self.shape, self.fft_shape
            w = self.workers
            if _real_axis(self.shape) == 1:
                spec = sfft.rfft(p, n=ly, axis=-1, workers=w)
                spec = sfft.fft(spec, n=lx, axis=-2, workers=w, overwrite_x=True)
                spec *= self.spectrum
                spec = sfft.ifft(spec, axis=-2, workers=w, overwrite_x=True)[..., :nx, :]
                return sfft.irfft(spec, n=ly, axis=-1, workers=w)[..., :ny]
            spec = sfft.rfft(p, n=lx, axis=-2, workers=w)
            spec = sfft.fft(spec, n=ly, axis=-1, workers=w, overwrite_x=True)
            spec *= self.spectrum
            spec = sfft.ifft(spec, axis=-1, workers=w, overwrite_x=True)[..., :ny]
            return sfft.irfft(spec, n=lx, axis=-2, workers=w)[..., :nx, :]
        axes = tuple(range(p.ndim - self.ndim, p.ndim))
        spec = sfft.rfftn(p, s=self.fft_shape, axes=axes, workers=self.workers)
        spec *= self.spectrum
        out = sfft.irfftn(spec, s=self.fft_shape, axes=axes, workers=self.workers)
        return out[(..., *(slice(0, n) for n in self.shape))]

    def inverse(self, *, floor: float = 1e-3, single: bool = False) -> Convolution:
        """The circulant inverse (spectrum 1/K̂, clipped below at ``floor``·max K̂).

        Not the inverse of the aperiodic operator, but close to it away from the grid's edges:
        a preconditioner (it maps displacements to pressures, like the Dirichlet-to-Neumann map).
        """
        spec = np.abs(self.spectrum) if np.iscomplexobj(self.spectrum) else self.spectrum
        spec = np.maximum(spec, floor * float(np.max(spec)))
        inv = 1.0 / spec
        if single:  # single precision: twice as fast, and exact enough for a preconditioner
            inv = (inv / np.max(inv)).astype(np.float32)
        return Convolution(
            shape=self.shape, fft_shape=self.fft_shape, spectrum=inv, workers=self.workers
        )

    def add_columns(self, out: np.ndarray, index: np.ndarray, values: np.ndarray) -> None:
        """``out += K @ v`` for a pressure ``v`` that is non-zero only at the flat ``index`` cells.

        A direct sum of kernel columns (each one a slice of :attr:`kernel`): cheaper than the
        FFT when only a few cells carry load, e.g. the cells a solver step clipped or added.
        ``out`` has the grid's shape.
        """
        if self.kernel is None:
            raise InputError("add_columns needs the kernel (build with from_kernel)")
        k = self.kernel
        if self.ndim == 1:
            (n,) = self.shape
            for j, v in zip(index.tolist(), values.tolist(), strict=True):
                out += v * k[n - 1 - j : 2 * n - 1 - j]
            return
        if self.ndim == 2:
            nx, ny = self.shape
            for j, v in zip(index.tolist(), values.tolist(), strict=True):
                jx, jy = divmod(j, ny)
                out += v * k[nx - 1 - jx : 2 * nx - 1 - jx, ny - 1 - jy : 2 * ny - 1 - jy]
            return
        raise InputError("add_columns supports 1D and 2D grids")

    @functools.cached_property
    def self_influence(self) -> float:
        """Self-influence coefficient K(0) [m/Pa]: a cell's displacement under its own 1 Pa
        (computed once per operator: an FFT pair)."""
        # inverse DFT at index 0 = mean of the full (Hermitian) spectrum
        return float(_self_coefficient(self))


def _real_axis(shape: tuple[int, ...]) -> int:
    """Axis of the real-to-complex transform: the last one, unless the first is longer."""
    if len(shape) == 2 and shape[0] > shape[1]:
        return 0
    return len(shape) - 1


def _forward(
    embedded: np.ndarray, fft_shape: tuple[int, ...], real_axis: int, workers: int
) -> np.ndarray:
    """The forward transform of :meth:`Convolution.__call__` applied to a padded kernel."""
    if len(fft_shape) == 2 and real_axis == 0:
        spec = sfft.rfft(embedded, axis=0, workers=workers)
        return sfft.fft(spec, axis=1, workers=workers)
    return sfft.rfftn(embedded, workers=workers)


def _self_coefficient(conv: Convolution) -> float:
    unit = np.zeros(conv.shape)
    unit[(0,) * conv.ndim] = 1.0
    return float(conv(unit)[(0,) * conv.ndim])


def surface_convolution(
    shape: tuple[int, int],
    dx: float,
    dy: float,
    *,
    modulus: float,
    workers: int | None = None,
) -> Convolution:
    """:class:`Convolution` for :func:`surface_kernel` on a ``(nx, ny)`` grid."""
    return Convolution.from_kernel(
        surface_kernel(shape, dx, dy, modulus=modulus), tuple(shape), workers=workers, even=True
    )


def strip_convolution(
    n: int, dx: float, width: float, *, modulus: float, workers: int | None = None
) -> Convolution:
    """:class:`Convolution` for :func:`strip_kernel` on ``n`` cells."""
    return Convolution.from_kernel(
        strip_kernel(n, dx, width, modulus=modulus), (n,), workers=workers, even=True
    )


def line_convolution(
    n: int,
    dx: float,
    *,
    modulus: float,
    reference_length: float = 1.0,
    workers: int | None = None,
) -> Convolution:
    """:class:`Convolution` for :func:`line_kernel` on ``n`` cells."""
    return Convolution.from_kernel(
        line_kernel(n, dx, modulus=modulus, reference_length=reference_length),
        (n,),
        workers=workers,
        even=True,
    )
