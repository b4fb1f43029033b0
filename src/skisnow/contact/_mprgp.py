"""The flexible-ski iteration: feasible active-set conjugate gradients with proportioning.

min ½⟨p, K p⟩ + ⟨p, h⟩ over p ≥ 0 with the force and moment balances of Kalliorinne et al.
(2023, eq. 3) kept exactly by projection: Dostál's MPRGP (Dostál & Schöberl 2005, Comput.
Optim. Appl. 30). Used by :func:`~skisnow.contact.solve_flexible` on the whole grid and, through
:mod:`skisnow.contact._flexible_candidates`, on the candidate contact cells. Every step lowers
the energy, so it does not stall where Polonsky & Keer's (1999) rescaling does when the beam
adds large long-wave eigenvalues to the operator.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from skisnow.contact._polonsky_keer import plane_fit

__all__ = ["active_set_cg"]

#: recompute g = K p + h from scratch every this many updates (round-off drift)
_REFRESH = 40
#: proportioning: release penetrating cells when their reduced gradient exceeds this multiple of
#: the projected gradient on the free set (Dostál & Schöberl 2005, Γ = 1)
_GAMMA = 1.0


def _project(v: np.ndarray, xi: np.ndarray, sel: np.ndarray) -> np.ndarray:
    """Orthogonal projection of v onto {d: d = 0 off sel, Σd = 0, Σξd = 0}."""
    a, b = plane_fit(v, xi, sel)
    return np.where(sel, v - a - b * xi, 0.0)


def _clip_to_constraints(
    p: np.ndarray, xi: np.ndarray, total: float, moment: float
) -> np.ndarray | None:
    """max(p, 0) put back on Σp = total, Σξp = moment by an additive plane on its support
    (repeated while that makes cells negative); None when the support cannot carry them."""
    q = np.maximum(p, 0.0)
    for _ in range(10):
        sel = q > 0.0
        n = int(sel.sum())
        if n < 2:
            return None
        xs = xi[sel]
        sx, sxx = float(xs.sum()), float(xs @ xs)
        det = n * sxx - sx * sx
        if det <= 1e-12 * n * sxx:
            return None
        ea, eb = float(q.sum()) - total, float(xi @ q) - moment
        b = (n * eb - sx * ea) / det
        a = (ea - b * sx) / n
        q = np.where(sel, q - a - b * xi, 0.0)
        if not (q < 0.0).any():
            return q
        q = np.maximum(q, 0.0)
    return None


def active_set_cg(
    apply: Callable[[np.ndarray], np.ndarray],
    precondition: Callable[[np.ndarray], np.ndarray],
    h: np.ndarray,
    xi: np.ndarray,
    p0: np.ndarray,
    *,
    tol: float,
    max_iter: int,
) -> tuple[np.ndarray, np.ndarray, float, float, int, list[float], bool, str, int]:
    """min ½⟨p, K p⟩ + ⟨p, h⟩ over p ≥ 0 with Σp and Σξp fixed (those of the feasible p0).

    Preconditioned conjugate gradients on the face of the free cells F = {p > 0}, projected onto
    the two balance constraints (so every iterate satisfies them exactly), with the feasible
    step length of the active-set method: a step that would make a pressure negative stops at
    the bound, drops that cell and restarts CG; cells off F whose gap is negative (reduced
    gradient g − δ − θξ < 0) are released by a projected steepest-descent step once their
    violation outweighs the free gradient (proportioning). This is Dostál's MPRGP (Dostál &
    Schöberl 2005, Comput. Optim. Appl. 30) with the equality constraints kept by projection:
    every step decreases the energy, so the iteration cannot cycle — unlike Polonsky & Keer's
    rescaling of p after a clipped step, which stalls when the operator has the large
    long-wave eigenvalues of a soft beam. Returns p, g = K p + h, δ, θ, iterations, history
    of the residual, converged, message and the number of operator applications.
    """
    p = np.array(p0, dtype=np.float64)
    kp = apply(p)
    n_apply = 1
    g = kp + h
    energy = 0.5 * float(p @ kp) + float(p @ h)
    total_force, total_moment = float(p.sum()), float(xi @ p)
    scale = float(np.ptp(h)) + float(np.abs(kp).max()) + 1e-300
    history: list[float] = []
    d = np.zeros_like(p)
    rz_old = 0.0
    conj = False
    converged, message, iterations = False, "maximum number of iterations reached", 0
    since_refresh = 0
    a = b = 0.0
    for iterations in range(1, max_iter + 1):  # noqa: B007 (reported after the loop)
        free = p > 0.0
        a, b = plane_fit(g, xi, free)
        reduced = g - a - b * xi  # the gap; on F its projection is the free gradient
        r = np.where(free, reduced, 0.0)
        chopped = np.where(~free, np.minimum(reduced, 0.0), 0.0)
        r_norm = float(np.abs(r).max(initial=0.0))
        c_norm = float(np.abs(chopped).max(initial=0.0))
        residual = max(r_norm, c_norm) / scale
        history.append(residual)
        if residual <= tol:
            converged, message = True, f"converged: max |gap residual| = {residual:.2e} ≤ {tol:.1e}"
            break
        if c_norm > _GAMMA * r_norm:
            # proportioning: release the penetrating cells along the projected steepest descent
            sel = free | (chopped < 0.0)
            for _ in range(8):
                step = -_project(precondition(_project(g, xi, sel)), xi, sel)
                wrong = ~free & sel & (step <= 0.0)
                if not wrong.any():
                    break
                sel &= ~wrong
            conj = False
        else:
            z = _project(precondition(r), xi, free)
            rz = float(r @ z)
            d = -z + (rz / rz_old) * d if conj and rz_old > 0.0 else -z
            rz_old = rz
            conj = True
            step = d
        kd = apply(step)
        n_apply += 1
        curv = float(step @ kd)
        slope = float(g @ step)
        if not (curv > 0.0) or slope >= 0.0:
            if conj:  # lost conjugacy (round-off): restart from the projected gradient
                conj = False
                continue
            message = "no descent direction (ill-conditioned operator)"
            break
        alpha = -slope / curv
        neg = step < 0.0
        if neg.any():
            limits = -p[neg] / step[neg]
            alpha_f = float(limits.min())
            if alpha_f < alpha:
                conj = False
                # the full step, clipped at p = 0 and put back on the balance constraints,
                # is taken when it lowers the energy more than stopping at the first bound
                # (a projected search: drops many cells at once instead of one per step)
                trial = _clip_to_constraints(p + alpha * step, xi, total_force, total_moment)
                if trial is not None:
                    kt = apply(trial)
                    n_apply += 1
                    e_trial = 0.5 * float(trial @ kt) + float(trial @ h)
                    e_bound = energy + alpha_f * slope + 0.5 * alpha_f**2 * curv
                    if e_trial < e_bound:
                        p, kp = trial, kt
                        g = kp + h
                        energy = e_trial
                        since_refresh = 0
                        continue
                alpha = alpha_f
        energy += alpha * slope + 0.5 * alpha**2 * curv
        p += alpha * step
        blocked = neg & (p <= 1e-14 * float(p.max()))
        p[blocked] = 0.0
        np.maximum(p, 0.0, out=p)
        since_refresh += 1
        if since_refresh >= _REFRESH:
            kp = apply(p)
            n_apply += 1
            g = kp + h
            energy = 0.5 * float(p @ kp) + float(p @ h)
            since_refresh = 0
        else:
            g += alpha * kd
    free = p > 0.0
    kp = apply(p)
    n_apply += 1
    g = kp + h
    a, b = plane_fit(g, xi, free)
    return p, g, a, b, iterations, history, converged, message, n_apply
