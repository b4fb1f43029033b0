"""Elastic–perfectly-plastic flat-ice contact: Hertz limit, rigid-plastic limit, KKT."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.contact.reference import hertz_sphere
from skisnow.micro import (
    elastoplastic_contact,
    flat_plastic_area,
    ice_base_modulus,
    make_topography,
)


def _bump(n: int = 96, dx: float = 1e-6, radius: float = 1e-3) -> object:
    x = (np.arange(n) - n / 2 + 0.5) * dx
    return make_topography(-(x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius), dx=dx)


def test_elastic_limit_is_hertz() -> None:
    t = _bump()
    e, p = 1e9, 2e5
    res = elastoplastic_contact(t, pressure=p, hardness=np.inf, modulus=e)
    hz = hertz_sphere(p * (96e-6) ** 2, 1e-3, modulus=e)
    assert res.converged
    # peak pressure at the central cell (not the exact centre, 0.5 px off): 1 %
    assert res.pressure.max() == pytest.approx(hz.max_pressure, rel=1e-2)
    # contact area counted in whole 1 µm cells on a ~17 µm radius: within 5 %
    assert res.fractional_area * (96e-6) ** 2 == pytest.approx(
        np.pi * hz.contact_radius**2, rel=5e-2
    )
    assert res.plastic_fraction == 0.0


def test_rigid_plastic_limit_is_the_bearing_area() -> None:
    t = _bump()
    p, h = 2e5, 2e6
    # E' = 100 GPa (50× ice on UHMWPE), a stiff body: the tolerance is tightened as for the
    # elastic–plastic rim every pressure step counts
    res = elastoplastic_contact(t, pressure=p, hardness=h, modulus=1e11, tol=1e-11)
    assert res.converged
    proj, _ = flat_plastic_area(t, pressure=p, hardness=h)
    assert proj == pytest.approx(p / h, rel=1e-12)
    # a stiff body: contact ≈ the highest pixels at H; the rim of the patch carries less
    # than H (elastic), which adds a ring of cells: measured +0.7 %, allow 1 %
    assert res.fractional_area == pytest.approx(p / h, rel=1e-2)
    assert res.plastic_fraction > 0.9


def test_complementarity_and_balance_on_a_grind() -> None:
    from skisnow.micro import grind_preset, lowpass

    t = lowpass(grind_preset("S1", size=200e-6, dx=2e-6, seed=1))
    p, h = 20e3, 15.9e6
    res = elastoplastic_contact(t, pressure=p, hardness=h)
    assert res.converged
    assert res.mean_pressure == pytest.approx(p, rel=1e-6)
    scale = np.ptp(t.heights)
    pr, g = res.pressure, res.gap
    assert pr.min() >= 0 and pr.max() <= h
    free = (pr > 0) & (pr < h)
    assert np.all(np.abs(g[free]) < 1e-6 * scale)  # in contact and elastic: g = 0
    assert np.all(g[pr == 0] > -1e-6 * scale)  # no pressure: no overlap
    assert np.all(g[pr >= h] < 1e-6 * scale)  # plastic: overlap allowed, no gap
    assert res.fractional_area >= p / h  # elastic points carry less than H
    assert 1.9e9 < ice_base_modulus() < 1.95e9  # ice 9.5 GPa/0.31 on UHMWPE 840 MPa/0.46


def test_status_and_the_partial_result_when_the_inner_solves_stop_early() -> None:
    from skisnow import ConvergenceError, SolverStatus

    t = _bump(n=32)
    kw = dict(pressure=2e5, hardness=2e6, modulus=1e9)
    res = elastoplastic_contact(t, max_iter=1, **kw)
    assert not res.converged and res.status is SolverStatus.MAX_STEPS_REACHED
    with pytest.raises(ConvergenceError) as info:
        elastoplastic_contact(t, max_iter=1, raise_on_failure=True, **kw)
    assert isinstance(info.value.result, type(res))
    assert info.value.status is SolverStatus.MAX_STEPS_REACHED
    ok = elastoplastic_contact(t, **kw)
    assert ok.converged and ok.status is SolverStatus.SUCCESSFUL
