"""The Polonsky–Keer constrained conjugate gradient: one core for every contact solve in skisnow.

Polonsky & Keer (1999), "A numerical method for solving rough contact problems based on the
multi-level multi-summation and conjugate gradient techniques", Wear 231: for a compliance
operator K (u = K p) and a rigid profile h, find p with

    p ≥ 0,   g = h + u − δ − θ·ξ ≥ 0,   p·g = 0,

under one of three controls:

* ``'moment'`` — Σp = ``total`` and Σ ξ p = 0 (force and moment balance about ξ = 0, the
  load point; Kalliorinne et al. 2023 eq. 3); δ and θ are the Lagrange multipliers. The rigid
  *plane* δ + θξ, fitted by least squares to the gap on the contact set, replaces Polonsky–Keer's
  mean gap, and after each step the constraints are restored by an affine factor α + βξ on p;
* ``'load'`` — Σp = ``total`` only (θ = 0: the original algorithm, mean gap and load rescaling);
* ``'displacement'`` — δ + θξ = ``target`` given, no constraint.

With ``hardness`` H the pressure is also capped, 0 ≤ p ≤ H (elastic–perfectly-plastic contact,
as in Sainsot & Lubrecht 2011, "Efficient solution of the dry contact of rough surfaces",
Proc. IMechE J 225): the CG runs on the free set 0 < p < H, iterates are projected on the box,
and cells at H with an open gap leave it the way overlapping cells at 0 enter the contact
(KKT: p = H ⇒ g ≤ 0). Offered under displacement control (a load-controlled PK with the cap
stalls when nearly every contact cell is plastic; meet a load by a root search on δ instead, as
:func:`skisnow.micro.elastoplastic_contact` does).

The CG may be preconditioned (Vollebregt 2014, J. Comput. Phys. 257: the circulant inverse of
the half-space operator); the preconditioned residual is restricted to the contact set and
projected on the constraints like the gap.

The seam: any compliance operator
---------------------------------
:func:`polonsky_keer` works on the flat vector of the ``n`` cells that may carry pressure and
never looks inside the operator. It needs a :class:`ComplianceOperator`:

* ``operator(v) -> K v`` on flat vectors of shape ``(n,)`` [Pa → m];
* ``operator.self_influence`` — the diagonal K(0) [m/Pa] (used to give cells that enter the
  contact the pressure that closes their own gap);
* optionally ``operator.add_columns(out, index, values)`` — ``out += K[:, index] @ values``
  for a few cells, cheaper than a full product (used when a step clips or adds ≤ 12 cells;
  without it, a full product is applied);

and, optionally, a ``preconditioner`` with the same call signature (an approximate K⁻¹).
:class:`~skisnow.contact.CellOperator` (in ``_operators``) adapts a
:class:`~skisnow.contact.Convolution` (any grid, optionally a
subset of its cells, e.g. a ski's footprint); the candidate-cell restriction
(:class:`~skisnow.contact._operators.RestrictedOperator`) is another implementation. A coupled
operator — e.g. the flexible ski, K = K_snow + K_beam (the half-space compliance plus the beam's
flexibility at the contact cells, same force and moment balance) — is a third: wrap it in an
object with ``__call__`` and ``self_influence`` (and the snow's circulant inverse as a
preconditioner, still a good one when K_beam is smooth) and call :func:`polonsky_keer` with
``control='moment'``, ``arm = x − x_m`` and ``total = W / cell area``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from skisnow._errors import InputError, SolverStatus
from skisnow.contact._operators import ComplianceOperator

__all__ = ["PolonskyKeerResult", "plane_fit", "polonsky_keer", "restore"]

Control = Literal["moment", "load", "displacement"]

#: at most this many cells changed by a step are added to u = K p by direct kernel columns
_DIRECT_COLUMNS = 12
#: recompute u = K p from scratch every this many steps (round-off drift of the updates)
_REFRESH = 25


@dataclass(frozen=True, kw_only=True, eq=False)
class PolonskyKeerResult:
    """Result of :func:`polonsky_keer` (flat cell vectors, SI units).

    Attributes
    ----------
    pressure
        p [Pa] on the cells.
    displacement
        u = K p [m] on the cells.
    translation, rotation
        δ [m] and θ [rad]: the rigid plane fitted to h + u on the final contact set (the
        multipliers of the constraints); 0 under displacement control (the caller knows them).
    iterations
        CG steps taken.
    convolutions
        Operator and preconditioner applications (the cost).
    history
        The Polonsky–Keer error Σ|Δp|/Σp of every step (``inf`` for a step that grew the
        contact set, 0 for an exact finish).
    status
        How the iteration ended (:class:`~skisnow.SolverStatus`).
    message
        A one-line report.
    """

    pressure: np.ndarray
    displacement: np.ndarray
    translation: float
    rotation: float
    iterations: int
    convolutions: int
    history: np.ndarray = field(repr=False)
    status: SolverStatus
    message: str

    @property
    def converged(self) -> bool:
        """``status.successful``."""
        return self.status.successful

    @property
    def residual(self) -> float:
        """The last Σ|Δp|/Σp (NaN before the first step)."""
        return float(self.history[-1]) if self.history.size else float("nan")


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Inner product; long vectors without BLAS threads (they spin and stall on a busy machine)."""
    if a.size < 8192:
        return float(a @ b)
    return float(np.einsum("i,i->", a, b))


