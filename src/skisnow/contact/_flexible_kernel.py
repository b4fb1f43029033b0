"""The compiled kernels of the flexible ski's active-set steps (:mod:`._flexible_pdas`).

The dense coupled compliance K_SS = K_snow,SS + A·K_beam,SS on a set of cells S of a strip grid
(Kalliorinne et al. 2023, eq. 2, plus the cantilever compliance of
:mod:`skisnow.contact._beam_operator`), assembled entry by entry from the half-space kernel and
the beam's generators, and the symmetric gather of a principal block of it. In a module of its
own so that numba is imported only when a flexible ski is solved.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["coupled_block", "gather_block"]


@numba.njit(cache=True, nogil=True)
def coupled_block(
    kernel: np.ndarray,
    n: int,
    cells: np.ndarray,
    side: np.ndarray,
    d: np.ndarray,
    u: np.ndarray,
    v: np.ndarray,
    area: float,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """out[i, j] = kernel[c_i − c_j + n − 1] + area · G(c_i, c_j) for the sorted cells c of a
    grid of n.

    G is the beam's block (:meth:`CantileverCompliance.block`): zero between the two halves,
    u_i d_j + v_i within a half with station i the nearer the clamp (d_i ≤ d_j); ``side``,
    ``d``, ``u``, ``v`` are the generators at every station of the grid (side 0, the rear half,
    lies before side 1). Every entry is computed, row by row (K is symmetric exactly: the
    kernel is even and G's formula symmetric).
    """
    m = cells.size
    ds = np.empty(m)
    us = np.empty(m)
    vs = np.empty(m)
    n_rear = 0
    for j in range(m):
        c = cells[j]
        ds[j] = d[c]
        us[j] = u[c]
        vs[j] = v[c]
        if side[c] == 0:
            n_rear += 1
    for i in range(m):  # one pass per row: the kernel plus, within i's half, the beam
        ci = cells[i] + n - 1
        row = out[i]
        di = ds[i]
        ui = us[i]
        vi = vs[i]
        if i < n_rear:  # rear: d decreases along the cells; j <= i is farther from the clamp
            for j in range(i + 1):
                row[j] = kernel[ci - cells[j]] + area * (ui * ds[j] + vi)
            for j in range(i + 1, n_rear):
                row[j] = kernel[ci - cells[j]] + area * (us[j] * di + vs[j])
            for j in range(n_rear, m):
                row[j] = kernel[ci - cells[j]]
        else:  # front: d increases along the cells
            for j in range(n_rear):
                row[j] = kernel[ci - cells[j]]
            for j in range(n_rear, i):
                row[j] = kernel[ci - cells[j]] + area * (us[j] * di + vs[j])
            for j in range(i, m):
                row[j] = kernel[ci - cells[j]] + area * (ui * ds[j] + vi)


@numba.njit(cache=True, nogil=True)
def gather_block(k: np.ndarray, index: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover
    """out = k[index][:, index]."""
    m = index.size
    for i in range(m):
        row = k[index[i]]
        dst = out[i]
        for j in range(m):
            dst[j] = row[index[j]]


# the argument list of coupled_block, repeated on purpose: a compiled kernel per operator
# block (numba kernels take no closures cheaply)
@numba.njit(cache=True, nogil=True)
def beam_block_apply(
    cells: np.ndarray,
    side: np.ndarray,
    d: np.ndarray,
    u: np.ndarray,
    v: np.ndarray,
    area: float,
    x: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """out = area · G_SS x for the sorted cells S, in O(|S|): within a half, with the cells
    ordered from the clamp outward, w_i = d_i Σ_{k≤i} u_k x_k + Σ_{k≤i} v_k x_k
    + u_i Σ_{k>i} d_k x_k + v_i Σ_{k>i} x_k (G_ik = u_near d_far + v_near)."""
    m = cells.size
    n_rear = 0
    for j in range(m):
        if side[cells[j]] == 0:
            n_rear += 1
    for half in range(2):
        # positions along the half from the clamp outward: rear cells in reverse order
        lo = 0 if half == 0 else n_rear
        cnt = n_rear if half == 0 else m - n_rear
        if cnt == 0:
            continue
        q1 = 0.0
        q2 = 0.0
        for jj in range(cnt):  # suffix sums first (from the far end inward)
            j = lo + jj if half == 0 else lo + cnt - 1 - jj  # far to near
            c = cells[j]
            out[j] = u[c] * q1 + v[c] * q2
            q1 += d[c] * x[j]
            q2 += x[j]
        p1 = 0.0
        p2 = 0.0
        for jj in range(cnt):  # near to far
            j = lo + cnt - 1 - jj if half == 0 else lo + jj
            c = cells[j]
            p1 += u[c] * x[j]
            p2 += v[c] * x[j]
            out[j] = area * (out[j] + d[c] * p1 + p2)
