"""Newton's method of the smoothed contact (:mod:`skisnow.identify._smooth`) compiled (numba).

One load case of the bench on the smoothed stone: the minimum of the strictly convex energy

    Π(u, a, b) = ½ uᵀKu - fᵀu + F a + M b + Σ_s w_s k ε² F₂(-h_s/ε),   F₂' = softplus,

h_s = z0(x_s) + a + b x_s + N_s u on the sub-grid (the penalty regularisation of the
complementarity, Wriggers 2006, §6.3; the softplus the smoothed positive part of Chen &
Mangasarian 1996), by Newton's method with an Armijo backtracking on Π: the steps, tests and
tolerances of :meth:`~skisnow.identify._smooth.SmoothedBench._newton_steps`, which this
replaces, in one compiled loop instead of ~70 NumPy calls per iteration (the smoothed contact
was about half of an identification's time; docs/validation/identification-uncertainty.md,
"Fifth pass: time"). The banded Cholesky and solves are those of
:mod:`skisnow.identify._banded_kernel`; ``expit`` and ``spence`` are SciPy's own (through
``scipy.special.cython_special``). The sums run in another order than NumPy's pairwise ones, so
the iterates agree with the NumPy route to round-off, not bitwise
(``tests/identify/test_speed_kernels.py``).
"""

from __future__ import annotations

import ctypes
import functools
import math

import numba
import numpy as np
from numpy.typing import NDArray

from skisnow.identify._banded_kernel import _factor, _smoothed_hessian, _solve

__all__ = ["NEWTON_CONVERGED", "NEWTON_FAILED", "NEWTON_NOT_PD", "newton_smoothed"]

#: status codes of :func:`newton_smoothed`
NEWTON_CONVERGED, NEWTON_FAILED, NEWTON_NOT_PD = range(3)

#: Below this t = -h/ε, eᵗ underflows to 0: the softplus, its derivative and F₂ are 0 there
#: exactly (sub-grid points more than 746 ε above the stone: most of the ski), so they are
#: skipped rather than evaluated.
_UNDERFLOW = -746.0


@functools.cache
def _special() -> tuple[object, object]:
    """(expit, spence) of SciPy for doubles, as ctypes functions."""
    from numba.extending import get_cython_function_address
    from scipy.special import expit, spence

    sig = ctypes.CFUNCTYPE(ctypes.c_double, ctypes.c_double)
    names = ("__pyx_fuse_0expit", "__pyx_fuse_1spence")  # the double variants
    funcs = tuple(
        sig(get_cython_function_address("scipy.special.cython_special", name)) for name in names
    )
    for fn, ref, x in zip(funcs, (expit, spence), (-0.7, 1.3), strict=True):
        if fn(x) != ref(x):  # pragma: no cover - another SciPy's order of fused variants
            raise RuntimeError(f"scipy.special.cython_special: {ref.__name__} not found")
    return funcs


@numba.njit(cache=True, nogil=True)
def _softplus(t):  # pragma: no cover - compiled
    """log(1 + eᵗ) as NumPy's ``logaddexp(0, t)``."""
    if t == 0.0:
        return math.log(2.0)
    if t > 0.0:
        return t + math.log1p(math.exp(-t))
    return math.log1p(math.exp(t))


@numba.njit(cache=True, nogil=True)
def _f2(spence, t):  # pragma: no cover - compiled
    """∫_{-∞}^t softplus = -Li₂(-eᵗ) (:func:`skisnow.identify._smooth._f2`)."""
    if t <= -40.0:
        return -0.0
    if t <= 0.0:
        return -spence(1.0 + math.exp(t))
    return 0.5 * t * t + math.pi**2 / 6.0 + spence(1.0 + math.exp(-t))


@numba.njit(cache=True, nogil=True)
def _banded_matvec(ab, x):  # pragma: no cover - compiled
    n = x.size
    y = ab[3] * x
    for d in range(1, 4):
        for j in range(d, n):
            y[j - d] += ab[3 - d, j] * x[j]
            y[j] += ab[3 - d, j] * x[j - d]
    return y


