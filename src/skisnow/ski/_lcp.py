"""The contact of a beam on a rigid plane as a mixed linear complementarity problem (LCP).

With the flexibility matrix C of the clamped beam and the gap g of the unloaded-by-contact beam,

    h = g + a + b x + C r >= 0,  r >= 0,  r·h = 0,  Σ r = F,  Σ r x = M,

the KKT system of the convex QP min ½ rᵀCr + gᵀr subject to r >= 0 and both balances (the
force and moment balance of Kalliorinne et al. 2023, eq. 3, on the rigid bench). Solved exactly
by the primal active-set method (Nocedal & Wright 2006, Alg. 16.3) from a feasible start, or by
block principal pivoting (Júdice & Pires 1994) from a previous contact set. Pure NumPy; the
caller (:func:`skisnow.ski.solve_beam`) builds C and g.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["BeamLcp", "LcpResult", "lower_hull_bracket"]


def lower_hull_bracket(x: NDArray[np.float64], g: NDArray[np.float64], xc: float) -> list[int]:
    """The two vertices of the lower convex hull of (x, g) whose segment contains xc."""
    hull: list[int] = []
    for i in range(x.size):
        while len(hull) >= 2:
            i0, i1 = hull[-2], hull[-1]
            cross = (x[i1] - x[i0]) * (g[i] - g[i0]) - (g[i1] - g[i0]) * (x[i] - x[i0])
            if cross <= 0.0:
                hull.pop()
            else:
                break
        hull.append(i)
    hx = x[hull]
    k = int(np.clip(np.searchsorted(hx, xc, side="right") - 1, 0, len(hull) - 2))
    return [hull[k], hull[k + 1]]


@dataclass(frozen=True, kw_only=True)
class LcpResult:
    """Where a pivoting method stopped: the contact set and the fields on it."""

    converged: bool  #: every sign condition met
    active: NDArray[np.bool_]  #: nodes in contact
    reactions: NDArray[np.float64]  #: nodal reactions r [N]
    gap: NDArray[np.float64]  #: nodal gaps h [m]
    translation: float  #: rigid translation a [m]
    rotation: float  #: rigid rotation b [-]
    iterations: int


@dataclass(frozen=True)
class BeamLcp:
    """The mixed LCP  h = g + a + b x + C r >= 0, r >= 0, r h = 0, Σ r = F, Σ r x = M."""

    flex: NDArray[np.float64]
    g: NDArray[np.float64]
    x: NDArray[np.float64]
    f_total: float
    m_total: float
    tol_r: float
    tol_h: float

    @staticmethod
    def _stop(
        converged: bool,
        active: NDArray[np.bool_],
        r: NDArray[np.float64],
        h: NDArray[np.float64],
        a: float,
        b: float,
        iterations: int,
    ) -> LcpResult:
        return LcpResult(
            converged=converged,
            active=active,
            reactions=r,
            gap=h,
            translation=a,
            rotation=b,
            iterations=iterations,
        )

    def solve_subset(self, idx: NDArray[np.intp]) -> tuple[NDArray[np.float64], float, float]:
        """Reactions on ``idx`` (others zero) with h = 0 on idx and both balances."""
        k = idx.size
        kkt = np.zeros((k + 2, k + 2))
        kkt[:k, :k] = self.flex[np.ix_(idx, idx)]
        kkt[:k, k] = 1.0
        kkt[:k, k + 1] = self.x[idx]
        kkt[k, :k] = 1.0
        kkt[k + 1, :k] = self.x[idx]
        rhs = np.concatenate([-self.g[idx], [self.f_total, self.m_total]])
        try:
            sol = np.linalg.solve(kkt, rhs)
        except np.linalg.LinAlgError:
            sol = np.linalg.lstsq(kkt, rhs, rcond=None)[0]
        return sol[:k], float(sol[k]), float(sol[k + 1])

    def gap(
        self, idx: NDArray[np.intp], r_idx: NDArray[np.float64], a: float, b: float
    ) -> NDArray[np.float64]:
        h = self.g + a + b * self.x + self.flex[:, idx] @ r_idx
        h[idx] = 0.0
        return h

    def block_pivoting(self, active: NDArray[np.bool_], *, max_iterations: int) -> LcpResult:
        """Júdice–Pires block principal pivoting from ``active``; may stop unconverged."""
        n = self.x.size
        best, budget = n + 1, 3
        r, h, a, b = np.zeros(n), self.g, 0.0, 0.0
        for it in range(1, max_iterations + 1):
            idx = np.flatnonzero(active)
            r_idx, a, b = self.solve_subset(idx)
            r = np.zeros(n)
            r[idx] = r_idx
            h = self.gap(idx, r_idx, a, b)
            drop = active & (r < -self.tol_r)
            add = ~active & (h < -self.tol_h)
            nbad = int(drop.sum() + add.sum())
            if nbad == 0:
                return self._stop(True, active, r, h, a, b, it)
            if nbad < best:
                best, budget = nbad, 3
            elif budget > 0:
                budget -= 1
            else:
                break
            new = active ^ (drop | add)
            if new.sum() < 2:
                break
            active = new
        return self._stop(False, active, r, h, a, b, max_iterations)

    def primal_active_set(self, r0: NDArray[np.float64], max_iterations: int) -> LcpResult:
        """Primal active-set method for the convex QP min ½rᵀCr + gᵀr, r >= 0, balances.

        Starts from a feasible r0 (r0 >= 0, both balances hold); every step keeps feasibility
        and does not increase the objective (Nocedal & Wright 2006, Alg. 16.3), adding the most
        violated gap or dropping blocking reactions one step at a time.
        """
        n = self.x.size
        r = r0.copy()
        free = r > 0
        h, a, b = self.g, 0.0, 0.0
        for it in range(1, max_iterations + 1):
            idx = np.flatnonzero(free)
            r_idx, a, b = self.solve_subset(idx)
            if np.all(r_idx >= -self.tol_r):
                r = np.zeros(n)
                r[idx] = np.maximum(r_idx, 0.0)
                h = self.gap(idx, r_idx, a, b)
                j = int(np.argmin(np.where(free, np.inf, h)))
                if free.all() or h[j] >= -self.tol_h:
                    return self._stop(True, free, r, h, a, b, it)
                free[j] = True
            else:
                d = r_idx - r[idx]
                neg = d < 0
                ratios = np.where(neg, r[idx] / np.where(neg, -d, 1.0), np.inf)
                alpha = min(1.0, float(np.min(ratios)))
                r_new = r[idx] + alpha * d
                blocking = neg & (ratios <= alpha * (1 + 1e-12))
                r_new[blocking] = 0.0
                r = np.zeros(n)
                r[idx] = r_new
                free = r > 0
                if free.sum() < 2:  # pragma: no cover - a feasible point needs two supports
                    free[idx[np.argsort(-r_idx)[:2]]] = True
        return self._stop(False, free, r, h, a, b, max_iterations)
