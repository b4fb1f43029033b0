"""The Polonsky–Keer iteration restricted to the candidate contact cells of a 1D grid.

A ski touches the snow over a few hundred of its 4096 stations. The candidates S are the cells of
the start's support plus those whose gap, estimated from the start (u₀ = K p₀, the rigid plane
fitted on the support), is below a margin of the largest displacement. On S the iteration runs
with the restricted operator ``K_SS`` (:class:`~skisnow.contact._operators.RestrictedOperator`,
a dense Toeplitz block up to 800 cells) and the preconditioner restricted the same way. Since
p = 0 off S, its iterates are those of the whole-grid iteration as long as no cell off S would
enter the contact; the gap is then checked on the whole grid (one FFT) and any missed cell added,
so the restriction changes the cost, not the answer.
"""

from __future__ import annotations

import numpy as np

from skisnow._errors import SolverStatus
from skisnow.contact._kernels import Convolution
from skisnow.contact._operators import CellOperator, RestrictedOperator, circulant_preconditioner
from skisnow.contact._polonsky_keer import (
    Control,
    PolonskyKeerResult,
    plane_fit,
    polonsky_keer,
    restore,
)

__all__ = ["CANDIDATE_MIN_CELLS", "solve_on_candidates"]

#: candidate cells: those whose estimated gap is below this fraction of the largest snow
#: displacement (plus the cells already in contact); the gap check after the solve adds any
#: cell that was missed, so the margin only trades set size against re-solves
_CANDIDATE_MARGIN = 0.05
#: the candidate iteration is used when the set is at most this fraction of the grid
_CANDIDATE_FRACTION = 0.8
#: candidate runs closer than this many cells are joined
_CANDIDATE_GAP = 32
#: grids shorter than this are solved whole (too small to gain)
CANDIDATE_MIN_CELLS = 1024


def solve_on_candidates(
    conv: Convolution,
    h: np.ndarray,
    xi: np.ndarray,
    *,
    total: float | None,
    control: Control,
    target: np.ndarray | None,
    p0: np.ndarray,
    tol: float,
    max_iter: int,
    precondition: bool,
    margin: float | None = None,
) -> PolonskyKeerResult | None:
    """:func:`~skisnow.contact.polonsky_keer` on the candidate cells of a 1D grid.

    After convergence the gap is checked on the whole grid (one FFT); cells without pressure
    that penetrate (g < −tol·max u) are added, with every cell whose gap is below the margin,
    they are given the pressure that closes their own gap, and the iteration resumes. Returns
    the result on the whole grid (u too), or None when the candidates are most of the grid from
    the start (then the caller iterates on the whole grid).
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
    inverse = circulant_preconditioner(conv) if precondition else None

    def gap(p: np.ndarray, u: np.ndarray, a: float | None = None, b: float = 0.0) -> np.ndarray:
        g = hh + u
        if a is None:
            a, b = 0.0, 0.0
            sel = p > 0
            if constrained and sel.any():
                a, b = plane_fit(g, xi, sel) if moment else (float(g[sel].mean()), 0.0)
        return g - a - b * xi

    def whole(res: PolonskyKeerResult, **changes: object) -> PolonskyKeerResult:
        """The candidates' result on the whole grid, with the cost and history so far."""
        fields = dict(
            pressure=p, displacement=u, translation=res.translation, rotation=res.rotation,
            iterations=iterations, convolutions=n_conv, history=np.asarray(history),
            status=res.status, message=res.message,
        )  # fmt: skip
        fields.update(changes)
        return PolonskyKeerResult(**fields)  # type: ignore[arg-type]

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
        res = polonsky_keer(
            op,
            h[cells],
            p0=p[cells],
            control=control,
            total=total,
            arm=xi[cells],
            target=None if target is None else target[cells],
            preconditioner=inv,
            tol=tol,
            max_iter=max_iter - iterations,
        )
        iterations += res.iterations
        history += res.history.tolist()
        n_conv += res.convolutions
        p = np.zeros(n)
        p[cells] = res.pressure
        u = conv(p)
        n_conv += 1
        if not res.converged:
            return whole(res)
        g = gap(p, u, res.translation, res.rotation)
        scale = float(np.max(np.abs(u))) + 1e-300
        # cells without pressure that penetrate (beyond the solver's tolerance): off the
        # candidates, or left behind when the step that added them was tiny
        missed = (p == 0.0) & (g < -tol * scale)
        if not missed.any():
            return whole(res)
        candidates |= missed | (g < margin * scale)
        # resume from a start that is not already converged: the missed cells carry the
        # pressure that closes their own gap (else the first step, scaled by the converged
        # residual, would add almost nothing and pass the Σ|Δp|/Σp test at once)
        p = p.copy()
        p[missed] = -g[missed] / conv.self_influence
        if constrained:
            assert total is not None
            p, ok = restore(p, xi, total, moment)
            if not ok:
                u = conv(p)
                n_conv += 1
                status = SolverStatus.INFEASIBLE
                return whole(res, status=status, message=status.message, displacement=u)
    # the candidates grew to most of the grid (or kept missing cells): finish on the whole grid
    res = polonsky_keer(
        CellOperator(conv),
        h,
        p0=p,
        control=control,
        total=total,
        arm=xi,
        target=target,
        preconditioner=CellOperator(inverse) if inverse is not None else None,
        tol=tol,
        max_iter=max(max_iter - iterations, 1),
    )
    return whole(
        res,
        pressure=res.pressure,
        displacement=res.displacement,
        iterations=iterations + res.iterations,
        convolutions=n_conv + res.convolutions,
        history=np.asarray(history + res.history.tolist()),
    )


def _close_gaps(mask: np.ndarray, width: int) -> None:
    """Set the gaps of at most ``width`` cells between True runs of ``mask`` (in place): fewer,
    longer runs make the restricted operator cheaper to assemble."""
    idx = np.flatnonzero(mask)
    if idx.size < 2:
        return
    jumps = np.flatnonzero((np.diff(idx) > 1) & (np.diff(idx) <= width + 1))
    for k in jumps.tolist():
        mask[idx[k] + 1 : idx[k + 1]] = True
