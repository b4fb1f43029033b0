"""The flexible ski on elastic snow: the free Euler–Bernoulli beam and the half-space together.

Kalliorinne et al. (2023, §3.2) press the profile loaded on the stone, as a rigid body, into the
snow, and name the cost: on soft snow the results "should be considered as more approximate due
to the error inherited from the BEM simulation with a rigid ski-camber profile". Here the ski
bends on the snow instead. Measured from the binding x_m, each half of the ski deflects as a
cantilever under the contact pressure on it (:mod:`skisnow.contact._beam_operator`), so the gap
between the ski and the snow is

    g(x) = z0(x) + w_boot(x) + w_beam(p)(x) + u_snow(p)(x) − δ − θ (x − x_m)

with z0 the free camber, w_boot the bending under the boot (a point force at x_m bends nothing;
a uniform boot plate bends the ski beside the binding), w_beam = K_beam q (q the pressure
integrated across the width) and u_snow = K_snow p the half-space displacement (eq. 2 modulus
E'). With p ≥ 0, g ≥ 0, p·g = 0 and the balances ∫p dA = W, ∫(x − x_m) p dA = 0 (eq. 3), this is
the problem of :func:`~skisnow.contact.solve_contact` with the compliance K_snow + K_beam in place
of K_snow and z0 + w_boot in place of the rigid loaded profile: δ and θ are again the Lagrange
multipliers, and once the balances hold the clamp at x_m carries nothing, so the solution is the
free ski. K_beam is symmetric positive semi-definite, so this is the convex QP
min ½⟨p, (K_snow + K_beam) p⟩ + ⟨p, z0 + w_boot⟩ over p ≥ 0 under the two balances. K_beam is
applied in O(n) by cumulative sums and the snow by FFT; the snow's circulant inverse is the
preconditioner (the snow dominates at short wavelengths). The iteration is a feasible active-set
conjugate gradient with proportioning (Dostál's MPRGP), not Polonsky & Keer's (1999): the beam
adds a few very large long-wave eigenvalues, and PK's rescaling of p after a clipped step then
stalls on some cambers (measured: 5000 iterations without converging on random skis of the
property tests); here every step lowers the energy and a projected search drops many cells at
once. It still moves the contact set a face at a time: 60–700 iterations on the classic of
version 2 (measured at 4096 stations; conditioning is not the cause, an exact preconditioner
leaves the count unchanged). So 1D grids of ≥ 1024 stations are solved first by primal–dual
active-set steps (Hintermüller, Ito & Kunisch 2002, SIAM J. Optim. 13) on nested grids
(:mod:`skisnow.contact._flexible_pdas`: each step a dense Cholesky of K on the contact set and
the two balance multipliers; 3–4 steps on the finest grid), which end at the KKT point to
round-off. Where the finest contact set is too large for the dense factorisation, or the steps
cycle, MPRGP goes on from the coarse grids' solution; without nested grids (or from a given
``initial_pressure``) it runs as before: on the candidate contact cells (dense blocks of both
operators) once a few whole-grid steps have shrunk the start, the gap checked on the whole grid
afterwards.

The Winkler (local) foundation, p = k·u_snow, replaces the half-space for the checks against
Hetényi's (1946) free beam on an elastic foundation (:func:`~skisnow.contact.reference.\
winkler_free_beam`).

This module holds the problem set-up, the checks of the input, the result
(:class:`FlexibleSolution`) and the public entry points :func:`solve_flexible` and
:func:`solve_flexible_ski`; the operators K_snow + K_beam are in
:mod:`skisnow.contact._coupled_operator`, the MPRGP iteration in :mod:`skisnow.contact._mprgp`,
its restriction to the candidate cells in :mod:`skisnow.contact._flexible_candidates` and the
active-set steps in :mod:`skisnow.contact._flexible_pdas`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from skisnow._errors import ConvergenceError, InputError, UnsupportedLoadError
from skisnow._parallel import single_threaded_blas
from skisnow.contact._beam_operator import cantilever_compliance
from skisnow.contact._coupled_operator import CoupledOperator, WinklerOperator
from skisnow.contact._flexible_candidates import (
    CANDIDATE_MIN_CELLS,
    CANDIDATE_WARMUP,
    flexible_on_candidates,
)
from skisnow.contact._flexible_pdas import multilevel_active_set
from skisnow.contact._kernels import Convolution
from skisnow.contact._mprgp import active_set_cg
from skisnow.contact._operators import circulant_preconditioner
from skisnow.contact._polonsky_keer import restore
from skisnow.contact._problem import DEFAULT_WIDTH, _operator, _uniform_grid
from skisnow.contact._solver import ContactSolution
from skisnow.contact._starts import rigid_start

__all__ = [
    "EQUIVALENT_MODULUS_RANGE",
    "FlexibleSolution",
    "solve_flexible",
    "solve_flexible_ski",
]

#: E' [Pa] accepted by the flexible solver: from the softest snow (E ≈ 0.1 MPa) to a rigid
#: counter-surface 10⁴ times stiffer than granite. Outside it the input is a unit slip (MPa for Pa).
EQUIVALENT_MODULUS_RANGE: tuple[float, float] = (1e5, 1e15)


@dataclass(frozen=True, kw_only=True, eq=False)
class FlexibleSolution:
    """The flexible ski on elastic snow (SI units), from :func:`solve_flexible`.

    Attributes
    ----------
    contact
        The contact as a :class:`ContactSolution` whose ``height`` is the *bent* ski in the frame
        of the binding (z0 + w_boot + w_beam) and whose ``displacement`` is the snow's: its gap,
        pressure, δ, θ, zones (:func:`~skisnow.contact.contact_zones`), figures and field files
        are those of the flexible ski.
    free_camber
        z0 at the stations [m].
    stiffness
        EI at the stations [N m²] (``inf`` for a rigid ski).
    boot_deflection, beam_deflection
        Bending of the ski [m] (upward positive, relative to the binding) by the boot load and
        by the contact pressure.
    boot_length, boot_distribution
        The boot plate [m] and ``'uniform'`` or ``'point'``.
    foundation
        ``'half-space'`` or ``'winkler'`` (then ``contact.modulus`` holds k [Pa/m]).
    complementarity
        max |p·g| / (max p · max|g|) over the grid (0 for an exact solution).
    """

    contact: ContactSolution
    free_camber: np.ndarray
    stiffness: np.ndarray
    boot_deflection: np.ndarray
    beam_deflection: np.ndarray
    boot_length: float
    boot_distribution: str
    foundation: str
    complementarity: float

    @property
    def x(self) -> np.ndarray:
        """Stations along the ski [m]."""
        return self.contact.x

    @property
    def shape(self) -> np.ndarray:
        """The bent ski's base above the undeformed snow surface [m] (negative where it sinks
        in): z0 + w − δ − θ(x − x_m), along x (the surface model's is the same across)."""
        c = self.contact
        h = c.height if c.height.ndim == 1 else c.height.min(axis=1)
        return h - c.translation - c.rotation * (c.x - c.load_position)

    @property
    def penetration(self) -> float:
        """Deepest sinking of the ski into the undeformed snow surface [m]."""
        return float(max(-self.shape.min(), 0.0))

    @property
    def converged(self) -> bool:
        """Whether the iteration reached its tolerance."""
        return self.contact.converged


def _check_modulus(modulus: float, foundation: str) -> float:
    try:
        value = float(modulus)
    except (TypeError, ValueError):
        raise InputError(f"modulus must be a number, got {modulus!r}") from None
    if foundation == "winkler":
        if not np.isfinite(value) or value <= 0:
            raise InputError(f"Winkler foundation modulus k must be > 0 Pa/m, got {value!r}")
        return value
    lo, hi = EQUIVALENT_MODULUS_RANGE
    if not np.isfinite(value) or not lo <= value <= hi:
        raise InputError(
            f"snow modulus: the equivalent modulus E' = {value!r} Pa lies outside the physical "
            f"range {lo:.0e}..{hi:.0e} Pa (snow is 20–400 MPa, E' ≈ 41–600 MPa against the "
            "base; E' is in Pa, not MPa)"
        )
    return value


@single_threaded_blas()  # small dense Cholesky factors: one BLAS thread (see _parallel)
def solve_flexible(
    x: ArrayLike,
    free_camber: ArrayLike,
    stiffness: ArrayLike | float,
    *,
    load: float,
    load_position: float,
    modulus: float,
    width: float = DEFAULT_WIDTH,
    model: Literal["strip", "surface"] = "strip",
    n_across: int = 8,
    foundation: Literal["half-space", "winkler"] = "half-space",
    boot_length: float = 0.10,
    boot_distribution: Literal["uniform", "point"] = "uniform",
    tol: float = 1e-8,
    max_iter: int = 5000,
    initial_pressure: ArrayLike | None = None,
    candidates: bool | None = None,
    edge_contact: Literal["error", "allow"] = "error",
    raise_on_failure: bool = True,
    workers: int | None = None,
) -> FlexibleSolution:
    """Contact of a free, flexible ski with an elastic half-space (Kalliorinne et al. 2023, eq.
    2–3, with the rigid profile of §3.2 replaced by an Euler–Bernoulli beam).

    Parameters
    ----------
    x
        Uniform stations (cell centres) along the ski [m], x = 0 at the balance point.
    free_camber
        Unloaded base height z0 at the stations [m].
    stiffness
        Bending stiffness EI [N m²]: a number or an array at the stations (``np.inf`` everywhere
        gives the rigid ski).
    load, load_position
        The skier's force W [N] (downward) and its centre x_m [m].
    modulus
        Equivalent modulus E' [Pa] of eq. 2 (or the Winkler foundation modulus k [Pa/m] with
        ``foundation='winkler'``).
    width
        Ski width [m] (strip: the kernel averages over it; surface: the footprint).
    model
        ``'strip'`` (1D along the ski, width-averaged kernel) or ``'surface'`` (2D grid; the beam
        couples to the pressure integrated across the width).
    n_across
        Cells across the width (surface model).
    foundation
        ``'half-space'`` (the snow) or ``'winkler'`` (a local foundation, for checks).
    boot_length, boot_distribution
        The load is spread uniformly over the boot plate (``'uniform'``, as the virtual bench
        does) or acts as a point force at x_m (``'point'``).
    tol, max_iter
        Stopping rule: the largest gap on the contact set and the deepest penetration off it,
        relative to the camber range plus the largest displacement, ≤ tol; iteration limit.
    initial_pressure
        A start (e.g. the previous load step's pressure) on the same grid [Pa]. With the
        nested active-set steps (see ``candidates``) it is used only when they give no start
        (measured on load chains: cold nested grids cost the same or less).
    candidates
        Strip model, half-space, ≥ 1024 stations (the default): primal–dual active-set steps on
        nested grids (Hintermüller et al. 2002), else MPRGP on the candidate contact cells only,
        with the dense blocks K_snow,SS + K_beam,SS; the gap is checked on the whole grid, so
        the answer is that of the whole-grid MPRGP iteration (``False``) to the tolerance.
    edge_contact
        ``'error'``: raise :class:`UnsupportedLoadError` when the contact reaches an end of the
        ski (it would tip over that end); ``'allow'``: return it.
    raise_on_failure
        Raise :class:`ConvergenceError` (with ``.result``) when not converged; otherwise the
        result carries ``converged=False`` and its message.
    workers
        FFT threads.

    Returns
    -------
    FlexibleSolution

    Raises
    ------
    InputError
        Non-finite or non-positive EI (naming the station), E' outside the physical range, a
        load position or boot plate off the ski, bad shapes.
    UnsupportedLoadError
        The free ski cannot carry the load within its length.
    """
    if model not in ("strip", "surface"):
        raise InputError(f"model must be 'strip' or 'surface', got {model!r}")
    if foundation not in ("half-space", "winkler"):
        raise InputError(f"foundation must be 'half-space' or 'winkler', got {foundation!r}")
    if foundation == "winkler" and model != "strip":
        raise InputError("the Winkler foundation is offered with model='strip' only")
    if boot_distribution not in ("uniform", "point"):
        raise InputError(
            f"boot_distribution must be 'uniform' or 'point', got {boot_distribution!r}"
        )
    if edge_contact not in ("error", "allow"):
        raise InputError(f"edge_contact must be 'error' or 'allow', got {edge_contact!r}")
    xs, dx = _uniform_grid("x", x)
    z0 = np.asarray(free_camber, dtype=np.float64)
    if z0.shape != xs.shape or not np.all(np.isfinite(z0)):
        raise InputError(f"free_camber must be finite with the shape of x {xs.shape}")
    modulus = _check_modulus(modulus, foundation)
    load = float(load)
    if not (np.isfinite(load) and load > 0):
        raise InputError(f"load must be a finite force > 0 N, got {load!r}")
    width = float(width)
    if not (np.isfinite(width) and width > 0):
        raise InputError(f"width must be > 0 m, got {width!r}")
    xm = float(load_position)
    boot_length = float(boot_length) if boot_distribution == "uniform" else 0.0
    if not (np.isfinite(boot_length) and boot_length >= 0):
        raise InputError(f"boot_length must be >= 0 m, got {boot_length!r}")
    lo, hi = xs[0] - 0.5 * dx, xs[-1] + 0.5 * dx
    if not (np.isfinite(xm) and lo <= xm - 0.5 * boot_length and xm + 0.5 * boot_length <= hi):
        raise UnsupportedLoadError(
            f"the load at x_m = {xm * 1e3:.1f} mm (boot plate {boot_length * 1e3:.0f} mm) is not "
            f"on the ski [{lo * 1e3:.1f}, {hi * 1e3:.1f}] mm: the free ski cannot carry it"
        )
    ei = np.broadcast_to(np.asarray(stiffness, dtype=np.float64), xs.shape)
    bad = ~(ei > 0) | np.isnan(ei)
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"bending stiffness EI must be > 0 N m² (finite, or inf for a rigid ski), got "
            f"{ei[k]!r} at x = {xs[k] * 1e3:.1f} mm"
        )
    rigid = bool(np.all(np.isinf(ei)))
    if np.any(np.isinf(ei)) and not rigid:
        raise InputError("bending stiffness EI must be finite at every station (or inf at all)")
    # the beam: clamp at x_m; a rigid ski has no beam compliance
    beam = cantilever_compliance(xs, 1e300 if rigid else ei, load_position=xm)
    w_boot = np.zeros_like(xs) if rigid else beam.boot_deflection(load, boot_length)

    if model == "surface":
        n_across = int(n_across)
        if n_across < 1:
            raise InputError(f"n_across must be >= 1, got {n_across}")
        dy = width / n_across
        shape: tuple[int, ...] = (xs.size, n_across)
        y: np.ndarray | None = (np.arange(n_across) + 0.5) * dy - 0.5 * width
    else:
        dy = width
        shape = (xs.size,)
        y = None
    cell_area = dx * dy
    if foundation == "winkler":
        snow_op: Convolution | WinklerOperator = WinklerOperator(shape=shape, foundation=modulus)
        inverse = snow_op.inverse()
    else:
        snow_op = _operator(model, shape, dx, dy, modulus, width, workers)
        inverse = circulant_preconditioner(snow_op)
    op = CoupledOperator(snow=snow_op, beam=beam, cell_area=cell_area)
    if rigid:
        op = CoupledOperator(snow=snow_op, beam=beam, cell_area=0.0)

    h_line = z0 + w_boot
    h = h_line if model == "strip" else np.repeat(h_line[:, None], shape[1], axis=1)
    xi_grid = np.broadcast_to((xs - xm)[:, None] if model == "surface" else xs - xm, shape)
    hf, xif = h.ravel(), np.ascontiguousarray(xi_grid).ravel()
    total = load / cell_area
    p0 = None
    if initial_pressure is not None:
        ip = np.asarray(initial_pressure, dtype=np.float64)
        if ip.shape != shape or not np.all(np.isfinite(ip)):
            raise InputError(f"initial_pressure must be finite with the grid's shape {shape}")
        if ip.sum() > 0:
            p0, ok = restore(np.maximum(ip.ravel(), 0.0), xif, total, True)
            p0 = p0 if ok else None

    def hull_start() -> np.ndarray:  # the rigid-hull start, for the paths that need one
        k0 = snow_op.self_influence
        return p0 if p0 is not None else rigid_start(hf, xif, total, True, k0, len(shape))

    if candidates is None:
        candidates = model == "strip" and foundation == "half-space" and not rigid
        candidates = candidates and xs.size >= CANDIDATE_MIN_CELLS
    result = None
    fields: tuple[np.ndarray, np.ndarray] | None = None
    if candidates:
        apply_full = lambda v: op(v.reshape(shape)).ravel()  # noqa: E731
        precond_full = lambda v: inverse(v.reshape(shape)).ravel()  # noqa: E731
        # the contact set by primal–dual active-set steps on nested grids (Hintermüller et
        # al. 2002); when the finest grid's set is too large for a dense Cholesky or the
        # steps cycle, MPRGP goes on from the coarse solution (already shrunk: no warm-up).
        # A warm start (initial_pressure) is used only if the nested grids give nothing:
        # measured on 5 kg load chains, the nested grids from cold cost as much as MPRGP
        # from the previous step on the skate and 2.5x less on the classic of version 2,
        # and active-set steps from the previous step's set cost 1.3x more on the skate
        result, start, cand, fields = multilevel_active_set(
            xs, h_line, np.asarray(ei), op=op, load=load, load_position=xm,
            modulus=modulus, width=width, tol=float(tol), workers=workers,
        )  # fmt: skip
        # where MPRGP goes on from: (pressure, iterations, residual history, applications)
        warm: tuple[np.ndarray, int, list[float], int] | None = None
        if result is None and start is not None:
            q, ok = restore(np.maximum(start, 0.0), xif, total, True)
            if ok:
                warm = (q, 0, [], 0)
        if result is None and warm is None:
            # a few whole-grid steps shrink the start's support (the rigid-hull start spreads
            # over far more cells than a bending ski touches)
            pre = active_set_cg(apply_full, precond_full, hf, xif, hull_start(), tol=float(tol),
                                max_iter=CANDIDATE_WARMUP)  # fmt: skip
            if pre[6]:
                result = pre
            else:
                warm = (pre[0], pre[4], pre[5], pre[8])
        if result is None and warm is not None:
            # then the candidate iteration takes over
            q, it0, hist0, nap0 = warm
            result = flexible_on_candidates(op, inverse, hf, xif, q, tol=float(tol),
                                            max_iter=int(max_iter) - it0,
                                            candidates=cand)  # fmt: skip
            if result is None:  # too many candidates: go on on the whole grid from there
                result = active_set_cg(apply_full, precond_full, hf, xif, q, tol=float(tol),
                                       max_iter=int(max_iter) - it0)  # fmt: skip
            p_, g_, a_, b_, it_, hist_, conv_, msg_, nap_ = result
            result = (p_, g_, a_, b_, it_ + it0, hist0 + hist_, conv_, msg_, nap_ + nap0)
    if result is None:
        result = active_set_cg(
            lambda v: op(v.reshape(shape)).ravel(),
            lambda v: inverse(v.reshape(shape)).ravel(),
            hf,
            xif,
            hull_start(),
            tol=float(tol),
            max_iter=int(max_iter),
        )
    p, _g, a, b, iters, hist, converged, message, n_conv = result
    pressure = p.reshape(shape)
    # the displacement and bending (those of the last whole-grid check of the active-set steps)
    u_snow, w_beam = fields or (snow_op(pressure), op.beam_part(pressure))
    w_beam_line = w_beam if model == "strip" else w_beam[:, 0]
    bent = h + w_beam
    gap = bent + u_snow - a - b * xi_grid
    force = float(pressure.sum() * cell_area)
    mom = float(np.sum(pressure * xi_grid) * cell_area)
    length = float(xs[-1] - xs[0] + dx)
    pmax = float(pressure.max()) if pressure.size else 0.0
    gscale = float(np.abs(gap).max()) + 1e-300
    compl = float(np.abs(pressure * gap).max() / (max(pmax, 1e-300) * gscale))
    contact = ContactSolution(
        x=xs,
        y=y,
        height=bent,
        pressure=pressure,
        gap=gap,
        displacement=u_snow,
        footprint=np.ones(shape, dtype=bool),
        translation=float(a),
        rotation=float(b),
        load=load,
        load_position=xm,
        modulus=modulus,
        width=width,
        model=model,
        control="moment",
        cell_area=cell_area,
        iterations=int(iters),
        convolutions=int(n_conv),
        residual=float(hist[-1]) if hist else float("nan"),
        residual_history=np.asarray(hist),
        converged=bool(converged),
        message=message,
        force_residual=abs(force - load) / load,
        moment_residual=abs(mom) / (load * length),
    )
    sol = FlexibleSolution(
        contact=contact,
        free_camber=z0,
        stiffness=np.array(ei),
        boot_deflection=w_boot,
        beam_deflection=w_beam_line,
        boot_length=boot_length,
        boot_distribution=boot_distribution,
        foundation=foundation,
        complementarity=compl,
    )
    if converged and edge_contact == "error":
        along = contact.contact_along
        if along[0] or along[-1]:
            end = "tail" if along[0] else "tip"
            raise UnsupportedLoadError(
                f"the flexible ski cannot carry W = {load:.4g} N at x_m = {xm * 1e3:.1f} mm "
                f"within its length: the contact reaches its {end} (it would tip over that "
                "end); move the load toward the balance point"
            )
    if not converged and raise_on_failure:
        raise ConvergenceError(
            f"the flexible-ski contact did not converge after {iters} iterations ({message}); "
            f"last relative gap residual {contact.residual:.3g}, tolerance {tol:.1e}",
            result=sol,
        )
    return sol


def solve_flexible_ski(
    ski: object,
    *,
    load: float,
    load_position: float,
    modulus: float,
    n_points: int = 4096,
    width: float | None = None,
    **options: object,
) -> FlexibleSolution:
    """:func:`solve_flexible` for a :class:`skisnow.ski.Ski` (EI(x), z0(x) and width from it).

    The stations are ``n_points`` evenly spaced from the tail to the tip, both ends included
    (the grid convention of :mod:`skisnow.pipeline`); ``width`` defaults to the ski's width;
    ``options`` go to :func:`solve_flexible`.
    """
    from skisnow.ski import Ski

    if not isinstance(ski, Ski):
        raise InputError(f"ski must be a skisnow.ski.Ski, got {type(ski).__name__}")
    n_points = int(n_points)
    if n_points < 16:
        raise InputError(f"n_points must be at least 16, got {n_points}")
    x = np.linspace(ski.x_tail, ski.x_tip, n_points)
    return solve_flexible(
        x,
        ski.free_camber(x),
        ski.stiffness(x),
        load=load,
        load_position=load_position,
        modulus=modulus,
        width=ski.width if width is None else width,
        **options,  # type: ignore[arg-type]
    )
