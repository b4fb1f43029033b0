"""Property tests of solve_contact on random profiles: balance, complementarity, invariance."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from skisnow import UnsupportedLoadError
from skisnow.contact import contact_zones, solve_contact

N = 256
X = -1.0 + (np.arange(N) + 0.5) * 2.0 / N


@st.composite
def problems(draw):
    """A random smooth profile with raised ends, a load, a load point and a modulus."""
    k = draw(st.integers(1, 4))
    amps = draw(st.lists(st.floats(0.0, 2e-4), min_size=k, max_size=k))
    phases = draw(st.lists(st.floats(0.0, 2 * np.pi), min_size=k, max_size=k))
    h = 2e-3 * X**4 + sum(
        a * np.cos((i + 1) * np.pi * X + ph)
        for i, (a, ph) in enumerate(zip(amps, phases, strict=True))
    )
    h = h - h.min()
    load = draw(st.floats(20.0, 1200.0))
    xm = draw(st.floats(-0.4, 0.4))
    modulus = draw(st.floats(30e6, 3e9))
    model = draw(st.sampled_from(["strip", "line"]))
    return h, load, xm, modulus, model


SETTINGS = settings(
    max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True
)


def solve(h, load, xm, modulus, model, x=X):
    try:
        return solve_contact(
            x, h, load=load, load_position=xm, modulus=modulus, model=model, tol=1e-10
        )
    except UnsupportedLoadError as exc:
        assert "end of the profile" in str(exc)
        assume(False)


@SETTINGS
@given(problems())
def test_balance_and_complementarity(problem) -> None:
    h, load, xm, modulus, model = problem
    sol = solve(h, load, xm, modulus, model)
    assert sol.converged, sol.message
    # balance laws: restored exactly after every step, so round-off only (1e-8 relative)
    assert sol.total_force == pytest.approx(load, rel=1e-8)
    assert abs(sol.total_moment) <= 1e-8 * load * 2.0
    assert np.all(sol.pressure >= 0)
    # complementarity to the solver tolerance, relative to the penetration scale
    scale = np.ptp(sol.displacement) + abs(sol.translation) + 1e-12
    assert np.min(sol.gap) > -1e-5 * scale
    assert np.max(np.abs(sol.gap[sol.contact])) < 1e-5 * scale
    # the zones account for all of the load
    z = contact_zones(sol)
    assert z.total.force == pytest.approx(load, rel=1e-8)
    assert z.rear.load_share + z.front.load_share == pytest.approx(1.0, rel=1e-9)


@SETTINGS
@given(problems(), st.floats(-3.0, 3.0))
def test_shift_and_mirror_invariance(problem, shift) -> None:
    h, load, xm, modulus, model = problem
    sol = solve(h, load, xm, modulus, model)
    moved = solve(h, load, xm + shift, modulus, model, x=X + shift)
    mirrored = solve(h[::-1], load, -xm, modulus, model)
    # identical discrete problems up to round-off amplified by the iteration
    atol = 1e-7 * sol.pressure.max()
    assert np.allclose(moved.pressure, sol.pressure, rtol=0, atol=atol)
    assert np.allclose(mirrored.pressure[::-1], sol.pressure, rtol=0, atol=atol)
    assert mirrored.rotation == pytest.approx(-sol.rotation, rel=1e-5, abs=1e-12)
