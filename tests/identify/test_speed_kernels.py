"""The identification's speed-ups (issue 25, fifth pass) give the numbers of the routes replaced.

The fit's path (which restarts run, which local minimum it reaches) can change with the last bit
of a residual, so each compiled or cached route is held to bitwise equality with the NumPy
expression it replaces, on the identification's own beams and random foundations.
"""

from __future__ import annotations

import numpy as np

from skisnow.identify._banded_kernel import smoothed_hessian
from skisnow.identify._lm import levenberg_marquardt
from skisnow.identify._model import _Problem
from skisnow.ski import SubGrid, banded_upper


def _reference_hessian(ab, d, shape, clamp):
    """The smoothed contact's Hessian as it was assembled before (einsum, banded_upper)."""
    n = ab.shape[1] // 2
    ke = np.einsum("es,esa,esb->eab", d, shape, shape)
    hess = ab + banded_upper(ke, n)
    for dof in (2 * clamp, 2 * clamp + 1):
        hess[:, dof] = 0.0
        for j in range(dof, min(dof + 4, 2 * n)):
            hess[3 + dof - j, j] = 0.0
        hess[3, dof] = 1.0
    return hess


def test_smoothed_hessian_is_bitwise_the_numpy_assembly() -> None:
    """Clamped stiffness of a random log-EI spline (EI 1-1e5 N m²) plus a foundation whose
    stiffness spans 14 decades and vanishes on half the sub-grid points (a ski lifting off)."""
    rng = np.random.default_rng(25)
    nodes = np.linspace(-0.95, 0.95, 191)
    problem = _Problem([], nodes, 14, 100, 5e-6)
    grid = SubGrid.of(nodes)
    shape = np.ascontiguousarray(grid.shape)
    for _ in range(40):
        ab, _ = problem._stiffness(rng.uniform(0.0, 11.5, 14))
        d = rng.random(grid.x.shape) * 10.0 ** rng.uniform(-5.0, 9.0, grid.x.shape)
        d[rng.random(grid.x.shape) < 0.5] = 0.0
        ref = _reference_hessian(ab, d, shape, problem.clamp)
        assert np.array_equal(smoothed_hessian(ab, d, shape, problem.clamp), ref)


def test_lm_normal_matrix_reused_is_the_product_at_the_solution() -> None:
    """The JᵀJ the Levenberg–Marquardt loop hands on (used by GCV, the discrepancy bound and
    the posterior) is bitwise JᵀJ of the returned Jacobian, on a small nonlinear problem
    (exponential decay, known optimum) whatever way the loop ended."""
    t = np.linspace(0.0, 3.0, 40)
    y = 2.0 * np.exp(-1.3 * t)

    def residuals(p, jacobian):
        e = np.exp(-p[1] * t)
        r = p[0] * e - y
        j = np.stack([e, -p[0] * t * e], axis=1) if jacobian else None
        return r, j, np.zeros((1, 2))

    for nfev in (3, 5, 100):
        sol = levenberg_marquardt(
            residuals, np.array([1.0, 0.5]), np.full(2, -np.inf), np.full(2, np.inf),
            max_nfev=nfev, tol=1e-20,
        )  # fmt: skip
        assert np.array_equal(sol.jtj, sol.jac.T @ sol.jac)
    np.testing.assert_allclose(sol.x, [2.0, 1.3], rtol=1e-8)


def test_softplus_integral_is_bitwise_the_full_evaluation() -> None:
    """F₂(t) = -Li₂(-eᵗ) with spence skipped far below the stone equals the evaluation at every
    point (both signs, the cut at t = -40, down to -1e12 where the sub-grid lies mm above the
    stone at ε = 1 nm), and is the integral of the softplus (trapezoid check)."""
    from scipy.special import spence

    from skisnow.identify._smooth import _F2_ZERO, _f2, _softplus

    rng = np.random.default_rng(7)
    t = np.concatenate([
        -(10.0 ** rng.uniform(-3.0, 12.0, 4000)), 10.0 ** rng.uniform(-3.0, 3.0, 1000),
        np.linspace(_F2_ZERO - 1.0, _F2_ZERO + 1.0, 2000), [0.0, -0.0, _F2_ZERO, -745.2, -37.0],
    ]).reshape(-1, 5)  # fmt: skip
    full = np.where(
        t <= 0.0,
        -spence(1.0 + np.exp(np.minimum(t, 0.0))),
        0.5 * t * t + np.pi**2 / 6.0 + spence(1.0 + np.exp(-np.maximum(t, 0.0))),
    )
    assert np.array_equal(_f2(t), full)
    assert np.array_equal(np.signbit(_f2(t)), np.signbit(full))
    grid = np.linspace(-30.0, 5.0, 200001)
    integral = np.concatenate([[0.0], np.cumsum(np.diff(grid) * 0.5 * (
        _softplus(grid[1:]) + _softplus(grid[:-1])))])  # fmt: skip
    np.testing.assert_allclose(_f2(grid) - _f2(grid[:1]), integral, rtol=1e-8, atol=1e-12)


