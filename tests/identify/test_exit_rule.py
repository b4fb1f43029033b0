"""The exit rule of the identification (issue 25, sixth pass): a fit that stopped on its
decrement at the noise plus a stated error of at most 0.46 σ is converged; a noise given
wrongly, a larger error or a fit stopped by its evaluation limit is not. The part of the error
correlated along the profiles (:func:`skisnow.identify._diagnosis.correlated_excess`) names a
white excess as a noise misestimate."""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from skisnow.identify._bands import discrepancy_rms
from skisnow.identify._diagnosis import (
    MODEL_ERROR_MAX,
    correlated_excess,
    diagnose,
    noise_bound,
)

#: a full plan's size: 39 load cases of 414 bins (issue 25's ski: 16,146 bins)
_CASES, _BINS = 39, 414


def _residuals(delta: float, scale: float = 1.0, seed: int = 0) -> np.ndarray:
    """σ-normalised residuals of a full plan: unit white noise plus a smooth error of rms
    ``delta`` (a sum of sines along each case, wavelengths 60-400 mm at 5 mm bins, as a
    bench's contact error or a smoothed stiffness step), all times ``scale`` (a noise given
    ``1 / scale`` times too small)."""
    rng = np.random.default_rng(seed)
    x = np.arange(_BINS) * 0.005
    parts = []
    for _ in range(_CASES):
        e = sum(
            np.sin(2 * np.pi * x / lam + rng.uniform(0, 2 * np.pi)) for lam in (0.06, 0.15, 0.4)
        )
        e *= delta / np.sqrt(np.mean(e**2))
        parts.append(scale * (e + rng.standard_normal(_BINS)))
    return np.concatenate(parts)


def test_the_correlated_excess_estimates_a_smooth_error_and_ignores_noise() -> None:
    sizes = [_BINS] * _CASES
    se = 1.4 / np.sqrt(_CASES * (_BINS - 1))  # standard error under pure noise
    for seed in range(5):
        assert correlated_excess(_residuals(0.0, seed=seed), sizes) <= 4 * se
        # a smooth error of 0.3 σ: δ² = 0.09 within its standard error, while the white excess
        # of a noise 1.2 times too small (χ² 1.44 n) adds nothing to it
        assert correlated_excess(_residuals(0.3, seed=seed), sizes) == pytest.approx(
            0.09, abs=4 * se + 0.01
        )
        assert correlated_excess(_residuals(0.0, scale=1.2, seed=seed), sizes) <= 4 * se
        # an error repeating every two bins (the fit's 10 mm elements against 5 mm bins)
        rng = np.random.default_rng(seed)
        two = 0.3 * np.cos(np.pi * np.arange(_BINS))
        r = np.concatenate([two + rng.standard_normal(_BINS) for _ in range(_CASES)])
        assert correlated_excess(r, sizes) == pytest.approx(0.09, abs=4 * se)


def _diagnosis(
    r: np.ndarray,
    *,
    lm_status: int = 1,
    noise_given: float | None = None,
    height_scale: float | None = None,
):
    n = r.size
    dof = float(n)  # residuals of no fit: their χ² at the noise has the mean n
    chi2 = float(r @ r)
    return diagnose(
        chi2=chi2, bound=dof + 2 * np.sqrt(2 * dof), misfit=float(np.sqrt(chi2 / n)),
        lm_status=lm_status, noise=5e-6, noise_given=noise_given, noise_data=5e-6,
        case_misfits=[(10.0 * (k + 1), -0.12, 1.0) for k in range(_CASES)], mesh_rms=1e-7,
        element_length=0.01, ei_x=np.linspace(-0.9, 0.9, 91), ei_determined=np.ones(91, bool),
        bent=(-0.8, 0.8), cases=[(10.0 * (k + 1), -0.12) for k in range(_CASES)],
        correlated2=correlated_excess(r, [_BINS] * _CASES), n_bins=n, dof=dof,
        height_scale=height_scale,
    )  # fmt: skip


def test_a_fit_at_the_noise_plus_a_stated_model_error_is_converged() -> None:
    # 0.3 σ of smooth error: misfit ~1.04 σ, above the noise-only bound (~1.004 σ) — exit 3 by
    # the old rule, exit 0 now with the error stated (~1.5 µm of a 5 µm noise)
    d = _diagnosis(_residuals(0.3, seed=1))
    assert d.converged and d.causes == ("model-error",)
    stated = float(re.search(r"plus an error of ([0-9.]+) µm rms", d.warnings[0]).group(1))
    # the excess over the noise is the smooth error's 0.3 σ (1.5 µm of 5 µm), all correlated
    assert stated == pytest.approx(1.5, abs=0.2)
    correlated = float(re.search(r"of which ([0-9.]+) µm is correlated", d.warnings[0]).group(1))
    assert correlated == pytest.approx(1.5, abs=0.2)


