"""A primal–dual active-set (semismooth Newton) solver for the flexible ski on a strip grid.

min ½⟨p, K p⟩ + ⟨p, h⟩ over p ≥ 0 with the force and moment balances of Kalliorinne et al.
(2023, eq. 3), K = K_snow + K_beam (:mod:`skisnow.contact._flexible`). The KKT conditions are
p ≥ 0, λ = K p + h − δ − θξ ≥ 0 (the gap), p·λ = 0, i.e. p = max(0, p − cλ) for any c > 0: a
semismooth equation whose Newton step is the primal–dual active-set step of Hintermüller, Ito &
Kunisch (2002, SIAM J. Optim. 13, 865–888, Algorithm 1 with the equality constraints kept as
Lagrange multipliers): on the current contact set A, solve K_AA p_A + h_A = δ + θξ_A with
Σp_A and Σξ_A p_A prescribed (a dense Cholesky of K_AA, the half-space's Toeplitz rows plus the
beam's block, and a 2 × 2 Schur system for δ, θ), set p = 0 off A, compute the gap λ on the whole
grid by FFT, and move *every* cell whose sign is wrong at once: cells of A with p ≤ 0 leave,
cells off A with λ < 0 enter. When A repeats the KKT point is exact (up to round-off) and p ≥ 0,
λ ≥ 0 hold on the whole grid.

From a poor set the steps are slow (a set too wide leaves a few cells per edge per step, with
large negative pressures at its edges), and a dense factorisation of the ~1400 cells that the
rigid-hull start spreads over costs ~50 ms. So the set is found on nested grids coarsened by 4
(cell averages; 256 and 1024 cells for 4096 stations), each grid's set repeated onto the next:
the finest grid then needs only the 3–4 steps that move the edges by a cell or two (measured on
the shipped skis of version 2).

On the classic of version 2 the MPRGP iteration (:mod:`skisnow.contact._mprgp`) spends 60–300
steps moving the contact set one face at a time (measured: an exact preconditioner on the
candidate block leaves the count unchanged); the active-set step moves it in a handful of
solves. It is not globally convergent for a dense, non-M-matrix K (it can cycle), so the caller
keeps MPRGP as the fallback: None is returned on a repeated set, too many steps or too large a
contact set, and the answer, when one is returned, satisfies the same stopping rule as MPRGP's.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import cho_factor, cho_solve

from skisnow.contact._beam_operator import cantilever_compliance
from skisnow.contact._coupled_operator import CoupledOperator
from skisnow.contact._kernels import Convolution
from skisnow.contact._operators import _toeplitz_rows
from skisnow.contact._polonsky_keer import plane_fit
from skisnow.contact._problem import _operator
from skisnow.contact._starts import rigid_start

__all__ = ["multilevel_active_set"]

#: largest contact set solved by a dense Cholesky on the finest grid (n³/3 flops: ~2 ms at 500
#: cells on one core; larger sets go to MPRGP from the coarse solution)
_PDAS_MAX_CELLS = 500
#: active-set steps per grid before giving up
_PDAS_MAX_STEPS = 25
#: the grids: the finest coarsened by this factor while at least _COARSEST cells remain
_COARSEN = 4
_COARSEST = 256
#: a cell off A enters only when its gap is below −this × tol × scale (no flip-flop on round-off)
_ENTER = 1e-2

#: the compiled steps that give the coarsest grid's first set: tolerance and limit
_FIRST_TOL = 1e-3
_FIRST_STEPS = 40

_Result = tuple[np.ndarray, np.ndarray, float, float, int, list[float], bool, str, int]


def _active_set_steps(
    op: CoupledOperator,
    h: np.ndarray,
    xi: np.ndarray,
    act: np.ndarray,
    total: float,
    *,
    tol: float,
    max_cells: int,
) -> tuple[np.ndarray, np.ndarray | None, _Result | None]:
    """Primal–dual active-set steps (Hintermüller et al. 2002) from the contact set ``act``.

    Each step solves K_AA p_A + h_A = δ + θξ_A with Σp_A = total, Σξ_A p_A = 0 (Cholesky of
    K_AA and a 2 × 2 Schur system), then moves every cell whose sign is wrong. Returns the last
    set, the last pressure (None before the first solve) and the result tuple of
    :func:`~skisnow.contact._mprgp.active_set_cg` when the set repeats with the residual at or
    below ``tol`` (else None: a cycle, a set larger than ``max_cells``, or too many steps).
    """
    snow = op.snow
    assert isinstance(snow, Convolution) and snow.kernel is not None
    n = h.size
    seen: set[bytes] = set()
    history: list[float] = []
    p_last = None
    for step in range(1, _PDAS_MAX_STEPS + 1):
        cells = np.flatnonzero(act)
        key = cells.tobytes()
        if not 2 <= cells.size <= max_cells or key in seen:
            break
        seen.add(key)
        k_aa = _toeplitz_rows(snow.kernel, n, cells)
        k_aa += op.beam.block(cells, lower_only=True) * op.cell_area
        try:
            factor = cho_factor(k_aa, lower=True, overwrite_a=True, check_finite=False)
            xa = xi[cells]
            y = cho_solve(factor, np.column_stack([-h[cells], np.ones(cells.size), xa]),
                          check_finite=False)  # fmt: skip
            # p_A = y0 + δ y1 + θ y2 with Σp_A = total, Σξp_A = 0
            e = np.column_stack([np.ones(cells.size), xa])
            a, b = np.linalg.solve(e.T @ y[:, 1:], np.array([total, 0.0]) - e.T @ y[:, 0])
        except np.linalg.LinAlgError:
            break
        p = np.zeros(n)
        p[cells] = y[:, 0] + a * y[:, 1] + b * y[:, 2]
        p_last = p
        u = snow(p)
        g = u + op.beam(p * op.cell_area) + h
        lam = g - a - b * xi  # the gap: zero on A by construction
        scale = float(np.ptp(h)) + float(np.abs(u).max()) + 1e-300
        on = float(np.abs(lam[cells]).max())
        off = -min(float(np.where(act, 0.0, lam).min()), 0.0)
        history.append(max(on, off) / scale)
        leave = act & (p <= 0.0)
        enter = ~act & (lam < -_ENTER * tol * scale)
        if not (leave.any() or enter.any()):
            if history[-1] > tol:
                break
            message = (
                f"converged: max |gap residual| = {history[-1]:.2e} ≤ {tol:.1e} "
                f"(primal–dual active set, {step} steps)"
            )
            return act, p, (p, g, float(a), float(b), step, history, True, message, step)
        act = (act & ~leave) | enter
    return act, p_last, None


def _first_set(
    op: CoupledOperator, h: np.ndarray, xi: np.ndarray, p0: np.ndarray, total: float
) -> np.ndarray:
    """The coarsest grid's first contact set: the support after a few compiled Polonsky–Keer
    steps on the dense K_snow + K_beam from the rigid-hull start (the hull's support is several
    times the contact, and active-set steps from it cycle: measured 25 steps without converging
    on the classic on the stone), or {p − λ/K(0) > 0} if those steps fail."""
    from skisnow.contact import _pk_kernel as pk
    from skisnow.contact._operators import _inverse_kernel

    snow = op.snow
    assert isinstance(snow, Convolution) and snow.kernel is not None
    n = h.size
    cells = np.arange(n)
    k = _toeplitz_rows(snow.kernel, n, cells) + op.beam.block(cells) * op.cell_area
    m = _toeplitz_rows(_inverse_kernel(snow), n, cells, dtype=np.float32)
    p, *_, status = pk.pk_dense(k, m, True, h, xi, p0, pk.MOMENT, float(total), _FIRST_TOL,
                                _FIRST_STEPS, snow.self_influence)  # fmt: skip
    if status in (pk.SUCCESSFUL, pk.MAX_STEPS, pk.EXACT) and (p > 0).sum() >= 2:
        return p > 0.0
    g = op(p0) + h
    a, b = plane_fit(g, xi, p0 > 0.0)
    return p0 - (g - a - b * xi) / snow.self_influence > 0.0


def multilevel_active_set(
    x: np.ndarray,
    h: np.ndarray,
    stiffness: np.ndarray,
    *,
    op: CoupledOperator,
    load: float,
    load_position: float,
    modulus: float,
    width: float,
    tol: float,
    workers: int | None = None,
) -> tuple[_Result | None, np.ndarray | None]:
    """The flexible ski on a strip grid by active-set steps on nested grids.

    The contact set is found on grids coarsened by 4 (cell averages of the stations, of z0 +
    w_boot and of EI; down to 256 cells), starting on the coarsest from the rigid-hull start
    (:func:`~skisnow.contact._starts.rigid_start`) with the first set {p − λ/K(0) > 0}; each
    grid's set, repeated onto the next finer one, starts the steps there, so the finest grid
    (the problem of :func:`~skisnow.contact.solve_flexible`) needs only the few steps that move
    the contact edges by a cell or two.

    Parameters
    ----------
    x, h, stiffness
        The stations [m] (uniform), z0 + w_boot [m] and EI [N m²] at them.
    op
        K_snow + K_beam on ``x`` (1D half-space).
    load, load_position, modulus, width
        W [N], x_m [m], E' [Pa] and the ski width [m], as in ``solve_flexible``.
    tol
        The stopping rule of :func:`~skisnow.contact._mprgp.active_set_cg`.
    workers
        FFT threads of the coarse operators.

    Returns
    -------
    result, start
        The result tuple of :func:`~skisnow.contact._mprgp.active_set_cg` (None if the finest
        grid did not converge: a contact set too large for the dense Cholesky, a cycle), and,
        when None, the pressure of the finest grid solved, repeated onto ``x`` [Pa] (a start
        for MPRGP; None if no grid was solved).
    """
    n = x.size
    sizes = [n]
    while sizes[0] % _COARSEN == 0 and sizes[0] // _COARSEN >= _COARSEST:
        sizes.insert(0, sizes[0] // _COARSEN)
    if len(sizes) == 1:
        return None, None
    act: np.ndarray | None = None
    start: np.ndarray | None = None
    for m in sizes:
        f = n // m
        if m == n:
            xc, hc, lop = x, h, op
        else:
            xc = x.reshape(m, f).mean(axis=1)
            hc = h.reshape(m, f).mean(axis=1)
            dxc = float(xc[1] - xc[0])
            beam = cantilever_compliance(
                xc, stiffness.reshape(m, f).mean(axis=1), load_position=load_position
            )
            snow = _operator("strip", (m,), dxc, width, modulus, width, workers)
            lop = CoupledOperator(snow=snow, beam=beam, cell_area=dxc * width)
        xic = xc - load_position
        total = load / lop.cell_area
        if act is None:
            p0 = rigid_start(hc, xic, total, True, lop.snow.self_influence, 1)
            act = _first_set(lop, hc, xic, p0, total)
        else:
            act = np.repeat(act, m // act.size)
        act, p, result = _active_set_steps(
            lop, hc, xic, act, total, tol=tol, max_cells=_PDAS_MAX_CELLS if m == n else m
        )
        if result is not None and m == n:
            return result, None
        if p is not None:
            start = np.repeat(p, n // m)
    return None, start
