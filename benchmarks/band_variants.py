"""Band variants evaluated by ``bench_band_variants.py`` on cached fits (issue 25, fourth pass).

Each variant maps the cached linearisation of a fit (``sol``: parameters, residuals, Jacobian,
penalty) to :class:`skisnow.identify._bands.Profiles` with the fit as centre and its own
covariance."""

from __future__ import annotations

import numpy as np

from skisnow.identify import _bands as B
from skisnow.identify import _model as M


def penalty(problem, lam: float, *, l1: float = M._LAMBDA_1, lz: float = M._LAMBDA_Z,
            se: float = M.PRIOR_LOG_EI_SD, sz: float = M.PRIOR_Z0_SD):  # fmt: skip
    """(P, t) of the fit's penalty with its scales free."""
    ne, nz = problem.n_e, problem.n_z - 2
    z_e = lambda r: np.zeros((r, nz))  # noqa: E731
    z_z = lambda r: np.zeros((r, ne))  # noqa: E731
    d1 = np.diff(np.eye(ne), axis=0)
    rows = [
        np.hstack([np.sqrt(lam) * problem.d2_e, z_e(ne - 2)]),
        np.hstack([np.sqrt(l1) * d1, z_e(ne - 1)]),
        np.hstack([np.eye(ne) / se, z_e(ne)]),
        np.hstack([z_z(problem.n_z - 2), np.sqrt(lz) * problem.d2_z @ problem.q_z]),
        np.hstack([z_z(nz), np.eye(nz) / sz]),
    ]
    p = np.vstack(rows)
    t = np.zeros(p.shape[0])
    start = (ne - 2) + (ne - 1)
    t[start : start + ne] = M.PRIOR_LOG_EI_MEAN / se
    return p, t


def _with_pen(sol, pen):
    from dataclasses import replace

    return replace(sol, pen=pen[0], pen_target=pen[1])


def _lam_u(lam: float) -> float:
    return min(lam / B.UNDERSMOOTHING, 0.01)


def evidence_scales(sol, problem, lam, grid=(100.0, 10.0, 1.0, 0.1, 0.01, 1e-3, 1e-4)):
    """(k_e, k_z) maximising the Laplace evidence, the smoothness rows of EI scaled by k_e
    (λ and λ₁), those of z0 by k_z."""
    best = None
    for ke in grid:
        for kz in grid:
            pen = penalty(problem, lam * ke, l1=M._LAMBDA_1 * ke, lz=M._LAMBDA_Z * kz)
            score = B._evidence(sol, pen, 0.0)[1]
            if best is None or score < best[0]:
                best = (score, ke, kz)
    return best[1], best[2]


def profiles_of(g: dict, variant: str):
    sol, problem, lam = g["sol"], g["problem"], g["lam"]
    merr = g["model_error"]
    lu = _lam_u(lam)
    smooth = None
    cov_sol = sol
    if variant == "plain":
        pass
    elif variant == "current":
        smooth = B.smoothing_bias(sol, problem.penalty(lu))
    elif variant == "s_all":
        smooth = B.smoothing_bias(
            sol, penalty(problem, lu, l1=M._LAMBDA_1 / 100, lz=M._LAMBDA_Z / 100)
        )
    elif variant == "under_cov":
        smooth = B.smoothing_bias(sol, problem.penalty(lu))
        cov_sol = _with_pen(sol, problem.penalty(lu))
    elif variant == "under_all":
        pen = penalty(problem, lu, l1=M._LAMBDA_1 / 100, lz=M._LAMBDA_Z / 100)
        smooth = B.smoothing_bias(sol, pen)
        cov_sol = _with_pen(sol, pen)
    elif variant == "under_l1":
        pen = penalty(problem, lu, l1=M._LAMBDA_1 / 100)
        smooth = B.smoothing_bias(sol, pen)
        cov_sol = _with_pen(sol, pen)
    elif variant == "under_z":
        pen = penalty(problem, lam, lz=M._LAMBDA_Z / 100)
        smooth = B.smoothing_bias(sol, problem.penalty(lu))
        cov_sol = _with_pen(sol, pen)
    elif variant == "evidence":
        ke, kz = evidence_scales(sol, problem, lam)
        print(f"    evidence scales: EI smoothness x{ke:g}, z0 smoothness x{kz:g}")
        pen = penalty(problem, lam * ke, l1=M._LAMBDA_1 * ke, lz=M._LAMBDA_Z * kz)
        smooth = B.smoothing_bias(sol, problem.penalty(lu))
        cov_sol = _with_pen(sol, pen)
    else:
        raise ValueError(variant)
    post = B.posterior(cov_sol, merr, smooth)
    return B.identified_profiles(problem, sol.x, post, g["x_tail"], g["x_tip"],
                                 bent=g["bent"], measured=g["measured"])  # fmt: skip


VARIANTS = ("plain", "current", "s_all", "under_cov", "under_l1", "under_z", "under_all",
            "evidence")  # fmt: skip
