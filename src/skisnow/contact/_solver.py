"""The apparent contact of a rigid loaded ski profile with an elastic half-space (eq. 3).

The rigid profile ``h(x)`` (the loaded camber height above a reference plane, Kalliorinne et al.
2023 §3.2) is lowered by a translation δ at the load point and rotated by θ about it; the
equivalent elastic half-space (modulus E' of eq. 2) deforms by ``u = K p``. The gap is

    g(x) = h(x) + u(x) − δ − θ·(x − x_m)

(θ > 0 lowers the part of the ski in front of the load point). The unknowns satisfy

    p ≥ 0,  g ≥ 0,  p·g = 0,  ∫ p dA = W = m·g₀,  ∫ (x − x_m) p dA = 0,

i.e. p minimises ½⟨p, K p⟩ + ⟨p, h⟩ over p ≥ 0 under the two linear constraints, whose
Lagrange multipliers are δ and θ. Paper's eq. 3 reads ∫ (x + x_m) p dx = 0: there x_m is the
*distance behind* the balance point (positive backwards), while skisnow's ``load_position`` is
the coordinate of the load point, positive toward the tip (paper's "120 mm behind" = −0.120 m);
both say that the pressure's resultant acts at the load point.

Solved as ONE constrained problem (no outer loop on θ) by :func:`solve_contact`, a short
pipeline over modules of one concern each:

1. :mod:`._problem` — validation, the grid, the ski's footprint and the cached half-space
   operator, in a frozen :class:`~skisnow.contact._problem.ContactProblem`;
2. :mod:`._starts` — the start: warm, multilevel (a coarse-grid solution, default on large
   surface grids) or the rigid contact plane;
3. :mod:`._polonsky_keer` — the Polonsky & Keer (1999) constrained conjugate gradient,
   generalised to the moment constraint and preconditioned (Vollebregt 2014), returning a
   frozen result with a :class:`~skisnow.SolverStatus`;
4. the operator restricted to where contact can be (the cost changes, not the answer: the gap
   is checked on the whole grid afterwards and any missed cell added):

   * :mod:`._strip` — 1D grids: the same problem on grids coarsened by 4 (down to ≤ 256 cells)
     gives the start, then :mod:`._candidates` iterates on the *candidate* cells only, with
     ``K_SS`` dense and the loop compiled (:mod:`._pk_kernel`) up to 800 cells, by FFT over
     the candidates' span beyond;
   * :mod:`._window` — the surface model: the iteration on the bounding box of the candidate
     cells, the same kernel on a smaller FFT grid;

5. here — the result back on the grid (:class:`ContactSolution`), the balance residuals, the
   end-station check and ``raise_on_failure``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from skisnow._errors import ConvergenceError, InputError, SolverStatus, UnsupportedLoadError
from skisnow._parallel import single_threaded_blas
from skisnow.contact._operators import CellOperator, circulant_preconditioner
from skisnow.contact._polonsky_keer import PolonskyKeerResult, _dot, polonsky_keer
from skisnow.contact._problem import ContactProblem, Control, Model, build_problem
from skisnow.contact._starts import starting_pressure
from skisnow.contact._strip import solve_strip
from skisnow.contact._window import solve_on_window

__all__ = ["ContactSolution", "solve_contact"]


@dataclass(frozen=True, kw_only=True, eq=False)
class ContactSolution:
    """Result of :func:`solve_contact` (SI units).

    Attributes
    ----------
    x, y
        Cell centres along [m] (shape ``(nx,)``) and, for the surface model, across the ski [m]
        (shape ``(ny,)``; ``None`` for strip and line).
    height
        Rigid profile h on the grid [m] (``(nx,)`` or ``(nx, ny)``).
    pressure
        Contact pressure p [Pa] on the grid; zero outside the footprint.
    gap
        Gap g = h + u − δ − θ(x − x_m) [m] (≥ 0; ≈ 0 where p > 0).
    displacement
        Normal displacement u of the counter-surface (snow) [m], positive into the snow.
    footprint
        Boolean mask of the cells inside the ski's outline (all True for strip/line).
    translation, rotation
        δ [m] (lowering of the profile at the load point) and θ [rad] (positive: the front
        goes down), the multipliers of the force and moment constraints.
    load, load_position, modulus, width, model, control
        The problem: W [N], x_m [m], E' [Pa], ski width [m] (scalar or per-x), model, control.
    cell_area
        Area of one cell [m²] (strip/line: dx·width).
    iterations, convolutions, residual, residual_history, converged, status, message
        Solver report: iterations, FFT convolutions applied (the cost), the Polonsky–Keer error
        Σ|Δp|/Σp of the last step and its history, whether it converged, how it ended
        (:class:`~skisnow.SolverStatus`; ``converged == status.successful``) and a message.
    force_residual, moment_residual
        |Σp dA − W|/W and |Σ(x − x_m) p dA|/(W·L) with L the profile length, after solving.
    """

    x: np.ndarray
    y: np.ndarray | None
    height: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    displacement: np.ndarray
    footprint: np.ndarray
    translation: float
    rotation: float
    load: float
    load_position: float
    modulus: float
    width: float | np.ndarray
    model: str
    control: str
    cell_area: float
    iterations: int
    convolutions: int
    residual: float
    residual_history: np.ndarray = field(repr=False)
    converged: bool
    status: SolverStatus | None = None
    message: str
    force_residual: float
    moment_residual: float

    def __post_init__(self) -> None:
        # a solution built without a status (e.g. by hand, as a test fixture) gets the one its
        # ``converged`` flag implies
        if self.status is None:
            status = SolverStatus.SUCCESSFUL if self.converged else SolverStatus.MAX_STEPS_REACHED
            object.__setattr__(self, "status", status)
        elif self.status.successful != self.converged:
            raise InputError(f"status {self.status.value} contradicts converged={self.converged}")

    @property
    def dx(self) -> float:
        """Cell length along the ski [m]."""
        return float(self.x[1] - self.x[0]) if self.x.size > 1 else float("nan")

    @property
    def contact(self) -> np.ndarray:
        """Boolean mask of the cells in contact (p > 0)."""
        return self.pressure > 0.0

    @property
    def line_load(self) -> np.ndarray:
        """Force per unit length along the ski q(x) [N/m] (pressure integrated across the width)."""
        if self.pressure.ndim == 2:
            return self.pressure.sum(axis=1) * (self.cell_area / self.dx)
        return self.pressure * np.asarray(self.width, dtype=float)

    @property
    def contact_along(self) -> np.ndarray:
        """Boolean mask along x: stations where any cell across the width is in contact."""
        c = self.contact
        return c.any(axis=1) if c.ndim == 2 else c

    @property
    def total_force(self) -> float:
        """Σ p dA [N]."""
        return float(self.pressure.sum() * self.cell_area)

    @property
    def total_moment(self) -> float:
        """Σ (x − x_m) p dA [N m] about the load point (0 under moment control)."""
        arm = self.x - self.load_position
        q = self.pressure.sum(axis=1) if self.pressure.ndim == 2 else self.pressure
        return float(_dot(arm, q) * self.cell_area)


# --------------------------------------------------------------------------------------------
# public entry point
# --------------------------------------------------------------------------------------------


def solve_contact(
    x: ArrayLike,
    height: ArrayLike,
    *,
    load: float | None = None,
    load_position: float | None = None,
    modulus: float,
    model: Model = "strip",
    control: Control = "moment",
    width: float | ArrayLike | Callable[[np.ndarray], np.ndarray] | None = None,
    y: ArrayLike | None = None,
    n_across: int = 16,
    translation: float | None = None,
    rotation: float = 0.0,
    initial_pressure: ArrayLike | None = None,
    tol: float = 1e-8,
    max_iter: int = 5000,
    edge_contact: Literal["error", "allow"] = "error",
    reference_length: float = 1.0,
    workers: int | None = None,
    multilevel: bool | None = None,
    precondition: bool = True,
    candidates: bool | None = None,
    raise_on_failure: bool = False,
) -> ContactSolution:
    """Press a rigid profile into an elastic half-space with force and moment balance.

    Kalliorinne et al. (2023) eq. 3 (force and moment balance about the load point) on the
    half-space of equivalent modulus E' (their eq. 2), solved by the Polonsky & Keer (1999)
    constrained conjugate gradient (:func:`~skisnow.contact.polonsky_keer`).

    Parameters
    ----------
    x
        Stations along the ski [m], uniformly spaced, increasing (positive toward the tip).
    height
        Rigid profile h [m] (the loaded camber height, e.g. from
        :func:`skisnow.network.camber_profile`): shape ``(nx,)``, uniform across the width; or, for
        ``model='surface'`` with ``y`` given, a full ``(nx, ny)`` surface (e.g. a sphere).
    load
        Total normal force W = m·g₀ [N] (required for 'moment' and 'load' control).
    load_position
        x_m [m], the load point (required for 'moment'; for 'displacement' the rotation centre,
        default 0). Must lie inside the profile.
    modulus
        Equivalent modulus E' of eq. 2 [Pa] (:func:`~skisnow.contact.effective_modulus`).
    model
        'strip' (1D along x, Boussinesq kernel averaged over a constant ``width``; pressure
        uniform across it), 'surface' (2D grid ``nx × n_across`` over the footprint of width
        ``w(x)``, full 3D half-space) or 'line' (plane strain: a 2D half-space, pressure
        uniform over ``width``, so W/width is the load per unit length; use ``width=1.0`` to
        give the load per unit length directly).
    control
        'moment' (force and moment balance about x_m, the paper's eq. 3), 'load' (force only,
        θ = 0) or 'displacement' (δ = ``translation`` and θ = ``rotation`` prescribed).
    width
        Ski width [m]: a number (default 44 mm); for 'surface' also an array over ``x`` or a
        callable ``w(x)``. With a 2D ``height`` the default is the whole ``y`` grid.
    y
        Cell centres across the ski [m] for a 2D ``height`` (uniform).
    n_across
        Cells across the width for 'surface' with a 1D ``height``.
    translation, rotation
        δ [m] and θ [rad] for 'displacement' control.
    initial_pressure
        Warm start [Pa] with the shape of :attr:`ContactSolution.pressure` (``(nx,)``, or
        ``(nx, ny)`` for the surface model), e.g. the previous solution along a load path; it
        is clipped to ≥ 0 and rescaled to the constraints (a start that cannot carry the
        moment is replaced by the default start).
    tol
        Polonsky–Keer tolerance on Σ|Δp|/Σp between iterations.
    max_iter
        Iteration limit.
    edge_contact
        'error' (default): raise :class:`~skisnow.UnsupportedLoadError` when the contact reaches
        the first or last station (the load cannot be carried within the profile: the ski would
        tip over that end). 'allow' for problems whose domain is the contact itself (punches).
    reference_length
        'line' only: depth [m] at which the plane-strain displacement is zero (matters only for
        displacement control).
    workers
        FFT threads (default: all cores).
    precondition
        Precondition the conjugate gradient with the circulant inverse of the half-space operator
        (its Fourier symbol inverted, restricted to the contact set and projected on the
        constraints): 3–4× fewer iterations at the price of one more FFT pair per iteration.
    multilevel
        Without ``initial_pressure``, start from the solution on a grid twice as coarse
        (recursively, down to 128² cells): fewer fine-grid iterations. Default: on for the
        surface model; strip/line with ``candidates`` start from their own nested grids
        (coarsened by 4, :mod:`skisnow.contact._strip`), which ``multilevel=False`` turns off
        (then the rigid start).
    candidates
        Iterate where contact can be (default ``True``): on 1D models, nested grids give the
        start and the iteration runs on the candidate contact cells (the start's support and
        the cells whose estimated gap is small) with the operator restricted to them (dense and
        compiled up to 800 cells, FFT over their span beyond); on the surface model, on the
        bounding box of the candidates. The gap is then checked on the whole grid and the
        iteration resumed with any missed cell: the solution of the whole-grid iteration at a
        fraction of the cost. ``False``: the Polonsky–Keer iteration on the whole grid (and, on
        1D models, from the rigid start), the reference the restricted solves are tested
        against.
    raise_on_failure
        Raise :class:`~skisnow.ConvergenceError` (with ``.result``) when not converged.

    Returns
    -------
    ContactSolution
        Pressure [Pa], gap [m], snow displacement [m], δ [m], θ [rad], convergence report with
        its :class:`~skisnow.SolverStatus`.

    Raises
    ------
    ConvergenceError
        With ``raise_on_failure=True``, when the status is not successful (``.result`` holds
        the unconverged solution).
    InputError
        NaN/inf heights, mismatched or irregular grids, non-positive modulus/load/width, a load
        position outside the profile, unknown model/control.
    UnsupportedLoadError
        The contact would have to leave the profile (reach an end) to carry the load.
    """
    if edge_contact not in ("error", "allow"):
        raise InputError(f"edge_contact must be 'error' or 'allow', got {edge_contact!r}")
    problem = build_problem(
        x, height, load=load, load_position=load_position, modulus=modulus, model=model,
        control=control, width=width, y=y, n_across=n_across, translation=translation,
        rotation=rotation, reference_length=reference_length, workers=workers,
    )  # fmt: skip
    if candidates is None:
        candidates = True
    if candidates and model != "surface" and initial_pressure is None and multilevel is not False:
        # 1D: the nested grids of :mod:`._strip` give the start
        with single_threaded_blas():
            result = solve_strip(problem, p0=None, tol=float(tol), max_iter=int(max_iter),
                                 precondition=precondition)  # fmt: skip
    else:
        p0 = starting_pressure(
            problem,
            initial_pressure=initial_pressure,
            multilevel=model == "surface" if multilevel is None else multilevel,
            tol=tol,
            solve=solve_contact,  # the multilevel start's coarse solve: this function, recursively
        )
        result = _iterate(problem, p0, tol=float(tol), max_iter=int(max_iter),
                          precondition=precondition, candidates=candidates)  # fmt: skip
    sol = _solution(problem, result)
    if sol.converged and edge_contact == "error":
        _check_ends(sol)
    if not sol.converged and raise_on_failure:
        raise ConvergenceError(
            f"solve_contact did not converge after {sol.iterations} iterations ({sol.message}); "
            f"last Σ|Δp|/Σp = {sol.residual:.3g}, tolerance {tol:.1e}",
            result=sol,
        )
    return sol


def _iterate(
    problem: ContactProblem,
    p0: np.ndarray,
    *,
    tol: float,
    max_iter: int,
    precondition: bool,
    candidates: bool,
) -> PolonskyKeerResult:
    """The Polonsky–Keer iteration on the candidate cells (1D) or on the whole footprint."""
    pr = problem
    kwargs = dict(control=pr.control, total=pr.total, target=pr.target, tol=tol,
                  max_iter=max_iter)  # fmt: skip
    if candidates and pr.model == "surface":
        result = solve_on_window(pr, p0, tol=tol, max_iter=max_iter, precondition=precondition)
        if result is not None:
            return result
    elif candidates:
        with single_threaded_blas():
            return solve_strip(pr, p0=p0, tol=tol, max_iter=max_iter, precondition=precondition)
    inverse = CellOperator(circulant_preconditioner(pr.conv), pr.cells)
    return polonsky_keer(
        pr.operator, pr.h, p0=p0, arm=pr.arm,
        preconditioner=inverse if precondition else None,
        **kwargs,  # type: ignore[arg-type]
    )  # fmt: skip


def _solution(problem: ContactProblem, result: PolonskyKeerResult) -> ContactSolution:
    """The iteration's flat result back on the grid, with the balance residuals."""
    pr = problem
    a, b = result.translation, result.rotation
    if pr.control == "displacement":
        a, b = float(pr.translation), float(pr.rotation)  # type: ignore[arg-type]
    full = pr.cells is None
    pressure = pr.to_grid(result.pressure)
    displacement = result.displacement.reshape(pr.height.shape) if full else pr.conv(pressure)
    gap = pr.height + displacement - a - b * pr.arm_grid
    gap = gap if full else np.where(pr.footprint, gap, np.inf)
    force = float(pressure.sum() * pr.cell_area)
    mom = float(np.sum(pressure * pr.arm_grid) * pr.cell_area)
    length = float(pr.x[-1] - pr.x[0] + pr.dx)
    load = pr.load
    force_res = abs(force - load) / load if load is not None else 0.0
    scale = (load if load is not None else max(force, 1e-300)) * length
    hist = result.history
    return ContactSolution(
        x=pr.x,
        y=pr.y,
        height=pr.height,
        pressure=pressure,
        gap=gap,
        displacement=displacement,
        footprint=pr.footprint,
        translation=float(a),
        rotation=float(b),
        load=float(load) if load is not None else force,
        load_position=pr.xm,
        modulus=pr.modulus,
        width=pr.width,
        model=pr.model,
        control=pr.control,
        cell_area=pr.cell_area,
        iterations=int(result.iterations),
        convolutions=int(result.convolutions),
        residual=float(hist[-1]) if hist.size else float("nan"),
        residual_history=hist,
        converged=result.converged,
        status=result.status,
        message=result.message,
        force_residual=force_res,
        moment_residual=abs(mom) / scale if pr.moment else 0.0,
    )