def plane_fit(v: np.ndarray, xi: np.ndarray, sel: np.ndarray) -> tuple[float, float]:
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


def restore(p: np.ndarray, xi: np.ndarray, total: float, moment: bool) -> tuple[np.ndarray, bool]:
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


def _check(
    height: np.ndarray,
    p0: np.ndarray,
    arm: np.ndarray | None,
    target: np.ndarray | None,
    control: str,
    total: float | None,
    hardness: float | None,
) -> tuple[np.ndarray, np.ndarray, float | None]:
    """Validate the arguments of :func:`polonsky_keer`; returns h − target, ξ and the cap."""
    if control not in ("moment", "load", "displacement"):
        raise InputError(f"control must be 'moment', 'load' or 'displacement', got {control!r}")
    h = np.asarray(height, dtype=np.float64)
    if h.ndim != 1:
        raise InputError(f"height must be a flat vector of cells, got shape {h.shape}")
    named = {"p0": p0, "arm": arm, "target": target}
    for name, v in named.items():
        if v is not None and np.shape(v) != h.shape:
            raise InputError(f"{name} has shape {np.shape(v)}; height has shape {h.shape}")
    if control in ("moment", "load") and not (total is not None and total > 0):
        raise InputError(f"control={control!r} needs total = Σp > 0 over the cells, got {total}")
    if control == "moment" and arm is None:
        raise InputError("control='moment' needs arm = ξ, the lever arm of every cell")
    if control == "displacement" and target is None:
        raise InputError("control='displacement' needs target = δ + θξ on the cells")
    cap = None
    if hardness is not None and not np.isinf(hardness):
        if not hardness > 0:
            raise InputError(f"hardness must be positive [Pa], got {hardness}")
        if control != "displacement":
            raise InputError(
                "a hardness cap is offered under control='displacement' only (meet a load by a "
                "root search on the approach, as skisnow.micro.elastoplastic_contact does)"
            )
        cap = float(hardness)
    if not np.all(np.isfinite(p0)) or np.any(np.asarray(p0) < 0):
        raise InputError("p0 must be finite and ≥ 0 on every cell")
    hh = h if target is None else h - target
    xi = np.zeros_like(h) if arm is None else np.asarray(arm, dtype=np.float64)
    return hh, xi, cap


