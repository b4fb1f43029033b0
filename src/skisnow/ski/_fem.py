"""Hermite-cubic Euler–Bernoulli beam elements: stiffness, shape functions, loads, references.

The finite-element core of the virtual ski (:mod:`skisnow.ski._beam`): element stiffness
∫ EI N''ᵀ N'' dx with 4-point Gauss–Legendre (EI(x) tabulated or constant), the global matrix,
Hermite interpolation of nodal deflections and slopes, the consistent load vector of a boot
plate, and the clamped banded assembly whose flexibility matrix the contact LCP uses. Hermite
cubics reproduce the Euler–Bernoulli solution at the nodes for nodal loads and piecewise-constant
EI. The closed-form deflections of two textbook cases (simply supported beam under a centre
load, F L³/(48 EI); cantilever under a tip load, F L³/(3 EI)) are here too, as references for
the tests. SI units.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import solveh_banded

from skisnow.ski._skis import Ski

__all__ = [
    "GAUSS4_W",
    "GAUSS4_X",
    "ClampedBeam",
    "assemble_clamped",
    "banded_upper",
    "beam_stiffness_matrix",
    "boot_load_vector",
    "cantilever_tip_deflection",
    "clamped_dofs",
    "hermite_interpolate",
    "shape_functions",
    "three_point_bending_deflection",
]

#: Four-point Gauss–Legendre rule on [0, 1] (points, weights) of the element integrals.
GAUSS4_X, GAUSS4_W = np.polynomial.legendre.leggauss(4)
GAUSS4_X = 0.5 * (GAUSS4_X + 1.0)  # on [0, 1]
GAUSS4_W = 0.5 * GAUSS4_W


def three_point_bending_deflection(force: float, span: float, stiffness: float) -> float:
    """Mid-span deflection F·L³/(48·EI) [m] of a simply supported uniform beam, centre load."""
    return force * span**3 / (48.0 * stiffness)


def cantilever_tip_deflection(force: float, length: float, stiffness: float) -> float:
    """Tip deflection F·L³/(3·EI) [m] of a uniform cantilever under a tip force."""
    return force * length**3 / (3.0 * stiffness)


def shape_functions(
    xi: NDArray[np.float64], le: NDArray[np.float64] | float
) -> NDArray[np.float64]:
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


def element_stiffness(x_nodes: NDArray[np.float64], ei_at: object) -> NDArray[np.float64]:
    """Element stiffness matrices (n_el, 4, 4) ∫ EI N''ᵀN'' dx with 4-point Gauss-Legendre."""
    le = np.diff(x_nodes)[:, None]  # (n_el, 1)
    xi = GAUSS4_X[None, :]
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
    w = (GAUSS4_W[None, :] * le * ei)[..., None, None]
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
    ke = element_stiffness(x, ei_at)
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
    nsh = shape_functions(xi, le)
    return (
        nsh[..., 0] * wn[e]
        + nsh[..., 1] * tn[e]
        + nsh[..., 2] * wn[e + 1]
        + nsh[..., 3] * tn[e + 1]
    )


@dataclass(frozen=True)
class ClampedBeam:
    """Assembled clamped beam: nodes, banded clamped stiffness, flexibility of all DOFs."""

    x: NDArray[np.float64]
    z0: NDArray[np.float64]
    clamp: int
    ab: NDArray[np.float64]  # upper banded clamped stiffness (4, 2n)
    flex_full: NDArray[np.float64]  # (2n, n): DOF response to unit upward force at node j
    flex: NDArray[np.float64]  # (n, n): deflection rows of flex_full


def banded_upper(ke: NDArray[np.float64], n: int) -> NDArray[np.float64]:
    ndof = 2 * n
    ab = np.zeros((4, ndof))
    for a in range(4):
        for b in range(a, 4):
            # global (i, j) = (2e + a, 2e + b), i <= j  -> ab[3 + i - j, j]
            np.add.at(ab[3 + a - b], 2 * np.arange(n - 1) + b, ke[:, a, b])
    return ab


@functools.lru_cache(maxsize=16)
def assemble_clamped(ski: Ski, n_elements: int) -> ClampedBeam:
    x = np.linspace(ski.x_tail, ski.x_tip, n_elements + 1)
    n = x.size
    ke = element_stiffness(x, ski.stiffness)
    ab = banded_upper(ke, n)
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
    return ClampedBeam(x=x, z0=z0, clamp=clamp, ab=ab, flex_full=flex_full, flex=flex)


def boot_load_vector(
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
        nsh = shape_functions(np.array((load_position - x[e]) / le), le)
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
        nsh = shape_functions((xq - x[e]) / le, le)  # (3, 4)
        f[2 * e : 2 * e + 4] -= q * 0.5 * (b - a) * (gw @ nsh)
    return f


def clamped_dofs(f: NDArray[np.float64], clamp: int) -> NDArray[np.float64]:
    out = f.copy()
    out[2 * clamp : 2 * clamp + 2] = 0.0
    return out
