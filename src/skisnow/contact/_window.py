"""The surface (2-D) contact iterated on the window where contact can be.

The half-space operator is a convolution: restricted to a rectangle of the grid (a window) it is
the convolution of the same kernel on the window's grid, applied by an FFT of about twice the
window instead of twice the grid. A Hertz contact of radius L/4 on a square grid of side L
(the benchmark's) fits a window of half the side: the FFTs cost about a quarter. The window is
the bounding box of the candidate cells — the start's support (the multilevel start's coarse
solution, :mod:`skisnow.contact._starts`) and the cells whose estimated gap is below a margin of
the largest displacement — plus a rim of cells. As on 1D grids
(:mod:`skisnow.contact._candidates`), the Polonsky–Keer iteration on the window has the iterates
of the whole-grid one as long as no cell outside would enter the contact; the gap is then checked
on the whole grid (one FFT) and any missed cell added to a larger window, so the restriction
changes the cost, not the answer.
"""

from __future__ import annotations

import functools

import numpy as np

from skisnow.contact._kernels import Convolution
from skisnow.contact._operators import CellOperator, circulant_preconditioner
from skisnow.contact._polonsky_keer import PolonskyKeerResult, plane_fit, polonsky_keer, restore
from skisnow.contact._problem import ContactProblem

__all__ = ["solve_on_window"]

#: candidate cells: estimated gap below this fraction of the largest snow displacement
_MARGIN = 0.05
#: cells added around the candidates' bounding box on every side
_RIM = 4
#: the window is used when its area is at most this fraction of the grid's
_MAX_FRACTION = 0.5


def rigid_body_gap(
    h: np.ndarray,
    arm: np.ndarray,
    p: np.ndarray,
    u: np.ndarray,
    a: float | None = None,
    b: float = 0.0,
    *,
    moment: bool,
    constrained: bool,
) -> np.ndarray:
    """The gap h + u − (a + b·arm) of a rigid body that translates (a) and, under moment
    control, rotates (b); without a and b given, the least-squares plane of h + u over the cells
    in contact (p > 0), as the Polonsky–Keer iteration closes it (Kalliorinne et al. 2023,
    eq. 3). Shared by the candidate-set solvers of the strip and of the surface."""
    g = h + u
    if a is None:
        a, b = 0.0, 0.0
        sel = p > 0
        if constrained and sel.any():
            a, b = plane_fit(g, arm, sel) if moment else (float(g[sel].mean()), 0.0)
    return g - a - b * arm


@functools.lru_cache(maxsize=8)
def _window_operator(conv: Convolution, shape: tuple[int, int]) -> Convolution:
    """The operator of ``conv`` on a window of ``shape`` cells: the same kernel, centred."""
    nx, ny = conv.shape
    bx, by = shape
    assert conv.kernel is not None
    sub = conv.kernel[nx - bx : nx - 1 + bx, ny - by : ny - 1 + by]
    even = not np.iscomplexobj(conv.spectrum)  # a centred window of an even kernel is even
    return Convolution.from_kernel(sub, shape, workers=conv.workers, even=even)


def solve_on_window(
    problem: ContactProblem,
    p0: np.ndarray,
    *,
    tol: float,
    max_iter: int,
    precondition: bool,
) -> PolonskyKeerResult | None:
    """Polonsky–Keer on the window of the candidate cells of a surface problem (module doc).

    Returns the result on the footprint cells (as the whole-grid iteration's), or None when the
    window would be most of the grid (the caller iterates on the whole grid).
    """
    pr = problem
    conv = pr.conv
    if conv.kernel is None or conv.ndim != 2:
        return None
    nx, ny = conv.shape
    moment, constrained = pr.moment, pr.control in ("moment", "load")
    target = pr.target
    hh = pr.h if target is None else pr.h - target
    p = np.asarray(p0, dtype=np.float64)
    u = pr.on_cells(conv(pr.to_grid(p)))
    n_conv = 1
    iterations, history = 0, []
    fp = pr.footprint

    gap = functools.partial(rigid_body_gap, hh, pr.arm, moment=moment, constrained=constrained)

    g = gap(p, u)
    scale = float(np.abs(u).max()) + 1e-300
    candidates = (p > 0) | (g < _MARGIN * scale)
    res = None
    for _ in range(6):
        mask = pr.to_grid(candidates.astype(np.float64)) > 0
        rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
        if rows.size == 0:
            return None
        i0, i1 = max(int(rows[0]) - _RIM, 0), min(int(rows[-1]) + _RIM + 1, nx)
        j0, j1 = max(int(cols[0]) - _RIM, 0), min(int(cols[-1]) + _RIM + 1, ny)
        if (i1 - i0) * (j1 - j0) > _MAX_FRACTION * nx * ny:
            if res is None:
                return None
            break
        window = _window_operator(conv, (i1 - i0, j1 - j0))
        inside = fp[i0:i1, j0:j1]
        local = np.flatnonzero(inside.ravel())
        # the footprint cells of the window, as indices into the problem's flat cell vector
        index = np.full(fp.shape, -1, dtype=np.intp)
        index[fp] = np.arange(int(fp.sum()))
        cells = index[i0:i1, j0:j1][inside]
        inverse = circulant_preconditioner(window) if precondition else None
        res = polonsky_keer(
            CellOperator(window, local), pr.h[cells], p0=p[cells], control=pr.control,
            total=pr.total, arm=pr.arm[cells], target=None if target is None else target[cells],
            preconditioner=CellOperator(inverse, local) if inverse is not None else None,
            tol=tol, max_iter=max_iter - iterations,
        )  # fmt: skip
        iterations += res.iterations
        n_conv += res.convolutions + 1
        history += res.history.tolist()
        p = np.zeros_like(p)
        p[cells] = res.pressure
        u = pr.on_cells(conv(pr.to_grid(p)))
        if not res.converged:
            break
        g = gap(p, u, res.translation, res.rotation)
        scale = float(np.abs(u).max()) + 1e-300
        missed = (p == 0.0) & (g < -tol * scale)
        if not missed.any():
            break
        candidates |= missed | (g < _MARGIN * scale)
        p[missed] = -g[missed] / conv.self_influence
        if constrained:
            assert pr.total is not None
            p, ok = restore(p, pr.arm, pr.total, moment)
            if not ok:
                return None
        res = None  # not done: a missed cell was added
    if res is None:
        return None
    return PolonskyKeerResult(
        pressure=p, displacement=u, translation=res.translation, rotation=res.rotation,
        iterations=iterations, convolutions=n_conv, history=np.asarray(history),
        status=res.status, message=res.message,
    )  # fmt: skip