@numba.njit(cache=True, nogil=True)
def _deflection(shape, v, out):  # pragma: no cover - compiled
    """out[e, s] = Σ_k N_esk v[2e + k]."""
    n_el, m = out.shape
    for e in range(n_el):
        for s in range(m):
            acc = 0.0
            for k in range(4):
                acc += shape[e, s, k] * v[2 * e + k]
            out[e, s] = acc


@numba.njit(cache=True, nogil=True)
def _solve2(a00, a01, a10, a11, b0, b1):  # pragma: no cover - compiled
    """The 2 × 2 system by LU with partial pivoting (LAPACK's ``gesv``): ``(x0, x1, ok)``,
    ``ok`` False at an exactly zero pivot."""
    if abs(a10) > abs(a00):
        a00, a01, a10, a11, b0, b1 = a10, a11, a00, a01, b1, b0
    if a00 == 0.0:
        return 0.0, 0.0, False
    lf = a10 / a00
    u11 = a11 - lf * a01
    if u11 == 0.0:
        return 0.0, 0.0, False
    x1 = (b1 - lf * b0) / u11
    return (b0 - a01 * x1) / a00, x1, True


@numba.njit(cache=True, nogil=True)
def _newton(
    expit,
    spence,
    ab,
    shape,
    xs,
    wts,
    z0s,
    f,
    f_total,
    m_total,
    kc,
    eps,
    u0,
    a0,
    b0,
    clamp,
    floor_h,
    max_iterations,
):  # pragma: no cover - compiled
    n_el, m = xs.shape
    ndof = u0.size
    u = u0.copy()
    a, b = a0, b0
    h = np.empty((n_el, m))
    t = np.empty((n_el, m))
    r = np.empty((n_el, m))
    d = np.empty((n_el, m))
    dh = np.empty((n_el, m))
    w = np.empty((n_el, m))
    rhs = np.empty((ndof, 3))
    for _ in range(max_iterations):
        _deflection(shape, u, w)
        g_a, g_b = f_total, m_total
        sd = sdx = sdxx = 0.0
        for e in range(n_el):
            for s in range(m):
                hh = z0s[e, s] + a + b * xs[e, s] + w[e, s]
                tt = -hh / eps
                h[e, s] = hh
                t[e, s] = tt
                r[e, s] = 0.0
                d[e, s] = 0.0
                if tt < _UNDERFLOW:  # eᵗ is 0: no reaction, no stiffness (most points)
                    continue
                rr = wts[e, s] * kc * eps * _softplus(tt)
                dd = wts[e, s] * kc * expit(tt)
                r[e, s] = rr
                d[e, s] = dd
                g_a -= rr
                g_b -= rr * xs[e, s]
                sd += dd
                sdx += dd * xs[e, s]
                sdxx += dd * xs[e, s] * xs[e, s]
        # g_u = K u - f - Σ r N; the bordered system's C = Σ d N [1, x]
        g_u = _banded_matvec(ab, u)
        for i in range(ndof):
            g_u[i] -= f[i]
            rhs[i, 1] = 0.0
            rhs[i, 2] = 0.0
        for e in range(n_el):
            for s in range(m):
                if d[e, s] == 0.0 and r[e, s] == 0.0:
                    continue
                for k in range(4):
                    nk = shape[e, s, k]
                    g_u[2 * e + k] -= r[e, s] * nk
                    rhs[2 * e + k, 1] += d[e, s] * nk
                    rhs[2 * e + k, 2] += d[e, s] * xs[e, s] * nk
        for dof in (2 * clamp, 2 * clamp + 1):
            g_u[dof] = 0.0
            rhs[dof, 1] = 0.0
            rhs[dof, 2] = 0.0
        c0 = rhs[:, 1].copy()
        c1 = rhs[:, 2].copy()
        for i in range(ndof):
            rhs[i, 0] = -g_u[i]
        hess = _smoothed_hessian(ab, d, shape, clamp)
        if _factor(hess) != 0:
            return u, a, b, NEWTON_NOT_PD
        _solve(hess, rhs)
        # Schur complement of the two rigid modes
        s00, s01, s10, s11, q0, q1 = sd, sdx, sdx, sdxx, -g_a, -g_b
        for i in range(ndof):
            s00 -= c0[i] * rhs[i, 1]
            s01 -= c0[i] * rhs[i, 2]
            s10 -= c1[i] * rhs[i, 1]
            s11 -= c1[i] * rhs[i, 2]
            q0 -= c0[i] * rhs[i, 0]
            q1 -= c1[i] * rhs[i, 0]
        sa, sb, ok = _solve2(s00, s01, s10, s11, q0, q1)
        if not ok:  # singular (as LAPACK's gesv): least squares
            sol = np.linalg.lstsq(np.array([[s00, s01], [s10, s11]]), np.array([q0, q1]))[0]
            sa, sb = sol[0], sol[1]
        su = rhs[:, 0] - rhs[:, 1] * sa - rhs[:, 2] * sb
        _deflection(shape, su, dh)
        slope = np.dot(g_u, su) + g_a * sa + g_b * sb
        step_h = 0.0
        finite = math.isfinite(slope)
        lin = slope
        for e in range(n_el):
            for s in range(m):
                v = dh[e, s] + sa + sb * xs[e, s]
                dh[e, s] = v
                lin += r[e, s] * v
                if not math.isfinite(v):
                    finite = False
                elif abs(v) > step_h:
                    step_h = abs(v)
        if not finite:
            return u, a, b, NEWTON_FAILED
        if step_h < max(1e-6 * eps, 1e-8 * np.max(np.abs(u)), floor_h):
            return u + su, a + sa, b + sb, NEWTON_CONVERGED
        if slope >= 0.0:
            return u, a, b, NEWTON_FAILED
        quad = np.dot(su, _banded_matvec(ab, su))
        for e in range(n_el):
            for s in range(m):
                w[e, s] = _f2(spence, t[e, s])  # F₂ at the current point
        alpha = 1.0
        while True:
            acc = 0.0
            for e in range(n_el):
                for s in range(m):
                    t1 = -(h[e, s] + alpha * dh[e, s]) / eps
                    acc += wts[e, s] * (_f2(spence, t1) - w[e, s])
            d_pi = alpha * lin + 0.5 * alpha**2 * quad + kc * eps**2 * acc
            if d_pi <= 1e-4 * alpha * slope:
                break
            alpha *= 0.5
            if alpha < 1e-10:
                return u, a, b, NEWTON_FAILED
        u = u + alpha * su
        a = a + alpha * sa
        b = b + alpha * sb
    return u, a, b, NEWTON_FAILED


