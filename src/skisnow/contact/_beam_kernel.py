"""The compiled kernel of the cantilever compliance (:mod:`skisnow.contact._beam_operator`).

In a module of its own so that numba is imported only when a flexible ski is solved.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["cantilever_apply"]


@numba.njit(cache=True, nogil=True)
def cantilever_apply(
    f: np.ndarray, d: np.ndarray, t: np.ndarray, c: np.ndarray, out: np.ndarray
) -> None:  # pragma: no cover - compiled
    """out = B C Bᵀ f for one half (the two cumulative sums of :meth:`_Half.apply`, fused)."""
    m = d.size
    kappa = np.empty(m + 1)
    kappa[m] = 0.0
    a0 = 0.0
    a1 = 0.0
    for j in range(m - 1, -1, -1):  # moment at the node t_j of the forces beyond it
        a0 += f[j]
        a1 += d[j] * f[j]
        kappa[j] = c[j] * (a1 - t[j] * a0)
    k0 = 0.0
    k1 = 0.0
    for i in range(m):  # deflection: Σ_{t_k < d_i} (d_i − t_k) κ_k
        k0 += kappa[i]
        k1 += kappa[i] * t[i]
        out[i] = d[i] * k0 - k1


@numba.njit(cache=True, nogil=True)
def cantilever_apply_strided(
    f: np.ndarray,
    start: int,
    step: int,
    d: np.ndarray,
    t: np.ndarray,
    c: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """:func:`cantilever_apply` for the half whose j-th station is ``start + step·j`` of the
    whole grid's ``f`` and ``out`` (no gathers: the stations of a half are contiguous)."""
    m = d.size
    kappa = np.empty(m + 1)
    kappa[m] = 0.0
    a0 = 0.0
    a1 = 0.0
    for j in range(m - 1, -1, -1):
        fj = f[start + step * j]
        a0 += fj
        a1 += d[j] * fj
        kappa[j] = c[j] * (a1 - t[j] * a0)
    k0 = 0.0
    k1 = 0.0
    for i in range(m):
        k0 += kappa[i]
        k1 += kappa[i] * t[i]
        out[start + step * i] = d[i] * k0 - k1


@numba.njit(cache=True, nogil=True)
def half_generators(
    c: np.ndarray, t: np.ndarray, d: np.ndarray, diag: np.ndarray, u: np.ndarray, v: np.ndarray
) -> None:  # pragma: no cover - compiled
    """The diagonal K_ii = d_i² S0 − 2 d_i S1 + S2 and the generators u_i = d_i S0 − S1,
    v_i = S2 − d_i S1 of one half (S0, S1, S2: the sums of c_k, c_k t_k, c_k t_k² over the
    nodes t_k < d_i, i.e. k ≤ i), in one pass."""
    s0 = 0.0
    s1 = 0.0
    s2 = 0.0
    for i in range(d.size):
        ct = c[i] * t[i]
        s0 += c[i]
        s1 += ct
        s2 += ct * t[i]
        di = d[i]
        diag[i] = di * di * s0 - 2 * di * s1 + s2
        u[i] = di * s0 - s1
        v[i] = s2 - di * s1


# numba kernels take no closures or callbacks cheaply: the strided station loop of
# cantilever_apply_strided is repeated here around the boot's load, on purpose
@numba.njit(cache=True, nogil=True)
def boot_deflect_strided(
    q: float,
    half_len: float,
    start: int,
    step: int,
    d: np.ndarray,
    t: np.ndarray,
    c: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """The deflection of one half under the boot's uniform load q [N/m] over |t| < half_len:
    the moment q (half_len − t)²/2 at the nodes, curvature c·M, summed as in
    :func:`cantilever_apply` (the j-th station of the half is ``start + step·j`` of ``out``)."""
    k0 = 0.0
    k1 = 0.0
    for i in range(d.size):
        r = half_len - t[i]
        if r > 0.0:
            kappa = c[i] * (0.5 * q * r * r)
            k0 += kappa
            k1 += kappa * t[i]
        out[start + step * i] = d[i] * k0 - k1
