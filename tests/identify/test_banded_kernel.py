"""The compiled banded Cholesky of the identification against SciPy's ``solveh_banded``."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solveh_banded

from skisnow.identify._banded_kernel import banded_cholesky, banded_solve, solveh_banded_fused
from skisnow.identify._model import _Problem


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


def _dense(ab: np.ndarray) -> np.ndarray:
    """The symmetric matrix of the upper banded storage ``ab[3 + i - j, j] = K[i, j]``."""
    n = ab.shape[1]
    k = np.zeros((n, n))
    for d in range(4):
        idx = np.arange(3 - d, n)
        k[idx - (3 - d), idx] = ab[d, idx]
    return np.triu(k) + np.triu(k, 1).T


def _solution_errors(
    k: np.ndarray, inv: np.ndarray, b: np.ndarray, x: np.ndarray, ref: np.ndarray
) -> dict:
    """Per column: the normwise backward errors ``‖Kx − b‖∞ / (‖K‖∞ ‖x‖∞)`` of ``x`` and of
    LAPACK's ``ref``, the forward difference ``‖x − ref‖∞ / ‖ref‖∞``, and its first-order bound.

    The bound: a solution with componentwise backward error ω (Oettli–Prager,
    ``max |Kx − b| / (|K||x| + |b|)``) is within ``ω ‖|K⁻¹|(|K||x| + |b|)‖∞ / ‖x‖∞`` of the exact
    one (Higham 2002, Thm. 7.4: the condition number of the system at this right-hand side, ~cond
    eps, here far below the normwise cond(K) eps); the two solutions are within the sum of their
    bounds, doubled for the rounding of the bound itself (``inv`` = |K⁻¹| computed in floating
    point)."""
    norm_k = np.linalg.norm(k, np.inf)

    def backward(y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r = np.abs(k @ y - b)
        eta = np.max(r, axis=0) / (norm_k * np.max(np.abs(y), axis=0))
        scale = np.abs(k) @ np.abs(y) + np.abs(b)
        omega = np.max(r / scale, axis=0)
        return eta, omega * np.max(inv @ scale, axis=0) / np.max(np.abs(y), axis=0)

    eta, bound = backward(x)
    eta_ref, bound_ref = backward(ref)
    forward = np.max(np.abs(x - ref), axis=0) / np.max(np.abs(ref), axis=0)
    return {"eta": eta, "eta_ref": eta_ref, "forward": forward, "bound": 2 * (bound + bound_ref)}


def _acceptable(err: dict) -> bool:
    """What a backward-stable banded Cholesky guarantees: a backward error at LAPACK's level
    (within 10x of dpbsv's, and at most 1e-13) and a forward difference within the bound."""
    return bool(
        np.all(err["eta"] <= 10 * err["eta_ref"])
        and np.all(err["eta"] < 1e-13)
        and np.all(err["forward"] <= err["bound"])
    )


@pytest.mark.parametrize("columns", [1, 3, 114])
def test_solution_is_as_accurate_as_scipy(columns: int) -> None:
    """As accurate as LAPACK's dpbsv: the same backward error to a factor (both at round-off)
    and a forward difference within what the conditioning allows. Bitwise equality with
    dpbsv (the module docstring) holds only where OpenBLAS's kernels do the same operations in
    the same order: the stiffness matrices here have cond(K) 1e10 to 1e14, so a different
    rounding of the same algorithm moves x by up to ~1e-8 relative (measured on an AVX-512 AMD
    EPYC)."""
    rng = np.random.default_rng(columns)
    for trial in range(12):
        ab = _stiffness(rng, trial)
        b = rng.standard_normal((ab.shape[1], columns))
        ref = solveh_banded(ab, b, check_finite=False)
        x = solveh_banded_fused(ab, b)
        k = _dense(ab)
        inv = np.abs(np.linalg.inv(k))
        err = _solution_errors(k, inv, b, x, ref)
        assert _acceptable(err), (trial, err)
        # the check is not vacuous: a solution off by 1e-10 relative in every entry fails it
        off = x * (1 + 1e-10 * rng.standard_normal(x.shape))
        assert not _acceptable(_solution_errors(k, inv, b, off, ref)), trial
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
