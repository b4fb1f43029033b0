"""The ski as a free-floating Euler–Bernoulli beam in unilateral contact with a rigid plane.

This is the *virtual camber bench* behind seed paper 000 (Kalliorinne et al. 2023), §3.1: the
SkiSelector presses a ski on a flat stone with a mass m through a boot at x_m and measures the
camber height h(x) (eq. 1, h = f(x, m, x_m)). Here h is computed instead of measured.

Model (SI units throughout):

* Euler–Bernoulli beam on x in [x_tail, x_tip] (x = 0 at the balance point, positive toward the
  tip), bending stiffness EI(x) [N m²], stress-free base shape z0(x) [m] above the plane.
* Load: a total force F = m·g [N] downward through the boot plate, centred at x_m [m], spread over
  ``boot_length`` [m] either uniformly (``'uniform'``, default: a stiff sole plate on the binding)
  or as a concentrated force (``'point'``, used for the beam-theory checks).
* Counter surface: the rigid flat plane z = 0. The ski is FREE-FLOATING: no supports, its rigid
  motion (translation a, rotation b) follows from equilibrium of the unilateral contact forces.
  Self-weight is neglected (a few N against hundreds).

Discretisation: Hermite-cubic beam elements (exact for the Euler–Bernoulli equation with nodal
loads and piecewise-constant EI; EI(x) is integrated with 4-point Gauss–Legendre per element).
Contact forces are nodal reactions r_j >= 0, so a contact point can only sit on a node: its
position is resolved to the element size, and the heights converge under refinement with a
non-monotone error of a few µm at the default 400 elements (≈5 mm) on the shipped skis — below
the bench's 0.01 mm resolution (see tests/ski/test_beam.py::test_mesh_refinement_converges).

Constrained problem (no penalty). Clamp the beam at the node nearest the balance point; its
flexibility matrix C (deflection at every node per unit upward nodal force) is computed once per
ski and mesh. With the boot load's deflection w_F of that clamped beam and g = z0 + w_F, the gap is
h = g + a + b·x + C r, and the contact problem is the mixed linear complementarity problem

    h >= 0,  r >= 0,  r·h = 0,   Σ r_j = F,   Σ r_j x_j = M_F,

in which a and b are the Lagrange multipliers of the force and moment balance. Once the balances
hold, the clamp carries nothing, so the clamped solution is the free-floating one. It is the KKT
system of the convex QP  min ½ rᵀCr + gᵀr  s.t. r >= 0, Σr = F, Σ r x = M_F, solved exactly by
the primal active-set method (Nocedal & Wright 2006, Alg. 16.3): every iterate is feasible and
the objective never increases; each step either adds the node of most negative gap or drops the
reactions that would turn negative. It starts from a feasible point: along a load sequence at one
position (the virtual bench), the previous reactions scaled to the new load (the balances scale
with F); otherwise the lever-rule reactions on the two supports of the lower convex hull of g
that bracket the load centroid (the rigid-ski solution). Given only a previous contact set, block
principal pivoting (Júdice & Pires 1994) is tried first for a few exchanges. Contact sets are a
few short intervals, so a solve takes a handful to a few tens of pivots.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import solveh_banded

from skisnow._errors import ConvergenceError, InputError, SolverStatus, UnsupportedLoadError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.ski._skis import Ski

__all__ = [
    "BeamSolution",
    "beam_stiffness_matrix",
    "cantilever_tip_deflection",
    "hermite_interpolate",
    "loaded_profile",
    "solve_beam",
    "three_point_bending_deflection",
]

#: Default boot-plate length [m]: the sole length through which the binding plate presses.
DEFAULT_BOOT_LENGTH: float = 0.10
#: Default number of Hermite elements along the ski (≈ 5 mm elements on a 2 m ski).
DEFAULT_N_ELEMENTS: int = 400

_GAUSS4_X, _GAUSS4_W = np.polynomial.legendre.leggauss(4)
_GAUSS4_X = 0.5 * (_GAUSS4_X + 1.0)  # on [0, 1]
_GAUSS4_W = 0.5 * _GAUSS4_W


# --------------------------------------------------------------------------- reference formulas


def three_point_bending_deflection(force: float, span: float, stiffness: float) -> float:
    """Mid-span deflection F·L³/(48·EI) [m] of a simply supported uniform beam, centre load."""
    return force * span**3 / (48.0 * stiffness)


def cantilever_tip_deflection(force: float, length: float, stiffness: float) -> float:
    """Tip deflection F·L³/(3·EI) [m] of a uniform cantilever under a tip force."""
    return force * length**3 / (3.0 * stiffness)


# --------------------------------------------------------------------------- FE core


def _shape(xi: NDArray[np.float64], le: NDArray[np.float64] | float) -> NDArray[np.float64]:
    """Hermite cubic shape functions N1..N4 at local xi in [0, 1] (last axis: 4)."""
    xi = np.asarray(xi, dtype=float)
    le = np.asarray(le, dtype=float)
    return np.stack(
        [
            1.0 - 3.0 * xi**2 + 2.0 * xi**3,
            le * (xi - 2.0 * xi**2 + xi**3),
            3.0 * xi**2 - 2.0 * xi**3,
            le * (-(xi**2) + xi**3),
        ],
        axis=-1,
    )


def _element_stiffness(x_nodes: NDArray[np.float64], ei_at: object) -> NDArray[np.float64]:
    """Element stiffness matrices (n_el, 4, 4) ∫ EI N''ᵀN'' dx with 4-point Gauss-Legendre."""
    le = np.diff(x_nodes)[:, None]  # (n_el, 1)
    xi = _GAUSS4_X[None, :]
    xq = x_nodes[:-1, None] + le * xi
    ei = np.asarray(ei_at(xq), dtype=float)  # type: ignore[operator]
    b = np.stack(
        [
            (-6.0 + 12.0 * xi) / le**2,
            (-4.0 + 6.0 * xi) / le,
            (6.0 - 12.0 * xi) / le**2,
            (-2.0 + 6.0 * xi) / le,
        ],
        axis=-1,
    )  # (n_el, nq, 4)
    w = (_GAUSS4_W[None, :] * le * ei)[..., None, None]
    return np.sum(w * b[..., :, None] * b[..., None, :], axis=1)


def beam_stiffness_matrix(x_nodes: ArrayLike, stiffness: ArrayLike | object) -> NDArray[np.float64]:
    """Dense global stiffness matrix of a Hermite-cubic Euler–Bernoulli beam.

    Parameters
    ----------
    x_nodes
        increasing node positions [m].
    stiffness
        EI [N m²], either a constant or a callable EI(x) (vectorised).

    Returns
    -------
    ndarray
        (2n, 2n) matrix for the DOF order (w_0, θ_0, w_1, θ_1, ...), w upward [m], θ = dw/dx.
    """
    x = np.asarray(x_nodes, dtype=float)
    ei_at = stiffness if callable(stiffness) else (lambda xx: np.full_like(xx, float(stiffness)))
    ke = _element_stiffness(x, ei_at)
    n = x.size
    k = np.zeros((2 * n, 2 * n))
    for e in range(n - 1):
        d = slice(2 * e, 2 * e + 4)
        k[d, d] += ke[e]
    return k


def hermite_interpolate(
    x_nodes: ArrayLike, w: ArrayLike, theta: ArrayLike, x: ArrayLike
) -> NDArray[np.float64]:
    """Interpolate a beam field from nodal values w and slopes θ with Hermite shape functions."""
    xn = np.asarray(x_nodes, dtype=float)
    wn = np.asarray(w, dtype=float)
    tn = np.asarray(theta, dtype=float)
    xs = np.asarray(x, dtype=float)
    e = np.clip(np.searchsorted(xn, xs, side="right") - 1, 0, xn.size - 2)
    le = xn[e + 1] - xn[e]
    xi = (xs - xn[e]) / le
    nsh = _shape(xi, le)
    return (
        nsh[..., 0] * wn[e]
        + nsh[..., 1] * tn[e]
        + nsh[..., 2] * wn[e + 1]
        + nsh[..., 3] * tn[e + 1]
    )


@dataclass(frozen=True)
class _Model:
    """Assembled clamped beam: nodes, banded clamped stiffness, flexibility of all DOFs."""

    x: NDArray[np.float64]
    z0: NDArray[np.float64]
    clamp: int
    ab: NDArray[np.float64]  # upper banded clamped stiffness (4, 2n)
    flex_full: NDArray[np.float64]  # (2n, n): DOF response to unit upward force at node j
    flex: NDArray[np.float64]  # (n, n): deflection rows of flex_full


def _banded_upper(ke: NDArray[np.float64], n: int) -> NDArray[np.float64]:
    ndof = 2 * n
    ab = np.zeros((4, ndof))
    for a in range(4):
        for b in range(a, 4):
            # global (i, j) = (2e + a, 2e + b), i <= j  -> ab[3 + i - j, j]
            np.add.at(ab[3 + a - b], 2 * np.arange(n - 1) + b, ke[:, a, b])
    return ab


@functools.lru_cache(maxsize=16)
def _assemble(ski: Ski, n_elements: int) -> _Model:
    x = np.linspace(ski.x_tail, ski.x_tip, n_elements + 1)
    n = x.size
    ke = _element_stiffness(x, ski.stiffness)
    ab = _banded_upper(ke, n)
    clamp = int(np.argmin(np.abs(x)))
    for dof in (2 * clamp, 2 * clamp + 1):
        ab[:, dof] = 0.0  # column entries (i, dof), i <= dof
        for j in range(dof, min(dof + 4, 2 * n)):
            ab[3 + dof - j, j] = 0.0  # row entries (dof, j), j >= dof
        ab[3, dof] = 1.0
    rhs = np.zeros((2 * n, n))
    rhs[2 * np.arange(n), np.arange(n)] = 1.0
    rhs[2 * clamp, clamp] = 0.0
    flex_full = solveh_banded(ab, rhs, check_finite=False)
    flex = np.ascontiguousarray(flex_full[0::2, :])
    flex = 0.5 * (flex + flex.T)  # symmetric up to round-off
    for arr in (x, flex_full, flex):
        arr.setflags(write=False)
    z0 = ski.free_camber(x)
    z0.setflags(write=False)
    return _Model(x=x, z0=z0, clamp=clamp, ab=ab, flex_full=flex_full, flex=flex)


def _boot_load_vector(
    x: NDArray[np.float64],
    force: float,
    load_position: float,
    boot_length: float,
    distribution: str,
) -> NDArray[np.float64]:
    """Consistent nodal load vector (2n,) of the downward boot load (total force ``force``)."""
    n = x.size
    f = np.zeros(2 * n)
    if distribution == "point" or boot_length == 0.0:
        e = int(np.clip(np.searchsorted(x, load_position, side="right") - 1, 0, n - 2))
        le = x[e + 1] - x[e]
        nsh = _shape(np.array((load_position - x[e]) / le), le)
        f[2 * e : 2 * e + 4] -= force * nsh
        return f
    lo, hi = load_position - 0.5 * boot_length, load_position + 0.5 * boot_length
    q = force / boot_length
    e0 = int(np.clip(np.searchsorted(x, lo, side="right") - 1, 0, n - 2))
    e1 = int(np.clip(np.searchsorted(x, hi, side="left") - 1, 0, n - 2))
    gx, gw = np.polynomial.legendre.leggauss(3)
    for e in range(e0, e1 + 1):
        a, b = max(lo, x[e]), min(hi, x[e + 1])
        if b <= a:
            continue
        le = x[e + 1] - x[e]
        xq = 0.5 * (a + b) + 0.5 * (b - a) * gx
        nsh = _shape((xq - x[e]) / le, le)  # (3, 4)
        f[2 * e : 2 * e + 4] -= q * 0.5 * (b - a) * (gw @ nsh)
    return f


def _lower_hull_bracket(x: NDArray[np.float64], g: NDArray[np.float64], xc: float) -> list[int]:
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


def _intervals(x: NDArray[np.float64], mask: NDArray[np.bool_]) -> tuple[tuple[float, float], ...]:
    out = []
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return ()
    splits = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[splits + 1]])
    ends = np.concatenate([idx[splits], [idx[-1]]])
    for s, e in zip(starts, ends, strict=True):
        out.append((float(x[s]), float(x[e])))
    return tuple(out)


# --------------------------------------------------------------------------- solution


@dataclass(frozen=True, kw_only=True)
class BeamSolution:
    """Equilibrium of the loaded ski on the rigid plane (all SI).

    Attributes
    ----------
    ski
        the ski that was solved.
    mass, load_position, boot_length, boot_distribution
        the load case [kg], [m], [m].
    force
        the total load m·g [N].
    x
        node positions [m].
    height
        loaded camber height h(x) >= 0 at the nodes [m] (gap to the plane).
    reactions
        nodal contact forces r >= 0 [N] (upward).
    contact_intervals
        ((start, end), ...) [m] of runs of nodes in contact (h = 0).
    deflection, slope
        elastic nodal deflection w [m] and slope θ [-] of the beam clamped at
        the node ``x[clamp]`` (the rigid motion is in ``translation`` and ``rotation``).
    translation, rotation
        rigid motion a [m], b [-] (Lagrange multipliers of the balances).
    active
        nodes of the final contact (active) set.
    iterations
        pivoting iterations.
    residual
        complementarity residual (dimensionless: max over nodes of |h| on the contact set,
        of the violations of h >= 0 and r >= 0 and of |r h|, scaled by F and the free-camber
        range).
    status
        how the active-set iteration ended (:class:`~skisnow.SolverStatus`): ``SUCCESSFUL``
        when it terminated with every sign condition met, ``MAX_STEPS_REACHED`` when the
        pivoting limit stopped it, ``NONFINITE`` when NaN/inf appeared. ``converged`` is
        ``status.successful``.
    """

    ski: Ski
    mass: float
    load_position: float
    boot_length: float
    boot_distribution: str
    force: float
    x: NDArray[np.float64]
    height: NDArray[np.float64]
    reactions: NDArray[np.float64]
    contact_intervals: tuple[tuple[float, float], ...]
    deflection: NDArray[np.float64]
    slope: NDArray[np.float64]
    translation: float
    rotation: float
    active: NDArray[np.bool_]
    iterations: int
    residual: float
    status: SolverStatus

    @property
    def converged(self) -> bool:
        """Whether the active-set iteration succeeded (``status.successful``)."""
        return self.status.successful

    @property
    def n_elements(self) -> int:
        """Number of beam elements."""
        return int(self.x.size - 1)

    def sample(self, x: ArrayLike, *, clip: bool = True) -> NDArray[np.float64]:
        """Loaded height h at arbitrary positions x [m] on the ski.

        The elastic part is interpolated with the Hermite shape functions (not linearly) and the
        free camber z0(x) is evaluated exactly. Between two contact nodes the interpolant can dip
        below the plane by an amount of order (Δx)⁴; with ``clip`` (default) such values are set
        to 0, as the rigid plane would.
        """
        xs = self.ski._check_x(x)
        h = (
            self.ski.free_camber(xs)
            + self.translation
            + self.rotation * xs
            + hermite_interpolate(self.x, self.deflection, self.slope, xs)
        )
        return np.maximum(h, 0.0) if clip else h


def _validate_load(
    ski: Ski, mass: float, load_position: float, boot_length: float, boot_distribution: str
) -> None:
    if not isinstance(ski, Ski):
        raise InputError(f"ski must be a skisnow.ski.Ski, got {type(ski).__name__}")
    if not (np.isfinite(mass) and mass > 0):
        raise InputError(f"mass must be a finite number > 0 kg, got {mass}")
    if not np.isfinite(load_position):
        raise InputError(
            f"load_position must be finite (metres from the balance point), got {load_position}"
        )
    if not (np.isfinite(boot_length) and boot_length >= 0):
        raise InputError(f"boot_length must be >= 0 m, got {boot_length}")
    if boot_distribution not in ("uniform", "point"):
        raise InputError(
            f"boot_distribution must be 'uniform' or 'point', got {boot_distribution!r}"
        )
    half = 0.0 if boot_distribution == "point" else 0.5 * boot_length
    if load_position - half < ski.x_tail or load_position + half > ski.x_tip:
        where = "tail" if load_position - half < ski.x_tail else "tip"
        raise UnsupportedLoadError(
            f"load at x_m = {load_position * 1e3:.1f} mm with a {boot_length * 1e3:.0f} mm "
            f"boot plate reaches beyond the {where} of ski {ski.name!r} (running surface "
            f"{ski.x_tail * 1e3:.0f}..{ski.x_tip * 1e3:.0f} mm): the ski would tip over its "
            f"{where}; move the load onto the ski"
        )


#: (converged, active set, reactions, gaps, translation a, rotation b, iterations)
_LcpResult = tuple[
    bool, NDArray[np.bool_], NDArray[np.float64], NDArray[np.float64], float, float, int
]


@dataclass(frozen=True)
class _Lcp:
    """The mixed LCP  h = g + a + b x + C r >= 0, r >= 0, r h = 0, Σ r = F, Σ r x = M."""

    flex: NDArray[np.float64]
    g: NDArray[np.float64]
    x: NDArray[np.float64]
    f_total: float
    m_total: float
    tol_r: float
    tol_h: float

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

    def block_pivoting(self, active: NDArray[np.bool_], *, max_iterations: int) -> _LcpResult:
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
                return True, active, r, h, a, b, it
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
        return False, active, r, h, a, b, max_iterations

    def primal_active_set(self, r0: NDArray[np.float64], max_iterations: int) -> _LcpResult:
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
                    return True, free, r, h, a, b, it
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
        return False, free, r, h, a, b, max_iterations


def solve_beam(
    ski: Ski,
    *,
    mass: float,
    load_position: float,
    boot_length: float = DEFAULT_BOOT_LENGTH,
    boot_distribution: Literal["uniform", "point"] = "uniform",
    n_elements: int = DEFAULT_N_ELEMENTS,
    warm_start: BeamSolution | Sequence[int] | None = None,
    max_iterations: int = 500,
    raise_on_failure: bool = True,
) -> BeamSolution:
    """Loaded camber of a free-floating ski on a rigid plane (seed paper 000, §3.1, eq. 1).

    Parameters
    ----------
    ski
        the ski (see :class:`~skisnow.ski.Ski`).
    mass
        load m [kg]; the force is m·g with g = STANDARD_GRAVITY.
    load_position
        x_m [m] from the balance point, positive toward the tip (the paper's
        "120 mm behind the balance point" is -0.120).
    boot_length
        length [m] of the boot plate over which the load is spread.
    boot_distribution
        ``'uniform'`` (default) or ``'point'`` (a concentrated force at x_m).
    n_elements
        number of Hermite-cubic beam elements.
    warm_start
        a previous :class:`BeamSolution` on the same mesh (or indices of nodes) to
        start the active set from; results do not depend on it, only the iteration count.
    max_iterations
        pivoting iteration limit.
    raise_on_failure
        raise :class:`ConvergenceError` (with ``.result`` and ``.status``) unless the status
        is ``SUCCESSFUL``; otherwise return the result with its status.

    Returns
    -------
    BeamSolution
        h >= 0, r >= 0, r·h = 0, Σr = m·g and Σ r x = moment of the boot load about the
        balance point (to round-off), and the ``status`` of the active-set iteration.

    Raises
    ------
    InputError
        Invalid arguments.
    UnsupportedLoadError
        The load is not on the ski (the ski would tip over an end).
    ConvergenceError
        See ``raise_on_failure``.
    """
    mass = float(mass)
    load_position = float(load_position)
    boot_length = float(boot_length)
    _validate_load(ski, mass, load_position, boot_length, boot_distribution)
    if not (isinstance(n_elements, int | np.integer) and n_elements >= 4):
        raise InputError(f"n_elements must be an integer >= 4, got {n_elements}")
    model = _assemble(ski, int(n_elements))
    x, flex = model.x, model.flex
    n = x.size
    force = mass * STANDARD_GRAVITY

    f_boot = _boot_load_vector(x, force, load_position, boot_length, boot_distribution)
    u_boot = solveh_banded(model.ab, _clamped(f_boot, model.clamp), check_finite=False)
    g = model.z0 + u_boot[0::2]
    # Balances consistent with the FE load vector (exact for the rigid modes of Hermite cubics):
    f_total = -float(np.sum(f_boot[0::2]))
    m_total = -float(np.sum(f_boot[0::2] * x + f_boot[1::2]))
    xc = m_total / f_total
    if not (x[0] <= xc <= x[-1]):  # pragma: no cover - excluded by _validate_load
        raise UnsupportedLoadError(f"load centroid {xc} m lies outside the ski")

    href = max(float(np.ptp(model.z0)), 1e-3)
    tol_h = 1e-10 * href
    tol_r = 1e-10 * force

    warm_active: NDArray[np.bool_] | None = None
    warm_r: NDArray[np.float64] | None = None
    if isinstance(warm_start, BeamSolution):
        if warm_start.x.size == n:
            warm_active = np.array(warm_start.active, dtype=bool)
            prev_xc = float(np.sum(warm_start.reactions * x)) / float(np.sum(warm_start.reactions))
            if abs(prev_xc - xc) <= 1e-12 * max(1.0, abs(xc)):
                warm_r = warm_start.reactions * (f_total / float(np.sum(warm_start.reactions)))
    elif warm_start is not None:
        warm_active = np.zeros(n, dtype=bool)
        warm_active[np.asarray(list(warm_start), dtype=int)] = True

    problem = _Lcp(flex=flex, g=g, x=x, f_total=f_total, m_total=m_total, tol_r=tol_r, tol_h=tol_h)
    converged, active, r, a, b, it = False, np.zeros(n, dtype=bool), np.zeros(n), 0.0, 0.0, 0
    if warm_active is not None and warm_active.sum() >= 2 and warm_r is None:
        converged, active, r, _h, a, b, it = problem.block_pivoting(warm_active, max_iterations=8)
    if not converged:
        if warm_r is None or np.any(warm_r < 0):
            warm_r = np.zeros(n)
            i, j = _lower_hull_bracket(x, g, xc)
            warm_r[i] = f_total * (x[j] - xc) / (x[j] - x[i])
            warm_r[j] = f_total * (xc - x[i]) / (x[j] - x[i])
        converged, active, r, _h, a, b, it2 = problem.primal_active_set(warm_r, max_iterations)
        it += it2

    u = u_boot + model.flex_full @ r
    w, theta = u[0::2].copy(), u[1::2].copy()
    height = model.z0 + a + b * x + w
    kkt_residual = float(np.max(np.abs(height[active]), initial=0.0)) / href
    height[active] = 0.0
    scale_r = force
    residual = float(
        max(
            kkt_residual,
            np.max(np.maximum(-height, 0.0)) / href,
            np.max(np.maximum(-r, 0.0)) / scale_r,
            np.max(np.abs(r * height)) / (scale_r * href),
        )
    )
    contact = height <= tol_h
    finite = bool(np.all(np.isfinite(height)) and np.all(np.isfinite(r)) and np.isfinite(residual))
    if not finite:
        status = SolverStatus.NONFINITE
    elif converged:
        status = SolverStatus.SUCCESSFUL
    else:
        status = SolverStatus.MAX_STEPS_REACHED
    result = BeamSolution(
        ski=ski,
        mass=mass,
        load_position=load_position,
        boot_length=boot_length,
        boot_distribution=boot_distribution,
        force=force,
        x=x,
        height=np.maximum(height, 0.0) if status.successful else height,
        reactions=r,
        contact_intervals=_intervals(x, contact),
        deflection=w,
        slope=theta,
        translation=a,
        rotation=b,
        active=active.copy(),
        iterations=it,
        residual=residual,
        status=status,
    )
    if not status.successful and raise_on_failure:
        raise ConvergenceError(
            f"beam contact: {status.message} ({max_iterations} pivots) for ski {ski.name!r}, "
            f"m = {mass} kg, x_m = {load_position * 1e3:.1f} mm (residual {residual:.2e})",
            result=result,
        )
    return result


def _clamped(f: NDArray[np.float64], clamp: int) -> NDArray[np.float64]:
    out = f.copy()
    out[2 * clamp : 2 * clamp + 2] = 0.0
    return out


def loaded_profile(
    ski: Ski,
    *,
    mass: float,
    load_position: float,
    x: ArrayLike | None = None,
    **options: object,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The rigid loaded camber profile (x [m], h [m]) of ``ski`` under m at x_m.

    ``x`` defaults to the beam nodes; other grids are interpolated with the Hermite shape
    functions. ``options`` go to :func:`solve_beam` (``boot_length``, ``n_elements``...).
    """
    sol = solve_beam(ski, mass=mass, load_position=load_position, **options)  # type: ignore[arg-type]
    if x is None:
        return sol.x.copy(), sol.height.copy()
    xs = np.asarray(x, dtype=float)
    return xs, sol.sample(xs)
