"""An opt-in population prior of the identification: what a family of skis is like, as a Gaussian.

The default fit's penalty (:meth:`skisnow.identify._model._Problem.penalty_matrix`) is a
smoothness prior of log EI (λ by GCV) and broad priors of its level and of z0: it knows nothing
of how skis are built. Along the directions a camber bench barely sees (the edges of a stiff
plateau, a glide zone pressed flat on the stone) the data leave log EI to that penalty, and no
λ removes the error there (issue 25, eighth pass: ``benchmarks/bench_identify_limit.py``).
A **population prior** replaces the penalty by the mean μ and covariance Σ of the fit's own
spline coefficients (log EI and z0 modulo its line) over a population of skis; the penalised
fit then is the maximum a posteriori estimate under that Gaussian, and its Gauss–Newton step the
linear minimum-mean-square-error (Bayes-linear) estimate, μ + Σ Jᵀ (J Σ Jᵀ + I)⁻¹ (y - J μ)
(Kailath, Sayed & Hassibi 2000, ch. 3; Tarantola 2005, ch. 3, the Gaussian linear inverse
problem; the prior's rows P with PᵀP = Σ⁻¹, t = P μ, :func:`gaussian_prior_rows`).

It is a modelling choice a user makes knowingly: the fit is then only as good as the population
is like the ski. :func:`population_prior` draws the population from
:func:`skisnow.bench.random_ski` (the synthetic family of the coverage studies: its ranges are
assumptions, not measurements), one kind at a time, with a diagonal floor so that the
covariance stays proper where the generator does not vary; the result's provenance records the
generator, the seeds and the count. ``identify_ski(prior=...)``; off by default.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import InputError
from skisnow.identify._model import _design

__all__ = ["PopulationPrior", "gaussian_prior_rows", "population_prior"]

#: The grid [m] (2 mm, balance point at 0) on which a population's curves are kept: fine against
#: the fit's knots (log EI ~35 mm, z0 10-20 mm), wide enough for any cross-country ski.
_GRID = np.round(np.arange(-1.10, 1.1001, 0.002), 6)


@dataclass(frozen=True, kw_only=True, eq=False)
class PopulationPrior:
    """A population of skis as curves on a common grid, read as a Gaussian prior of the fit.

    Attributes
    ----------
    x
        Grid [m] from the balance point.
    log_ei, z0
        ``(count, x.size)``: each ski's ln EI [ln N m²] and free camber [m] on ``x`` (held
        constant beyond the ski's ends).
    jitter_log_ei, jitter_z0
        Standard deviations added to the diagonal of the coefficients' covariance (log EI [-],
        z0 [m]): the prior's floor where the population does not vary.
    description
        Where the population came from (generator, kind, seeds, count): recorded in the
        identified ski's provenance.
    """

    x: NDArray[np.float64]
    log_ei: NDArray[np.float64]
    z0: NDArray[np.float64]
    jitter_log_ei: float
    jitter_z0: float
    description: str

    def rows(self, problem: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The penalty rows ``(P, t)`` of this prior on ``problem``'s splines: each ski's log EI
        and z0 projected by least squares between the mesh's end nodes (z0 modulo a line), the
        mean and covariance of the coefficients over the population, plus the floor."""
        keep = (self.x >= problem.nodes[0]) & (self.x <= problem.nodes[-1])
        x = self.x[keep]
        bz = _design(problem.t_z, x) @ problem.q_z
        lin = np.stack([np.ones_like(x), x], axis=1)
        m_e = np.linalg.pinv(_design(problem.t_e, x))
        m_z = np.linalg.pinv(np.hstack([bz, lin]))[: bz.shape[1]]
        coef = np.hstack([self.log_ei[:, keep] @ m_e.T, self.z0[:, keep] @ m_z.T])
        cov = np.atleast_2d(np.cov(coef, rowvar=False))
        floor = np.r_[
            np.full(problem.n_e, self.jitter_log_ei),
            np.full(bz.shape[1], self.jitter_z0),
        ]
        return gaussian_prior_rows(coef.mean(axis=0), cov + np.diag(floor**2))


def gaussian_prior_rows(
    mean: NDArray[np.float64], cov: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Penalty rows ``(P, t)`` of the Gaussian prior N(``mean``, ``cov``): PᵀP = Σ⁻¹ (P the
    transposed Cholesky factor of the precision), t = P μ, so that |P p - t|² = (p - μ)ᵀ Σ⁻¹
    (p - μ) and the penalised least squares min |J p - y|² + |P p - t|² is the posterior mean
    μ + Σ Jᵀ (J Σ Jᵀ + I)⁻¹ (y - J μ) (module docstring).

    Raises
    ------
    InputError
        ``cov`` not symmetric positive definite.
    """
    cov = np.asarray(cov, dtype=float)
    try:
        p_mat = np.linalg.cholesky(np.linalg.inv(0.5 * (cov + cov.T))).T
    except np.linalg.LinAlgError:
        raise InputError("the prior's covariance must be symmetric positive definite") from None
    return p_mat, p_mat @ np.asarray(mean, dtype=float)


def population_prior(
    kind: Literal["classic", "skate"],
    *,
    count: int = 2000,
    seed: int = 100_000,
    jitter_log_ei: float = 0.05,
    jitter_z0: float = 2e-6,
) -> PopulationPrior:
    """A population prior from ``count`` skis of :func:`skisnow.bench.random_ski` of ``kind``
    (seeds ``seed`` … ``seed + count - 1``; the coverage studies use seeds 1-24 and 1001-1003,
    so the default seeds are none of them), with the diagonal floor ``jitter_log_ei`` (log EI)
    and ``jitter_z0`` [m] (module docstring).

    Raises
    ------
    InputError
        Unknown kind, fewer than 10 skis or a floor that is not positive.
    """
    from skisnow.bench import random_ski

    if kind not in ("classic", "skate"):
        raise InputError(f"kind must be 'classic' or 'skate', got {kind!r}")
    if not (isinstance(count, int) and count >= 10):
        raise InputError(f"count must be an integer >= 10, got {count!r}")
    if not (jitter_log_ei > 0 and jitter_z0 > 0):
        raise InputError(f"the floors must be > 0, got {jitter_log_ei}, {jitter_z0}")
    log_ei = np.empty((count, _GRID.size))
    z0 = np.empty((count, _GRID.size))
    for k in range(count):
        ski = random_ski(seed + k, kind=kind)
        xc = np.clip(_GRID, ski.x_tail, ski.x_tip)
        log_ei[k], z0[k] = np.log(ski.stiffness(xc)), ski.free_camber(xc)
    return PopulationPrior(
        x=_GRID, log_ei=log_ei, z0=z0, jitter_log_ei=float(jitter_log_ei),
        jitter_z0=float(jitter_z0),
        description=(
            f"population prior: {count} skis of skisnow.bench.random_ski(seed, kind={kind!r}), "
            f"seeds {seed}-{seed + count - 1}; mean and covariance of the fit's log-EI and z0 "
            f"spline coefficients, diagonal floor {jitter_log_ei:g} (log EI) and "
            f"{jitter_z0 * 1e6:g} um (z0)"
        ),
    )  # fmt: skip
