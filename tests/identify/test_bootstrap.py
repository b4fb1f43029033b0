"""The parametric bootstrap of an identification (:func:`skisnow.identify.bootstrap_bands`):
its z0 scatter is taken modulo the line the bench cannot see (an invariance), it widens the
bands by the replicates' scatter exactly where the bench determines z0, and a simulated bench
reproduces the identified ski's loaded profiles at the bench's stations."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import skisnow.identify._identify as ident
from skisnow.bench import run_bench
from skisnow.identify import bootstrap_bands, identify_ski
from skisnow.identify._bootstrap import _simulated_bench
from skisnow.ski import solve_beam

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def fitted():
    bench = run_bench("classic", masses=[20, 40, 60], load_positions=[-0.12], dx=0.01,
                      noise=5e-6, seed=1)  # fmt: skip
    return bench, identify_ski(bench, n_stiffness=20, max_nfev=10)


def _replicates(monkeypatch, res, shapes):
    """Make every replicate's identification return the fit with its z0 plus the next shape."""
    it = iter(shapes)

    def fake(_bench, **_kw):
        s = res.ski
        z = np.asarray(s.camber_values) + next(it)(np.asarray(s.camber_x))
        return dataclasses.replace(res, ski=dataclasses.replace(s, camber_values=z))

    monkeypatch.setattr(ident, "identify_ski", fake)


def test_a_line_is_invisible(monkeypatch, fitted) -> None:
    bench, res = fitted
    _replicates(monkeypatch, res, [lambda x: 3e-5 + 2e-5 * x, lambda x: -1e-5 * x])
    out = bootstrap_bands(res, bench, replicates=2)
    np.testing.assert_allclose(out.ski.camber_sd, res.ski.camber_sd, rtol=1e-6, atol=1e-9)
    assert out.bootstrap[0] == 2


def test_the_replicates_scatter_widens_determined_stations_only(monkeypatch, fitted) -> None:
    bench, res = fitted
    bump = lambda x: 2e-5 * np.cos(np.pi * x / 0.5)  # noqa: E731
    _replicates(monkeypatch, res, [bump, lambda x: -bump(x)])
    out = bootstrap_bands(res, bench, replicates=2)
    s0, s1 = np.asarray(res.ski.camber_sd), np.asarray(out.ski.camber_sd)
    det = np.asarray(res.ski.camber_determined, dtype=bool)
    np.testing.assert_array_equal(s1[~det], s0[~det])
    x = np.asarray(res.ski.camber_x)[det]
    a = np.stack([np.ones(x.size), x], axis=1)
    w = 1.0 / s0[det]
    b = bump(x)
    dev = b - a @ np.linalg.lstsq(a * w[:, None], b * w, rcond=None)[0]
    np.testing.assert_allclose(s1[det], np.hypot(s0[det], np.abs(dev)), rtol=1e-6)
    np.testing.assert_array_equal(out.ski.stiffness_log_sd, res.ski.stiffness_log_sd)


def test_the_simulated_bench_is_the_identified_ski_plus_its_noise(fitted) -> None:
    bench, res = fitted
    label = bench.ski_name(None)
    sim = _simulated_bench(res, bench, label, seed=5)
    t = sim.table
    for m in (20, 60):
        g = t[t.mass_kg == m]
        x = g.x_mm.to_numpy() * 1e-3
        h = solve_beam(res.ski, mass=m, load_position=-0.12, boot_length=0.1,
                       contact="continuous", n_elements=800).sample(x)  # fmt: skip
        resid = g.height_mm.to_numpy() * 1e-3 - h
        # the noise of the case's σ (about 5 µm): rms within 25 % on ~180 stations
        assert abs(np.sqrt(np.mean(resid**2)) / res.noise - 1.0) < 0.25


def test_too_few_replicates_is_an_input_error(fitted) -> None:
    from skisnow import InputError

    bench, res = fitted
    with pytest.raises(InputError, match="replicates"):
        bootstrap_bands(res, bench, replicates=1)
