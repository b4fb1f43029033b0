"""The opt-in basin check of an identification (:mod:`skisnow.identify._basins`): its starts are
the posterior's weakest z0 directions (the largest z0 variance per standard deviation, computed
independently here), symmetric about the fit; the fit itself is kept; the warning fires exactly
for a near basin whose z0 differs by more than the band."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.bench import run_bench
from skisnow.identify import identify_ski
from skisnow.identify._basins import BASIN_CHI2, Basin, _z0_rows, basin_check, basin_warning
from skisnow.identify._model import _design

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def bench():
    return run_bench("classic", masses=[20, 40, 60], load_positions=[-0.12], dx=0.01,
                     noise=5e-6, seed=1)  # fmt: skip


def test_the_warning_needs_a_near_basin_that_differs_by_more_than_the_band() -> None:
    band = 10e-6
    far = Basin(start="+1", delta_cost=BASIN_CHI2 + 1.0, z0_difference=50e-6, misfit=1.0)
    near_small = Basin(start="-1", delta_cost=2.0, z0_difference=8e-6, misfit=1.0)
    lower_big = Basin(start="+2", delta_cost=-30.0, z0_difference=25e-6, misfit=1.0)
    assert basin_warning((), band) is None
    assert basin_warning((far, near_small), band) is None
    text = basin_warning((far, near_small, lower_big), band)
    assert text is not None and "+2" in text and "25 µm" in text and "±10 µm" in text


class _Frozen:
    """A stand-in Levenberg–Marquardt result: the parameters it is given and their residuals."""

    def __init__(self, problem, p):
        self.x = p
        self.fun, _ = problem.evaluate(p, jacobian=False)


@pytest.fixture(scope="module")
def fitted(bench):
    """The default fit of ``bench`` with its problem, LM result and posterior."""
    import skisnow.identify._identify as ident

    grabbed: dict = {}
    post0, problem0 = ident.posterior, ident._Problem

    def spy(sol, *args):
        out = post0(sol, *args)
        grabbed.update(sol=sol, post=out)
        return out

    class Keep(problem0):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            grabbed["problem"] = self

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(ident, "posterior", spy)
        mp.setattr(ident, "_Problem", Keep)
        res = identify_ski(bench, n_stiffness=20, max_nfev=10)
    return res, grabbed["problem"], grabbed["sol"], grabbed["post"]


def test_the_starts_are_the_posterior_s_weakest_z0_directions(fitted) -> None:
    """With a refit that stays where it starts, each start's z0 difference is sd times the
    largest z0 spread per posterior standard deviation (the top eigenvalue of the posterior's
    z0 covariance, line removed), the same for + and -, and its cost is the cost there."""
    res, problem, sol, post = fitted
    cx = np.asarray(res.ski.camber_x)[np.asarray(res.ski.camber_determined)]
    pen = (sol.pen, sol.target)
    basins = basin_check(problem, sol, post.covariance, pen, lambda p0: _Frozen(problem, p0),
                         cx=cx, starts=2, sd=2.0)  # fmt: skip
    # independently: z0 at cx without its line, its covariance, the largest eigenvalue
    tz = _design(problem.t_z, cx) @ problem.q_z
    lin = np.stack([np.ones_like(cx), cx], axis=1)
    tz = tz - lin @ np.linalg.lstsq(lin, tz, rcond=None)[0]
    czz = tz @ post.covariance[problem.n_e :, problem.n_e :] @ tz.T
    top = float(np.linalg.eigvalsh(czz)[-1])
    expected = 2.0 * np.sqrt(top / cx.size)
    assert [b.start for b in basins] == ["+1", "-1"]
    # (to the roundoff of the covariance's square root: its eigenvalues below zero are clipped)
    for b in basins:
        assert b.z0_difference == pytest.approx(expected, rel=1e-4)
    assert np.allclose(_z0_rows(problem, cx)[:, problem.n_e :], tz)
    # the costs are those at the starts: symmetric steps about a minimum raise it on both sides
    assert all(b.delta_cost > 0 for b in basins)


def test_the_fit_is_kept_and_the_check_recorded(bench, fitted) -> None:
    plain = fitted[0]
    checked = identify_ski(bench, n_stiffness=20, max_nfev=10, starts=2)
    assert np.array_equal(plain.ski.camber_values, checked.ski.camber_values)
    assert np.array_equal(plain.ski.stiffness_values, checked.ski.stiffness_values)
    assert plain.basins == () and 1 <= len(checked.basins) <= 2
    details = dict(checked.ski.provenance.details)
    assert details["basin_starts"].endswith("of 2 ended")
    for b in checked.basins:
        assert np.isfinite(b.delta_cost) and b.z0_difference >= 0.0
    with pytest.raises(Exception, match="starts"):
        identify_ski(bench, starts=-1)
