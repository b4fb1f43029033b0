"""The Polonsky–Keer iteration restricted to the candidate contact cells of a 1D grid.

A ski touches the snow over a few hundred of its 4096 stations. The candidates S are the cells of
the start's support plus those whose gap, estimated from the start (u₀ = K p₀, the rigid plane
fitted on the support), is below a margin of the largest displacement. On S the iteration runs
with the restricted operator ``K_SS`` and the preconditioner restricted the same way: up to
:data:`DENSE_MAX` cells as dense matrices, iterated by the compiled loop of
:mod:`skisnow.contact._pk_kernel`; beyond, by FFT over the span of S only
(:class:`~skisnow.contact._operators.RestrictedOperator`). Since p = 0 off S, its iterates are
those of the whole-grid iteration as long as no cell off S would enter the contact; the gap is
then checked on the whole grid (one FFT) and any missed cell added, so the restriction changes
the cost, not the answer.
"""

from __future__ import annotations

import functools

import numpy as np

from skisnow._errors import SolverStatus
from skisnow.contact._kernels import Convolution
from skisnow.contact._operators import (
    CellOperator,
    RestrictedOperator,
    _inverse_kernel,
    _toeplitz_rows,
    circulant_preconditioner,
)
from skisnow.contact._polonsky_keer import (
    Control,
    PolonskyKeerResult,
    plane_fit,
    polonsky_keer,
    restore,
)
from skisnow.contact._window import rigid_body_gap

__all__ = ["CANDIDATE_MIN_CELLS", "DENSE_MAX", "solve_on_candidates"]

#: candidate cells: those whose estimated gap is below this fraction of the largest snow
#: displacement (plus the cells already in contact); the gap check after the solve adds any
#: cell that was missed, so the margin only trades set size against re-solves
_CANDIDATE_MARGIN = 0.02
#: the candidate iteration is used when the set is at most this fraction of the grid
_CANDIDATE_FRACTION = 0.8
#: candidate runs closer than this many cells are joined
_CANDIDATE_GAP = 32
#: grids shorter than this are solved whole (too small to gain); kept for compatibility
CANDIDATE_MIN_CELLS = 1024
#: up to this many cells the restricted operator is a dense matrix and the iteration compiled
#: (a product of 800² entries: ~60 µs, against ~60 µs for the FFT pair of a 4096-cell grid)
DENSE_MAX = 800

_STATUS = {
    0: (SolverStatus.SUCCESSFUL, None),
    1: (SolverStatus.MAX_STEPS_REACHED, None),
    2: (SolverStatus.CONTACT_LOST, None),
    3: (SolverStatus.INFEASIBLE, None),
    4: (SolverStatus.BREAKDOWN, None),
    5: (SolverStatus.NONFINITE, None),
    6: (SolverStatus.SUCCESSFUL, "exact solution on the contact set"),
    7: (SolverStatus.SUCCESSFUL, "no contact (every gap open)"),
}


@functools.lru_cache(maxsize=16)
def _whole_dense(conv: Convolution) -> tuple[np.ndarray, np.ndarray]:
    """K and its circulant inverse on every cell of a small 1D grid, dense (cached)."""
    (n,) = conv.shape
    cells = np.arange(n)
    return (
        _toeplitz_rows(conv.kernel, n, cells),  # type: ignore[arg-type]
        _toeplitz_rows(_inverse_kernel(conv), n, cells, dtype=np.float32),
    )


_NO_PRECONDITIONER = np.zeros((0, 0), dtype=np.float32)