def polonsky_keer(
    operator: ComplianceOperator,
    height: np.ndarray,
    *,
    p0: np.ndarray,
    control: Control = "moment",
    total: float | None = None,
    arm: np.ndarray | None = None,
    target: np.ndarray | None = None,
    hardness: float | None = None,
    preconditioner: ComplianceOperator | None = None,
    tol: float = 1e-8,
    max_iter: int = 5000,
) -> PolonskyKeerResult:
    """Polonsky & Keer's (1999) constrained conjugate gradient on flat cell vectors.

    Solves p ≥ 0, g = h + K p − δ − θξ ≥ 0, p·g = 0 (the paper's eq. 3 of Kalliorinne et al.
    (2023) under ``control='moment'``) — see the module docstring for the controls, the cap and
    the operator seam.

    Parameters
    ----------
    operator
        A :class:`ComplianceOperator` on the ``n`` cells (e.g. :class:`CellOperator`).
    height
        Rigid profile h [m] on the cells, shape ``(n,)``.
    p0
        Start [Pa], shape ``(n,)``, ≥ 0; under load or moment control it should already meet
        the constraints (see :func:`restore`).
    control
        'moment', 'load' or 'displacement'.
    total
        Σp over the cells [Pa] (load W divided by the cell area) for 'moment' and 'load'.
    arm
        Lever arm ξ = x − x_m of every cell [m] ('moment').
    target
        The prescribed rigid position δ + θξ on the cells [m] ('displacement').
    hardness
        Pressure cap H [Pa] (0 ≤ p ≤ H; 'displacement' only); ``None`` or ``inf``: no cap.
    preconditioner
        An approximate inverse of K with the operator's call signature, or None.
    tol
        Tolerance on the Polonsky–Keer error Σ|Δp|/Σp between steps.
    max_iter
        Iteration limit.

    Returns
    -------
    PolonskyKeerResult
        Pressure, displacement, multipliers, cost, error history and
        :class:`~skisnow.SolverStatus`.

    Notes
    -----
    Written for speed on large grids: masked dot products instead of boolean indexing, and
    u = K p updated from K t while the contact set does not change (one operator product a
    step, plus the preconditioner's).
    """
    hh, xi, cap = _check(height, p0, arm, target, control, total, hardness)
    k0 = operator.self_influence
    direct = getattr(operator, "add_columns", None)
    n_conv = 0

    def apply(v: np.ndarray, op: ComplianceOperator = operator) -> np.ndarray:
        nonlocal n_conv
        n_conv += 1
        return op(v)

    inv = preconditioner
    moment = control == "moment"
    constrained = control in ("moment", "load")
    p = np.array(p0, dtype=np.float64)
    u = apply(p)
    # "nothing to move" when the projected gap is below 1e-13 of the heights and displacements
    h_scale = float(np.ptp(hh)) + float(np.abs(u).max()) + 1e-300
    t = np.zeros_like(p)
    g = np.empty_like(p)
    m = np.empty_like(p)  # 1.0 on the free contact set, 0.0 elsewhere
    xm_ = np.empty_like(p)  # ξ on the contact set
    trial = np.empty_like(p)
    g_old = 1.0
    conj = False
    history: list[float] = []
    status = SolverStatus.MAX_STEPS_REACHED
    message = status.message
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
        # capped: the free cells, and the cells at H that the gap pushes back (g > 0)
        sel = p > 0.0 if cap is None else (p > 0.0) & ((p < cap) | (g > 0.0))
        cnt = float(np.count_nonzero(sel))
        if cnt == 0:
            if not constrained:
                # no contact (or, capped, every contact cell at H with g ≤ 0): either the exact
                # answer (no gap overlaps without pressure) or a start from the overlap
                if not ((p == 0.0) & (g < 0)).any():
                    status = SolverStatus.SUCCESSFUL
                    message = "no contact (every gap open)" if not p.any() else "fully plastic"
                    history.append(0.0)
                    break
                if cap is None:
                    p = np.where(g < 0, -g / k0, 0.0)
                else:
                    p = np.where((p == 0.0) & (g < 0), np.minimum(-g / k0, cap), p)
                u = apply(p)
                continue
            status = SolverStatus.CONTACT_LOST
            message = status.message
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
                status = SolverStatus.SUCCESSFUL
                message = "exact solution on the contact set"
                history.append(0.0)
                break
            p = p.copy()
            p[overlap] = -g[overlap] / k0
            if cap is not None:
                np.minimum(p, cap, out=p)
            conj = False
            if constrained:
                assert total is not None
                p, ok = restore(p, xi, total, moment)
                if not ok:
                    status = SolverStatus.INFEASIBLE
                    message = status.message
                    break
            u = apply(p)
            history.append(float("inf"))
            continue
        r = apply(t)
        denom = float(_dot(r, t))  # t is zero off the contact set and orthogonal to the plane
        if not np.isfinite(denom):
            status = SolverStatus.NONFINITE
            message = status.message
            break
        if denom <= 0.0:
            status = SolverStatus.BREAKDOWN
            message = status.message
            break
        tau = float(_dot(gm, t)) / denom
        p_old = p
        np.multiply(t, -tau, out=trial)
        trial += p
        p = np.maximum(trial, 0.0)
        overlap = (p == 0.0) & (g < 0.0)
        any_overlap = bool(overlap.any())
        if any_overlap:
            p[overlap] -= tau * g[overlap]
        changed = (trial < 0.0) | overlap if any_overlap else trial < 0.0
        if cap is not None:
            # the box's upper face (cells at H with g > 0 are in the CG set and step back)
            np.minimum(p, cap, out=p)
            changed |= p < trial
        conj = not any_overlap
        any_changed = any_overlap or bool(changed.any())
        scale = 1.0
        if constrained:
            assert total is not None
            ok = True
            if moment:
                if any_changed:
                    p, ok = restore(p, xi, total, moment)
            else:
                s_p = float(p.sum())
                ok = s_p > 0
                scale = total / s_p if ok else 1.0
                p *= scale
            if not ok:
                status = SolverStatus.INFEASIBLE
                message = status.message
                break
        if it % _REFRESH == 0 or (moment and any_changed):
            u = apply(p)
        else:
            # K p_new = c·(K p − τ K t + K Δ), Δ = the clipped and overlap corrections: exact and
            # free when the active set did not change (Δ = 0), one product otherwise
            r *= tau
            u -= r
            if any_changed:
                cells = np.flatnonzero(changed)
                delta = p[cells] / scale - trial[cells]
                if direct is not None and cells.size <= _DIRECT_COLUMNS:
                    direct(u, cells, delta)
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
            status = SolverStatus.SUCCESSFUL
            message = f"converged: Σ|Δp|/Σp = {err:.2e} ≤ {tol:.1e}"
            break
        if not np.isfinite(err):
            status = SolverStatus.NONFINITE
            message = status.message
            break
    # final multipliers from the converged contact set
    u = apply(p)
    g = u + hh
    sel = p > 0
    a = b = 0.0
    if constrained and sel.any():
        if moment:
            a, b = plane_fit(g, xi, sel)
        else:
            a = float(g[sel].mean())
    return PolonskyKeerResult(
        pressure=p,
        displacement=u,
        translation=a,
        rotation=b,
        iterations=it,
        convolutions=n_conv,
        history=np.asarray(history, dtype=np.float64),
        status=status,
        message=message,
    )
