"""Contact with the stone resolved between the nodes of the beam (no penetration anywhere).

With contact forces at the nodes only (:mod:`skisnow.ski._lcp`), a contact point of the
continuous beam that falls between two nodes is moved to a node, and the ski may dip through the
stone between nodes. On a glide zone that is almost flat the loaded profile is extremely
sensitive to where the ski touches: measured against an independent finite-difference bench with
contact at every 0.03 mm (:func:`skisnow.bench.reference_profile`), 400 Hermite elements (5 mm)
with nodal contact miss the loaded heights by 0.3-12 µm rms (33 µm worst), and refining the mesh
converges slowly (800 elements: up to 10 µm; the contact position is resolved to h / 2, an error
of first order in h that the flat zone amplifies).

Here the non-penetration condition h(x) = z0(x) + a + b x + w(x) >= 0 holds along the whole
ski, with w the Hermite cubic of each element: a semi-infinite constraint, enforced by an
exchange (cutting-plane) method (Hettich & Kortanek 1993, §7; the classical treatment of a
semi-infinite program by adaptive discretisation). The candidate contact points are the nodes
plus points inside elements; a point force r_p at x_p inside element e acts through the element's
Hermite shape functions N(ξ_p) (the consistent load vector), so its flexibility with every other
point is N_pᵀ K⁻¹ N_q, and the mixed LCP of :class:`~skisnow.ski.BeamLcp` holds unchanged over
the candidates. After each solve the gap is evaluated on a sub-grid of every element; where it
dips below the stone by more than ``tol_penetration``, the deepest point (refined by a parabola
through the sub-grid) becomes a new candidate, and the LCP is solved again from the previous
reactions (a feasible start of the primal active set). Candidates only grow, so the iteration
ends (each round removes the deepest violation; the violations shrink as the candidates
densify where the ski touches).

The tolerance matters on flat glide zones: 1 nm of residual penetration moved heights by up to
0.4 µm; 10 pm (the default) agrees with the finest reference to 0.02-0.07 µm rms on the shipped
skis and on a ski with flat glide zones and 15 µm waviness (2-7 rounds from the nodal solution).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import csr_matrix

from skisnow.ski._fem import shape_functions
from skisnow.ski._lcp import BeamLcp, LcpResult, lower_hull_bracket

__all__ = [
    "DEFAULT_TOL_PENETRATION",
    "PointContact",
    "SubGrid",
    "hermite_rows",
    "solve_point_contact",
]

#: Largest penetration [m] of the ski into the stone left between candidate points.
DEFAULT_TOL_PENETRATION = 1e-11
#: Sub-grid points per element on which the gap is checked.
_SUB = 8
#: Gap [m] below which an element's sub-grid minimum is refined (a dip may hide between points).
_NEAR = 1e-7


@dataclass(frozen=True)
class SubGrid:
    """The points inside the elements of a uniform-or-not mesh on which the gap is checked.

    ``x`` (n_el, SUB + 1) positions including both nodes, ``shape`` (n_el, SUB + 1, 4) the
    Hermite shape functions there (slopes scaled by the element length)."""

    nodes: NDArray[np.float64]
    x: NDArray[np.float64]
    shape: NDArray[np.float64]
    #: the sparse interpolation matrix (n_el (SUB + 1), 2n): w at the sub-grid from the DOFs
    matrix: Any = field(repr=False)

    @classmethod
    def of(cls, nodes: NDArray[np.float64], sub: int = _SUB) -> SubGrid:
        xi = np.linspace(0.0, 1.0, sub + 1)
        le = np.diff(nodes)
        x = nodes[:-1, None] + le[:, None] * xi[None, :]
        xi2, le2 = np.broadcast_arrays(xi[None, :], le[:, None])
        shape = shape_functions(xi2, le2)  # (n_el, sub + 1, 4)
        n_el, m = x.shape
        rows = np.repeat(np.arange(n_el * m), 4)
        cols = (2 * np.arange(n_el)[:, None, None] + np.arange(4)[None, None, :]).repeat(m, 1)
        matrix = csr_matrix((shape.ravel(), (rows, cols.ravel())), shape=(n_el * m, 2 * nodes.size))
        return cls(nodes=nodes, x=x, shape=shape, matrix=matrix)

    def deflection(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """w at the sub-grid (n_el, SUB + 1) from the DOF vector u (w, θ per node)."""
        return (self.matrix @ u).reshape(self.x.shape)


def hermite_rows(nodes: NDArray[np.float64], x: NDArray[np.float64]):
    """Element index and the 4 Hermite shape functions at positions ``x``: ``(e, N)``."""
    e = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2)
    le = nodes[e + 1] - nodes[e]
    return e, shape_functions((x - nodes[e]) / le, le)


@dataclass(frozen=True, kw_only=True, eq=False)
class PointContact:
    """The contact of one load case resolved between nodes.

    ``x`` the candidate points (the nodes, then the interior points in the order they were
    added), ``node`` which of them are nodes, ``reactions`` [N] and ``active`` per candidate,
    ``u`` the DOFs of the clamped beam (boot load and reactions), ``translation``/``rotation``
    the rigid motion, ``interior`` the interior candidates' positions, ``flex`` the flexibility
    of the candidates (deflection at candidate i per unit upward force at j), ``response`` the
    DOF response to a unit force at each candidate (2n, n_c), ``rounds`` the exchange rounds,
    ``penetration`` the deepest remaining dip below the stone [m] (>= 0), ``converged``.
    """

    x: NDArray[np.float64]
    node: NDArray[np.bool_]
    reactions: NDArray[np.float64]
    active: NDArray[np.bool_]
    u: NDArray[np.float64]
    translation: float
    rotation: float
    flex: NDArray[np.float64]
    response: NDArray[np.float64]
    gap: NDArray[np.float64]
    rounds: int
    iterations: int
    penetration: float
    converged: bool

    @property
    def interior(self) -> NDArray[np.float64]:
        return self.x[~self.node]

    def nodal_reactions(self, nodes: NDArray[np.float64]) -> NDArray[np.float64]:
        """The reactions lumped on the nodes linearly (force and moment about any point kept)."""
        out = np.zeros(nodes.size)
        out[: nodes.size] += self.reactions[: nodes.size]
        xi = self.x[nodes.size :]
        if xi.size:
            e = np.clip(np.searchsorted(nodes, xi, side="right") - 1, 0, nodes.size - 2)
            t = (xi - nodes[e]) / (nodes[e + 1] - nodes[e])
            r = self.reactions[nodes.size :]
            np.add.at(out, e, (1 - t) * r)
            np.add.at(out, e + 1, t * r)
        return out


def _first_solve(lcp: BeamLcp, warm_active, warm_r, max_iterations: int) -> LcpResult:
    n = lcp.x.size
    if warm_r is not None and np.all(warm_r >= 0):
        return lcp.primal_active_set(warm_r, max_iterations)
    if warm_active is not None and warm_active.sum() >= 2:
        sol = lcp.block_pivoting(warm_active, max_iterations=8)
        if sol.converged:
            return sol
    r0 = np.zeros(n)
    xc = lcp.m_total / lcp.f_total
    order = np.argsort(lcp.x, kind="stable")
    i, j = lower_hull_bracket(lcp.x[order], lcp.g[order], xc)
    i, j = order[i], order[j]
    r0[i] = lcp.f_total * (lcp.x[j] - xc) / (lcp.x[j] - lcp.x[i])
    r0[j] = lcp.f_total * (xc - lcp.x[i]) / (lcp.x[j] - lcp.x[i])
    return lcp.primal_active_set(r0, max_iterations)


def solve_point_contact(
    *,
    nodes: NDArray[np.float64],
    solve: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    clamp: int,
    flex_full: NDArray[np.float64],
    flex: NDArray[np.float64],
    u_boot: NDArray[np.float64],
    z0_nodes: NDArray[np.float64],
    z0_at: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    z0_sub: NDArray[np.float64],
    subgrid: SubGrid,
    f_total: float,
    m_total: float,
    tol_r: float,
    tol_h: float,
    tol_penetration: float = DEFAULT_TOL_PENETRATION,
    points: NDArray[np.float64] | None = None,
    warm_active: NDArray[np.bool_] | None = None,
    warm_reactions: NDArray[np.float64] | None = None,
    max_rounds: int = 40,
    max_iterations: int = 500,
) -> PointContact:
    """The contact of the clamped beam with the stone, resolved between the nodes (module
    docstring).

    Parameters
    ----------
    nodes, clamp
        The mesh [m] and the clamped node.
    solve
        K⁻¹ of the clamped beam applied to a (2n, k) right-hand side.
    flex_full, flex
        DOF response (2n, n) and deflection (n, n) under a unit upward force at each node.
    u_boot
        DOFs under the boot load (2n,).
    z0_nodes, z0_at, z0_sub
        The free camber at the nodes, at any positions, and at ``subgrid.x``.
    f_total, m_total
        The balances Σ r = F and Σ r x = M of the LCP.
    tol_r, tol_h
        Tolerances of the LCP (reactions [N], gaps [m]).
    points, warm_active, warm_reactions
        Interior candidates to start with [m], and an active set or feasible reactions (>= 0,
        both balances) over nodes + ``points`` (e.g. the last solution of the same load case:
        the primal active set then starts from it).
    """
    n = nodes.size
    tol_penetration = max(tol_penetration, 3.0 * tol_h)  # below the LCP's own tolerance: no
    pts = np.zeros(0) if points is None else np.asarray(points, dtype=float)
    inside = (pts > nodes[0]) & (pts < nodes[-1])
    pts = pts[inside]
    warm_r: NDArray[np.float64] | None = None
    act0 = warm_active
    if act0 is not None and act0.size != n + pts.size:
        act0 = None
    if warm_reactions is not None and warm_reactions.size == n + inside.size:
        warm_r = np.concatenate([warm_reactions[:n], warm_reactions[n:][inside]])
        act0 = None
    iterations = 0
    for rounds in range(1, max_rounds + 1):
        e, shp = hermite_rows(nodes, pts)
        k = pts.size
        if k:
            rhs = np.zeros((2 * n, k), order="F")
            for a in range(4):
                rhs[2 * e + a, np.arange(k)] += shp[:, a]
            rhs[2 * clamp : 2 * clamp + 2] = 0.0
            resp_p = solve(rhs)
            c_pp = _pair_flex(shp, e, resp_p)
            c_np = resp_p[0::2, :]
            flex_c = np.block([[flex, c_np], [c_np.T, 0.5 * (c_pp + c_pp.T)]])
            response = np.concatenate([flex_full, resp_p], axis=1)
            ub = np.einsum("pa,pa->p", shp, _element_dofs(u_boot, e))
            g = np.concatenate([z0_nodes + u_boot[0::2], z0_at(pts) + ub])
        else:
            flex_c, response = flex, flex_full
            g = z0_nodes + u_boot[0::2]
        xc = np.concatenate([nodes, pts])
        lcp = BeamLcp(flex=flex_c, g=g, x=xc, f_total=f_total, m_total=m_total, tol_r=tol_r,
                      tol_h=tol_h)  # fmt: skip
        sol = _first_solve(lcp, act0, warm_r, max_iterations)
        iterations += sol.iterations
        if not sol.converged:
            break
        r = sol.reactions
        act = np.flatnonzero(sol.active)
        u = u_boot + response[:, act] @ r[act]
        a, b = sol.translation, sol.rotation
        h = z0_sub + a + b * subgrid.x + subgrid.deflection(u)  # (n_el, SUB + 1)

        def gap_at(el: NDArray[np.intp], xq: NDArray[np.float64], u=u, a=a, b=b):
            le = nodes[el + 1] - nodes[el]
            shp_q = shape_functions((xq - nodes[el]) / le, le)
            w = np.einsum("pa,pa->p", shp_q, _element_dofs(u, el))
            return z0_at(xq) + a + b * xq + w

        new, depth = _deepest_dips(h, subgrid, gap_at, tol_penetration)
        if new.size == 0 or rounds == max_rounds:
            return PointContact(
                x=xc, node=np.arange(xc.size) < n, reactions=r, active=sol.active.copy(), u=u,
                translation=float(a), rotation=float(b), flex=flex_c, response=response,
                gap=g + a + b * xc + flex_c[:, act] @ r[act], rounds=rounds,
                iterations=iterations, penetration=depth,
                converged=new.size == 0,
            )  # fmt: skip
        pts = np.concatenate([pts, new])
        warm_r = np.concatenate([r, np.zeros(new.size)])
        act0 = None
    return PointContact(
        x=xc, node=np.arange(xc.size) < n, reactions=sol.reactions, active=sol.active.copy(),
        u=u_boot, translation=float(sol.translation), rotation=float(sol.rotation), flex=flex_c,
        response=response, gap=sol.gap, rounds=rounds, iterations=iterations, penetration=np.inf,
        converged=False,
    )  # fmt: skip


def _element_dofs(u: NDArray[np.float64], e: NDArray[np.intp]) -> NDArray[np.float64]:
    return np.stack([u[2 * e], u[2 * e + 1], u[2 * e + 2], u[2 * e + 3]], axis=1)


def _pair_flex(shp, e, resp) -> NDArray[np.float64]:
    """N_pᵀ K⁻¹ N_q for interior points p, q from the responses ``resp`` (2n, k)."""
    rows = np.stack([2 * e + a for a in range(4)], axis=1)  # (k, 4) DOFs of each point
    # the deflection at point p under the unit force at q: Σ_a N_pa resp[rows_pa, q]
    return np.einsum("pa,paq->pq", shp, resp[rows, :])


def _deepest_dips(
    h: NDArray[np.float64],
    grid: SubGrid,
    gap_at: Callable[[NDArray[np.intp], NDArray[np.float64]], NDArray[np.float64]],
    tol: float,
) -> tuple[NDArray[np.float64], float]:
    """Positions of the deepest dip below ``-tol`` inside each element, and the deepest
    penetration found (>= 0).

    The sub-grid minimum of every element that comes within :data:`_NEAR` of the stone is
    refined by zooming: the gap ``gap_at(e, x)`` at 9 points over the two sub-cells around the
    current minimum, four times (a bracket of 1/8⁴ of two sub-cells: 0.3 µm on 5 mm
    elements), so a dip narrower than the sub-grid is found too."""
    x = grid.x
    k = 1 + np.argmin(h[:, 1:-1], axis=1)  # inside the element (the nodes are candidates)
    hmin = h[np.arange(h.shape[0]), k]
    # between sub-grid points a smooth gap dips below its sampled minimum by at most Δ² max|h''|
    # / 8; |h''| Δ² from the second differences (twice, for their own sampling)
    reach = 0.25 * np.max(np.abs(np.diff(h, 2, axis=1)), axis=1)
    near = np.flatnonzero(hmin < np.minimum(reach, _NEAR) + tol)
    if near.size == 0:
        return np.zeros(0), 0.0
    lo, hi = x[near, k[near] - 1], x[near, k[near] + 1]
    t = np.linspace(0.0, 1.0, 9)
    best_x, best_h = x[near, k[near]], hmin[near]
    for _ in range(4):
        xq = lo[:, None] + (hi - lo)[:, None] * t[None, :]
        hq = gap_at(np.repeat(near, t.size), xq.ravel()).reshape(xq.shape)
        j = np.argmin(hq, axis=1)
        best_x, best_h = xq[np.arange(near.size), j], hq[np.arange(near.size), j]
        step = (hi - lo) / (t.size - 1)
        lo, hi = np.maximum(best_x - step, lo), np.minimum(best_x + step, hi)
    depth = float(max(0.0, -float(best_h.min())))
    bad = best_h < -tol
    e0, e1 = x[near, 0], x[near, -1]
    inside = bad & (best_x > e0 + 1e-9 * (e1 - e0)) & (best_x < e1 - 1e-9 * (e1 - e0))
    return best_x[inside], depth
