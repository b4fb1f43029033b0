"""The flexible-ski iteration restricted to the candidate contact cells of a strip grid.

A bending ski touches the snow over a few hundred of its 4096 stations. When the contact is too
large for the dense active-set steps (:mod:`skisnow.contact._flexible_pdas`), MPRGP
(:func:`~skisnow.contact._mprgp.active_set_cg`) runs from the coarse grids' solution on the
candidate cells S only: the snow by FFT over the span of S (the window of a Toeplitz operator,
:class:`~skisnow.contact._operators.RestrictedOperator`), the beam by prefix sums of its
generators on S (O(|S|), :func:`~skisnow.contact._flexible_kernel.beam_block_apply`), the
snow's circulant preconditioner restricted the same way. The gap is then checked on the whole
grid and missed cells added, so the restriction changes the cost, not the answer (Kalliorinne
et al. 2023, eq. 2–3, with the flexible ski of :func:`~skisnow.contact.solve_flexible`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from skisnow.contact._coupled_operator import CoupledOperator
from skisnow.contact._kernels import Convolution
from skisnow.contact._mprgp import active_set_cg
from skisnow.contact._polonsky_keer import plane_fit

__all__ = ["CANDIDATE_MIN_CELLS", "CANDIDATE_WARMUP", "flexible_on_candidates"]

#: grids shorter than this are solved whole; candidate sets larger than _CANDIDATE_FRACTION of
#: the grid too
CANDIDATE_MIN_CELLS = 1024
_CANDIDATE_FRACTION = 0.5
#: cells found penetrating off the candidates are added with this many neighbours each side
_WIDEN = 8
#: candidates: cells whose estimated gap is below this fraction of the largest snow
#: displacement (the whole-grid check afterwards adds any cell that was missed)
_CANDIDATE_MARGIN = 0.2
#: whole-grid steps before the candidate iteration
CANDIDATE_WARMUP = 6


def _restricted(
    op: CoupledOperator, inverse: Convolution, cells: np.ndarray
) -> tuple[Callable[[np.ndarray], np.ndarray], Callable[[np.ndarray], np.ndarray]]:
    """K_SS = K_snow,SS + K_beam,SS and the snow preconditioner restricted to the cells S: the
    snow by FFT over the span of S, the beam by the prefix sums of its generators on S."""
    from skisnow.contact._flexible_kernel import beam_block_apply
    from skisnow.contact._operators import RestrictedOperator

    snow = op.snow
    assert isinstance(snow, Convolution)
    rest = RestrictedOperator.build(snow, cells, dense=False)
    prec = rest.preconditioner(inverse)
    area = op.cell_area
    side, d, u, v = op.beam.generators
    bent = np.empty(cells.size)

    def apply(x: np.ndarray) -> np.ndarray:
        beam_block_apply(cells, side, d, u, v, area, np.ascontiguousarray(x), bent)
        return rest(x) + bent

    return apply, prec


def flexible_on_candidates(
    op: CoupledOperator,
    inverse: Convolution,
    h: np.ndarray,
    xi: np.ndarray,
    p0: np.ndarray,
    *,
    tol: float,
    max_iter: int,
    candidates: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, float, float, int, list[float], bool, str, int] | None:
    """:func:`active_set_cg` on the candidate contact cells S of a strip grid.

    As p = 0 off S, the iteration on S with the operators restricted to S (:func:`_restricted`)
    is the whole-grid iteration as long as no cell off S enters the contact. S is
    ``candidates`` (with the start's support), else the start's support and every cell whose
    gap is below the margin. The gap is checked on the whole grid afterwards (one application
    of the full operator); cells that penetrate are added, with the cells near them, and the
    iteration resumes from the pressure found. Returns None when the candidates are too many
    (then the caller iterates on the whole grid).
    """
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

    if candidates is None:
        gap, u_max = full_gap(p)
        cand = (p > 0) | (gap < _CANDIDATE_MARGIN * u_max)
    else:
        cand = candidates | (p > 0)
    for _ in range(6):
        cells = np.flatnonzero(cand)
        if cells.size > _CANDIDATE_FRACTION * n or cells.size < 2:
            return None
        apply, precondition = _restricted(op, inverse, cells)
        ps, _, a, b, it, hist, converged, message, nap = active_set_cg(
            apply, precondition, h[cells], xi[cells], p[cells], tol=tol,
            max_iter=max_iter - iterations,
        )  # fmt: skip
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
        cand |= np.convolve(missed, np.ones(2 * _WIDEN + 1), mode="same") > 0
        if candidates is None:
            cand |= gap < _CANDIDATE_MARGIN * u_max
    return None
