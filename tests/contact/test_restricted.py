"""The restricted-operator solves equal the old whole-grid Polonsky–Keer solve (issue 29).

1D problems are solved on nested grids and on their candidate cells with the operator restricted
to them (dense and compiled, or by FFT over their span), the flexible ski's coarsest grid starts
from compiled steps on its dense K_snow + K_beam. Each case here is compared with the *old*
algorithm, ``candidates=False``: the Polonsky–Keer iteration (or, for the flexible ski, MPRGP)
on the whole grid by full-grid FFTs from the rigid-hull start — not with itself.

The measure is the solvers' own, Σ|Δp|/Σp (the load-weighted pressure error), at tolerance
1e-12 for both: 1e-9 of it is 1e-9 of the load misplaced. Pressures compared cell by cell are
worse conditioned (at the contact edges a gap flat to 1e-13 of the heights, where the old
iteration stops, still moves a cell's pressure by up to 2e-8 of the largest, measured on the
skate at 400 MPa), so the max-norm check is 1e-7.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.constants import STANDARD_GRAVITY
from skisnow.contact import STONE, effective_modulus, snow, solve_contact, solve_flexible
from skisnow.ski import camber_profile, get_ski

N = 4096


def _profile(ski: str, mass: float, xm: float) -> tuple[np.ndarray, np.ndarray]:
    s = get_ski(ski)
    edges = np.linspace(s.x_tail, s.x_tip, N + 1)
    x = 0.5 * (edges[1:] + edges[:-1])
    return camber_profile(ski, mass=mass, load_position=xm, x=x, source="beam")


def _rel1(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).sum() / np.abs(b).sum())


RIGID_CASES = [
    # (ski, kg, x_m [m], E_snow [Pa]): the benchmark case; soft snow with the kick zone of the
    # classic pressed down over its whole length; the skate at 400 MPa, touching near both ends
    pytest.param("classic", 60.0, -0.12, 100e6, id="classic-60kg-100MPa"),
    pytest.param("classic", 130.0, -0.12, 20e6, id="classic-130kg-20MPa-kick-down"),
    pytest.param("skate", 30.0, -0.12, 400e6, id="skate-30kg-400MPa-wide"),
]


@pytest.mark.parametrize("control", ["moment", "load"])
@pytest.mark.parametrize(("ski", "mass", "xm", "e_snow"), RIGID_CASES)
def test_rigid_strip_equals_the_whole_grid_solve(ski, mass, xm, e_snow, control) -> None:
    x, h = _profile(ski, mass, xm)
    kw = dict(load=mass * STANDARD_GRAVITY, load_position=xm,
              modulus=effective_modulus(snow(e_snow)), control=control, tol=1e-12)  # fmt: skip
    old = solve_contact(x, h, candidates=False, **kw)
    new = solve_contact(x, h, **kw)
    assert old.converged and new.converged
    assert _rel1(new.pressure, old.pressure) <= 1e-9
    assert np.abs(new.pressure - old.pressure).max() <= 1e-7 * old.pressure.max()
    assert np.array_equal(new.contact, old.contact)
    assert new.force_residual < 1e-12 and new.moment_residual < 1e-12
    if ski == "classic" and mass > 100:  # the kick zone touches down over its whole length
        k0, k1 = get_ski("classic").kick_zone
        assert new.contact[(x > k0) & (x < k1)].all()


def test_rigid_strip_contact_over_most_of_the_grid() -> None:
    # a nearly flat profile under a heavy load on soft snow: the contact covers ~90 % of the
    # stations, the candidates are most of the grid (the FFT path over their span)
    x = (np.arange(N) + 0.5) / N * 2.0 - 1.0
    h = 2e-3 * x**16
    kw = dict(load=3000.0, load_position=0.05, modulus=effective_modulus(snow(20e6)), tol=1e-12)
    old = solve_contact(x, h, candidates=False, **kw)
    new = solve_contact(x, h, **kw)
    assert 0.8 < new.contact.mean() < 0.99
    assert _rel1(new.pressure, old.pressure) <= 1e-9
    assert np.array_equal(new.contact, old.contact)


@pytest.mark.parametrize(
    ("ski", "mass", "xm", "e_snow"),
    [
        pytest.param("classic", 60.0, -0.07, 400e6, id="classic-400MPa"),
        pytest.param("classic", 30.0, -0.12, None, id="classic-stone"),
        pytest.param("skate", 30.0, -0.12, 100e6, id="skate-100MPa"),
        # contacts too large for the dense steps (581, 797 and 1151 cells): MPRGP on the
        # candidate cells from the coarse grids' solution
        pytest.param("classic", 60.0, -0.07, 100e6, id="classic-100MPa-mprgp"),
        pytest.param("skate", 60.0, -0.12, 20e6, id="skate-20MPa-mprgp"),
        pytest.param("classic", 60.0, -0.07, 20e6, id="classic-20MPa-mprgp"),
    ],
)
def test_flexible_equals_the_whole_grid_solve(ski, mass, xm, e_snow) -> None:
    s = get_ski(ski)
    x = np.linspace(s.x_tail, s.x_tip, N)
    e = effective_modulus(STONE) if e_snow is None else effective_modulus(snow(e_snow))
    kw = dict(load=mass * STANDARD_GRAVITY, load_position=xm, modulus=e, width=s.width)
    # MPRGP stops on the gap residual: at 1e-14 of the camber range it is where the active-set
    # steps end, at the KKT point (measured on the stone: 3e-6, 6e-8, 1e-8, 2e-10, 4e-11 at
    # 1e-10 ... 1e-14)
    old = solve_flexible(x, s.free_camber(x), s.stiffness(x), candidates=False, tol=1e-14, **kw)
    new = solve_flexible(x, s.free_camber(x), s.stiffness(x), tol=1e-12, **kw)
    assert old.converged and new.converged
    assert _rel1(new.contact.pressure, old.contact.pressure) <= 1e-9
    assert np.array_equal(new.contact.contact, old.contact.contact)


def test_flexible_without_nested_grids_equals_the_whole_grid_solve() -> None:
    # 1100 stations cannot be coarsened by 8: a few whole-grid MPRGP steps from the rigid-hull
    # start, then the candidate iteration with its own margin
    s = get_ski("skate")
    x = np.linspace(s.x_tail, s.x_tip, 1100)
    kw = dict(load=30 * STANDARD_GRAVITY, load_position=-0.12,
              modulus=effective_modulus(snow(100e6)), width=s.width, tol=1e-12)  # fmt: skip
    old = solve_flexible(x, s.free_camber(x), s.stiffness(x), candidates=False, **kw)
    new = solve_flexible(x, s.free_camber(x), s.stiffness(x), **kw)
    assert old.converged and new.converged
    assert _rel1(new.contact.pressure, old.contact.pressure) <= 1e-9
    assert np.array_equal(new.contact.contact, old.contact.contact)


def test_compiled_blocks_equal_the_operators() -> None:
    # the coupled block K_snow,SS + A·K_beam,SS assembled by the compiled kernel, and the beam
    # block applied in O(|S|) by its generators, against the operators themselves (the FFT
    # convolution and the cumulative-sum cantilever applied to unit vectors)
    from skisnow.contact import cantilever_compliance, strip_convolution
    from skisnow.contact._coupled_operator import CoupledOperator
    from skisnow.contact._flexible_kernel import beam_block_apply
    from skisnow.contact._flexible_pdas import _dense

    n, width = 400, 0.045
    x = (np.arange(n) + 0.5) / n * 2.0 - 1.0
    beam = cantilever_compliance(x, 40.0 + 20.0 * np.cos(2.0 * x), load_position=0.137)
    conv = strip_convolution(n, x[1] - x[0], width, modulus=effective_modulus(snow(100e6)))
    op = CoupledOperator(snow=conv, beam=beam, cell_area=(x[1] - x[0]) * width)
    cells = np.sort(np.random.default_rng(3).choice(n, 150, replace=False))  # both halves
    eye = np.eye(n)
    whole = op(eye)  # K applied to every unit vector (K is symmetric)
    k_ss = _dense(op, cells)
    assert np.array_equal(k_ss, k_ss.T)
    assert np.abs(k_ss - whole[np.ix_(cells, cells)]).max() <= 1e-12 * np.abs(whole).max()
    v = np.random.default_rng(4).random(cells.size)
    out = np.empty(cells.size)
    beam_block_apply(cells, *beam.generators, op.cell_area, v, out)
    ref = beam.block(cells) @ v * op.cell_area
    assert np.abs(out - ref).max() <= 1e-13 * np.abs(ref).max()
    # the one-vector path of the cantilever (compiled, on the grid) against the batched one
    f = np.random.default_rng(5).standard_normal(n)
    assert np.abs(beam(f) - beam(f[None, :])[0]).max() <= 1e-13 * np.abs(beam(f)).max()


def test_prolonged_set_places_a_contact_edge() -> None:
    # a coarse pressure with a contact edge's profile p ∝ √(x_e − x): carried onto a grid 8
    # times finer, the set ends at the last fine centre before the edge (np.repeat would end at
    # the coarse cell's boundary, up to 7 fine cells away)
    from skisnow.contact._flexible_pdas import _prolong_set

    for edge in (10.2, 10.45, 10.8):  # in coarse cells (centres at 0, 1, ...)
        xc = np.arange(16.0)
        p = np.sqrt(np.clip(edge - xc, 0.0, None))
        fine = _prolong_set(p > 0, p, 8)
        centres = (np.arange(fine.size) + 0.5) / 8 - 0.5
        last = centres[np.flatnonzero(fine)[-1]]
        assert last <= edge < last + 1 / 8


def test_compiled_active_set_steps_reach_the_kkt_point() -> None:
    # from a set far too wide (every cell: the interior factored first must be chosen again as
    # cells deep inside it leave), the compiled steps end on a set whose solution meets the KKT
    # conditions of the dense problem: p ≥ 0, λ ≥ 0, p·λ = 0, the two balances
    from skisnow.contact import _pdas_kernel as pk
    from skisnow.contact import cantilever_compliance, strip_convolution
    from skisnow.contact._coupled_operator import CoupledOperator
    from skisnow.contact._flexible_pdas import _dense

    n, width = 300, 0.045
    x = (np.arange(n) + 0.5) / n * 2.0 - 1.0
    dx = x[1] - x[0]
    beam = cantilever_compliance(x, 60.0, load_position=-0.05)
    conv = strip_convolution(n, dx, width, modulus=effective_modulus(snow(200e6)))
    op = CoupledOperator(snow=conv, beam=beam, cell_area=dx * width)
    k = _dense(op, np.arange(n))
    h = 1.5e-3 * (1.0 - x**2) ** 2 + 1e-4 * np.sin(9.0 * x)  # a camber pocket, wavy
    xi = x + 0.05
    total = 600.0 / op.cell_area
    act = np.ones(n, dtype=bool)
    seen, hist = np.zeros(64, dtype=np.uint64), np.empty(64)
    p, a, b, steps, status, _, _ = pk.pdas_dense(
        *pk.lapack(), k, h, xi, act, total, 0.0, 1.0, n, 60, np.arange(n), 8, seen, 0, hist, 0
    )
    assert status == pk.CONVERGED and steps > 2
    lam = k @ p + h - a - b * xi
    scale = np.ptp(h)
    assert p.min() >= 0.0 and lam.min() >= -1e-12 * scale
    assert np.abs(lam[p > 0]).max() <= 1e-12 * scale
    assert p.sum() == pytest.approx(total, rel=1e-12)
    assert abs(xi @ p) <= 1e-12 * total
    assert 2 < (p > 0).sum() < n - 10  # the set shrank a long way from every cell
