"""The Polonsky–Keer core on its own: the hardness cap against rigid-plastic limits, KKT,
the operator seam (any compliance operator), and the status of every result."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import ConvergenceError, InputError, SolverStatus
from skisnow.contact import (
    CellOperator,
    PolonskyKeerResult,
    line_convolution,
    polonsky_keer,
    reference,
    solve_contact,
    strip_convolution,
    surface_convolution,
)


def cells(n: int, lo: float, hi: float) -> np.ndarray:
    dx = (hi - lo) / n
    return lo + (np.arange(n) + 0.5) * dx


def _punch(n: int = 200, a: float = 1e-3, modulus: float = 1e9, delta: float = 1e-6):
    """A rigid flat punch of half-width a (the grid is its face) in plane strain, pushed δ."""
    x = cells(n, -a, a)
    op = CellOperator(line_convolution(n, 2 * a / n, modulus=modulus, reference_length=0.1))
    h = np.zeros(n)
    target = np.full(n, delta)
    return x, op, h, target


def test_elastic_punch_is_the_analytic_one() -> None:
    # the uncapped core under displacement control: the plane-strain flat punch (Johnson §2.8),
    # cell averages of W'/(π √(a² − x²)) away from the two edge cells
    x, op, h, target = _punch()
    res = polonsky_keer(op, h, p0=np.zeros_like(h), control="displacement", target=target,
                        tol=1e-12)  # fmt: skip
    assert res.status is SolverStatus.SUCCESSFUL
    dx = x[1] - x[0]
    ref = reference.flat_punch(res.pressure.sum() * dx, 1e-3, modulus=1e9)
    edges = np.append(x - dx / 2, x[-1] + dx / 2)
    inner = slice(5, -5)
    np.testing.assert_allclose(res.pressure[inner], ref.cell_average(edges)[inner], rtol=2e-2)


def test_fully_plastic_punch_carries_the_hardness_everywhere() -> None:
    # H below the smallest elastic punch pressure (at the centre, W'/(π a)): every cell of the
    # face yields, p = H exactly, and the gap is closed or overlapping (g ≤ 0) everywhere
    _, op, h, target = _punch()
    elastic = polonsky_keer(op, h, p0=np.zeros_like(h), control="displacement", target=target)
    hardness = 0.5 * elastic.pressure.min()
    res = polonsky_keer(op, h, p0=np.zeros_like(h), control="displacement", target=target,
                        hardness=hardness)  # fmt: skip
    assert res.status is SolverStatus.SUCCESSFUL
    assert np.array_equal(res.pressure, np.full_like(h, hardness))
    assert np.all(res.displacement + h - target <= 0.0)


def test_partly_plastic_punch_satisfies_the_box_complementarity() -> None:
    # H between the centre and the edge pressures: plastic at the edges, elastic in the middle
    x, op, h, target = _punch()
    elastic = polonsky_keer(op, h, p0=np.zeros_like(h), control="displacement", target=target)
    hardness = 1.5 * elastic.pressure.min()
    res = polonsky_keer(op, h, p0=np.zeros_like(h), control="displacement", target=target,
                        hardness=hardness, tol=1e-12)  # fmt: skip
    assert res.converged
    p, g = res.pressure, res.displacement + h - target
    assert p.min() >= 0.0 and p.max() <= hardness
    plastic, free = p == hardness, (p > 0) & (p < hardness)
    assert plastic[0] and plastic[-1] and free[x.size // 2]
    assert np.all(g[plastic] <= 1e-9 * 1e-6)  # p = H ⇒ g ≤ 0
    assert np.max(np.abs(g[free])) <= 1e-9 * 1e-6  # 0 < p < H ⇒ g = 0
    # the cap can only lower the force at a given approach
    assert p.sum() < elastic.pressure.sum()


def test_rigid_plastic_sphere_is_the_geometric_bearing_area() -> None:
    # A sphere pushed δ into a half-space of hardness H so low that the elastic displacement
    # (≤ H·Σ|K|) stays below the distance of every height level from δ: the plastic contact is
    # the geometric overlap {h < δ}, p = H there and 0 elsewhere (Abbott–Firestone bearing
    # area), the force H·|A| exactly.
    n, dx, radius = 48, 1e-6, 1e-3
    x = (np.arange(n) - n / 2 + 0.5) * dx
    h = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius)
    conv = surface_convolution((n, n), dx, dx, modulus=1e9)
    levels = np.unique(h)
    k = np.searchsorted(levels, 2e-8)  # r ≈ 6 µm: about 120 cells
    delta = 0.5 * (levels[k] + levels[k + 1])  # halfway between two height levels
    margin = 0.5 * (levels[k + 1] - levels[k])
    hardness = 0.5 * margin / float(np.abs(conv.kernel).sum())
    op = CellOperator(conv)
    res = polonsky_keer(op, h.ravel(), p0=np.zeros(n * n), control="displacement",
                        target=np.full(n * n, delta), hardness=hardness)  # fmt: skip
    assert res.converged
    overlap = (h < delta).ravel()
    assert overlap.sum() > 20
    assert np.array_equal(res.pressure, np.where(overlap, hardness, 0.0))


def test_infinite_hardness_is_no_cap() -> None:
    x, op, h, target = _punch()
    h = 2e-6 * (x / x[-1]) ** 2
    kw = dict(p0=np.zeros_like(h), control="displacement", target=target)
    a = polonsky_keer(op, h, **kw)
    b = polonsky_keer(op, h, hardness=np.inf, **kw)
    assert np.array_equal(a.pressure, b.pressure) and a.iterations == b.iterations


def test_hardness_needs_displacement_control() -> None:
    _, op, h, _ = _punch()
    with pytest.raises(InputError, match="displacement"):
        polonsky_keer(op, h, p0=np.ones_like(h), control="load", total=1.0, hardness=1e6)


class DenseOperator:
    """The seam: a compliance operator that is only a matrix (no add_columns), e.g. what a
    coupled beam + half-space operator looks like to the core."""

    def __init__(self, matrix: np.ndarray) -> None:
        self.matrix = matrix

    @property
    def self_influence(self) -> float:
        return float(self.matrix[0, 0])

    def __call__(self, v: np.ndarray) -> np.ndarray:
        return self.matrix @ v


def test_any_operator_with_moment_balance_gives_the_same_answer() -> None:
    # a cambered strip under force and moment balance: the dense-matrix operator (no direct
    # columns, no preconditioner) and the FFT operator (both) reach the same pressure
    n, dx = 400, 2e-3
    x = cells(n, -0.4, 0.4)
    h = 1e-4 * (1 - np.cos(2 * np.pi * x / 0.8)) + 2e-5 * x
    conv = strip_convolution(n, dx, 0.044, modulus=2e8)
    idx = np.arange(n)
    matrix = conv.kernel[idx[:, None] - idx[None, :] + n - 1]
    arm = x - (-0.05)
    total = 500.0 / (dx * 0.044)
    p0 = np.full(n, total / n)
    kw = dict(p0=p0, control="moment", total=total, arm=arm, tol=1e-12)
    a = polonsky_keer(DenseOperator(matrix), h, **kw)
    b = polonsky_keer(CellOperator(conv), h, preconditioner=CellOperator(conv.inverse()), **kw)
    assert a.converged and b.converged
    np.testing.assert_allclose(a.pressure, b.pressure, rtol=0, atol=1e-8 * b.pressure.max())
    for r in (a, b):  # force and moment balance, complementarity
        assert r.pressure.sum() == pytest.approx(total, rel=1e-12)
        assert abs(arm @ r.pressure) <= 1e-10 * total * 0.8
        gap = h + r.displacement - r.translation - r.rotation * arm
        assert gap.min() >= -1e-10 * np.ptp(h)
        assert np.abs(gap[r.pressure > 0]).max() <= 1e-8 * np.ptp(h)


def test_status_when_the_iteration_limit_is_reached() -> None:
    x = cells(256, -0.5, 0.5)
    h = 1e-4 * (x / 0.5) ** 2
    kw = dict(load=300.0, load_position=0.0, modulus=2e8, edge_contact="allow")
    sol = solve_contact(x, h, max_iter=2, **kw)
    assert sol.status is SolverStatus.MAX_STEPS_REACHED and not sol.converged
    assert sol.iterations == 2
    with pytest.raises(ConvergenceError) as info:
        solve_contact(x, h, max_iter=2, raise_on_failure=True, **kw)
    assert info.value.result is not None
    assert info.value.result.status is SolverStatus.MAX_STEPS_REACHED
    assert info.value.status is SolverStatus.MAX_STEPS_REACHED
    ok = solve_contact(x, h, **kw)
    assert ok.status is SolverStatus.SUCCESSFUL and ok.converged


def test_status_of_a_nonfinite_operator() -> None:
    _, _, h, target = _punch(n=32)
    bad = DenseOperator(np.full((32, 32), np.nan))
    bad.matrix[np.diag_indices(32)] = 1e-12
    res = polonsky_keer(bad, h, p0=np.ones(32), control="displacement", target=target)
    assert isinstance(res, PolonskyKeerResult)
    assert res.status is SolverStatus.NONFINITE and not res.converged


def test_cell_operator_on_a_footprint_is_the_restriction() -> None:
    # K on a subset of a 2D grid's cells (a ski's outline) is the rows and columns of K on the
    # whole grid; its direct columns agree with its products
    conv = surface_convolution((12, 6), 1e-3, 2e-3, modulus=1e8)
    cells = np.flatnonzero((np.add.outer(np.arange(12), np.arange(6)) % 3 != 0).ravel())
    op = CellOperator(conv, cells)
    v = np.random.default_rng(3).random(cells.size)
    grid = np.zeros(72)
    grid[cells] = v
    np.testing.assert_allclose(op(v), conv(grid.reshape(12, 6)).ravel()[cells], rtol=1e-12)
    some = np.array([0, 5, cells.size - 1])
    out = np.zeros(cells.size)
    op.add_columns(out, some, v[some])
    w = np.zeros(cells.size)
    w[some] = v[some]
    np.testing.assert_allclose(out, op(w), rtol=1e-9, atol=1e-12 * np.abs(out).max())
    assert op.self_influence == conv.self_influence
