"""Compiled Cholesky factorisation and solves of the symmetric banded beam stiffness.

The identification (:mod:`skisnow.identify._model`, :mod:`skisnow.identify._smooth`)
solves the clamped Hermite-beam stiffness (bandwidth 3, upper banded storage
``ab[3 + i - j, j] = K[i, j]`` as :func:`scipy.linalg.solveh_banded`) tens of thousands of times
per fit, mostly with one to three right-hand sides (Newton steps of the smoothed contact) or with
one per parameter (the Jacobian). SciPy's ``solveh_banded`` refactors the matrix at every call
and LAPACK's ``dpbtrs`` solves the right-hand sides one at a time (``dtbsv``): measured 15 µs
per column on 802 unknowns, 3 ms for the 211 columns of a Jacobian. Here the factor is kept and
all columns are solved in one pass.

The arithmetic is that of LAPACK's unblocked ``dpbtf2`` (the reciprocal of the pivot scales its
row, then a rank-1 update) and of the two ``dtbsv`` sweeps of ``dpbtrs`` (a dot product, then
the division by the pivot; the back sweep divides, then an axpy), every multiply-add fused as
OpenBLAS's kernels do on FMA hardware: where OpenBLAS orders the operations the same way
(measured on an AMD EPYC with OpenBLAS 0.3.31) factor and solutions are bitwise those of SciPy's
``solveh_banded``; elsewhere (an AVX-512 EPYC) they agree to round-off: the same backward error
as LAPACK's, a forward difference within what the conditioning allows (cond(K) 1e10-1e14, so up
to ~1e-8 relative; ``tests/ski/test_banded_kernel.py``). Bitwise agreement matters here because
the identification's path (which restarts run, which local minimum is reached) can change with
the last bit of the data.
"""

from __future__ import annotations

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic
from numpy.typing import NDArray

__all__ = ["banded_cholesky", "banded_solve", "smoothed_hessian", "solveh_banded_fused"]


