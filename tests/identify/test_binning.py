"""The identification compares each bin's data mean with the same mean of the model: against an
independent bench (finite differences, contact at every node), stations finer than the bins."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from skisnow.identify._cases import load_cases
from skisnow.identify._model import _bin_average, _bins, _design, _Problem


def test_the_bin_average_is_the_bins_mean_and_not_the_value_at_the_mean_position():
    rng = np.random.default_rng(4)
    x = np.sort(rng.uniform(-0.5, 0.5, 400))
    h = rng.normal(size=x.size)
    xb, hb, counts, *_ = _bins(x, h, 0.005)
    avg = _bin_average(x, 0.005)
    assert np.allclose(avg @ h, hb, rtol=0, atol=1e-15)
    assert np.allclose(avg @ x, xb, rtol=0, atol=1e-15)
    assert np.allclose(np.asarray(avg.sum(axis=1)).ravel(), 1.0)
    # a parabola c x²: the bin mean exceeds the value at x̄ by c var(x) in every bin
    c = 3.0
    var = avg @ (x**2) - xb**2
    assert np.allclose(avg @ (c * x**2) - c * xb**2, c * var, rtol=1e-9, atol=1e-15)
    assert np.max(var[counts >= 2]) > 0


@pytest.mark.slow
def test_the_binned_model_meets_an_independent_bench_where_the_profile_bends():
    """The spline ski of the fit's own basis (so the basis is exact) on the independent reference
    bench at 0.5 mm, 2 mm stations in 5 mm bins (the full plan's): the fit's forward model at its
    parameters meets the bench within the bench's own and the 10 mm mesh's error (0.53 and
    0.37 µm rms on issue 25's full plan, ``benchmarks/bench_identify_mesh.py``) when each bin's
    model is the mean over its stations; evaluated at the bins' mean positions it misses by
    about 2 µm rms (9 µm at the tip: the shovel's curvature across a bin)."""
    from skisnow.bench import issue25_ski, reference_bench
    from skisnow.identify._cases import _bench_cases
    from skisnow.identify._start import _camber_fit

    true = issue25_ski()
    nodes = np.linspace(true.x_tail, true.x_tip, 208)  # 10 mm elements, the fit's default
    shell = _Problem([], nodes, 60, 210, 1.0)
    xs = np.linspace(true.x_tail, true.x_tip, 4001)
    theta_e = np.linalg.lstsq(_design(shell.t_e, xs), np.log(true.stiffness(xs)), rcond=None)[0]
    p = np.concatenate([theta_e, _camber_fit(shell, xs) @ true.free_camber(xs)])
    te, tz = shell.split(p)
    spline = dataclasses.replace(
        true, stiffness_x=tuple(xs), stiffness_values=tuple(np.exp(_design(shell.t_e, xs) @ te)),
        camber_x=tuple(xs), camber_values=tuple(_design(shell.t_z, xs) @ tz),
    )  # fmt: skip
    bench = reference_bench(spline, masses=(20.0, 80.0), load_positions=(-0.12,),
                            station_step=0.002, dx=0.5e-3)  # fmt: skip
    raw = _bench_cases(bench, bench.ski_name(None))
    cases, *_ = load_cases(raw, nodes, 0.10, 0.005)
    problem = _Problem(cases, nodes, 60, 210, 1.0)
    r, _ = problem.evaluate(p, jacobian=False)
    w = np.concatenate([c.w for c in cases])
    counts = w**2
    binned = r / w  # model - data per bin [m]
    rms = float(np.sqrt(np.sum(counts * binned**2) / counts.sum()))
    assert rms < 1.0e-6  # measured 0.65 µm
    # the same model at the bins' mean positions (the fit before issue 25's seventh pass)
    at_centre = [dataclasses.replace(c, stations=None, average=None) for c in cases]
    for c, cc in zip(cases, at_centre, strict=True):
        from skisnow.identify._model import _hermite_matrix

        object.__setattr__(cc, "hermite", _hermite_matrix(nodes, c.x))
    old = _Problem(at_centre, nodes, 60, 210, 1.0)
    r_old, _ = old.evaluate(p, jacobian=False)
    rms_old = float(np.sqrt(np.sum(counts * (r_old / w) ** 2) / counts.sum()))
    assert rms_old > 1.5e-6  # measured 2.07 µm
    assert rms_old > 2.5 * rms


def test_one_station_per_bin_leaves_the_model_rows_bitwise_unchanged():
    # a shop bench (stations every 10 mm, 5 mm bins): the bin mean of one station is the
    # station itself, so shop-plan fits are those of the model evaluated at x̄ (bit for bit)
    from skisnow.identify._model import _hermite_matrix

    nodes = np.linspace(-1.0, 1.0, 201)
    x = np.arange(-0.95, 0.95, 0.010) + 0.0013
    h = 1e-3 * np.cos(3 * x)
    (case,), *_ = load_cases([(40.0, -0.12, x, h)], nodes, 0.10, 0.005)
    assert np.array_equal(case.w, np.ones(x.size))
    assert abs(case.hermite - _hermite_matrix(nodes, case.x)).max() == 0.0
    problem = _Problem([case], nodes, 20, 40, 1e-5)
    assert np.array_equal(problem.phi_z_cases[0], _design(problem.t_z, case.x))