def _bench_problem():
    """The identification's problem of a four-mass bench of the first release's classic (10
    µm noise), at the parameters of the true ski."""
    from skisnow.bench import run_bench
    from skisnow.identify._cases import _bench_cases, load_cases
    from skisnow.identify._model import _design
    from skisnow.identify._start import _camber_fit
    from skisnow.ski import DEFAULT_BOOT_LENGTH
    from skisnow.ski._shipped import build_shipped

    true = build_shipped("classic")
    bench = run_bench(true, masses=(20, 40, 60, 80), load_positions=(-0.04, -0.12), noise=1e-5,
                      seed=3, contact="continuous")  # fmt: skip
    raw = _bench_cases(bench, bench.ski_name(None))
    nodes = np.linspace(true.x_tail, true.x_tip, 191)
    cases = load_cases(raw, nodes, DEFAULT_BOOT_LENGTH, 0.005)[0]
    problem = _Problem(cases, nodes, 30, 120, 1e-5)
    theta_e = np.linalg.lstsq(_design(problem.t_e, nodes), np.log(true.stiffness(nodes)))[0]
    phi = _camber_fit(problem, nodes) @ true.free_camber(nodes)
    return problem, np.concatenate([theta_e, phi])


def test_compiled_newton_of_the_smoothed_contact_is_the_numpy_one() -> None:
    """Newton's method of the smoothed stone compiled against its NumPy route (the same steps
    and tests; sums in another order): from the exact contact of every load case, at ε = 10,
    1, 0.1 µm and at parameters 0.1 µm-1 % off the true ski, both converge, to the same loaded
    heights within 1e-4 of the noise (the Newton tolerance is 1e-3 of it) and the same
    Jacobian within 1e-6 relative."""
    from skisnow.identify._smooth import SmoothedBench

    problem, p_true = _bench_problem()
    rng = np.random.default_rng(3)
    for eps in (1e-5, 1e-6, 1e-7):
        p = (
            p_true
            + rng.normal(0.0, 1.0, p_true.size)
            * np.r_[np.full(problem.n_e, 1e-2), np.full(problem.n_z - 2, 1e-7)]
        )
        out = {}
        for compiled in (False, True):
            smooth = SmoothedBench(problem)
            smooth.compiled = compiled
            problem.warm_points = [None] * len(problem.cases)
            out[compiled] = smooth.evaluate(p, eps, jacobian=True)
        (r0, j0), (r1, j1) = out[False], out[True]
        assert np.max(np.abs(r1 - r0)) < 1e-4
        assert np.linalg.norm(j1 - j0) < 1e-6 * np.linalg.norm(j0)


def test_identification_runs_on_one_blas_thread(monkeypatch) -> None:
    """identify_ski limits BLAS to one thread while it runs (two OpenBLAS threads cost 4 times
    the CPU time on the shared machine) and gives the previous setting back."""
    import pytest
    from threadpoolctl import threadpool_info, threadpool_limits

    from skisnow.bench import run_bench
    from skisnow.identify import _identify, identify_ski
    from skisnow.ski._shipped import build_shipped

    class Seen(Exception):
        pass

    def blas_threads() -> list[int]:
        return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

    def spy(*args, **kwargs):
        raise Seen(blas_threads())

    bench = run_bench(build_shipped("classic"), masses=(20, 40), load_positions=(-0.12,))
    monkeypatch.setattr(_identify, "estimate_noise", spy)
    with threadpool_limits(limits=2, user_api="blas"):  # the suite runs on one (conftest)
        before = blas_threads()
        with pytest.raises(Seen) as seen:
            identify_ski(bench)
        assert blas_threads() == before
    assert seen.value.args[0] and all(n == 1 for n in seen.value.args[0])
    assert any(n == 2 for n in before)