@intrinsic
def _fma(typingctx, a, b, c):  # pragma: no cover - compiled
    """a * b + c with one rounding (LLVM's fma intrinsic)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        d = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [d], ir.FunctionType(d, [d, d, d]))
        return builder.call(fn, args)

    return sig, codegen


@numba.njit(cache=True, nogil=True)
def _factor(u: np.ndarray) -> int:  # pragma: no cover - compiled
    """In place: the upper banded matrix ``u`` -> its Cholesky factor U (K = UᵀU), as
    ``dpbtf2``; returns 0, or the 1-based index of a non-positive pivot."""
    kd = 3
    n = u.shape[1]
    for j in range(n):
        ajj = u[kd, j]
        if not ajj > 0.0:
            return j + 1
        ajj = np.sqrt(ajj)
        u[kd, j] = ajj
        kn = min(kd, n - 1 - j)
        r = 1.0 / ajj
        for i in range(kn):
            u[kd - 1 - i, j + 1 + i] *= r
        for q in range(kn):
            temp = -u[kd - 1 - q, j + 1 + q]
            for p in range(q + 1):
                u[kd + p - q, j + 1 + q] = _fma(
                    u[kd - 1 - p, j + 1 + p], temp, u[kd + p - q, j + 1 + q]
                )
    return 0


@numba.njit(cache=True, nogil=True)
def _solve(u: np.ndarray, x: np.ndarray) -> None:  # pragma: no cover - compiled
    """In place: x <- K⁻¹ x for the factor ``u`` of :func:`_factor` (bandwidth 3), x of shape
    (n, m): the two triangular sweeps of ``dpbtrs``, a row of all columns at a time (the
    columns' divisions pipeline, where one column's sweep waits on each of its 2n)."""
    n = u.shape[1]
    m = x.shape[1]
    for i in range(n):  # Uᵀ y = b
        piv = u[3, i]
        if i >= 3:
            a0, a1, a2 = u[0, i], u[1, i], u[2, i]
            for c in range(m):
                dot = _fma(x[i - 3, c], a0, 0.0)
                dot = _fma(x[i - 2, c], a1, dot)
                dot = _fma(x[i - 1, c], a2, dot)
                x[i, c] = (x[i, c] - dot) / piv
        else:
            for c in range(m):
                dot = 0.0
                for t in range(i):
                    dot = _fma(x[t, c], u[3 - i + t, i], dot)
                x[i, c] = (x[i, c] - dot) / piv
    for i in range(n - 1, -1, -1):  # U x = y
        piv = u[3, i]
        if i >= 3:
            a0, a1, a2 = u[0, i], u[1, i], u[2, i]
            for c in range(m):
                xi = x[i, c] / piv
                x[i, c] = xi
                x[i - 3, c] = _fma(-xi, a0, x[i - 3, c])
                x[i - 2, c] = _fma(-xi, a1, x[i - 2, c])
                x[i - 1, c] = _fma(-xi, a2, x[i - 1, c])
        else:
            for c in range(m):
                xi = x[i, c] / piv
                x[i, c] = xi
                for t in range(i):
                    x[t, c] = _fma(-xi, u[3 - i + t, i], x[t, c])


@numba.njit(cache=True, nogil=True)
def _smoothed_hessian(ab, d, shape, clamp):  # pragma: no cover - compiled
    n_el, m = d.shape
    ndof = ab.shape[1]
    band = np.zeros((4, ndof))
    for e in range(n_el):
        for a in range(4):
            for b in range(a, 4):
                acc = 0.0
                for s in range(m):  # in einsum's order: (d N_a) N_b summed over s in turn
                    acc += d[e, s] * shape[e, s, a] * shape[e, s, b]
                band[3 + a - b, 2 * e + b] += acc  # two terms per entry: order-free
    out = np.empty((4, ndof))
    for i in range(4):
        for j in range(ndof):
            out[i, j] = ab[i, j] + band[i, j]
    for dof in (2 * clamp, 2 * clamp + 1):
        for i in range(4):
            out[i, dof] = 0.0
        for j in range(dof, min(dof + 4, ndof)):
            out[3 + dof - j, j] = 0.0
        out[3, dof] = 1.0
    return out


def smoothed_hessian(
    ab: NDArray[np.float64], d: NDArray[np.float64], shape: NDArray[np.float64], clamp: int
) -> NDArray[np.float64]:
    """The clamped stiffness ``ab`` (upper banded) plus the foundation's element matrices
    Σ_s d_es N_es N_esᵀ of the smoothed contact (:mod:`skisnow.identify._smooth`; ``d`` (n_el,
    m) the foundation's stiffness at the sub-grid points, ``shape`` (n_el, m, 4) the Hermite
    shape functions there), the DOFs of node ``clamp`` clamped: in one compiled pass the
    numbers of ``ab + banded_upper(einsum('es,esa,esb->eab', d, shape, shape))`` with the
    clamped rows and columns set to the identity, bitwise (the same products and sums in the
    same order; ``tests/identify/test_speed_kernels.py``), 14 times faster (0.03 against 0.44
    ms on 210 elements: the three-operand ``einsum`` is not optimised by NumPy)."""
    return _smoothed_hessian(
        np.ascontiguousarray(ab, dtype=np.float64), np.ascontiguousarray(d, dtype=np.float64),
        np.ascontiguousarray(shape, dtype=np.float64), int(clamp),
    )  # fmt: skip


def banded_cholesky(ab: NDArray[np.float64]) -> NDArray[np.float64]:
    """The Cholesky factor of the symmetric positive definite matrix in upper banded storage
    ``ab`` (a new array of the same layout). Raises :class:`numpy.linalg.LinAlgError` if the
    matrix is not positive definite."""
    if ab.ndim != 2 or ab.shape[0] != 4:
        raise ValueError(f"upper banded storage of bandwidth 3 expected, got shape {ab.shape}")
    u = np.array(ab, dtype=np.float64, order="C", copy=True)
    info = _factor(u)
    if info:
        raise np.linalg.LinAlgError(f"{info}th leading minor not positive definite")
    return u


def banded_solve(
    u: NDArray[np.float64], b: NDArray[np.float64], *, overwrite_b: bool = False
) -> NDArray[np.float64]:
    """K⁻¹ b for the factor ``u`` of :func:`banded_cholesky`; ``b`` of shape (n,) or (n, m)
    (the solution in Fortran order, as LAPACK returns it; in ``b`` itself if ``overwrite_b``
    and ``b`` is a Fortran-ordered float64 array)."""
    if overwrite_b and b.dtype == np.float64 and b.flags.f_contiguous and b.flags.writeable:
        x = b
    else:
        x = np.array(b, dtype=np.float64, order="F", copy=True)
    _solve(u, x.reshape(x.shape[0], -1, order="F"))
    return x


def solveh_banded_fused(ab: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`scipy.linalg.solveh_banded` (upper storage) by :func:`banded_cholesky` and
    :func:`banded_solve`."""
    return banded_solve(banded_cholesky(ab), b)
