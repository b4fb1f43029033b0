"""The bench-plan prediction (skisnow.ski.predict_identification_uncertainty): the Fisher
information of the identification at a ski, its Cramér–Rao bound and the penalised covariance.

Physics checked: the Cramér–Rao bound scales with the noise σ; load cases only add
information (the bound of a plan never grows when cases are added, with the linearisation
point fixed); one mass at one position cannot separate EI from z0 (not identifiable); and the
predicted standard deviation is the spread of the penalised estimates over noise seeds of the
virtual bench (samples with Gaussian noise, binned as identify_ski bins them).
A coarse mesh (200 elements) keeps the tests fast; the prediction is built on the same mesh.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow._errors import InputError
from skisnow.bench import run_bench
from skisnow.identify import predict_identification_uncertainty
from skisnow.identify._bench_plan import fit_parameters, plan_problem, ski_parameters
from skisnow.identify._model import _design
from skisnow.ski import get_ski

N_EL = 200
USER = (-0.9, 0.85)  # the stations of the user bench (benchmarks/bench_identify.py)
FOUR = (20.0, 40.0, 60.0, 80.0)


@pytest.fixture(scope="module")
def classic():
    return get_ski("classic")


def predict(ski, masses, positions, noise, **kw):
    kw.setdefault("n_elements", N_EL)
    kw.setdefault("stations", USER)
    return predict_identification_uncertainty(ski, masses, positions, noise, **kw)


def test_cramer_rao_bound_scales_with_noise(classic):
    # at a fixed linearisation point J ∝ 1/σ, so F⁻¹ ∝ σ² and every standard deviation ∝ σ
    a = predict(classic, FOUR, (-0.12,), 5e-6, linearisation="projection", regularisation=10.0)
    b = predict(classic, FOUR, (-0.12,), 2e-5, linearisation="projection", regularisation=10.0)
    assert a.rank == b.rank
    assert b.ei_sd_crb / a.ei_sd_crb == pytest.approx(4.0, rel=1e-6)
    assert b.z0_sd_crb / a.z0_sd_crb == pytest.approx(4.0, rel=1e-6)
    assert a.ei_sd_crb > 0 and a.z0_sd_crb > 0


def test_adding_load_cases_never_loses_information(classic):
    # F of a plan is the sum over its load cases (independent noise): a larger plan's bound is
    # at most the smaller one's, for EI and for z0, and its rank is not lower
    kw = {"linearisation": "projection", "regularisation": 10.0}
    one = predict(classic, FOUR, (-0.12,), 1e-5, **kw)
    two = predict(classic, FOUR, (-0.12, -0.04), 1e-5, **kw)
    more = predict(classic, (*FOUR, 30.0, 50.0, 70.0), (-0.12, -0.04), 1e-5, **kw)
    for small, big in ((one, two), (two, more)):
        assert big.rank >= small.rank
        assert big.ei_sd_crb <= small.ei_sd_crb
        assert big.z0_sd_crb <= small.z0_sd_crb
    assert two.ei_sd_crb < 0.9 * one.ei_sd_crb  # a second position is new information


def test_one_mass_does_not_identify_ei(classic):
    # one profile: any change of EI is matched by z0 (h = z0 + deflection), so EI is not
    # identifiable: a null space of the Fisher information that the EI window sees
    one = predict(classic, (60.0,), (-0.12,), 1e-5, linearisation="projection")
    assert not one.ei_identifiable
    assert one.ei_sd_crb == np.inf
    assert one.null_dimension > 0
    four = predict(classic, FOUR, (-0.12,), 1e-5, linearisation="projection")
    assert four.ei_identifiable and np.isfinite(four.ei_sd_crb)
    assert four.null_dimension < one.null_dimension


def test_predicted_sd_is_the_spread_over_noise_seeds(classic):
    # Monte Carlo: virtual benches with seeded noise (1 mm samples, binned as the fit bins),
    # the penalised Gauss–Newton estimate from the noise-free fit p* at each; the spread of log
    # EI over the window and of z0 modulo a line over the stations against the prediction.
    # Sampling error: with N seeds the sample variance at a station has relative standard
    # deviation √(2/(N-1)); the mean over stations at most that (fully correlated stations),
    # so the rms sd's ratio has standard deviation ≤ 1/√(2(N-1)) = 0.11 for N = 40: the test
    # allows three of it. (Linearised estimates: the nonlinear fit from p* stays nearer p*,
    # the exact contact's kinks; see the README's bench-plan section.)
    lam, sigma, n_seeds = 10.0, 1e-5, 40
    pred = predict(classic, FOUR, (-0.12,), sigma, regularisation=lam)
    kw = {"masses": FOUR, "load_positions": (-0.12,), "n_elements": N_EL}
    base = plan_problem(classic, run_bench(classic, **kw), sigma, stations=USER, n_elements=N_EL)
    star = fit_parameters(base, ski_parameters(base, classic), lam).x
    _, jac = base.evaluate(star, jacobian=True)
    pen = base.penalty_matrix(lam)
    a = jac.T @ jac + pen.T @ pen
    x_ei = np.linspace(-0.45, 0.40, 86)
    x_z = np.linspace(USER[0] + 0.02, USER[1] - 0.02, 400)
    b_e, b_z = _design(base.t_e, x_ei), _design(base.t_z, x_z) @ base.q_z
    ei, z0 = [], []
    for seed in range(1, n_seeds + 1):
        bench = run_bench(classic, noise=sigma, seed=seed, **kw)
        r, _ = plan_problem(classic, bench, sigma, stations=USER, n_elements=N_EL).evaluate(
            star, jacobian=False
        )
        p = star + np.linalg.solve(a, -(jac.T @ r + pen.T @ (pen @ star)))
        ei.append(b_e @ p[: base.n_e])
        z = b_z @ p[base.n_e :]
        z0.append(z - np.polyval(np.polyfit(x_z, z, 1), x_z))
    spread_ei = np.sqrt(np.mean(np.var(ei, axis=0, ddof=1)))
    spread_z0 = np.sqrt(np.mean(np.var(z0, axis=0, ddof=1)))
    tol = 3.0 / np.sqrt(2 * (n_seeds - 1))
    assert spread_ei / pred.ei_sd == pytest.approx(1.0, abs=tol)
    assert spread_z0 / pred.z0_sd == pytest.approx(1.0, abs=tol)


def test_bad_plans_are_refused(classic):
    with pytest.raises(InputError, match="at least one mass"):
        predict(classic, (), (-0.12,), 1e-5)
    with pytest.raises(InputError, match="noise"):
        predict(classic, FOUR, (-0.12,), 0.0)
    with pytest.raises(InputError, match="not on the ski"):
        predict(classic, FOUR, (-3.0,), 1e-5)
    with pytest.raises(InputError, match="stations"):
        predict(classic, FOUR, (-0.12,), 1e-5, stations=(-0.1, 0.0))
