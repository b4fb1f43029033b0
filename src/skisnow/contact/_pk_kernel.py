"""The Polonsky–Keer iteration compiled, on a dense restricted operator (numba).

The same algorithm, line for line, as :func:`skisnow.contact.polonsky_keer` (Polonsky & Keer
1999, with the moment constraint of Kalliorinne et al. 2023 eq. 3 and the circulant
preconditioner of Vollebregt 2014), without the hardness cap, for a compliance given as a dense
matrix ``K`` (the half-space operator restricted to a few hundred candidate contact cells of a 1D
grid: :mod:`skisnow.contact._strip`) and an optional dense preconditioner ``M``. On such small
problems the interpreted loop costs more than the products (~40 NumPy calls of ~1 µs per
iteration against two matrix–vector products of ~15 µs at 500 cells); compiled, an iteration
costs its products. In a module of its own so that numba is imported only when a 1D problem is
solved.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["DISPLACEMENT", "LOAD", "MOMENT", "pk_dense"]

#: control codes of :func:`pk_dense`
MOMENT, LOAD, DISPLACEMENT = 0, 1, 2
#: status codes returned by :func:`pk_dense` (mapped to SolverStatus by the caller)
SUCCESSFUL, MAX_STEPS, CONTACT_LOST, INFEASIBLE, BREAKDOWN, NONFINITE, EXACT, NO_CONTACT = range(8)

#: as in :mod:`skisnow.contact._polonsky_keer`
_DIRECT_COLUMNS = 12
_REFRESH = 25


@numba.njit(cache=True, nogil=True)
def _restore(p: np.ndarray, xi: np.ndarray, total: float, moment: bool) -> bool:
    """:func:`skisnow.contact._polonsky_keer.restore`, in place."""
    n = p.size
    if not moment:
        s = p.sum()
        if s > 0:
            p *= total / s
            return True
        return False
    for _ in range(8):
        m0 = 0.0
        m1 = 0.0
        m2 = 0.0
        for i in range(n):
            m0 += p[i]
            m1 += xi[i] * p[i]
            m2 += xi[i] * xi[i] * p[i]
        det = m0 * m2 - m1 * m1
        if m0 <= 0 or det <= 1e-14 * m0 * m2:
            return False
        alpha = total * m2 / det
        beta = -total * m1 / det
        neg = False
        for i in range(n):
            if p[i] > 0 and alpha + beta * xi[i] <= 0:
                neg = True
                p[i] = 0.0
        if not neg:
            for i in range(n):
                p[i] *= alpha + beta * xi[i]
            return True
    return False


@numba.njit(cache=True, nogil=True)
def _fit(v, m, xm_, cnt, sx, sxx, moment):
    """Least-squares plane a + bξ of v on the contact set (masked sums)."""
    sv = np.dot(v, m)
    if not moment:
        return sv / cnt, 0.0
    sxv = np.dot(v, xm_)
    det = cnt * sxx - sx * sx
    if det <= 1e-12 * max(cnt * sxx, 1e-300):
        return sv / cnt, 0.0
    b = (cnt * sxv - sx * sv) / det
    return (sv - b * sx) / cnt, b


@numba.njit(cache=True, nogil=True)
def pk_dense(k, m_inv, use_inv, hh, xi, p0, control, total, tol, max_iter, k0):
    """Polonsky–Keer on a dense operator ``k`` (n × n, float64) with preconditioner ``m_inv``
    (float32, used when ``use_inv``); ``hh`` = h − target. Returns (p, u, iterations,
    products, history, status)."""
    n = hh.size
    moment = control == MOMENT
    constrained = control != DISPLACEMENT
    p = p0.copy()
    u = np.dot(k, p)
    n_conv = 1
    ptp = hh.max() - hh.min() if n else 0.0
    h_scale = ptp + np.abs(u).max() + 1e-300
    t = np.zeros(n)
    g = np.empty(n)
    m = np.empty(n)
    xm_ = np.zeros(n)
    trial = np.empty(n)
    chg = np.zeros(n, dtype=np.bool_)
    history = np.empty(max_iter)
    n_hist = 0
    g_old = 1.0
    conj = False
    status = MAX_STEPS
    it = 0
    for it in range(1, max_iter + 1):
        cnt = 0
        for i in range(n):
            g[i] = u[i] + hh[i]
            if p[i] > 0.0:
                m[i] = 1.0
                cnt += 1
            else:
                m[i] = 0.0
        if cnt == 0:
            if not constrained:
                any_ov = False
                for i in range(n):
                    if p[i] == 0.0 and g[i] < 0:
                        any_ov = True
                if not any_ov:
                    status = NO_CONTACT
                    history[n_hist] = 0.0
                    n_hist += 1
                    break
                for i in range(n):
                    p[i] = -g[i] / k0 if g[i] < 0 else 0.0
                u = np.dot(k, p)
                n_conv += 1
                continue
            status = CONTACT_LOST
            break
        sx = 0.0
        sxx = 0.0
        if moment:
            for i in range(n):
                xm_[i] = xi[i] * m[i]
                sx += xm_[i]
                sxx += xm_[i] * xi[i]
        if constrained:
            a_, b_ = _fit(g, m, xm_, cnt, sx, sxx, moment)
            for i in range(n):
                g[i] -= a_ + b_ * xi[i]
        gm = g * m
        big_gm = np.dot(gm, gm)
        if use_inv:
            # the preconditioner in single precision: half the memory traffic of the product,
            # and it only steers the iteration (the converged field is K's, to the tolerance)
            z = np.dot(m_inv, gm.astype(np.float32)).astype(np.float64)
            n_conv += 1
            z *= m
            if constrained:
                za, zb = _fit(z, m, xm_, cnt, sx, sxx, moment)
                for i in range(n):
                    z[i] -= za * m[i] + zb * xm_[i]
            big_g = np.dot(gm, z)
        else:
            z = gm
            big_g = big_gm
        if conj and g_old > 0:
            f = big_g / g_old
            for i in range(n):
                t[i] = t[i] * f * m[i] + z[i]
        else:
            t[:] = z
        g_old = big_g
        if constrained:
            ta, tb = _fit(t, m, xm_, cnt, sx, sxx, moment)
            for i in range(n):
                t[i] -= ta * m[i] + tb * xm_[i]
        if big_gm <= (1e-13 * h_scale) ** 2 * cnt:
            any_ov = False
            for i in range(n):
                if p[i] == 0.0 and g[i] < 0.0:
                    any_ov = True
            if not any_ov:
                status = EXACT
                history[n_hist] = 0.0
                n_hist += 1
                break
            p = p.copy()
            for i in range(n):
                if p[i] == 0.0 and g[i] < 0.0:
                    p[i] = -g[i] / k0
            conj = False
            if constrained and not _restore(p, xi, total, moment):
                status = INFEASIBLE
                break
            u = np.dot(k, p)
            n_conv += 1
            history[n_hist] = np.inf
            n_hist += 1
            continue
        r = np.dot(k, t)
        n_conv += 1
        denom = np.dot(r, t)
        if not np.isfinite(denom):
            status = NONFINITE
            break
        if denom <= 0.0:
            status = BREAKDOWN
            break
        tau = np.dot(gm, t) / denom
        p_old = p
        p = np.empty(n)
        any_overlap = False
        any_changed = False
        n_changed = 0
        for i in range(n):
            trial[i] = p_old[i] - tau * t[i]
            p[i] = max(trial[i], 0.0)
            chg[i] = trial[i] < 0.0
            if p[i] == 0.0 and g[i] < 0.0:
                p[i] -= tau * g[i]
                any_overlap = True
                chg[i] = True
            if chg[i]:
                n_changed += 1
        any_changed = n_changed > 0
        conj = not any_overlap
        scale = 1.0
        if constrained:
            ok = True
            if moment:
                if any_changed:
                    ok = _restore(p, xi, total, moment)
            else:
                s_p = p.sum()
                ok = s_p > 0
                scale = total / s_p if ok else 1.0
                p *= scale
            if not ok:
                status = INFEASIBLE
                break
        if it % _REFRESH == 0 or (moment and any_changed):
            u = np.dot(k, p)
            n_conv += 1
        else:
            r *= tau
            u -= r
            if any_changed:
                if n_changed <= _DIRECT_COLUMNS:
                    for j in range(n):
                        if chg[j]:
                            d = p[j] / scale - trial[j]
                            for i in range(n):
                                u[i] += k[j, i] * d  # k is symmetric: row j, contiguous
                else:
                    delta = np.zeros(n)
                    for j in range(n):
                        if chg[j]:
                            delta[j] = p[j] / scale - trial[j]
                    u += np.dot(k, delta)
                    n_conv += 1
            if scale != 1.0:
                u *= scale
        norm = p.sum()
        diff = 0.0
        for i in range(n):
            diff += abs(p_old[i] - p[i])
        err = diff / norm if norm > 0 else 0.0
        history[n_hist] = err
        n_hist += 1
        if err <= tol:
            status = SUCCESSFUL
            break
        if not np.isfinite(err):
            status = NONFINITE
            break
    u = np.dot(k, p)
    n_conv += 1
    return p, u, it, n_conv, history[:n_hist], status
