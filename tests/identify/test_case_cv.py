"""λ by leave-one-load-case-out cross-validation (:mod:`skisnow.identify._cv`; Rice & Silverman
1991) against what it must be: the closed-form prediction of a left-out case equals the refit
without it, and where every curve carries its own correlated error (a bench's model error), it
chooses the smoothing that recovers the shared function better than GCV, while on white noise it
does as well as GCV."""

from __future__ import annotations

from itertools import pairwise

import numpy as np

from skisnow.identify._bands import _gcv
from skisnow.identify._cv import case_cv, choose
from skisnow.identify._lm import _LmResult


def _linear_fit(jac, pen, y):
    p = np.linalg.solve(jac.T @ jac + pen.T @ pen, jac.T @ y)
    return _LmResult(x=p, fun=jac @ p - y, jac=jac, pen=pen, cost=0.0, nfev=1, status=1,
                     message="")  # fmt: skip


def _pen(lam: float, k: int) -> np.ndarray:
    return np.vstack([np.sqrt(lam) * np.diff(np.eye(k), 2, axis=0), 0.05 * np.eye(k)])


def test_the_left_out_prediction_is_the_refit_without_the_case() -> None:
    rng = np.random.default_rng(11)
    k, sizes = 15, [30, 25, 40, 35]
    jac = rng.standard_normal((sum(sizes), k))
    y = jac @ rng.standard_normal(k) + rng.standard_normal(sum(sizes))
    sol = _linear_fit(jac, _pen(3.0, k), y)  # the linearisation point: another λ
    lam = 0.7
    _, score, _, _, _, shares = case_cv(sol, _pen(lam, k), lam, sizes=sizes)
    cuts = np.cumsum([0, *sizes])
    brute = 0.0
    for a, b in pairwise(cuts):
        keep = np.r_[0:a, b : cuts[-1]]
        p = _linear_fit(jac[keep], _pen(lam, k), y[keep]).x
        brute += float(np.sum((jac[a:b] @ p - y[a:b]) ** 2))
    assert np.isclose(score, brute / cuts[-1], rtol=1e-10)
    assert np.isclose(shares.sum(), score)


def _curves(rng, correlated: float, n_cases: int = 12, n: int = 120, k: int = 30):
    """``n_cases`` noisy views of one smooth function on a k-coefficient hat basis, each with
    white unit noise plus its own smooth error of rms ``correlated`` (a Gaussian process with
    a correlation length of 3 % of the span, shorter than the function)."""
    x = np.linspace(0.0, 1.0, n)
    knots = np.linspace(0.0, 1.0, k)
    basis = np.maximum(0.0, 1.0 - np.abs(x[:, None] - knots[None, :]) * (k - 1))
    truth = 3.0 * np.sin(2 * np.pi * knots)
    kern = np.exp(-0.5 * ((x[:, None] - x[None, :]) / 0.03) ** 2)
    root = np.linalg.cholesky(kern + 1e-9 * np.eye(n))
    jac = np.tile(basis, (n_cases, 1))
    y = np.concatenate(
        [basis @ truth + rng.standard_normal(n) + correlated * root @ rng.standard_normal(n)
         for _ in range(n_cases)]
    )  # fmt: skip
    return jac, y, truth, [n] * n_cases


def _risk(correlated: float, trials: int = 30) -> tuple[float, float]:
    """Mean squared error of the estimate against the truth at the λ chosen by GCV and by
    case-CV, over ``trials`` draws."""
    rng = np.random.default_rng(12)
    grid = [0.01, 0.1, 1.0, 10.0, 100.0, 1000.0, 1e4]
    err = {"gcv": 0.0, "cv": 0.0}
    for _ in range(trials):
        jac, y, truth, sizes = _curves(rng, correlated)
        k = truth.size
        sol = _linear_fit(jac, _pen(10.0, k), y)
        for key, crit in (("gcv", _gcv), ("cv", None)):
            if crit is None:
                scores = [case_cv(sol, _pen(v, k), v, sizes=sizes)[1] for v in grid]
            else:
                scores = [crit(sol, _pen(v, k), v)[1] for v in grid]
            lam = grid[int(np.argmin(scores))]
            p = _linear_fit(jac, _pen(lam, k), y).x
            err[key] += float(np.mean((p - truth) ** 2)) / trials
    return err["gcv"], err["cv"]


def test_case_cv_smooths_away_an_error_of_each_case() -> None:
    # each curve's own smooth error (rms 1.5 noise sd): GCV reads it as signal and undersmooths
    gcv, cv = _risk(correlated=1.5)
    assert cv < 0.8 * gcv


def test_case_cv_on_white_noise_does_as_well_as_gcv() -> None:
    gcv, cv = _risk(correlated=0.0)
    assert cv < 1.25 * gcv


def _records(lams, per_case):
    return [
        (lam, float(np.sum(s)), 1.0, 1.0, None, np.asarray(s))
        for lam, s in zip(lams, per_case, strict=True)
    ]


def test_the_rule_takes_the_smoothest_lambda_within_one_standard_error() -> None:
    # scores per case (K = 4) at λ = 1, 10, 100: λ = 10 is worse than λ = 1 by less than the
    # scatter of the difference over the cases, λ = 100 by far more
    rng = np.random.default_rng(13)
    base = 1.0 + 0.1 * rng.standard_normal(4)
    noisy = base + np.array([0.02, -0.01, 0.03, -0.02])  # mean +0.005, se ~0.011
    worse = base + 0.2
    assert choose(_records([1.0, 10.0, 100.0], [base, noisy, worse])) == 1
    # a clear minimum is kept
    assert choose(_records([1.0, 10.0, 100.0], [base + 0.2, base, worse])) == 1
    assert choose(_records([1.0, 10.0], [base, base + 0.05])) == 0