def _check_ends(sol: ContactSolution) -> None:
    """Raise :class:`~skisnow.UnsupportedLoadError` when the contact reaches an end station.

    The message names the cause that fits the solution first: contact at BOTH ends means the
    whole profile is pressed down (a flat profile, or a load high enough to close its relief),
    not a tipping ski; contact at one end means the load sits too close to that end (the ski
    would tip over it) when the load point lies on that end's half, else a profile cut too short.
    """
    along = sol.contact_along
    if not (along[0] or along[-1]):
        return
    x = sol.x
    what = f"W = {sol.load:.4g} N at x_m = {sol.load_position * 1e3:.1f} mm"
    if along[0] and along[-1]:
        h = np.asarray(sol.height, dtype=np.float64)
        h = h if h.ndim == 1 else h.min(axis=1)
        relief = float(np.ptp(h - sol.rotation * (x - sol.load_position)))
        flat = relief <= 1e-9
        why = (
            "the profile is flat (in full contact at any load)"
            if flat
            else f"the load closes its relief ({relief * 1e6:.3g} µm over its length after the "
            f"rotation, indentation δ = {sol.translation * 1e6:.3g} µm)"
        )
        raise UnsupportedLoadError(
            f"the contact reaches both ends of the profile (x = {x[0] * 1e3:.1f} and "
            f"{x[-1] * 1e3:.1f} mm) under {what}: {why}, so the whole profile is in contact and "
            "the contact zone is cut by the profile's ends, not found by the solve. Give a "
            "profile that extends past the contact (a ski's camber rises toward its ends)"
            + ("" if flat else " or a lower load")
        )
    at_tail = bool(along[0])
    end = "tail (first station)" if at_tail else "tip (last station)"
    xe = x[0] if at_tail else x[-1]
    mid = 0.5 * (x[0] + x[-1])
    near = sol.load_position <= mid if at_tail else sol.load_position >= mid
    cause = (
        "the ski would tip over that end, or the profile is cut too short; move the load toward "
        "the balance point or extend the profile"
        if near
        else "the profile is cut too short on that side (or its height there is too low); "
        "extend the profile"
    )
    raise UnsupportedLoadError(
        f"the contact reaches the {end} of the profile at x = {xe * 1e3:.1f} mm: the profile "
        f"cannot carry {what} within its length ({cause})"
    )
