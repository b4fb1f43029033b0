"""Starting pressures for the Polonsky–Keer iteration of :func:`~skisnow.contact.solve_contact`.

Three starts, tried in this order by :func:`starting_pressure`:

1. a warm start given by the caller (e.g. the previous solution along a load path), clipped to
   p ≥ 0 and rescaled to the constraints;
2. the multilevel start (:func:`coarse_start`): the same problem solved on a grid twice as coarse,
   recursively (by the solver the caller passes in, :func:`~skisnow.contact.solve_contact`),
   and prolonged (the coarse-to-fine idea of Polonsky & Keer 1999's multi-level
   scheme, here only as a start);
3. the rigid start (:func:`rigid_start`): the rigid contact plane of the profile plus a crude
   penetration estimate, rescaled to the constraints.

Under displacement control the default start is the rigid overlap divided by K(0).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from skisnow._errors import InputError, UnsupportedLoadError
from skisnow.contact._polonsky_keer import restore
from skisnow.contact._problem import ContactProblem

__all__ = ["coarse_start", "rigid_start", "starting_pressure"]

#: below these sizes the multilevel start is not worth it (cells along x; cells in total)
_COARSE_MIN_1D = 512
_COARSE_MIN_2D = 128 * 128
#: tolerance of the coarse solves (they only provide the start)
_COARSE_TOL = 1e-6


def starting_pressure(
    problem: ContactProblem,
    *,
    initial_pressure: ArrayLike | None,
    multilevel: bool,
    tol: float,
    solve: Callable[..., Any],
) -> np.ndarray:
    """The start on the footprint cells (flat): the warm start if usable, else the multilevel
    start if asked for and usable, else the rigid start (see the module docstring). ``solve``
    solves the coarse problem of the multilevel start (:func:`~skisnow.contact.solve_contact`,
    passed in by it: the recursion)."""
    pr = problem
    total, moment = pr.total, pr.moment
    p0 = None
    if initial_pressure is not None:
        ip = np.asarray(initial_pressure, dtype=np.float64)
        if ip.shape != pr.height.shape:
            raise InputError(
                f"initial_pressure has shape {ip.shape}; the grid has shape {pr.height.shape}"
            )
        if not np.all(np.isfinite(ip)):
            raise InputError("initial_pressure has non-finite values")
        ipf = np.maximum(pr.on_cells(ip), 0.0)
        if pr.control == "displacement":
            p0 = ipf
        elif ipf.sum() > 0:
            p0, ok = restore(ipf, pr.arm, total, moment)  # type: ignore[arg-type]
            if not ok:
                p0 = None
    if p0 is None and pr.control != "displacement" and multilevel:
        coarse = coarse_start(pr, tol=tol, solve=solve)
        if coarse is not None:
            cf = pr.on_cells(coarse)
            if cf.sum() > 0:
                p0, ok = restore(np.maximum(cf, 0.0), pr.arm, total, moment)  # type: ignore[arg-type]
                if not ok:
                    p0 = None
    if p0 is None:
        k0 = pr.conv.self_influence
        if pr.control == "displacement":
            p0 = np.maximum(pr.target - pr.h, 0.0) / k0  # type: ignore[operator]
        else:
            p0 = rigid_start(pr.h, pr.arm, total, moment, k0, pr.dims)  # type: ignore[arg-type]
    return p0


def rigid_start(
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
    p, _ = restore(p, xi, total, moment)
    return p


def coarse_start(
    problem: ContactProblem, *, tol: float, solve: Callable[..., Any]
) -> np.ndarray | None:
    """Solve the same problem on a grid twice as coarse (recursively) and prolong the pressure.

    Heights are averaged over pairs (2 × 2 blocks) of cells; the coarse pressure is repeated on
    the fine cells (a grid field). ``solve`` is :func:`~skisnow.contact.solve_contact` (passed
    in by it: the recursion, one level coarser). Returns None when the grid is too small or of
    odd size, or when the coarse problem cannot be solved.
    """
    pr = problem
    x, h, y, width = pr.x, pr.height, pr.y, pr.width
    nx = x.size
    if pr.model == "surface":
        assert y is not None
        ny = y.size
        if nx % 2 or ny % 2 or nx * ny < _COARSE_MIN_2D or min(nx, ny) < 8:
            return None
        xc = 0.5 * (x[0::2] + x[1::2])
        hc = 0.25 * (h[0::2, 0::2] + h[1::2, 0::2] + h[0::2, 1::2] + h[1::2, 1::2])
        kwargs: dict = {}
        if pr.two_d_height:
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
        sol = solve(
            xc,
            hc,
            load=pr.load,
            load_position=pr.load_position,
            modulus=pr.modulus,
            model=pr.model,
            control=pr.control,
            tol=max(tol, _COARSE_TOL),
            edge_contact="allow",
            reference_length=pr.reference_length,
            workers=pr.workers,
            **kwargs,
        )
    except (InputError, UnsupportedLoadError):
        return None
    pc = sol.pressure
    if pc.ndim == 2:
        return np.repeat(np.repeat(pc, 2, axis=0), 2, axis=1)
    return np.repeat(pc, 2)
