"""The 1D (strip, line) contact solve at the cost of its contact: nested grids, candidate cells.

A ski of 4096 stations touches the snow over a few hundred; the rigid start
(:func:`~skisnow.contact._starts.rigid_start`) spreads over thousands, and the Polonsky–Keer
iteration from it pays full-grid FFTs until the support has shrunk. Here the same problem is
first solved on grids coarsened by 4 (cell averages of the heights and lever arms, the same
load, modulus and width; down to ≤ 256 cells, solved whole by the compiled dense loop), each
grid's pressure repeated onto the next finer grid as its start (the coarse-to-fine idea of
Polonsky & Keer 1999's multi-level scheme, used only as a start). On each finer grid the start
is then already the contact to a cell or two, so the candidate set
(:func:`~skisnow.contact._candidates.solve_on_candidates`) is the contact plus a margin, small
enough for the dense restricted operator, and the iteration from it takes about half the steps.
The answer is that of the Polonsky–Keer iteration on the whole grid (the start changes the path,
not the solution: the gap is checked on the whole grid at the end).
"""

from __future__ import annotations

import numpy as np

from skisnow.contact._candidates import solve_on_candidates
from skisnow.contact._operators import CellOperator, circulant_preconditioner
from skisnow.contact._polonsky_keer import PolonskyKeerResult, polonsky_keer, restore
from skisnow.contact._problem import ContactProblem, _operator
from skisnow.contact._starts import rigid_start

__all__ = ["solve_strip"]

#: the grids are coarsened by this factor ...
_COARSEN = 4
#: ... while the coarser grid keeps at least this many cells
_COARSEST = 256
#: tolerance of the coarse solves (they only provide the start)
_COARSE_TOL = 1e-4


def _levels(n: int) -> list[int]:
    sizes = [n]
    while sizes[0] % _COARSEN == 0 and sizes[0] // _COARSEN >= _COARSEST:
        sizes.insert(0, sizes[0] // _COARSEN)
    return sizes


def _prolong(p: np.ndarray, f: int) -> np.ndarray:
    """A coarse cell field onto the cells f times finer: linear between the coarse centres
    (constant beyond the outer ones)."""
    m = p.size
    fine = (np.arange(m * f) + 0.5) / f - 0.5  # fine centres in coarse-cell units
    return np.interp(fine, np.arange(m, dtype=np.float64), p)


def solve_strip(
    problem: ContactProblem,
    *,
    p0: np.ndarray | None,
    tol: float,
    max_iter: int,
    precondition: bool,
) -> PolonskyKeerResult:
    """The Polonsky–Keer solve of a 1D problem on its candidate cells, started from nested grids
    (or from ``p0``, a warm start meeting the constraints, on the given grid alone)."""
    pr = problem
    n = pr.h.size
    control = pr.control
    moment = control == "moment"
    target = pr.target
    extra = pr.width if pr.model == "strip" else pr.reference_length
    sizes = [n] if p0 is not None else _levels(n)
    p = p0
    res = None
    iterations, n_conv = 0, 0
    for m in sizes:
        f = n // m
        if m == n:
            conv, h, xi, tg = pr.conv, pr.h, pr.arm, target
        else:
            conv = _operator(pr.model, (m,), pr.dx * f, 0.0, pr.modulus, extra, pr.workers)  # type: ignore[arg-type]
            h = pr.h.reshape(m, f).mean(axis=1)
            xi = pr.arm.reshape(m, f).mean(axis=1)
            tg = None if target is None else target.reshape(m, f).mean(axis=1)
        total = None if pr.total is None else pr.total / f
        if p is None:
            k0 = conv.self_influence
            if control == "displacement":
                p = np.maximum(tg - h, 0.0) / k0  # type: ignore[operator]
            else:
                p = rigid_start(h, xi, total, moment, k0, 1)  # type: ignore[arg-type]
        elif p.size != m:
            p = _prolong(p, m // p.size)
            if total is not None:
                p, ok = restore(p, xi, total, moment)
                if not ok:
                    p = rigid_start(h, xi, total, moment, conv.self_influence, 1)
        level_tol = tol if m == n else max(tol, _COARSE_TOL)
        kw = dict(control=control, total=total, target=tg, tol=level_tol)
        res = solve_on_candidates(conv, h, xi, p0=p, max_iter=max_iter, precondition=precondition,
                                  **kw)  # type: ignore[arg-type]  # fmt: skip
        if res is None:  # the candidates are most of a large grid: iterate on all of it by FFT
            inverse = CellOperator(circulant_preconditioner(conv)) if precondition else None
            res = polonsky_keer(CellOperator(conv), h, p0=p, arm=xi, preconditioner=inverse,
                                max_iter=max_iter, **kw)  # type: ignore[arg-type]  # fmt: skip
        iterations += res.iterations
        n_conv += res.convolutions
        p = res.pressure if res.converged else None
    assert res is not None
    if len(sizes) == 1:
        return res
    # the report counts the coarse grids' steps and products too (they are the cost)
    return PolonskyKeerResult(
        pressure=res.pressure, displacement=res.displacement, translation=res.translation,
        rotation=res.rotation, iterations=iterations, convolutions=n_conv,
        history=res.history, status=res.status, message=res.message,
    )  # fmt: skip
