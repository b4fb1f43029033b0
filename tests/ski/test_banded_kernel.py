"""The compiled banded Cholesky of the identification against SciPy's ``solveh_banded``."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solveh_banded

from skisnow.ski._banded_kernel import banded_cholesky, banded_solve, solveh_banded_fused
from skisnow.ski._identify_model import _Problem


def _stiffness(rng: np.random.Generator, trial: int) -> np.ndarray:
    """A clamped beam stiffness of the identification (EI from 1 to 1e5 N m², varying along
    the ski, some with a contact foundation on the translations)."""
    nodes = np.linspace(-0.95, 0.95, 401)
    problem = _Problem([], nodes, 14, 100, 5e-6)
    theta = rng.uniform(0.0, 11.5, 14) if trial % 2 else np.full(14, rng.uniform(0.0, 11.5))
    ab, _ = problem._stiffness(theta)
    if trial % 3 == 0:
        ab = ab.copy()
        ab[3, ::2] += rng.random(401) * 10 ** rng.uniform(-3.0, 8.0)
    return ab


@pytest.mark.parametrize("columns", [1, 3, 114])
def test_solution_equals_scipy(columns: int) -> None:
    """Same solution as LAPACK's dpbsv: to round-off anywhere (bitwise on FMA hardware with
    OpenBLAS, the module docstring)."""
    rng = np.random.default_rng(columns)
    for trial in range(12):
        ab = _stiffness(rng, trial)
        b = rng.standard_normal((ab.shape[1], columns))
        ref = solveh_banded(ab, b, check_finite=False)
        x = solveh_banded_fused(ab, b)
        scale = np.max(np.abs(ref), axis=0)
        np.testing.assert_array_less(np.max(np.abs(x - ref), axis=0), 1e-9 * scale)
        # one column at a time is the same as all at once, and a vector as a column
        u = banded_cholesky(ab)
        np.testing.assert_array_equal(banded_solve(u, b[:, 0]), x[:, 0])
        # in place in a Fortran-ordered right-hand side: the same numbers
        bf = np.asfortranarray(b)
        xf = banded_solve(u, bf, overwrite_b=True)
        assert xf is bf
        np.testing.assert_array_equal(xf, x)


def test_factor_is_cholesky() -> None:
    """UᵀU reproduces the matrix; a matrix that is not positive definite is refused."""
    rng = np.random.default_rng(7)
    ab = _stiffness(rng, 1)
    n = ab.shape[1]
    u = banded_cholesky(ab)
    full_u = np.zeros((n, n))
    full_k = np.zeros((n, n))
    for d in range(4):
        idx = np.arange(3 - d, n)
        full_u[idx - (3 - d), idx] = u[d, idx]
        full_k[idx - (3 - d), idx] = ab[d, idx]
    full_k = np.triu(full_k) + np.triu(full_k, 1).T
    np.testing.assert_allclose(full_u.T @ full_u, full_k, rtol=0, atol=1e-12 * np.abs(full_k).max())
    ab[3, 10] = -1.0
    with pytest.raises(np.linalg.LinAlgError):
        banded_cholesky(ab)
