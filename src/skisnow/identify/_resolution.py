"""The z0 resolution by the discrepancy principle, and the tests of a fit against the noise.

A fit that ends above the noise is refitted with the z0 knot spacing halved while that stays
within ``n_camber_max``, and the refinement is kept only if it lowers the Bayesian information
criterion (Morozov 1966; Schwarz 1978; the module docstring of :mod:`skisnow.identify._identify`):
:func:`refine_resolution`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow.identify._fit import BenchFit, fit_bench
from skisnow.identify._model import _Case, _design, _Problem

__all__ = [
    "AT_NOISE",
    "at_noise_bound",
    "refine_resolution",
    "refined_parameters",
    "significant_decrease",
]


#: Misfit (σ-normalised rms of the bins) above which a fit is not at the noise: a fit at the
#: noise has 1 ± (2 n)^-1/2 with n ~ 10³ bins; the margin allows for σ being estimated and for
#: the model's discretisation. Measured on the four-mass bench of the shipped classic (version
#: 2, benchmarks/bench_identify.py's "user" coverage) before the globalisation (stage 5 of the
#: module docstring): 10 µm noise, seed 1: 1.03 (EI 8.9 % off); seed 5: 1.24 (EI 15 %); 5 µm
#: noise, seed 1, stalled in a local minimum: 2.05 (EI 63 %); with it, seed 5: 1.00 (EI 3.8 %),
#: 5 µm seed 1: 1.07 (EI 9.0 %).
AT_NOISE = 1.2


def at_noise_bound(n_bins: int) -> float:
    """The discrepancy bound of the σ-normalised misfit (rms over ``n_bins`` bins): a fit at the
    noise has misfit² ~ χ²_n / n, mean 1 and standard deviation (2 / n)^1/2, so the misfit is
    1 ± (2 n)^-1/2; the bound is two of those standard deviations above 1, 1 + 2 (2 n)^-1/2.
    Used by the discrepancy principle (Morozov 1966) that chooses the z0 resolution: a fit
    above it does not explain the bench down to its noise."""
    return 1.0 + 2.0 / np.sqrt(2.0 * max(int(n_bins), 1))


def significant_decrease(chi2_coarse: float, chi2_fine: float, added: int, n_data: int) -> bool:
    """Whether refining a model by ``added`` parameters is worth it by the Bayesian information
    criterion (Schwarz 1978), BIC = χ² + k ln n for σ-normalised residuals of ``n_data`` bins:
    the sum of squares must fall by more than ``added`` ln n. (Fitting noise alone lowers it by
    χ²_added, about ``added``; the ln n factor, 7-10 for benches of 10³-10⁴ bins, keeps a
    refinement that only trades z0 against EI within the noise of a small bench from being
    chosen: measured on the four-mass benches of ``benchmarks/bench_identify.py``, where a
    refinement that lowered χ² by 3.7 times its added parameters made the held-out profiles
    worse, 2.8 -> 7.3 µm.)"""
    return bool(chi2_coarse - chi2_fine > added * np.log(max(int(n_data), 2)))


def refined_parameters(
    coarse: _Problem, fine: _Problem, parameters: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The parameters of ``coarse`` on the z0 basis of ``fine`` (same log-EI basis): the z0
    spline by least squares on the fine basis at four points per fine knot interval, exact when
    the fine knots contain the coarse ones (uniform knots with the spacing halved, 2 n - 3
    coefficients: knot insertion, Boehm 1980), then without its linear part (a straight line,
    invisible to the bench)."""
    theta_e, theta_z = coarse.split(parameters)
    x0, x1 = float(fine.nodes[0]), float(fine.nodes[-1])
    xs = np.linspace(x0, x1, 4 * (fine.n_z - 3) + 1)
    theta_fine = np.linalg.lstsq(
        _design(fine.t_z, xs), _design(coarse.t_z, xs) @ theta_z, rcond=None
    )[0]
    return np.concatenate([theta_e, fine.q_z.T @ theta_fine])


def refine_resolution(
    problem: _Problem,
    fitted: BenchFit,
    cases: list[_Case],
    nodes: NDArray[np.float64],
    *,
    n_stiffness: int,
    sigma: Any,
    n_camber_max: int,
    options: dict[str, Any],
) -> tuple[_Problem, BenchFit, list[tuple[int, float]]]:
    """The z0 resolution of a fit by the discrepancy principle: ``(problem, fit, resolution)``
    of the kept resolution, ``resolution`` the ``(n_camber, misfit)`` of each one fitted.

    While the fit ``fitted`` of ``problem`` stays above the noise (χ² above its discrepancy
    bound), the z0 knot spacing is halved (2 n - 3 coefficients, started at the coarse fit) up
    to ``n_camber_max`` coefficients; a refinement is kept only if it lowers the Bayesian
    information criterion (:func:`significant_decrease`). ``options`` are those of
    :func:`~skisnow.identify._fit.fit_bench` (``say`` among them).
    """
    say: Callable[[str], None] = options["say"]
    # The z0 resolution by the discrepancy principle (Morozov 1966): while the fit stays above
    # the noise, the z0 knot spacing is halved (the coarse fit is exactly a spline of the fine
    # basis, the start of the fine fit), up to n_camber_max coefficients; a refinement is kept
    # only if it lowers the Bayesian information criterion (Schwarz 1978).
    resolution = [(problem.n_z, float(fitted.solution.misfit_rms))]
    while 2 * problem.n_z - 3 <= n_camber_max:
        chi2_fit, bound = float(fitted.solution.fun @ fitted.solution.fun), fitted.chi2_bound
        if chi2_fit <= bound:
            break
        fine = _Problem(cases, nodes, n_stiffness, 2 * problem.n_z - 3, sigma, problem.prior)
        say(
            f"χ² {chi2_fit:.0f} above the noise (discrepancy bound {bound:.0f}): z0 on "
            f"{fine.n_z} coefficients"
        )
        trial = fit_bench(
            fine, cases, nodes, initial=None,
            start_parameters=refined_parameters(problem, fine, fitted.solution.x), **options,
        )  # fmt: skip
        resolution.append((fine.n_z, float(trial.solution.misfit_rms)))
        chi2 = [float(f.solution.fun @ f.solution.fun) for f in (fitted, trial)]
        if not significant_decrease(chi2[0], chi2[1], fine.n_z - problem.n_z, problem.n_data):
            say(f"z0 on {fine.n_z} coefficients: not significantly better, not kept")
            break
        problem, fitted = fine, trial
    return problem, fitted, resolution
