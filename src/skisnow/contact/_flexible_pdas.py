"""A primal–dual active-set (semismooth Newton) solver for the flexible ski on a strip grid.

min ½⟨p, K p⟩ + ⟨p, h⟩ over p ≥ 0 with the force and moment balances of Kalliorinne et al.
(2023, eq. 3), K = K_snow + K_beam (:mod:`skisnow.contact._flexible`). The KKT conditions are
p ≥ 0, λ = K p + h − δ − θξ ≥ 0 (the gap), p·λ = 0, i.e. p = max(0, p − cλ) for any c > 0: a
semismooth equation whose Newton step is the primal–dual active-set step of Hintermüller, Ito &
Kunisch (2002, SIAM J. Optim. 13, 865–888, Algorithm 1 with the equality constraints kept as
Lagrange multipliers): on the current contact set A, solve K_AA p_A + h_A = δ + θξ_A with
Σp_A and Σξ_A p_A prescribed (a Cholesky factorisation of K_AA, the half-space's Toeplitz rows
plus the beam's block, and a 2 × 2 Schur system for δ, θ), set p = 0 off A, compute the gap λ,
and move *every* cell whose sign is wrong at once: cells of A with p ≤ 0 leave, cells off A with
λ < 0 enter. When A repeats the KKT point is exact (up to round-off) and p ≥ 0, λ ≥ 0 hold.

From a poor set the steps are slow (a set too wide leaves a few cells per edge per step, with
large negative pressures at its edges), and a dense factorisation of the ~1400 cells that the
rigid-hull start spreads over costs ~50 ms. So the set is found on nested grids coarsened by 8
(cell averages; 64 and 512 cells for 4096 stations), each grid's set carried onto the next with
its edges where the coarse pressure, extrapolated as a contact edge's p ∝ √distance, reaches
zero: the finest grid then needs only the 2–4 steps that move the edges by a cell or two
(measured on the shipped skis of version 2). The steps of a grid run on its candidate cells
only (the carried set widened by a coarse cell: every cell on the coarsest grid) with the
dense coupled block K_SS (compiled assembly, :mod:`skisnow.contact._flexible_kernel`), λ on S by
one dense product, and compiled (:mod:`skisnow.contact._pdas_kernel`: the set's interior is
factored once, the moving border through a small Schur complement); on the finest grid λ is then
checked on every cell (one FFT, one beam product) and penetrating cells are added.

On the classic of version 2 the MPRGP iteration (:mod:`skisnow.contact._mprgp`) spends 60–300
steps moving the contact set one face at a time (measured: an exact preconditioner on the
candidate block leaves the count unchanged); the active-set step moves it in a handful of
solves. It is not globally convergent for a dense, non-M-matrix K (it can cycle), so the caller
keeps MPRGP as the fallback: None is returned on a repeated set, too many steps or too large a
contact set, and the answer, when one is returned, satisfies the same stopping rule as MPRGP's.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from skisnow.contact._beam_operator import cantilever_compliance
from skisnow.contact._coupled_operator import CoupledOperator
from skisnow.contact._kernels import Convolution
from skisnow.contact._problem import _operator
from skisnow.contact._starts import rigid_start

__all__ = ["Multilevel", "multilevel_active_set"]

#: largest contact set solved by a dense Cholesky on the finest grid (n³/3 flops: ~0.3 ms at
#: 300 cells, ~2 ms at 600 on one core; larger sets go to MPRGP from the coarse solution)
_PDAS_MAX_CELLS = 500
#: active-set steps per grid before giving up
_PDAS_MAX_STEPS = 25
#: the grids: the finest coarsened by this factor while at least _COARSEST cells remain
_COARSEN = 8
_COARSEST = 64
#: a cell off A enters only when its gap is below −this × tol × scale (no flip-flop on round-off)
_ENTER = 1e-2
#: the cells a finer grid's steps may use: its start set widened by this many cells each side
#: (the prolonged edges are right to a fine cell or two; a coarse cell is _COARSEN fine cells);
#: cells beyond that the whole-grid check finds penetrating are added with the same margin
_MARGIN = _COARSEN
#: the cells of a set farther than this from its edges are factored once (their block), the
#: others (where the steps move the set) at every step: :mod:`skisnow.contact._pdas_kernel`
_DEEP = _COARSEN
#: whole-grid checks on the finest grid before giving up
_ROUNDS = 6

#: the compiled steps that give the coarsest grid's first set: tolerance and limit
_FIRST_TOL = 1e-3
_FIRST_STEPS = 40

_Result = tuple[np.ndarray, np.ndarray, float, float, int, list[float], bool, str, int]


class Multilevel(NamedTuple):
    """What :func:`multilevel_active_set` returns (see there)."""

    result: _Result | None
    start: np.ndarray | None
    candidates: np.ndarray | None
    fields: tuple[np.ndarray, np.ndarray] | None


def _dense(op: CoupledOperator, cells: np.ndarray) -> np.ndarray:
    """K_SS = K_snow,SS + A·K_beam,SS on the sorted ``cells`` of a strip grid (compiled)."""
    from skisnow.contact._flexible_kernel import coupled_block

    snow = op.snow
    assert isinstance(snow, Convolution) and snow.kernel is not None
    side, d, u, v = op.beam.generators
    out = np.empty((cells.size, cells.size))
    coupled_block(snow.kernel, snow.shape[0], cells, side, d, u, v, op.cell_area, out)
    return out


def _prolong_set(act: np.ndarray, p: np.ndarray | None, f: int) -> np.ndarray:
    """A coarse contact set on the grid ``f`` times finer, its edges placed where the coarse
    pressure extrapolates to zero as a contact edge does, p ∝ √(distance) (p² linear through
    the edge cell and its inner neighbour), within the cell beyond the edge cell."""
    fine = np.repeat(act, f)
    if p is None or p.size != act.size:
        return fine
    q = np.where(act, p, 0.0) ** 2
    m = act.size
    edge = act & ~(np.r_[act[1:], True] & np.r_[True, act[:-1]])  # a neighbour off the set
    for k in np.flatnonzero(edge).tolist():
        for out, inner in ((k + 1, k - 1), (k - 1, k + 1)):  # a right edge, then a left one
            if not (0 <= out < m and 0 <= inner < m) or act[out] or not act[inner]:
                continue
            drop = q[inner] - q[k]
            reach = q[k] / drop if drop > 0 else 0.5  # coarse cells beyond the centre of k
            reach = min(max(reach, 0.0), 1.0)
            # fine cells of k and of the cell beyond: in contact up to the extrapolated edge
            lo, hi = min(k, out) * f, (max(k, out) + 1) * f
            centre = (np.arange(lo, hi) + 0.5) / f - 0.5  # in coarse cells
            fine[lo:hi] = (centre - k) * (out - k) < reach
    return fine


def _widen(mask: np.ndarray, r: int) -> np.ndarray:
    """The cells within ``r`` cells of a True cell of ``mask``."""
    c = np.concatenate([[0], np.cumsum(mask)])
    i = np.arange(mask.size)
    return c[np.minimum(i + r + 1, mask.size)] > c[np.maximum(i - r, 0)]


def _active_set_steps(
    kss: np.ndarray,
    h: np.ndarray,
    xi: np.ndarray,
    act: np.ndarray,
    total: float,
    *,
    threshold: float,
    scale: float,
    max_cells: int,
    history: list[float],
    seen: list[int],
    cells: np.ndarray,
) -> tuple[np.ndarray, np.ndarray | None, float, float, int, bool]:
    """Primal–dual active-set steps (Hintermüller et al. 2002) on the cells of a dense block.

    ``kss`` is K on the cells S (``cells``: their grid indices), ``h``, ``xi`` and ``act`` (the
    contact set) are on S. Each step solves K_AA p_A + h_A = δ + θξ_A with Σp_A = total,
    Σξ_A p_A = 0 (a block Cholesky factorisation: the set's interior factored once,
    :mod:`skisnow.contact._pdas_kernel`), computes the gap λ on S (one dense product) and moves
    every cell whose sign is wrong (a cell enters when λ < −``threshold``); compiled
    (:func:`skisnow.contact._pdas_kernel.pdas_dense`). Returns the set, the pressure on S (None
    before the first solve), δ, θ, the steps taken and whether the set repeated (the KKT point
    on S); False on a cycle (a set in ``seen``, hashes of the sets solved), a set larger than
    ``max_cells`` (or of fewer than 2 cells), a system not positive definite or too many steps.
    """
    from skisnow.contact import _pdas_kernel as pk

    act = np.array(act, dtype=bool)
    keys = np.zeros(len(seen) + _PDAS_MAX_STEPS, dtype=np.uint64)
    keys[: len(seen)] = seen
    hist = np.empty(_PDAS_MAX_STEPS)
    p_s, a, b, steps, status, n_seen, n_hist = pk.pdas_dense(
        *pk.lapack(), kss, h, xi, act, float(total), float(threshold), float(scale),
        int(max_cells), _PDAS_MAX_STEPS, np.asarray(cells, dtype=np.int64), _DEEP, keys,
        len(seen), hist, 0,
    )  # fmt: skip
    seen[:] = keys[:n_seen].tolist()
    history += hist[:n_hist].tolist()
    return act, (p_s if steps else None), float(a), float(b), int(steps), status == pk.CONVERGED


def _first_set(kss: np.ndarray, snow: Convolution, h: np.ndarray, xi: np.ndarray,
               p0: np.ndarray, total: float) -> np.ndarray:  # fmt: skip
    """The coarsest grid's first contact set: the support after a few compiled Polonsky–Keer
    steps on the dense K_snow + K_beam (``kss``, every cell) from the rigid-hull start (the
    hull's support is several times the contact, and active-set steps from it cycle: measured 25
    steps without converging on the classic on the stone), or {p − λ/K(0) > 0} if those steps
    fail."""
    from skisnow.contact import _pk_kernel as pk
    from skisnow.contact._candidates import _whole_dense
    from skisnow.contact._polonsky_keer import plane_fit

    m = _whole_dense(snow)[1]  # the snow's circulant inverse, float32 (cached with the grid)
    p, *_, status = pk.pk_dense(kss, m, True, h, xi, p0, pk.MOMENT, float(total), _FIRST_TOL,
                                _FIRST_STEPS, snow.self_influence)  # fmt: skip
    if status in (pk.SUCCESSFUL, pk.MAX_STEPS, pk.EXACT) and (p > 0).sum() >= 2:
        return p > 0.0
    g = kss @ p0 + h
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
) -> Multilevel:
    """The flexible ski on a strip grid by active-set steps on nested grids.

    The contact set is found on grids coarsened by 4 (cell averages of the stations, of z0 +
    w_boot and of EI; down to 256 cells), starting on the coarsest from the compiled steps of
    :func:`_first_set`; each grid's set, repeated onto the next finer one, starts the steps
    there, so the finest grid (the problem of :func:`~skisnow.contact.solve_flexible`) needs
    only the few steps that move the contact edges by a cell or two. The steps of a grid use
    the dense coupled operator on its candidate cells only (the start set widened by
    :data:`_MARGIN` cells; every cell on the coarsest grid); on the finest grid the gap is then
    checked on the whole grid (one FFT, one beam product) and penetrating cells are added, so
    the answer is the KKT point of the whole grid.

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
    Multilevel
        ``result``: the result tuple of :func:`~skisnow.contact._mprgp.active_set_cg` (None if
        the finest grid did not converge: a contact set too large for the dense Cholesky, a
        cycle); ``fields``: with it, the snow displacement and the beam deflection [m] of its
        pressure. Else ``start``: the pressure of the finest grid solved, repeated onto ``x``
        [Pa] (a start for MPRGP; None if no grid was solved) and ``candidates``: the finest
        grid's candidate cells (its start set widened; None if it was not reached).
    """
    n = x.size
    sizes = [n]
    while sizes[0] % _COARSEN == 0 and sizes[0] // _COARSEN >= _COARSEST:
        sizes.insert(0, sizes[0] // _COARSEN)
    if len(sizes) == 1:
        return Multilevel(None, None, None, None)
    act: np.ndarray | None = None
    p_coarse: np.ndarray | None = None
    u_max = 0.0
    history: list[float] = []
    n_steps = 0
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
        snow = lop.snow
        assert isinstance(snow, Convolution)
        xic = xc - load_position
        total = load / lop.cell_area
        kss = None
        if act is None:
            cand = np.ones(m, dtype=bool)
            kss = _dense(lop, np.arange(m))
            p0 = rigid_start(hc, xic, total, True, snow.self_influence, 1)
            act = _first_set(kss, snow, hc, xic, p0, total)
            u_max = float(np.abs(snow(p0)).max())
        else:
            act = _prolong_set(act, p_coarse, m // act.size)
            cand = _widen(act, _MARGIN)
        ptp = float(np.ptp(hc))
        seen: list[int] = []
        p = None
        if m == n and act.sum() > _PDAS_MAX_CELLS:
            break  # too large for the dense factorisation: MPRGP from the coarse solution
        for _ in range(_ROUNDS):
            cells = np.flatnonzero(cand)
            if kss is None or kss.shape[0] != cells.size:
                kss = _dense(lop, cells)
            scale = ptp + u_max + 1e-300
            act_s, p_s, a, b, steps, ok = _active_set_steps(
                kss, hc[cells], xic[cells], act[cells], total, threshold=_ENTER * tol * scale,
                scale=scale, max_cells=_PDAS_MAX_CELLS if m == n else m, history=history,
                seen=seen, cells=cells,
            )  # fmt: skip
            n_steps += steps
            act = np.zeros(m, dtype=bool)
            act[cells] = act_s
            if p_s is not None:
                p = np.zeros(m)
                p[cells] = p_s
            if not ok or p is None:
                break
            if m < n:
                break  # a coarse grid only gives the next one its start
            # the finest grid: the gap on every cell
            u = snow(p)
            u_max = float(np.abs(u).max())
            w = lop.beam(p * lop.cell_area)
            g = u + w + hc
            lam = g - a - b * xic
            scale = ptp + u_max + 1e-300
            missed = ~act & (lam < -_ENTER * tol * scale)
            if missed.any():
                act |= missed
                cand |= _widen(missed, _MARGIN)
                kss = None
                continue
            on = float(np.abs(lam[act]).max())
            off = -min(float(lam[~act].min(initial=0.0)), 0.0)
            history.append(max(on, off) / scale)
            if history[-1] > tol:
                break
            message = (
                f"converged: max |gap residual| = {history[-1]:.2e} ≤ {tol:.1e} "
                f"(primal–dual active set, {n_steps} steps)"
            )
            result = (p, g, float(a), float(b), n_steps, history, True, message, n_steps)
            return Multilevel(result, None, None, (u, w))
        if p is not None:
            p_coarse = p
    start = None
    if p_coarse is not None:  # the finest solved grid's pressure, on the finest grid
        f = n // p_coarse.size
        fine = (np.arange(n) + 0.5) / f - 0.5
        start = np.interp(fine, np.arange(p_coarse.size), p_coarse)
        start *= _prolong_set(p_coarse > 0, p_coarse, f)
    return Multilevel(None, start, cand if m == n else None, None)
