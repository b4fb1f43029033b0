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

Solved as ONE constrained problem with the Polonsky & Keer (1999) constrained conjugate
gradient, generalised: the rigid *plane* δ + θ(x − x_m), fitted by least squares to the gap on
the current contact set, replaces the mean gap; the search direction and its image are projected
the same way; after each step the two constraints are restored by multiplying p by an affine
factor α + β(x − x_m) (β = 0 is Polonsky–Keer's load rescaling). No outer loop on θ.
The CG is preconditioned with the circulant inverse of the half-space operator (the inverse
Fourier symbol, in the spirit of Vollebregt 2014, J. Comput. Phys. 257, "A new solver for
the elastic normal contact problem using conjugate gradients, deflation, and an FFT-based
preconditioner"), and u = K p is updated from K t (one FFT pair a step, plus the
preconditioner's) while the contact set holds; a coarse-grid solution is the start on large
surface grids.
Plain load control (θ = 0, the mean gap) and displacement control (δ, θ given) are the same
iteration with fewer constraints.

On 1D grids the iteration runs on the *candidate* cells only (the start's support and the cells
whose estimated gap is small): a ski touches the snow over a few hundred of its 4096 stations, so
the operator restricted to them (a dense Toeplitz block up to 800 cells) and the vectors are
several times smaller. Since p = 0 off the candidates, the iterates are those of the whole-grid
iteration; the gap is checked on the whole grid afterwards (one FFT) and any missed cell added,
so the restriction changes the cost, not the answer.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from skisnow._errors import ConvergenceError, InputError, UnsupportedLoadError
from skisnow.contact._kernels import (
    Convolution,
    RestrictedOperator,
    line_convolution,
    strip_convolution,
    surface_convolution,
)

__all__ = ["ContactSolution", "solve_contact"]

Model = Literal["strip", "surface", "line"]
Control = Literal["moment", "load", "displacement"]

#: Default ski width [m] (the paper's skis are about 44 mm wide under the foot).
DEFAULT_WIDTH = 0.044


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
    iterations, convolutions, residual, residual_history, converged, message
        Solver report: iterations, FFT convolutions applied (the cost), the Polonsky–Keer error
        Σ|Δp|/Σp of the last step and its history, and a status message.
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
    message: str
    force_residual: float
    moment_residual: float

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
# input handling
# --------------------------------------------------------------------------------------------


def _finite_positive(name: str, value: float) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not np.isfinite(value) or value <= 0.0:
        raise InputError(f"{name} must be finite and positive, got {value!r}")
    return value


def _uniform_grid(name: str, x: ArrayLike) -> tuple[np.ndarray, float]:
    x = np.asarray(x, dtype=np.float64)
    if x.ndim != 1 or x.size < 2:
        raise InputError(f"{name} must be a 1D array of at least 2 stations, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        bad = int(np.flatnonzero(~np.isfinite(x))[0])
        raise InputError(f"{name} has a non-finite value at index {bad}")
    d = np.diff(x)
    dx = float(d.mean())
    if dx <= 0 or np.max(np.abs(d - dx)) > 1e-6 * abs(dx):
        raise InputError(
            f"{name} must be uniformly spaced and increasing (the FFT half-space needs a regular "
            f"grid); spacing varies from {d.min():.6g} to {d.max():.6g} m — resample the profile"
        )
    return x, dx


# --------------------------------------------------------------------------------------------
# the constrained conjugate gradient
# --------------------------------------------------------------------------------------------


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Inner product; long vectors without BLAS threads (they spin and stall on a busy machine)."""
    if a.size < 8192:
        return float(a @ b)
    return float(np.einsum("i,i->", a, b))


def _plane_fit(v: np.ndarray, xi: np.ndarray, sel: np.ndarray) -> tuple[float, float]:
    """Least-squares a + b·ξ to v on the selected cells (b = 0 if only one ξ is present)."""
    vs, xs = v[sel], xi[sel]
    n = vs.size
    if n == 0:
        return 0.0, 0.0
    sx, sv = xs.sum(), vs.sum()
    sxx, sxv = _dot(xs, xs), _dot(xs, vs)
    det = n * sxx - sx * sx
    if det <= 1e-12 * max(n * sxx, 1e-300):
        return float(sv / n), 0.0
    b = (n * sxv - sx * sv) / det
    a = (sv - b * sx) / n
    return float(a), float(b)


def _restore(p: np.ndarray, xi: np.ndarray, total: float, moment: bool) -> tuple[np.ndarray, bool]:
    """Scale p ≥ 0 by an affine factor α + βξ so that Σp = total and (moment) Σξp = 0.

    Returns the new p and whether both constraints could be met (the support must straddle ξ = 0
    for the moment; cells where the factor would be ≤ 0 are dropped and the fit repeated).
    """
    if not moment:
        s = p.sum()
        return (p * (total / s), True) if s > 0 else (p, False)
    for _ in range(8):
        m0 = p.sum()
        m1 = _dot(xi, p)
        m2 = _dot(xi * xi, p)
        det = m0 * m2 - m1 * m1
        if m0 <= 0 or det <= 1e-14 * m0 * m2:
            return p, False
        alpha = total * m2 / det
        beta = -total * m1 / det
        factor = alpha + beta * xi
        neg = (factor <= 0) & (p > 0)
        if not neg.any():
            return p * factor, True
        p = np.where(neg, 0.0, p)
    return p, False


def _start(
    h: np.ndarray,
    xi: np.ndarray,
    total: float,
    moment: bool,
    k0: float,
    dims: int,
) -> np.ndarray:
    """A starting pressure: the rigid contact plane plus a penetration estimate.

    The rigid plane touches the profile's lower convex hull at the load point (moment control)
    or is horizontal at the lowest point (load control); the start is p ∝ (s − d)₊ with d the
    height above that plane and s chosen so that a crude compliance ``k0·n^(1/dims)`` of the
    ``n`` cells within reach would carry the load.
    """
    if moment:
        # the supporting line of the profile at ξ = 0 (lower convex hull), found by pivoting:
        # start from the lowest point on each side, replace the one on the side of the deepest
        # point below the line until no point lies below it
        left, right = xi < 0, xi >= 0
        if not left.any() or not right.any():
            plane = np.full_like(h, h.min())
        else:
            il = np.flatnonzero(left)[np.argmin(h[left])]
            ir = np.flatnonzero(right)[np.argmin(h[right])]
            tol_h = 1e-12 * (np.ptp(h) + 1e-300)
            for _ in range(200):
                slope = (h[ir] - h[il]) / (xi[ir] - xi[il])
                plane = h[il] + slope * (xi - xi[il])
                k = int(np.argmin(h - plane))
                if h[k] - plane[k] >= -tol_h:
                    break
                if xi[k] < 0:
                    il = k
                else:
                    ir = k
    else:
        plane = np.full_like(h, h.min())
    d = np.maximum(h - plane, 0.0)
    ds = np.sort(d)
    n = np.arange(1, ds.size + 1)
    # load carried if the contact reached d = ds[n-1]: Σ (s − d) / (k0·n^(1/dims))
    csum = np.cumsum(ds)
    carried = (n * ds - csum) / (k0 * n ** (1.0 / dims))
    m = int(np.searchsorted(carried, total))
    m = min(max(m, 2 if ds.size > 1 else 1), ds.size)
    s = ds[m - 1] if m < ds.size else ds[-1]
    s = max(s, ds[min(1, ds.size - 1)])
    # (s = 0: a flat profile, e.g. a punch: start uniform on the lowest cells)
    p = np.where(d <= s, (s - d) + 0.1 * s, 0.0) if s > 0 else (d <= 0.0).astype(np.float64)
    if moment:
        # make sure the support straddles the load point
        for side in (xi <= 0, xi >= 0):
            if not (p[side] > 0).any() and side.any():
                p[np.flatnonzero(side)[np.argmin(d[side])]] = s
    p, _ = _restore(p, xi, total, moment)
    return p


#: at most this many cells changed by a step are added to u = K p by direct kernel columns
_DIRECT_COLUMNS = 12


def _pk(
    conv: Convolution,
    h: np.ndarray,
    xi: np.ndarray,
    idx: np.ndarray | None,
    *,
    total: float | None,
    control: str,
    target: np.ndarray | None,
    p0: np.ndarray,
    tol: float,
    max_iter: int,
    precondition: bool = False,
    inverse: Convolution | RestrictedOperator | None = None,
) -> tuple[np.ndarray, np.ndarray, float, float, int, list[float], bool, str, int]:
    """Polonsky–Keer constrained CG on the footprint cells (flat vectors).

    ``control``: 'moment' (plane fit, Σp = total, Σξp = 0), 'load' (mean, Σp = total) or
    'displacement' (no constraint; ``target`` = δ + θξ is subtracted from h beforehand).
    Returns p, u (flat), δ, θ, iterations, history, converged, message, convolutions.

    Written for speed on large grids: masked dot products instead of boolean indexing, and
    u = K p updated from K t when the contact set does not change (one convolution a step).
    """
    shape = conv.shape
    n_conv = 0

    inv = inverse
    if inv is None and precondition:
        inv = _preconditioner(conv)  # type: ignore[arg-type]

    def add_direct(out: np.ndarray, cells: np.ndarray, values: np.ndarray) -> None:
        """out += K Δ for Δ on a few (flat footprint) cells, by kernel columns."""
        if idx is None:
            conv.add_columns(out.reshape(shape), cells, values)
        else:
            full = np.zeros(shape)
            conv.add_columns(full, idx[cells], values)
            out += full.ravel()[idx]

    if idx is None:

        def apply(v: np.ndarray, op: Convolution = conv) -> np.ndarray:
            nonlocal n_conv
            n_conv += 1
            return op(v.reshape(shape)).ravel()

    else:
        grid = np.zeros(int(np.prod(shape)))

        def apply(v: np.ndarray, op: Convolution = conv) -> np.ndarray:
            nonlocal n_conv
            n_conv += 1
            grid[idx] = v
            return op(grid.reshape(shape)).ravel()[idx]

    moment = control == "moment"
    constrained = control in ("moment", "load")
    refresh = 25  # recompute u = K p from scratch every `refresh` steps (round-off drift)
    hh = h if target is None else h - target
    p = np.array(p0, dtype=np.float64)
    u = apply(p)
    # "nothing to move" when the projected gap is below 1e-13 of the heights and displacements
    h_scale = float(np.ptp(hh)) + float(np.abs(u).max()) + 1e-300
    t = np.zeros_like(p)
    g = np.empty_like(p)
    m = np.empty_like(p)  # 1.0 on the contact set, 0.0 elsewhere
    xm_ = np.empty_like(p)  # ξ on the contact set
    trial = np.empty_like(p)
    g_old = 1.0
    conj = False
    history: list[float] = []
    message = "maximum number of iterations reached"
    converged = False
    it = 0

    def fit(v: np.ndarray, cnt: float, sx: float, sxx: float) -> tuple[float, float]:
        """Least-squares plane a + bξ of v on the contact set (masked sums)."""
        sv = float(_dot(v, m))
        if not moment:
            return sv / cnt, 0.0
        sxv = float(_dot(v, xm_))
        det = cnt * sxx - sx * sx
        if det <= 1e-12 * max(cnt * sxx, 1e-300):
            return sv / cnt, 0.0
        b_ = (cnt * sxv - sx * sv) / det
        return (sv - b_ * sx) / cnt, b_

    for it in range(1, max_iter + 1):
        np.add(u, hh, out=g)
        sel = p > 0.0
        cnt = float(np.count_nonzero(sel))
        if cnt == 0:
            if not constrained:
                # no contact: either the exact answer (all gaps open) or a start from the overlap
                if not (g < 0).any():
                    converged, message = True, "no contact (every gap open)"
                    history.append(0.0)
                    break
                p = np.where(g < 0, -g / conv.self_influence, 0.0)
                u = apply(p)
                continue
            message = "the contact set vanished"
            break
        np.copyto(m, sel)
        sx = sxx = 0.0
        if moment:
            np.multiply(xi, m, out=xm_)
            sx = float(xm_.sum())
            sxx = float(_dot(xm_, xi))
        if constrained:
            a_, b_ = fit(g, cnt, sx, sxx)
            g -= a_
            if b_ != 0.0:
                g -= b_ * xi
        gm = g * m
        big_gm = _dot(gm, gm)
        if inv is not None:
            z = apply(gm, inv)
            z *= m
            if constrained:
                za, zb = fit(z, cnt, sx, sxx)
                z -= za * m
                if zb != 0.0:
                    z -= zb * xm_
            big_g = float(_dot(gm, z))
        else:
            z = gm
            big_g = big_gm
        if conj and g_old > 0:
            t *= big_g / g_old
            t *= m
            t += z
        else:
            t[:] = z
        g_old = big_g
        if constrained:
            # keep t in the constraint space on the contact set: then p − τt satisfies the
            # balance laws exactly unless cells are clipped or added
            ta, tb = fit(t, cnt, sx, sxx)
            t -= ta * m
            if tb != 0.0:
                t -= tb * xm_
        if big_gm <= (1e-13 * h_scale) ** 2 * cnt:
            # the gap is flat on this contact set: exact there; grow it by the overlapping cells
            overlap = (p == 0.0) & (g < 0.0)
            if not overlap.any():
                converged, message = True, "exact solution on the contact set"
                history.append(0.0)
                break
            p = p.copy()
            p[overlap] = -g[overlap] / conv.self_influence
            conj = False
            if constrained:
                assert total is not None
                p, ok = _restore(p, xi, total, moment)
                if not ok:
                    message = "the contact set cannot carry the load and the moment"
                    break
            u = apply(p)
            history.append(float("inf"))
            continue
        r = apply(t)
        denom = float(_dot(r, t))  # t is zero off the contact set and orthogonal to the plane
        if denom <= 0.0 or not np.isfinite(denom):
            message = "search direction lost positivity (ill-conditioned operator)"
            break
        tau = float(_dot(gm, t)) / denom
        p_old = p
        np.multiply(t, -tau, out=trial)
        trial += p
        p = np.maximum(trial, 0.0)
        overlap = (p == 0.0) & (g < 0.0)
        any_overlap = bool(overlap.any())
        if any_overlap:
            conj = False
            p[overlap] -= tau * g[overlap]
            changed = (trial < 0.0) | overlap
        else:
            conj = True
            changed = trial < 0.0
        any_changed = any_overlap or bool(changed.any())
        scale = 1.0
        if constrained:
            assert total is not None
            ok = True
            if moment:
                if any_changed:
                    p, ok = _restore(p, xi, total, moment)
            else:
                s_p = float(p.sum())
                ok = s_p > 0
                scale = total / s_p if ok else 1.0
                p *= scale
            if not ok:
                message = "the contact set cannot carry the load and the moment"
                break
        if it % refresh == 0 or (moment and any_changed):
            u = apply(p)
        else:
            # K p_new = c·(K p − τ K t + K Δ), Δ = the clipped and overlap corrections: exact and
            # free when the active set did not change (Δ = 0), one convolution otherwise
            r *= tau
            u -= r
            if any_changed:
                cells = np.flatnonzero(changed)
                delta = p[cells] / scale - trial[cells]
                if cells.size <= _DIRECT_COLUMNS:
                    add_direct(u, cells, delta)
                else:
                    full_delta = np.zeros_like(p)
                    full_delta[cells] = delta
                    u += apply(full_delta)
            if scale != 1.0:
                u *= scale
        norm = float(p.sum())
        p_old -= p
        err = float(np.abs(p_old).sum() / norm) if norm > 0 else 0.0
        history.append(err)
        if err <= tol:
            converged, message = True, f"converged: Σ|Δp|/Σp = {err:.2e} ≤ {tol:.1e}"
            break
    # final multipliers from the converged contact set
    u = apply(p)
    g = u + hh
    sel = p > 0
    a = b = 0.0
    if constrained and sel.any():
        if moment:
            a, b = _plane_fit(g, xi, sel)
        else:
            a = float(g[sel].mean())
    return p, u, a, b, it, history, converged, message, n_conv


#: candidate cells: those whose estimated gap is below this fraction of the largest snow
#: displacement (plus the cells already in contact); the gap check after the solve adds any
#: cell that was missed, so the margin only trades set size against re-solves
_CANDIDATE_MARGIN = 0.05
#: the candidate iteration is used when the set is at most this fraction of the grid
_CANDIDATE_FRACTION = 0.8
#: candidate runs closer than this many cells are joined
_CANDIDATE_GAP = 32
#: grids shorter than this are solved whole (too small to gain)
_CANDIDATE_MIN_CELLS = 1024


def _pk_candidates(
    conv: Convolution,
    h: np.ndarray,
    xi: np.ndarray,
    *,
    total: float | None,
    control: str,
    target: np.ndarray | None,
    p0: np.ndarray,
    tol: float,
    max_iter: int,
    precondition: bool,
    margin: float | None = None,
) -> tuple[np.ndarray, np.ndarray, float, float, int, list[float], bool, str, int] | None:
    """The Polonsky–Keer iteration of :func:`_pk` on the candidate contact cells of a 1D grid.

    Candidates S are the cells of the start's support plus those whose gap, estimated from the
    start (u₀ = K p₀, the rigid plane fitted on the support), is below ``margin``·max u₀. On S
    the iteration runs with ``K_SS`` (dense for small S) and the preconditioner restricted the
    same way: as p = 0 off S, its iterates are those of the whole-grid iteration as long as no
    cell off S would enter the contact. After convergence the gap is checked on the whole grid
    (one FFT); cells without pressure that penetrate (g < −tol·max u) are added, with every
    cell whose gap is below the margin, they are given the pressure that closes their own gap,
    and the iteration resumes. Returns the same tuple as :func:`_pk` (u on the whole grid), or
    None when the candidates are most of the grid from the start.
    """
    n = h.size
    if margin is None:
        margin = _CANDIDATE_MARGIN
    hh = h if target is None else h - target
    moment = control == "moment"
    constrained = control in ("moment", "load")
    p = np.asarray(p0, dtype=np.float64)
    u = conv(p)
    n_conv = 1
    inverse = _preconditioner(conv) if precondition else None

    def gap(p: np.ndarray, u: np.ndarray, a: float | None = None, b: float = 0.0) -> np.ndarray:
        g = hh + u
        if a is None:
            a, b = 0.0, 0.0
            sel = p > 0
            if constrained and sel.any():
                a, b = _plane_fit(g, xi, sel) if moment else (float(g[sel].mean()), 0.0)
        return g - a - b * xi

    g = gap(p, u)
    scale = float(np.max(np.abs(u))) + 1e-300
    candidates = (p > 0) | (g < margin * scale)
    iterations, history = 0, []
    for _ in range(8):
        _close_gaps(candidates, _CANDIDATE_GAP)
        cells = np.flatnonzero(candidates)
        if cells.size > _CANDIDATE_FRACTION * n or cells.size == 0:
            if iterations == 0:
                return None
            break
        op = RestrictedOperator.build(conv, cells)
        inv = op.preconditioner(inverse) if inverse is not None else None
        ps, _, a, b, it, hist, converged, message, nc = _pk(
            op,  # type: ignore[arg-type]
            h[cells],
            xi[cells],
            None,
            total=total,
            control=control,
            target=None if target is None else target[cells],
            p0=p[cells],
            tol=tol,
            max_iter=max_iter - iterations,
            precondition=precondition,
            inverse=inv,
        )
        iterations += it
        history += hist
        n_conv += nc
        p = np.zeros(n)
        p[cells] = ps
        u = conv(p)
        n_conv += 1
        if not converged:
            return p, u, a, b, iterations, history, converged, message, n_conv
        g = gap(p, u, a, b)
        scale = float(np.max(np.abs(u))) + 1e-300
        # cells without pressure that penetrate (beyond the solver's tolerance): off the
        # candidates, or left behind when the step that added them was tiny
        missed = (p == 0.0) & (g < -tol * scale)
        if not missed.any():
            return p, u, a, b, iterations, history, converged, message, n_conv
        candidates |= missed | (g < margin * scale)
        # resume from a start that is not already converged: the missed cells carry the
        # pressure that closes their own gap (else the first step, scaled by the converged
        # residual, would add almost nothing and pass the Σ|Δp|/Σp test at once)
        p = p.copy()
        p[missed] = -g[missed] / conv.self_influence
        if constrained:
            assert total is not None
            p, ok = _restore(p, xi, total, moment)
            if not ok:
                return p, conv(p), a, b, iterations, history, False, (
                    "the contact set cannot carry the load and the moment"
                ), n_conv + 1  # fmt: skip
    # the candidates grew to most of the grid (or kept missing cells): finish on the whole grid
    p, u, a, b, it, hist, converged, message, nc = _pk(
        conv, h, xi, None, total=total, control=control, target=target, p0=p, tol=tol,
        max_iter=max(max_iter - iterations, 1), precondition=precondition,
    )  # fmt: skip
    return p, u, a, b, iterations + it, history + hist, converged, message, n_conv + nc


def _close_gaps(mask: np.ndarray, width: int) -> None:
    """Set the gaps of at most ``width`` cells between True runs of ``mask`` (in place): fewer,
    longer runs make the restricted operator cheaper to assemble."""
    idx = np.flatnonzero(mask)
    if idx.size < 2:
        return
    jumps = np.flatnonzero((np.diff(idx) > 1) & (np.diff(idx) <= width + 1))
    for k in jumps.tolist():
        mask[idx[k] + 1 : idx[k + 1]] = True


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
    """Press a rigid profile into an elastic half-space with force and moment balance (eq. 3).

    Parameters
    ----------
    x
        Stations along the ski [m], uniformly spaced, increasing (positive toward the tip).
    height
        Rigid profile h [m] (the loaded camber height, e.g. from
        :func:`skisnow.ski.camber_profile`): shape ``(nx,)``, uniform across the width; or, for
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
        surface model, off for strip/line (where the coarse solves cost more than they save).
    candidates
        1D models: iterate on the candidate contact cells only (the start's support and the
        cells whose estimated gap is small), with the operator restricted to them (a dense
        matrix for up to 800 cells), then check the gap on the whole grid and resume with any
        missed cell added. The same solution as the whole-grid iteration at a fraction of the
        cost when the contact covers a small part of the ski. Default: on for strip and line
        grids of at least 1024 stations.
    raise_on_failure
        Raise :class:`~skisnow.ConvergenceError` (with ``.result``) when not converged.

    Returns
    -------
    ContactSolution
        Pressure [Pa], gap [m], snow displacement [m], δ [m], θ [rad], convergence report.

    Raises
    ------
    InputError
        NaN/inf heights, mismatched or irregular grids, non-positive modulus/load/width, a load
        position outside the profile, unknown model/control.
    UnsupportedLoadError
        The contact would have to leave the profile (reach an end) to carry the load.
    """
    if model not in ("strip", "surface", "line"):
        raise InputError(f"model must be 'strip', 'surface' or 'line', got {model!r}")
    if control not in ("moment", "load", "displacement"):
        raise InputError(f"control must be 'moment', 'load' or 'displacement', got {control!r}")
    if edge_contact not in ("error", "allow"):
        raise InputError(f"edge_contact must be 'error' or 'allow', got {edge_contact!r}")
    if candidates and model == "surface":
        raise InputError("candidates=True is offered for the 1D models (strip, line) only")
    x, dx = _uniform_grid("x", x)
    h = np.asarray(height, dtype=np.float64)
    modulus = _finite_positive("modulus (E')", modulus)
    if control in ("moment", "load"):
        if load is None:
            raise InputError(f"control={control!r} needs load= (the normal force in N)")
        load = _finite_positive("load", load)
    if control == "moment" and load_position is None:
        raise InputError("control='moment' needs load_position= (x_m in m)")
    if control == "displacement":
        if translation is None or not np.isfinite(translation):
            raise InputError("control='displacement' needs a finite translation= (δ in m)")
        if not np.isfinite(rotation):
            raise InputError(f"rotation must be finite, got {rotation!r}")
    xm = 0.0 if load_position is None else float(load_position)
    if not np.isfinite(xm):
        raise InputError(f"load_position must be finite, got {load_position!r}")
    if load_position is not None and not (x[0] <= xm <= x[-1]):
        raise InputError(
            f"load position x_m = {xm * 1e3:.1f} mm lies outside the profile "
            f"[{x[0] * 1e3:.1f}, {x[-1] * 1e3:.1f}] mm"
        )

    # ---- the grid, the footprint and the operator
    if model == "surface":
        if h.ndim == 2:
            if y is None:
                raise InputError("a 2D height needs y= (cell centres across, m)")
            yy, dy = _uniform_grid("y", y)
            if h.shape != (x.size, yy.size):
                raise InputError(
                    f"height has shape {h.shape}, but x and y give a grid of ({x.size}, {yy.size})"
                )
            full_width = np.full(x.size, yy[-1] - yy[0] + dy)
            wx = full_width if width is None else _width_profile(width, x)
        elif h.ndim == 1:
            wx = _width_profile(DEFAULT_WIDTH if width is None else width, x)
            n_across = int(n_across)
            if n_across < 1:
                raise InputError(f"n_across must be ≥ 1, got {n_across}")
            wmax = float(wx.max())
            dy = wmax / n_across
            yy = (np.arange(n_across) + 0.5) * dy - wmax / 2
            if h.shape != x.shape:
                raise InputError(f"height has shape {h.shape}; x has shape {x.shape}")
            h = np.repeat(h[:, None], n_across, axis=1)
        else:
            raise InputError(f"height must be 1D or 2D, got shape {h.shape}")
        footprint = np.abs(yy)[None, :] <= wx[:, None] / 2 + 1e-9 * dy
        if not footprint.any(axis=1).all():
            raise InputError("the width profile leaves stations without any cell; refine n_across")
        conv = _operator("surface", (x.size, yy.size), dx, dy, modulus, 0.0, workers)
        cell_area = dx * dy
        width_out: float | np.ndarray = wx if not np.allclose(wx, wx[0]) else float(wx[0])
        y_out: np.ndarray | None = yy
    else:
        if h.shape != x.shape:
            raise InputError(f"height has shape {h.shape}; x has shape {x.shape} (must match)")
        if width is None:
            w = DEFAULT_WIDTH
        elif callable(width) or np.ndim(width) != 0:
            raise InputError(
                f"model={model!r} needs a constant width (a number); use model='surface' "
                "for a width profile w(x)"
            )
        else:
            w = _finite_positive("width", width)
        footprint = np.ones(x.shape, dtype=bool)
        extra = w if model == "strip" else float(reference_length)
        conv = _operator(model, (x.size,), dx, 0.0, modulus, extra, workers)
        cell_area = dx * w
        width_out = w
        y_out = None
    if not np.all(np.isfinite(h)):
        bad = np.argwhere(~np.isfinite(h))[0]
        raise InputError(f"height has a non-finite value (NaN or inf) at index {tuple(bad)}")

    full = footprint.all()
    idx = None if full else np.flatnonzero(footprint.ravel())
    hf = h.ravel() if full else h.ravel()[idx]
    xi_grid = np.broadcast_to((x - xm)[:, None] if h.ndim == 2 else x - xm, h.shape)
    xif = xi_grid.ravel() if full else xi_grid.ravel()[idx]
    total = None if load is None else load / cell_area  # Σp over cells
    moment = control == "moment"
    dims = 2 if model == "surface" else 1

    # ---- start
    target = None
    if control == "displacement":
        target = float(translation) + float(rotation) * xif  # type: ignore[arg-type]
    p0 = None
    if initial_pressure is not None:
        ip = np.asarray(initial_pressure, dtype=np.float64)
        if ip.shape != h.shape:
            raise InputError(f"initial_pressure has shape {ip.shape}; the grid has shape {h.shape}")
        if not np.all(np.isfinite(ip)):
            raise InputError("initial_pressure has non-finite values")
        ipf = np.maximum(ip.ravel() if full else ip.ravel()[idx], 0.0)
        if control == "displacement":
            p0 = ipf
        elif ipf.sum() > 0:
            p0, ok = _restore(ipf, xif, total, moment)  # type: ignore[arg-type]
            if not ok:
                p0 = None
    if multilevel is None:
        multilevel = model == "surface"
    if p0 is None and control != "displacement" and multilevel:
        coarse = _coarse_start(
            x,
            h,
            y_out,
            model=model,
            load=load,  # type: ignore[arg-type]
            load_position=load_position,
            modulus=modulus,
            control=control,
            width=width_out,
            two_d_height=np.ndim(height) == 2,
            tol=tol,
            workers=workers,
            reference_length=reference_length,
        )
        if coarse is not None:
            cf = coarse.ravel() if full else coarse.ravel()[idx]
            if cf.sum() > 0:
                p0, ok = _restore(np.maximum(cf, 0.0), xif, total, moment)  # type: ignore[arg-type]
                if not ok:
                    p0 = None
    if p0 is None:
        if control == "displacement":
            p0 = np.maximum(target - hf, 0.0) / conv.self_influence  # type: ignore[operator]
        else:
            p0 = _start(hf, xif, total, moment, conv.self_influence, dims)  # type: ignore[arg-type]

    if candidates is None:
        candidates = model != "surface" and hf.size >= _CANDIDATE_MIN_CELLS
    problem: dict = dict(
        total=total, control=control, target=target, p0=p0, tol=float(tol),
        max_iter=int(max_iter), precondition=precondition,
    )  # fmt: skip
    result = _pk_candidates(conv, hf, xif, **problem) if candidates else None
    if result is None:  # the whole grid (also when the candidates are most of it)
        result = _pk(conv, hf, xif, idx, **problem)
    p, u, a, b, iters, hist, converged, message, n_conv = result
    if control == "displacement":
        a, b = float(translation), float(rotation)  # type: ignore[arg-type]

    # ---- back to the grid
    pressure = np.zeros(h.size)
    disp_flat = conv(_scatter(p, idx, h.shape)).ravel() if not full else u
    if full:
        pressure[:] = p
    else:
        pressure[idx] = p
    pressure = pressure.reshape(h.shape)
    displacement = disp_flat.reshape(h.shape)
    gap = h + displacement - a - b * xi_grid
    gap = np.where(footprint, gap, np.inf) if not full else gap
    force = float(pressure.sum() * cell_area)
    mom = float(np.sum(pressure * xi_grid) * cell_area)
    length = float(x[-1] - x[0] + dx)
    force_res = abs(force - load) / load if load is not None else 0.0
    scale = (load if load is not None else max(force, 1e-300)) * length
    moment_res = abs(mom) / scale if moment else 0.0

    sol = ContactSolution(
        x=x,
        y=y_out,
        height=h,
        pressure=pressure,
        gap=gap,
        displacement=displacement,
        footprint=footprint,
        translation=float(a),
        rotation=float(b),
        load=float(load) if load is not None else force,
        load_position=xm,
        modulus=modulus,
        width=width_out,
        model=model,
        control=control,
        cell_area=cell_area,
        iterations=int(iters),
        convolutions=int(n_conv),
        residual=float(hist[-1]) if hist else float("nan"),
        residual_history=np.asarray(hist),
        converged=bool(converged),
        message=message,
        force_residual=force_res,
        moment_residual=moment_res,
    )
    if converged and edge_contact == "error":
        along = sol.contact_along
        if along[0] or along[-1]:
            end = "tail (first station)" if along[0] else "tip (last station)"
            xe = x[0] if along[0] else x[-1]
            raise UnsupportedLoadError(
                f"the contact reaches the {end} of the profile at x = {xe * 1e3:.1f} mm: the "
                f"profile cannot carry W = {sol.load:.4g} N at x_m = {xm * 1e3:.1f} mm within its "
                "length (the ski would tip over that end, or the profile is cut too short); "
                "move the load toward the balance point or extend the profile"
            )
    if not converged and raise_on_failure:
        raise ConvergenceError(
            f"solve_contact did not converge after {iters} iterations ({message}); "
            f"last Σ|Δp|/Σp = {sol.residual:.3g}, tolerance {tol:.1e}",
            result=sol,
        )
    return sol


#: below these sizes the multilevel start is not worth it (cells along x; cells in total)
_COARSE_MIN_1D = 512
_COARSE_MIN_2D = 128 * 128
#: tolerance of the coarse solves (they only provide the start)
_COARSE_TOL = 1e-6


def _coarse_start(
    x: np.ndarray,
    h: np.ndarray,
    y: np.ndarray | None,
    *,
    model: str,
    load: float,
    load_position: float | None,
    modulus: float,
    control: str,
    width: float | np.ndarray,
    two_d_height: bool,
    tol: float,
    workers: int | None,
    reference_length: float,
) -> np.ndarray | None:
    """Solve the same problem on a grid twice as coarse (recursively) and prolong the pressure.

    Heights are averaged over pairs (2 × 2 blocks) of cells; the coarse pressure is repeated on
    the fine cells. Returns None when the grid is too small or of odd size.
    """
    nx = x.size
    if model == "surface":
        assert y is not None
        ny = y.size
        if nx % 2 or ny % 2 or nx * ny < _COARSE_MIN_2D or min(nx, ny) < 8:
            return None
        xc = 0.5 * (x[0::2] + x[1::2])
        hc = 0.25 * (h[0::2, 0::2] + h[1::2, 0::2] + h[0::2, 1::2] + h[1::2, 1::2])
        kwargs: dict = {}
        if two_d_height:
            yc = 0.5 * (y[0::2] + y[1::2])
            kwargs = {"y": yc}
            wc = None if np.ndim(width) == 0 else 0.5 * (width[0::2] + width[1::2])  # type: ignore[index]
            if np.ndim(width) == 0 and not np.isclose(float(width), y[-1] - y[0] + y[1] - y[0]):  # type: ignore[arg-type]
                wc = float(width)  # type: ignore[arg-type]
            kwargs["width"] = wc
        else:
            hc = hc[:, 0]
            kwargs = {
                "n_across": ny // 2,
                "width": width if np.ndim(width) == 0 else 0.5 * (width[0::2] + width[1::2]),  # type: ignore[index]
            }
    else:
        if nx % 2 or nx < _COARSE_MIN_1D:
            return None
        xc = 0.5 * (x[0::2] + x[1::2])
        hc = 0.5 * (h[0::2] + h[1::2])
        kwargs = {"width": width}
    try:
        sol = solve_contact(
            xc,
            hc,
            load=load,
            load_position=load_position,
            modulus=modulus,
            model=model,  # type: ignore[arg-type]
            control=control,  # type: ignore[arg-type]
            tol=max(tol, _COARSE_TOL),
            edge_contact="allow",
            reference_length=reference_length,
            workers=workers,
            **kwargs,
        )
    except (InputError, UnsupportedLoadError):
        return None
    pc = sol.pressure
    if pc.ndim == 2:
        return np.repeat(np.repeat(pc, 2, axis=0), 2, axis=1)
    return np.repeat(pc, 2)


@functools.lru_cache(maxsize=8)
def _preconditioner(conv: Convolution) -> Convolution:
    """The circulant inverse of a (cached) operator, cached with it.

    On large grids (≥ 2¹⁶ cells) it runs in single precision: its FFTs are ~40 % cheaper and a
    preconditioner only steers the iteration (the converged field is the same to the tolerance;
    measured 7e-11 rel-L2 on the 512² Hertz problem at tol 1e-10).
    """
    return conv.inverse(single=int(np.prod(conv.shape)) >= 2**16)


@functools.lru_cache(maxsize=8)
def _operator(
    model: str,
    shape: tuple[int, ...],
    dx: float,
    dy: float,
    modulus: float,
    extra: float,
    workers: int | None,
) -> Convolution:
    """The half-space operator of a model on a grid, cached (sweeps reuse the same few grids)."""
    if model == "surface":
        return surface_convolution(shape, dx, dy, modulus=modulus, workers=workers)  # type: ignore[arg-type]
    if model == "strip":
        return strip_convolution(shape[0], dx, extra, modulus=modulus, workers=workers)
    return line_convolution(shape[0], dx, modulus=modulus, reference_length=extra, workers=workers)


def _scatter(p: np.ndarray, idx: np.ndarray | None, shape: tuple[int, ...]) -> np.ndarray:
    if idx is None:
        return p.reshape(shape)
    out = np.zeros(int(np.prod(shape)))
    out[idx] = p
    return out.reshape(shape)


def _width_profile(
    width: float | ArrayLike | Callable[[np.ndarray], np.ndarray], x: np.ndarray
) -> np.ndarray:
    w = width(x) if callable(width) else width
    w = np.broadcast_to(np.asarray(w, dtype=np.float64), x.shape) if np.ndim(w) == 0 else w
    w = np.asarray(w, dtype=np.float64)
    if w.shape != x.shape:
        raise InputError(f"width profile has shape {w.shape}; x has shape {x.shape}")
    if not np.all(np.isfinite(w)) or np.any(w <= 0):
        raise InputError("width must be finite and positive at every station")
    return w.copy()
