"""Intervals on a case's answers from an identified ski's posterior (issue 25, item 4).

What they must be: an interval holds its estimate; it shrinks with the ski's band and is zero
wide for a ski with zero-width bands; a ski without a posterior gets none; and the truth lies in
the 95 % interval at about 95 % of seeded cases when the identified ski is the truth moved by a
draw from the posterior the ski carries (the case where Monte Carlo propagation is exact to
first order)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from _posterior import with_posterior
from skisnow.pipeline import case_intervals, case_quantities, sample_intervals, solve_case
from skisnow.ski import get_ski, sample_skis

_CASE = dict(mass=70.0, load_position=-0.12, snow_modulus=100e6)


def _widths(iv, names):
    return np.array([iv.high[n] - iv.low[n] for n in names])


_SMOOTH = ("total.mean_pressure", "rear.load_share", "front.load_share", "total.area")


def test_intervals_hold_the_estimate_and_shrink_with_the_band() -> None:
    widths = []
    for scale in (1.0, 0.5, 0.25):
        ski = with_posterior(get_ski("classic"), scale=scale)
        case = solve_case(ski, **_CASE)
        iv = case_intervals(case, samples=60, seed=3)
        assert iv is not None and iv.samples == 60 and iv.failed == 0
        point = case_quantities(case)
        for name, value in point.items():
            if np.isnan(value):
                continue
            assert iv.low[name] <= value <= iv.high[name], name
        widths.append(_widths(iv, _SMOOTH))
    assert np.all(widths[0] > widths[1]) and np.all(widths[1] > widths[2])
    # first order: halving the band halves the interval of the footprint's area and mean
    # pressure (within 30 %); the load shares shrink less than linearly (measured 0.77: where
    # the split between the glide zones falls on very flat glide zones is not smooth)
    ratio = widths[1][[0, 3]] / widths[0][[0, 3]]
    assert np.all((ratio > 0.35) & (ratio < 0.65)), ratio


def test_zero_width_bands_give_zero_width_intervals() -> None:
    ski = with_posterior(get_ski("skate"), scale=0.0)
    case = solve_case(ski, **_CASE)
    iv = case_intervals(case, samples=10)
    for name, value in case_quantities(case).items():
        if np.isnan(value):
            continue
        assert iv.low[name] == pytest.approx(value, rel=1e-9, abs=1e-12)
        assert iv.high[name] == pytest.approx(value, rel=1e-9, abs=1e-12)
    assert iv.worst_mc_error() == pytest.approx(0.0, abs=1e-6)


def test_a_ski_without_posterior_gets_no_interval() -> None:
    assert case_intervals(solve_case("classic", **_CASE)) is None
    with pytest.raises(Exception, match="carries no posterior"):
        sample_intervals(get_ski("classic"), lambda s: {"a": 1.0}, estimate={"a": 1.0})


def test_sample_quantiles_of_a_linear_answer_match_the_band() -> None:
    # an answer linear in the parameters: log EI at one station. Its 95 % interval is the
    # stored band ±1.96 sd within the Monte Carlo error of 400 samples (bootstrap SE carried)
    ski = with_posterior(get_ski("classic"))
    j = len(ski.stiffness_x) // 3
    sd = ski.stiffness_log_sd[j]
    est = np.log(ski.stiffness_values[j])
    iv = sample_intervals(ski, lambda s: {"log_ei": np.log(s.stiffness_values[j])},
                          estimate={"log_ei": est}, samples=400, seed=5)  # fmt: skip
    half = 1.959964 * sd
    tol = 4 * iv.mc_error["log_ei"] * 2 * half  # four Monte Carlo standard errors
    assert iv.low["log_ei"] == pytest.approx(est - half, abs=tol)
    assert iv.high["log_ei"] == pytest.approx(est + half, abs=tol)
    assert 0.01 < iv.mc_error["log_ei"] < 0.1


@pytest.mark.slow
def test_contact_intervals_cover_the_true_ski() -> None:
    # The truth is the shipped classic; each "identified" ski is the truth moved by one draw of
    # the posterior it then carries (3 % in EI, 2 µm in z0, smooth modes), so the truth is a draw
    # from the identified ski's posterior. Over 16 seeds × 4 smooth answers the truth must lie in
    # the 95 % interval at the nominal rate: 64 trials, P(≤ 55 inside | p = 0.95) < 0.5 %.
    truth = get_ski("classic")
    true_answers = case_quantities(solve_case(truth, **_CASE))
    inside = total = 0
    for seed in range(16):
        (moved,) = sample_skis(with_posterior(truth), 1, seed=100 + seed)
        ident = with_posterior(dataclasses.replace(moved, name="identified"))
        iv = case_intervals(solve_case(ident, **_CASE), samples=100, seed=seed)
        for name in _SMOOTH:
            total += 1
            inside += iv.low[name] <= true_answers[name] <= iv.high[name]
    assert 56 <= inside <= total, (inside, total)


def test_every_shipped_ski_says_it_is_calibrated_not_identified() -> None:
    from skisnow.ski import PLAUSIBLE_SKIS, REPRODUCTION_SKIS, uncertainty_note

    for names, kind in ((PLAUSIBLE_SKIS, "plausible"), (REPRODUCTION_SKIS, "reproduction")):
        for name in names:
            note = uncertainty_note(get_ski(name))
            assert f"shipped {kind} ski" in note and "not identified" in note
            assert "no stated interval" in note
    changed = dataclasses.replace(get_ski("classic"), stiffness_values=tuple(
        1.1 * v for v in get_ski("classic").stiffness_values))  # fmt: skip
    assert "shipped" not in uncertainty_note(changed)  # the name alone does not make it shipped
    assert "no uncertainty recorded" in uncertainty_note(changed)
    assert "posterior" in uncertainty_note(with_posterior(get_ski("classic")))


def test_sample_quantiles_are_numpys_nanquantile_to_the_bit() -> None:
    # _quantiles takes np.quantile at once over the rows without NaN (nanquantile loops over
    # rows in Python): the same numbers, bit for bit, with NaNs, ties, all-NaN rows, 2-D and 3-D
    import warnings

    from skisnow.pipeline._intervals import _quantiles

    rng = np.random.default_rng(11)
    for trial in range(60):
        shape = (*rng.integers(1, 13, size=1 + trial % 2), int(rng.integers(2, 150)))
        v = rng.standard_normal(shape) * 10.0 ** rng.integers(-8, 8)
        if trial % 3 == 0:
            v[rng.random(shape) < 0.1] = np.nan
        if trial % 4 == 0:
            v = np.round(v, 1)  # ties
        if trial % 5 == 0:
            v[0] = np.nan  # an answer undefined in every sample
        for level in (0.95, 0.5, 0.8):
            a = (1.0 - level) / 2.0
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices
                want = (np.nanquantile(v, a, axis=-1), np.nanquantile(v, 1 - a, axis=-1))
            got = _quantiles(v, level)
            for w, g in zip(want, got, strict=True):
                assert g.shape == w.shape
                assert np.array_equal(g, w, equal_nan=True), (trial, level)