def newton_smoothed(
    *,
    ab: NDArray[np.float64],
    shape: NDArray[np.float64],
    xs: NDArray[np.float64],
    weights: NDArray[np.float64],
    z0s: NDArray[np.float64],
    f: NDArray[np.float64],
    f_total: float,
    m_total: float,
    kc: float,
    eps: float,
    start: tuple[NDArray[np.float64], float, float],
    clamp: int,
    floor_h: float,
    max_iterations: int = 100,
) -> tuple[NDArray[np.float64], float, float] | None:
    """The smoothed contact of one load case from ``start`` = (u, a, b): ``(u, a, b)``, or None
    if Newton fails (no descent above the roundoff floor, a step of no finite size, no Armijo
    step, or ``max_iterations``). Raises :class:`numpy.linalg.LinAlgError` if the Hessian is
    not positive definite (as the NumPy route's Cholesky did). ``ab`` the clamped stiffness
    (upper banded), ``shape`` / ``xs`` / ``weights`` / ``z0s`` the sub-grid's Hermite shape
    functions, positions, quadrature weights and free camber, ``f`` the boot load (clamped),
    ``kc`` the foundation's stiffness, ``eps`` its width, ``floor_h`` the step [m] below which
    it has converged besides 1e-6 ε and 1e-8 max|u| (module docstring)."""
    expit, spence = _special()
    u0, a0, b0 = start
    u, a, b, status = _newton(
        expit, spence, np.ascontiguousarray(ab), shape, xs, weights, z0s,
        np.ascontiguousarray(f, dtype=np.float64), float(f_total), float(m_total), float(kc),
        float(eps), np.ascontiguousarray(u0, dtype=np.float64), float(a0), float(b0),
        int(clamp), float(floor_h), int(max_iterations),
    )  # fmt: skip
    if status == NEWTON_NOT_PD:
        raise np.linalg.LinAlgError("the smoothed contact's Hessian is not positive definite")
    return (u, float(a), float(b)) if status == NEWTON_CONVERGED else None