def _dense_solve(
    conv: Convolution,
    cells: np.ndarray,
    hh: np.ndarray,
    xi: np.ndarray,
    p0: np.ndarray,
    *,
    control: Control,
    total: float | None,
    tol: float,
    max_iter: int,
    precondition: bool,
) -> PolonskyKeerResult:
    """The compiled Polonsky–Keer loop on the dense K_SS (``hh`` = h − target on the cells)."""
    from skisnow.contact import _pk_kernel as pk

    (n,) = conv.shape
    if cells.size == n:
        k, m = _whole_dense(conv)
    else:
        k = _toeplitz_rows(conv.kernel, n, cells)  # type: ignore[arg-type]
        m = _NO_PRECONDITIONER
        if precondition:
            m = _toeplitz_rows(_inverse_kernel(conv), n, cells, dtype=np.float32)
    code = {"moment": pk.MOMENT, "load": pk.LOAD, "displacement": pk.DISPLACEMENT}[control]
    p, u, it, n_conv, hist, status = pk.pk_dense(
        k, m, bool(precondition), hh, xi, np.ascontiguousarray(p0, dtype=np.float64), code,
        float(total or 0.0), float(tol), int(max_iter), conv.self_influence,
    )  # fmt: skip
    st, message = _STATUS[int(status)]
    if message is None:
        message = st.message
        if st.successful and hist.size:
            message = f"converged: Σ|Δp|/Σp = {hist[-1]:.2e} ≤ {tol:.1e}"
    a = b = 0.0
    sel = p > 0
    if control != "displacement" and sel.any():
        g = u + hh
        a, b = plane_fit(g, xi, sel) if control == "moment" else (float(g[sel].mean()), 0.0)
    return PolonskyKeerResult(
        pressure=p, displacement=u, translation=a, rotation=b, iterations=int(it),
        convolutions=int(n_conv), history=hist, status=st, message=message,
    )  # fmt: skip


def solve_cells(
    conv: Convolution,
    cells: np.ndarray,
    h: np.ndarray,
    xi: np.ndarray,
    p0: np.ndarray,
    *,
    control: Control,
    total: float | None,
    target: np.ndarray | None,
    tol: float,
    max_iter: int,
    precondition: bool,
) -> PolonskyKeerResult:
    """Polonsky–Keer on the cells ``cells`` of a 1D grid (p = 0 elsewhere), restricted operator:
    dense and compiled up to :data:`DENSE_MAX` cells, FFT over their span beyond."""
    tg = None if target is None else target[cells]
    if cells.size <= DENSE_MAX:
        hh = h[cells] if tg is None else h[cells] - tg
        return _dense_solve(conv, cells, hh, xi[cells], p0[cells], control=control, total=total,
                            tol=tol, max_iter=max_iter, precondition=precondition)  # fmt: skip
    op = RestrictedOperator.build(conv, cells)
    inv = op.preconditioner(circulant_preconditioner(conv)) if precondition else None
    return polonsky_keer(op, h[cells], p0=p0[cells], control=control, total=total,
                         arm=xi[cells], target=tg, preconditioner=inv, tol=tol,
                         max_iter=max_iter)  # fmt: skip


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
    the result on the whole grid (u too), or None when the candidates are most of a grid too
    large for the dense operator (then the caller iterates on the whole grid by FFT).
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

    gap = functools.partial(rigid_body_gap, hh, xi, moment=moment, constrained=constrained)

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
    small = n <= DENSE_MAX
    kw = dict(control=control, total=total, target=target, precondition=precondition)
    for _ in range(8):
        _close_gaps(candidates, _CANDIDATE_GAP)
        cells = np.flatnonzero(candidates)
        if cells.size == 0 or (cells.size > _CANDIDATE_FRACTION * n and not small):
            if iterations == 0:
                return None
            break
        res = solve_cells(conv, cells, h, xi, p, tol=tol, max_iter=max_iter - iterations,
                          **kw)  # type: ignore[arg-type]  # fmt: skip
        iterations += res.iterations
        history += res.history.tolist()
        n_conv += res.convolutions
        p = np.zeros(n)
        p[cells] = res.pressure
        if cells.size == n:
            u = res.displacement
        else:
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
    inverse = circulant_preconditioner(conv) if precondition else None
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
