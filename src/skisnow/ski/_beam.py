"""The ski as a free-floating Euler–Bernoulli beam in unilateral contact with a rigid plane.

This is the *virtual camber bench* behind Kalliorinne et al. (2023), §3.1: the
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

Modules: the Hermite elements, assembly and load vectors are in :mod:`skisnow.ski._fem`, the LCP
and its pivoting methods in :mod:`skisnow.ski._lcp`; this module sets up one load case, runs
them and returns a :class:`BeamSolution` with its status.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import solveh_banded

from skisnow._errors import ConvergenceError, InputError, SolverStatus, UnsupportedLoadError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.ski._contact_points import (
    DEFAULT_TOL_PENETRATION,
    PointContact,
    SubGrid,
    solve_point_contact,
)
from skisnow.ski._fem import (
    assemble_clamped,
    beam_stiffness_matrix,
    boot_load_vector,
    cantilever_tip_deflection,
    clamped_dofs,
    hermite_interpolate,
    three_point_bending_deflection,
)
from skisnow.ski._lcp import BeamLcp, LcpResult, lower_hull_bracket
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


def _point_intervals(
    points: NDArray[np.float64], spacing: float
) -> tuple[tuple[float, float], ...]:
    """Runs of contact points [m] (sorted) less than ``spacing`` (an element, with a margin)
    apart, as ((start, end), ...)."""
    if points.size == 0:
        return ()
    cuts = np.flatnonzero(np.diff(points) > 1.01 * spacing) + 1
    return tuple((float(run[0]), float(run[-1])) for run in np.split(points, cuts))


@functools.lru_cache(maxsize=16)
def _subgrid(n: int, x0: float, x1: float) -> SubGrid:
    return SubGrid.of(np.linspace(x0, x1, n))


@functools.lru_cache(maxsize=16)
def _z0_sub_cached(ski: Ski, n: int, x0: float, x1: float) -> NDArray[np.float64]:
    grid = _subgrid(n, x0, x1)
    z = ski.free_camber(np.clip(grid.x, ski.x_tail, ski.x_tip))
    z.setflags(write=False)
    return z


def _z0_sub(ski: Ski, grid: SubGrid) -> NDArray[np.float64]:
    nodes = grid.nodes
    return _z0_sub_cached(ski, nodes.size, float(nodes[0]), float(nodes[-1]))


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
        nodal contact forces r >= 0 [N] (upward); with ``contact='continuous'`` the forces of
        contact points between nodes are lumped on the element's two nodes linearly (force and
        moment kept).
    contact_intervals
        ((start, end), ...) [m] of the contact: runs of contact points (nodes with h = 0 and,
        with ``contact='continuous'``, points between nodes) less than an element apart.
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
    contact
        ``'continuous'`` (no penetration anywhere along the ski: contact points between nodes,
        :mod:`skisnow.ski._contact_points`) or ``'nodal'`` (contact at the nodes only).
    contact_points, point_reactions
        positions [m] and forces [N] of every contact point (nodes and points between them).
    penetration
        the deepest dip of the ski below the stone between contact points [m] (``'nodal'``: not
        checked, 0).
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
    contact: str = "continuous"
    contact_points: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    point_reactions: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    penetration: float = 0.0

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
    contact: Literal["continuous", "nodal"] = "nodal",
    tol_penetration: float = DEFAULT_TOL_PENETRATION,
) -> BeamSolution:
    """Loaded camber of a free-floating ski on a rigid plane (Kalliorinne et al. 2023, §3.1, eq. 1).

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
    contact
        ``'continuous'``: the ski does not penetrate the stone anywhere, contact points may lie
        between nodes (:mod:`skisnow.ski._contact_points`; the loaded heights within 0.1 µm of
        a 0.03 mm finite-difference reference at 400 elements; what the identification and the
        virtual bench use); ``'nodal'`` (default): contact at the nodes only (0.3-12 µm rms off
        at 400 elements on flat glide zones). The default stays ``'nodal'`` for the forward
        solves of the pipeline: with the continuous contact the shipped skis' calibration
        records moved (load shares by up to 0.16 points, the classic's plausibility hinge off
        zero) and their golden outputs would need re-fitting (issue 25, not done).
    tol_penetration
        the deepest dip below the stone [m] left between contact points (``'continuous'``).

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
    model = assemble_clamped(ski, int(n_elements))
    x, flex = model.x, model.flex
    n = x.size
    force = mass * STANDARD_GRAVITY

    f_boot = boot_load_vector(x, force, load_position, boot_length, boot_distribution)
    u_boot = solveh_banded(model.ab, clamped_dofs(f_boot, model.clamp), check_finite=False)
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

    if contact not in ("continuous", "nodal"):
        raise InputError(f"contact must be 'continuous' or 'nodal', got {contact!r}")
    if contact == "continuous":
        pts = None
        if isinstance(warm_start, BeamSolution) and warm_start.x.size == n:
            inner = warm_start.contact_points
            on_node = np.isin(inner, x)
            pts = inner[~on_node]
        grid = _subgrid(x.size, float(x[0]), float(x[-1]))
        pc: PointContact = solve_point_contact(
            nodes=x, solve=lambda rhs: solveh_banded(model.ab, rhs, check_finite=False),
            clamp=model.clamp, flex_full=model.flex_full, flex=flex, u_boot=u_boot,
            z0_nodes=model.z0, z0_at=ski.free_camber, z0_sub=_z0_sub(ski, grid), subgrid=grid,
            f_total=f_total, m_total=m_total, tol_r=tol_r, tol_h=tol_h,
            tol_penetration=tol_penetration, points=pts,
            warm_active=None if warm_active is None or pts is None
            else np.concatenate([warm_active, np.ones(pts.size, dtype=bool)]),
            max_iterations=max_iterations,
        )  # fmt: skip
        converged, a, b = pc.converged, pc.translation, pc.rotation
        active = pc.active[:n].copy()
        r = pc.nodal_reactions(x)
        it = pc.iterations
        u = pc.u
        on = pc.active
        points, point_r, penetration = pc.x[on], pc.reactions[on], pc.penetration
        point_gap, point_neg = (
            float(np.max(np.abs(pc.gap[on]), initial=0.0)),
            float(np.max(np.maximum(-pc.reactions, 0.0), initial=0.0)),
        )
        order = np.argsort(points)
        points, point_r = points[order], point_r[order]
    else:
        problem = BeamLcp(
            flex=flex, g=g, x=x, f_total=f_total, m_total=m_total, tol_r=tol_r, tol_h=tol_h
        )
        lcp: LcpResult | None = None
        it = 0
        if warm_active is not None and warm_active.sum() >= 2 and warm_r is None:
            lcp = problem.block_pivoting(warm_active, max_iterations=8)
            it = lcp.iterations
        if lcp is None or not lcp.converged:
            if warm_r is None or np.any(warm_r < 0):
                warm_r = np.zeros(n)
                i, j = lower_hull_bracket(x, g, xc)
                warm_r[i] = f_total * (x[j] - xc) / (x[j] - x[i])
                warm_r[j] = f_total * (xc - x[i]) / (x[j] - x[i])
            lcp = problem.primal_active_set(warm_r, max_iterations)
            it += lcp.iterations
        converged, active, r = lcp.converged, lcp.active, lcp.reactions
        a, b = lcp.translation, lcp.rotation
        u = u_boot + model.flex_full @ r
        points, point_r, penetration = x[active], r[active], 0.0
        point_gap = point_neg = 0.0

    w, theta = u[0::2].copy(), u[1::2].copy()
    height = model.z0 + a + b * x + w
    kkt_residual = float(np.max(np.abs(height[active]), initial=0.0)) / href
    height[active] = 0.0
    scale_r = force
    # complementarity at the contact points: the nodes (nodal contact) or every candidate point
    comp = np.max(np.abs(r * height)) / (scale_r * href) if contact == "nodal" else point_gap / href
    residual = float(
        max(
            kkt_residual if contact == "nodal" else 0.0,
            np.max(np.maximum(-height, 0.0)) / href,
            np.max(np.maximum(-r, 0.0)) / scale_r,
            point_neg / scale_r,
            comp,
        )
    )
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
        contact_intervals=_point_intervals(points, float(x[1] - x[0])),
        deflection=w,
        slope=theta,
        translation=a,
        rotation=b,
        active=active.copy(),
        iterations=it,
        residual=residual,
        status=status,
        contact=contact,
        contact_points=points,
        point_reactions=point_r,
        penetration=penetration,
    )
    if not status.successful and raise_on_failure:
        raise ConvergenceError(
            f"beam contact: {status.message} ({max_iterations} pivots) for ski {ski.name!r}, "
            f"m = {mass} kg, x_m = {load_position * 1e3:.1f} mm (residual {residual:.2e})",
            result=result,
        )
    return result


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
