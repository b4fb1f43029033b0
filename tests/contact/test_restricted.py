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
