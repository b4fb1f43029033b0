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
