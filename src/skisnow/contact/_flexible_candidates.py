"""The flexible-ski iteration restricted to the candidate contact cells of a strip grid.

A bending ski touches the snow over a few hundred of its 4096 stations. After a few whole-grid
steps of :func:`~skisnow.contact._mprgp.active_set_cg`, the iteration runs on the candidate cells
S with the dense blocks K_snow,SS + K_beam,SS (the snow's Toeplitz rows,
:class:`~skisnow.contact._operators.RestrictedOperator`, plus the beam's block) and the snow
preconditioner restricted to S; the gap is then checked on the whole grid and missed cells
added, so the restriction changes the cost, not the answer (Kalliorinne et al. 2023, eq. 2–3,
with the flexible ski of :func:`~skisnow.contact.solve_flexible`).
"""

from __future__ import annotations

import numpy as np

from skisnow.contact._coupled_operator import CoupledOperator
from skisnow.contact._kernels import Convolution
from skisnow.contact._mprgp import active_set_cg
from skisnow.contact._polonsky_keer import plane_fit

__all__ = ["CANDIDATE_MIN_CELLS", "CANDIDATE_WARMUP", "flexible_on_candidates"]

#: grids shorter than this are solved whole; candidate sets larger than _CANDIDATE_MAX (or
#: than _CANDIDATE_FRACTION of the grid) too: a dense block costs more than the FFT there
CANDIDATE_MIN_CELLS = 1024
_CANDIDATE_MAX = 700
_CANDIDATE_FRACTION = 0.5
#: candidates: cells whose estimated gap is below this fraction of the largest snow
#: displacement (the whole-grid check afterwards adds any cell that was missed)
_CANDIDATE_MARGIN = 0.2
#: whole-grid steps before the candidate iteration
CANDIDATE_WARMUP = 6


def flexible_on_candidates(
    op: CoupledOperator,
    inverse: Convolution,
    h: np.ndarray,
    xi: np.ndarray,
    p0: np.ndarray,
    *,
    tol: float,
    max_iter: int,
) -> tuple[np.ndarray, np.ndarray, float, float, int, list[float], bool, str, int] | None:
    """:func:`active_set_cg` on the candidate contact cells S of a strip grid.

    As p = 0 off S, the iteration on S with the dense blocks K_SS (snow Toeplitz rows plus the
    beam's block) and the snow preconditioner restricted to S is the whole-grid iteration as long
    as no cell off S enters the contact. The gap is checked on the whole grid afterwards (one
    application of the full operator); cells that penetrate are added, with every cell whose gap
    is below the margin, and the iteration resumes from the pressure found. Returns None when the
    candidates are too many for a dense block (then the caller iterates on the whole grid).
    """
    from skisnow.contact._operators import RestrictedOperator

    snow = op.snow
    assert isinstance(snow, Convolution)
    n = h.size
    p = np.array(p0, dtype=np.float64)
    n_apply = 0
    iterations, history = 0, []

    def full_gap(p: np.ndarray) -> tuple[np.ndarray, float]:
        nonlocal n_apply
        u_s = snow(p)
        g = u_s + op.beam(p * op.cell_area) + h
        n_apply += 1
        a, b = plane_fit(g, xi, p > 0)
        return g - a - b * xi, float(np.abs(u_s).max()) + 1e-300

    gap, u_max = full_gap(p)
    cand = (p > 0) | (gap < _CANDIDATE_MARGIN * u_max)
    for _ in range(6):
        cells = np.flatnonzero(cand)
        if cells.size > min(_CANDIDATE_MAX, _CANDIDATE_FRACTION * n) or cells.size < 2:
            return None
        rest = RestrictedOperator.build(snow, cells, dense=True)
        assert rest.matrix is not None
        k_ss = rest.matrix + op.beam.block(cells) * op.cell_area
        m_ss = rest.preconditioner(inverse).matrix
        assert m_ss is not None
        ps, _, a, b, it, hist, converged, message, nap = active_set_cg(
            lambda v: k_ss @ v,  # noqa: B023 (used within this pass)
            lambda v: m_ss @ v,  # noqa: B023
            h[cells],
            xi[cells],
            p[cells],
            tol=tol,
            max_iter=max_iter - iterations,
        )
        iterations += it
        history += hist
        n_apply += nap
        p = np.zeros(n)
        p[cells] = ps
        if not converged:
            return None
        gap, u_max = full_gap(p)
        scale = float(np.ptp(h)) + u_max
        missed = (p == 0.0) & (gap < -tol * scale)
        if not missed.any():
            g = gap + plane_fit(gap, xi, p > 0)[0]  # (only δ, θ are used by the caller)
            return p, g, a, b, iterations, history, True, message, n_apply
        cand |= missed | (gap < _CANDIDATE_MARGIN * u_max)
    return None
