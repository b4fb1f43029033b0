"""Solves with the principal blocks K_AA of a dense SPD matrix for a sequence of nearby sets A.

The primal–dual active-set steps of the flexible ski (:mod:`skisnow.contact._flexible_pdas`)
solve K_AA y = r_A on contact sets A that differ from one step to the next by a few cells at
the contact edges. The cells deep inside the first set (I: farther than a few cells from its
edges) stay in contact; only the border B = A \\ I changes. In the order [I, B] the Cholesky
factor of K_AA is the block factor (Golub & Van Loan 2013, Matrix Computations, §4.2.9)

    K_AA = [L_I   0 ] [L_Iᵀ  W  ],   W = L_I⁻¹ K_IB,   L_S L_Sᵀ = K_BB − Wᵀ W,
           [Wᵀ   L_S] [ 0   L_Sᵀ]

so L_I is factored once, the columns of W once per border cell, and each step factors only
the small Schur complement: O(|I|·|B|²) per step instead of |A|³/3, with the backward
stability of the Cholesky factorisation (it *is* one, of K_AA reordered). When a cell of I
leaves the set, I is chosen again from the current set.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.linalg import lapack

__all__ = ["BlockSolver"]


class BlockSolver:
    """y = K_AA⁻¹ r_A for sets A of the rows of ``k`` (symmetric positive definite on them).

    Parameters
    ----------
    k
        The dense matrix on a set of cells S (C order).
    rhs
        The right-hand sides on every row of S, shape (|S|, c).
    interior
        A function of a set A (sorted rows) returning the rows of A to keep factored (I).
    """

    def __init__(
        self, k: np.ndarray, rhs: np.ndarray, interior: Callable[[np.ndarray], np.ndarray]
    ) -> None:
        self.k = k
        self.rhs = rhs
        self.interior = interior
        self.inner: np.ndarray | None = None  # the rows I (sorted)
        self.in_inner = np.zeros(k.shape[0], dtype=bool)
        self.factor = np.zeros((0, 0))
        self.z_inner = np.zeros((0, rhs.shape[1]))  # L_I⁻¹ r_I
        self.w = np.zeros((0, 0), order="F")  # columns L_I⁻¹ K_Ib of the border cells b
        self.slot = np.full(k.shape[0], -1)  # row b → its column of w, else −1
        self.n_cols = 0
        self.current: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None

    def _gather(self, index: np.ndarray) -> np.ndarray:
        from skisnow.contact._flexible_kernel import gather_block

        out = np.empty((index.size, index.size))
        gather_block(self.k, index, out)
        return out

    def _base(self, index: np.ndarray) -> bool:
        inner = np.asarray(self.interior(index), dtype=np.intp)
        self.inner = inner
        self.in_inner[:] = False
        self.in_inner[inner] = True
        self.slot[:] = -1
        self.n_cols = 0
        self.w = np.zeros((inner.size, self.k.shape[0] - inner.size), order="F")
        if not inner.size:
            self.factor = np.zeros((0, 0))
            self.z_inner = np.zeros((0, self.rhs.shape[1]))
            return True
        # (the transpose is the same symmetric matrix in Fortran order: no copy)
        factor, info = lapack.dpotrf(self._gather(inner).T, lower=1, clean=0, overwrite_a=1)
        if info != 0:
            self.inner = None
            return False
        z, info = lapack.dtrtrs(factor, self.rhs[inner], lower=1)
        self.factor, self.z_inner = factor, z
        return info == 0

    def solve(self, index: np.ndarray) -> np.ndarray | None:
        """K_AA⁻¹ r_A for the sorted rows ``index`` (= A), shape (|A|, c); None if K_AA is not
        positive definite. The factor is kept for :meth:`apply`."""
        self.current = None
        stale = self.inner is None or self.in_inner[index].sum() != self.inner.size
        if stale and not self._base(index):
            return None
        inner = self.inner
        assert inner is not None
        border = index[~self.in_inner[index]]
        new = border[self.slot[border] < 0]
        if new.size and inner.size:
            cols, info = lapack.dtrtrs(self.factor, self.k[np.ix_(inner, new)], lower=1)
            if info != 0:
                return None
            self.w[:, self.n_cols : self.n_cols + new.size] = cols
            self.slot[new] = np.arange(self.n_cols, self.n_cols + new.size)
            self.n_cols += new.size
        w_b = self.w[:, self.slot[border]] if inner.size else np.zeros((0, border.size))
        schur = self._gather(border)
        schur -= w_b.T @ w_b
        l_s, info = lapack.dpotrf(schur.T, lower=1, clean=0, overwrite_a=1)
        if info != 0:
            return None
        self.current = (index, border, w_b, l_s)
        return self._solve(self.z_inner, self.rhs[border])

    def _solve(self, z_i: np.ndarray, r_b: np.ndarray) -> np.ndarray | None:
        index, border, w_b, l_s = self.current  # type: ignore[misc]
        z_b, info = lapack.dtrtrs(l_s, r_b - w_b.T @ z_i, lower=1)
        y_b, info2 = lapack.dtrtrs(l_s, z_b, lower=1, trans=1)
        y = np.empty((self.k.shape[0], r_b.shape[1]))
        if self.inner is not None and self.inner.size:
            y_i, info3 = lapack.dtrtrs(self.factor, z_i - w_b @ y_b, lower=1, trans=1)
            info = info or info3
            y[self.inner] = y_i
        if info or info2:
            return None
        y[border] = y_b
        return y[index]

    def apply(self, r: np.ndarray) -> np.ndarray | None:
        """K_AA⁻¹ r for the set of the last :meth:`solve` (``r`` on A, shape (|A|, c'))."""
        assert self.current is not None
        index = self.current[0]
        inside = self.in_inner[index]
        z_i = np.zeros((0, r.shape[1]))
        if self.inner is not None and self.inner.size:
            z_i, info = lapack.dtrtrs(self.factor, r[inside], lower=1)
            if info != 0:
                return None
        return self._solve(z_i, r[~inside])
