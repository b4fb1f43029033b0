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
