"""Issue 25's pieces of the identification's uncertainty, each against what it must be: the
Laplace posterior of a linear Gaussian problem (exact coverage when the truth is drawn from the
prior), samples of an identified ski (their spread is the stored band), the ski file's version 2
fields (round trip, validation, version 1 unchanged), the Huber threshold (no weight changed on
clean data) and the diagnosis naming the cause."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from skisnow import FileFormatError
from skisnow.identify._bands import (
    _evidence,
    _gcv,
    discrepancy_covariance,
    posterior,
    smoothing_bias,
)
from skisnow.identify._diagnosis import diagnose
from skisnow.identify._lm import _LmResult
from skisnow.identify._robust import huber_threshold
from skisnow.ski import get_ski, read_ski, sample_skis, ski_to_document, write_ski


def _linear_fit(jac, pen, y):
    """The penalised least-squares estimate of y = J p + e, e ~ N(0, 1), prior P p ~ N(0, 1)."""
    p = np.linalg.solve(jac.T @ jac + pen.T @ pen, jac.T @ y)
    return _LmResult(x=p, fun=jac @ p - y, jac=jac, pen=pen, cost=0.0, nfev=1, status=1,
                     message="")  # fmt: skip


def test_laplace_posterior_covers_the_truth_at_its_nominal_rate() -> None:
    # Linear Gaussian model, truth drawn from the prior (smoothness of second differences plus
    # a weak ridge): the posterior (JᵀJ + PᵀP)⁻¹ is exact, so ±2 sd covers 95.4 % of the
    # parameters. The noise-only sandwich of the fit before issue 25 covers far less where the
    # prior dominates (here the unobserved half of the parameters).
    rng = np.random.default_rng(3)
    n, k = 120, 40
    jac = np.zeros((n, k))
    jac[:, : k // 2] = rng.standard_normal((n, k // 2))  # the data see half the parameters
    d2 = np.diff(np.eye(k), 2, axis=0)
    pen = np.vstack([3.0 * d2, 0.05 * np.eye(k)])
    cov_prior = np.linalg.inv(pen.T @ pen)
    root = np.linalg.cholesky(cov_prior)
    inside = inside_sandwich = 0
    trials = 400
    for _ in range(trials):
        truth = root @ rng.standard_normal(k)
        y = jac @ truth + rng.standard_normal(n)
        sol = _linear_fit(jac, pen, y)
        post = posterior(sol)
        sd = np.sqrt(np.diag(post.covariance) / post.inflation)  # no inflation on exact data
        inside += int(np.sum(np.abs(sol.x - truth) <= 2 * sd))
        a = np.linalg.inv(jac.T @ jac + pen.T @ pen)
        sd_s = np.sqrt(np.diag(a @ jac.T @ jac @ a))
        inside_sandwich += int(np.sum(np.abs(sol.x - truth) <= 2 * sd_s))
    rate = inside / (trials * k)
    assert 0.94 < rate < 0.97
    assert inside_sandwich / (trials * k) < 0.8


def test_a_model_error_widens_the_posterior_by_its_parameter_shift() -> None:
    rng = np.random.default_rng(4)
    jac = rng.standard_normal((50, 5))
    pen = 0.1 * np.eye(5)
    sol = _linear_fit(jac, pen, rng.standard_normal(50))
    delta = 0.3 * rng.standard_normal(50)
    post = posterior(sol, delta)
    shift = np.linalg.solve(jac.T @ jac + pen.T @ pen, jac.T @ delta)
    assert np.allclose(post.bias, shift)
    base = posterior(sol)
    assert np.allclose(post.covariance - base.covariance, np.outer(shift, shift))


def _identified_like(ski, k: int = 3):
    """A ski carrying bands, flags and a posterior of k smooth modes (as identify_ski writes)."""
    ex, cx = np.asarray(ski.stiffness_x), np.asarray(ski.camber_x)
    me = np.array([0.05 * np.sin((i + 1) * np.pi * (ex - ex[0]) / np.ptp(ex)) for i in range(k)])
    mz = np.array([4e-6 * np.cos((i + 1) * np.pi * (cx - cx[0]) / np.ptp(cx)) for i in range(k)])
    return dataclasses.replace(
        ski, stiffness_log_sd=tuple(np.sqrt(np.sum(me**2, axis=0))),
        camber_sd=tuple(np.sqrt(np.sum(mz**2, axis=0))),
        stiffness_determined=tuple(ex > ex[0] + 0.1), camber_determined=tuple(cx < cx[-1] - 0.1),
        stiffness_modes=tuple(map(tuple, me)), camber_modes=tuple(map(tuple, mz)),
    )  # fmt: skip


def test_samples_spread_as_the_stored_band() -> None:
    # log EI of the samples: mean the identified ski's, standard deviation the stored band (the
    # modes' root sum of squares) within the sampling error of 600 draws (~3 % at 2.9 sd).
    ski = _identified_like(get_ski("classic"))
    samples = sample_skis(ski, 600, seed=1)
    log_ei = np.log([s.stiffness_values for s in samples])
    sd = np.std(log_ei, axis=0)
    band = np.asarray(ski.stiffness_log_sd)
    keep = band > 1e-3
    assert np.all(np.abs(sd[keep] / band[keep] - 1) < 0.12)
    assert np.all(
        np.abs(np.mean(log_ei, axis=0) - np.log(ski.stiffness_values)) < 4 * band / 24 + 1e-12
    )
    with pytest.raises(Exception, match="carries no posterior"):
        sample_skis(get_ski("classic"), 3)


def test_ski_file_version_2_round_trip_and_validation(tmp_path: Path) -> None:
    ski = _identified_like(get_ski("skate"))
    back = read_ski(write_ski(ski, tmp_path / "id.json"))
    assert back == ski
    assert back.stiffness_determined == ski.stiffness_determined
    assert back.camber_modes == ski.camber_modes and back.stiffness_modes == ski.stiffness_modes
    assert back.determined_span("stiffness")[0] > ski.x_tail
    doc = json.loads((tmp_path / "id.json").read_text())
    assert doc["format_version"] == 2
    assert ski_to_document(get_ski("skate"))["format_version"] == 1  # a definition stays v1
    doc["stiffness"]["determined"][3] = 1
    (tmp_path / "bad.json").write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match=r"stiffness\.determined\[3\]: must be true or"):
        read_ski(tmp_path / "bad.json")
    doc = json.loads((tmp_path / "id.json").read_text())
    doc["camber"]["modes_mm"] = doc["camber"]["modes_mm"][:1]
    (tmp_path / "bad2.json").write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match="as many rows"):
        read_ski(tmp_path / "bad2.json")
    doc = json.loads((tmp_path / "id.json").read_text())
    doc["format_version"] = 1  # version 1 has no such fields
    (tmp_path / "bad3.json").write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match="unknown key"):
        read_ski(tmp_path / "bad3.json")


def test_huber_threshold_leaves_clean_data_alone() -> None:
    # the largest of n standard normal residuals stays below the threshold almost always
    rng = np.random.default_rng(0)
    for n in (500, 2500, 15000):
        c = huber_threshold(n)
        worst = np.abs(rng.standard_normal((200, n))).max(axis=1)
        assert np.mean(worst > c) < 0.05


_BASE = dict(
    chi2=1000.0, bound=1100.0, misfit=1.0, lm_status=1, noise=5e-6, noise_given=None,
    noise_data=5e-6, case_misfits=[(20.0, -0.12, 1.0), (40.0, -0.12, 1.0)], mesh_rms=1e-7,
    element_length=0.01, ei_x=np.linspace(-0.9, 0.9, 91), ei_determined=np.ones(91, bool),
    bent=(-0.8, 0.8), cases=[(20.0, -0.12), (40.0, -0.12)],
)  # fmt: skip


@pytest.mark.parametrize(
    ("change", "cause", "converged", "words"),
    [
        ({}, None, True, None),
        ({"mesh_rms": 2e-6}, "mesh", False, "--mesh-mm"),
        ({"mesh_rms": np.inf}, "mesh", False, "could not be estimated"),
        ({"noise_given": 5e-7}, "noise", True, "noise misestimate"),
        ({"chi2": 2000.0, "misfit": 1.4, "lm_status": 0}, "evaluations", False, "--max-nfev"),
        ({"chi2": 2000.0, "misfit": 1.4}, "model", False, "local minimum"),
        ({"chi2": 2000.0, "misfit": 1.4, "case_misfits": [(20.0, -0.12, 1.0), (40.0, -0.12, 2.0)]},
         "noise", False, "40 kg at -120 mm"),
        ({"ei_determined": np.r_[np.ones(40, bool), np.zeros(10, bool), np.ones(41, bool)]},
         "information", True, "masses below 20 kg"),
    ],
)  # fmt: skip
def test_the_diagnosis_names_the_cause(change, cause, converged, words) -> None:
    d = diagnose(**{**_BASE, **change})
    assert d.converged is converged
    if cause is None:
        assert not d.causes and not d.warnings
    else:
        assert d.causes[0] == cause
        assert any(words in w for w in d.warnings)


def _pen(lam: float, k: int) -> np.ndarray:
    """Penalty rows of a smoothness prior of scale λ on second differences plus a weak ridge."""
    return np.vstack([np.sqrt(lam) * np.diff(np.eye(k), 2, axis=0), 0.05 * np.eye(k)])


def test_the_laplace_evidence_recovers_the_prior_scale() -> None:
    # Type-II maximum likelihood (MacKay 1992): truths drawn from the prior of λ = 9, data
    # y = J p + e; over a grid of decades the evidence picks λ = 9 (measured 39 of 40 draws;
    # GCV 33 of 40), evaluated on the linearisation at a fit of another λ (exact here).
    rng = np.random.default_rng(5)
    k, n = 40, 80
    grid = [0.09, 0.9, 9.0, 90.0, 900.0]
    root = np.linalg.cholesky(np.linalg.inv(_pen(9.0, k).T @ _pen(9.0, k)))
    hits = 0
    for _ in range(40):
        jac = 0.3 * rng.standard_normal((n, k))
        truth = root @ rng.standard_normal(k)
        sol = _linear_fit(jac, _pen(0.9, k), jac @ truth + rng.standard_normal(n))
        scores = [_evidence(sol, _pen(v, k), v)[1] for v in grid]
        hits += int(grid[int(np.argmin(scores))] == 9.0)
    assert hits >= 35


def test_the_smoothing_bias_term_covers_a_sharp_step() -> None:
    # A smooth truth with a sharp step (a laminate end), observed with unit noise, smoothed at
    # the GCV λ: the Laplace bands assume a truth typical of the smoothness prior and miss the
    # step (measured 39 % coverage at the 4 stations next to it); with the estimated smoothing
    # bias (step to the fit at λ / 100) 87 % there and 97.5 % over all stations.
    rng = np.random.default_rng(6)
    k = 40
    x = np.linspace(0.0, 1.0, k)
    truth = 3.0 * np.sin(2 * np.pi * x) + 4.0 * (x > 0.5)
    near = np.abs(x - 0.5) < 0.05
    grid = [0.09, 0.9, 9.0, 90.0, 900.0]
    inside = {"plain": [0, 0], "bias": [0, 0]}  # [near the step, all]
    trials = 200
    for _ in range(trials):
        y = truth + rng.standard_normal(k)
        first = _linear_fit(np.eye(k), _pen(1.0, k), y)
        lam = grid[int(np.argmin([_gcv(first, _pen(v, k), v)[1] for v in grid]))]
        sol = _linear_fit(np.eye(k), _pen(lam, k), y)
        under = smoothing_bias(sol, _pen(min(lam / 100, grid[0]), k))
        err = np.abs(sol.x - truth)
        for key, post in (("plain", posterior(sol)), ("bias", posterior(sol, None, under))):
            ok = err <= 2 * np.sqrt(np.diag(post.covariance))
            inside[key][0] += int(ok[near].sum())
            inside[key][1] += int(ok.sum())
    n_near, n_all = trials * int(near.sum()), trials * k
    assert inside["plain"][0] / n_near < 0.5
    assert inside["bias"][0] / n_near > 0.8
    assert 0.93 < inside["bias"][1] / n_all < 0.99


_SMOOTH_RMS, _SMOOTH_LENGTH = 0.5, 0.05  # the smooth error: rms (σ units), correlation [m]


def _smooth_error_problem(n: int, span: float, k: int):
    """A linear fit of k cosines (period 3 m) to n bins over ``span`` metres, a weak ridge
    penalty, and the Cholesky root of a squared-exponential smooth error (Gaussian process)
    of rms 0.5 σ and correlation length 50 mm at the bins."""
    x = np.linspace(0.0, span, n)
    jac = np.stack([np.cos(np.pi * i * x / 1.5) for i in range(k)], axis=1)
    kern = _SMOOTH_RMS**2 * np.exp(-0.5 * ((x[:, None] - x[None, :]) / _SMOOTH_LENGTH) ** 2)
    return x, jac, 0.1 * np.eye(k), np.linalg.cholesky(kern + 1e-10 * np.eye(n))


def test_a_smooth_model_discrepancy_is_covered_by_its_term() -> None:
    # Data with white noise plus a smooth error (a Gaussian process of rms 0.5 σ, correlation
    # length 50 mm over 1.5 m): the white-noise posterior covers the parameters of a smooth
    # model at 60 % (a smooth error does not average out); with the discrepancy's covariance
    # (Kennedy & O'Hagan 2001, propagated through the linear fit) at its nominal 95 %.
    rng = np.random.default_rng(7)
    n, k = 300, 12
    x, jac, pen, root = _smooth_error_problem(n, 1.5, k)
    rms, length = _SMOOTH_RMS, _SMOOTH_LENGTH
    plain = with_term = 0
    trials = 300
    for _ in range(trials):
        truth = 3.0 * rng.standard_normal(k)
        y = jac @ truth + rng.standard_normal(n) + root @ rng.standard_normal(n)
        sol = _linear_fit(jac, pen, y)
        err = np.abs(sol.x - truth)
        disc = discrepancy_covariance(sol, [(x, np.ones(n))], rms=rms, length=length)
        plain += int(np.sum(err <= 2 * np.sqrt(np.diag(posterior(sol).covariance))))
        cov = posterior(sol, None, None, disc).covariance
        with_term += int(np.sum(err <= 2 * np.sqrt(np.diag(cov))))
    assert plain / (trials * k) < 0.75
    assert 0.93 < with_term / (trials * k) < 0.98


def test_the_discrepancy_of_the_fits_own_excess_covers_the_truth() -> None:
    # The smooth error of the test above (rms 0.5 σ over 50 mm), its size not given but read
    # from each fit's residuals as the excess over the noise, δ² = (χ² - dof) / n (the
    # diagnosis's δ, dof = n - tr(2H - H²)), and turned into the discrepancy's height rms by
    # discrepancy_rms (residual weights 2: a noise of 0.5 in the heights' units, so the height
    # rms is δ / 2). The excess is an estimate: over 200 correlation lengths (2000 bins, 10 m)
    # its spread is small and part of the error is absorbed by the fit, so the coverage is
    # checked within issue 25's 90-98 % (not the known-rms test's 93-98 %); over 1.5 m (300
    # bins, 30 correlation lengths) δ reads 0 in a quarter of the fits and the coverage falls
    # to 75 % (measured; the limit of a band from the fit's own excess, docs/validation/
    # identification-uncertainty.md, seventh pass).
    from skisnow.identify._bands import discrepancy_rms
    from skisnow.identify._homotopy import restart_bound

    rng = np.random.default_rng(11)
    n, k = 2000, 12
    x, jac, pen, root = _smooth_error_problem(n, 10.0, k)
    length = _SMOOTH_LENGTH
    weights = np.full(n, 2.0)
    dof = restart_bound(jac, pen)[1]
    plain = with_term = 0
    trials = 60
    for _ in range(trials):
        truth = 3.0 * rng.standard_normal(k)
        y = jac @ truth + rng.standard_normal(n) + root @ rng.standard_normal(n)
        sol = _linear_fit(jac, pen, y)
        err = np.abs(sol.x - truth)
        delta = np.sqrt(max(float(sol.fun @ sol.fun) - dof, 0.0) / n)
        h_rms = discrepancy_rms(delta, [(x, weights)])
        assert h_rms == pytest.approx(delta / 2.0)
        disc = discrepancy_covariance(sol, [(x, weights)], rms=h_rms, length=length)
        plain += int(np.sum(err <= 2 * np.sqrt(np.diag(posterior(sol).covariance))))
        cov = posterior(sol, None, None, disc).covariance
        with_term += int(np.sum(err <= 2 * np.sqrt(np.diag(cov))))
    assert plain / (trials * k) < 0.75
    assert 0.90 < with_term / (trials * k) < 0.98