def test_the_stated_error_is_a_height_on_benches_finer_than_their_bins() -> None:
    # The same σ-normalised residuals, but each bin the mean of 4 stations (2 mm stations in
    # 8 mm bins): a bin's weight is √4 / σ, so the 0.3 σ excess is a smooth height error of
    # 0.3 σ / 2 = 0.75 µm, not the 1.5 µm that δ σ would read (issue 25, seventh pass)
    rows = [(np.arange(_BINS) * 8e-3, np.full(_BINS, 2.0 / 5e-6)) for _ in range(_CASES)]
    d = _diagnosis(_residuals(0.3, seed=1), height_scale=discrepancy_rms(1.0, rows))
    assert d.converged and d.causes == ("model-error",)
    stated = float(re.search(r"plus an error of ([0-9.]+) µm rms", d.warnings[0]).group(1))
    assert stated == pytest.approx(0.75, abs=0.1)
    assert d.delta == pytest.approx(_diagnosis(_residuals(0.3, seed=1)).delta)  # the rule's δ


@pytest.mark.parametrize(
    ("delta", "scale", "lm_status", "noise_given", "cause"),
    [
        (0.6, 1.0, 1, None, "model"),  # a systematic error above the cap (misfit ~1.17 σ)
        (0.3, 1.25, 1, None, "noise"),  # white excess: the noise 1.25 times underestimated
        (0.3, 10.0, 1, 0.5e-6, "noise"),  # σ given 10 times too small: δ = 3 σ_given
        (0.9, 1.0, 0, None, "evaluations"),  # stopped by the evaluation limit far off
    ],
)
def test_what_the_allowance_does_not_excuse(delta, scale, lm_status, noise_given, cause) -> None:
    d = _diagnosis(_residuals(delta, scale, seed=2), lm_status=lm_status, noise_given=noise_given)
    assert not d.converged
    assert d.causes[0] == cause and "model-error" not in d.causes


def test_the_cap_is_the_issues_misfit_of_1_1_sigma() -> None:
    assert np.sqrt(1.0 + MODEL_ERROR_MAX**2) == pytest.approx(1.1)


def test_the_bound_with_an_estimated_noise_holds_its_level() -> None:
    # χ² of a fit at the noise, read with σ̂ = σ e^η (η ~ N(0, s²), s = 0.8 % as on a full
    # plan): above the bound of the estimated noise in ~2.3 % of draws (two standard deviations),
    # while the bound of a known noise is crossed in ~12 % of them
    rng = np.random.default_rng(3)
    dof, s = 16000.0, 0.008
    chi2 = rng.chisquare(dof, 20000) * np.exp(-2.0 * s * rng.standard_normal(20000))
    assert 0.012 <= np.mean(chi2 > noise_bound(dof, s)) <= 0.035
    assert np.mean(chi2 > dof + 2.0 * np.sqrt(2.0 * dof)) > 0.08
    assert noise_bound(dof, 0.0) == pytest.approx(dof + 2.0 * np.sqrt(2.0 * dof))


@pytest.mark.slow
def test_the_true_ski_on_a_fine_full_plan_is_at_the_noise_and_a_far_capped_fit_exits_3() -> None:
    # Issue 25's ski, 21 load cases (10-130 kg in 20 kg steps at -40, -120, -200 mm), stations
    # every 2 mm, 5 µm noise, heights by the independent reference bench at 0.5 mm (finite
    # differences, contact at every node; not the fit's forward model). Measured: started at the
    # true ski the fit ended at 1.027 σ, above the noise-only bound 1.002 σ (8694 bins), while
    # the model was evaluated at the bins' mean positions: the shovel's curvature across a bin
    # (2 or 3 stations) is 1-2 µm rms on these plans, which the old rule exited 3 on and the
    # model-error allowance passed with 1.4 µm stated. Since each bin's model is the mean over
    # its stations (issue 25, seventh pass) the true ski's fit is within the noise-only bound.
    from skisnow.bench import issue25_ski, reference_bench
    from skisnow.identify import identify_ski

    true = issue25_ski()
    bench = reference_bench(true, masses=tuple(range(10, 131, 20)),
                            load_positions=(-0.04, -0.12, -0.2), station_step=0.002,
                            noise=5e-6, seed=1, dx=0.5e-3)  # fmt: skip
    res = identify_ski(bench, initial=true)
    assert res.at_noise and res.converged and "model-error" not in res.causes
    assert res.model_error[1] <= MODEL_ERROR_MAX
    # (a noise given 10 times too small, exit 3 with the noise named: the diagnosis above, and on
    # an issue-sized bench through the CLI, tests/cli/test_identify_robustness.py)
    # a far start (EI 300 N m² everywhere) stopped after three evaluations: exit 3
    flat = dataclasses.replace(true, stiffness_values=np.full(len(true.stiffness_values), 300.0))
    far = identify_ski(bench, initial=flat, max_nfev=3)
    assert not far.converged and far.causes[0] == "evaluations"
