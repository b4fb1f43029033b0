"""The basin check of a fit (opt-in): refits from its weakest-determined z0 directions.

The penalised cost of the bench fit (:mod:`skisnow.identify._fit`) has several basins that
trade z0 against EI through the contact: a smooth bowl of z0 (high in the middle, low at the
ends, or the reverse) against the stiffness. Measured on issue 25's validation skis (ninth
pass, ``benchmarks/bench_z0_basins.py``, docs/validation/identification-uncertainty.md): refits
from the fit moved along the first modes of its own Laplace posterior reach basins whose
penalised cost differs from the fit's by a few to a few tens of χ² units while their z0
differs by 10-40 µm, and **the lowest cost is not the closest to the truth** (it was closer on
one of four shop fits at 5 µm): keeping the lowest cost does not mend z0, so the fit is kept,
and the check only says how far the bench leaves z0 open. That the cost cannot tell the basins
apart is the finding; that their z0 differs by more than the band is what a user must see.

Starts: the fit plus and minus ``sd`` standard deviations of the first principal modes of its
Laplace posterior in z0 (at the determined stations, without a line: the joint parameter step,
so the EI correlated with that z0 moves along), each refitted at the fit's λ on the fit's
problem (bins, Huber weights, z0 resolution) by ``refit``. A basin is *near* when its cost is
within :data:`BASIN_CHI2` of the fit's or below it; a warning names the largest z0 difference
(rms over the determined stations, line removed) of a near basin when it exceeds the fit's own
median 95 % z0 band.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import ConvergenceError
from skisnow.identify._model import _design, _Problem

__all__ = ["BASIN_CHI2", "Basin", "basin_check", "basin_warning"]

#: A basin within this many units of the fit's penalised cost (χ² + penalty, σ-normalised) is
#: *near*: "a few χ² units" — well inside the spread of the cost at the truth itself (the truth's
#: cost was 0.5-81 units above or below the fit's on issue 25's validation skis).
BASIN_CHI2 = 10.0


@dataclass(frozen=True, kw_only=True)
class Basin:
    """Where one start of the basin check ended.

    Attributes
    ----------
    start
        ``'+1'``, ``'-1'``, ``'+2'`` ...: the sign and number of the posterior mode started on.
    delta_cost
        Its penalised cost minus the fit's (σ-normalised χ² units; negative: lower).
    z0_difference
        Rms [m] of its z0 minus the fit's over the determined stations, line removed.
    misfit
        Its rms misfit [σ].
    """

    start: str
    delta_cost: float
    z0_difference: float
    misfit: float


def _z0_rows(problem: _Problem, cx: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rows mapping the parameters to z0 at ``cx`` without its least-squares line."""
    tz = _design(problem.t_z, cx) @ problem.q_z
    lin = np.stack([np.ones_like(cx), cx], axis=1)
    tz = tz - lin @ np.linalg.lstsq(lin, tz, rcond=None)[0]
    rows = np.zeros((cx.size, problem.n_params))
    rows[:, problem.n_e :] = tz
    return rows


def basin_check(
    problem: _Problem,
    solution: Any,
    covariance: NDArray[np.float64],
    penalty: tuple[NDArray[np.float64], NDArray[np.float64]],
    refit: Callable[[NDArray[np.float64]], Any],
    *,
    cx: NDArray[np.float64],
    starts: int,
    sd: float = 3.0,
) -> tuple[Basin, ...]:
    """Refit from ``starts`` points along the fit's weakest z0 directions (module docstring).

    Parameters
    ----------
    problem, solution, penalty
        The fit's problem, its Levenberg–Marquardt result (``x``, ``fun``) and its penalty rows
        ``(P, t)`` at its λ.
    covariance
        The fit's posterior covariance of the parameters.
    refit
        ``refit(p0) -> solution``: the fit's own refit at its λ from ``p0``.
    cx
        The determined z0 stations [m].
    starts
        Number of starts: ±mode 1, ±mode 2, ... in turn.
    sd
        Distance of each start from the fit, in posterior standard deviations of its mode.

    Returns
    -------
    tuple of Basin
        One per start that ended (a start whose contact could not be solved is left out).
    """
    p_mat, target = penalty

    def cost(p: NDArray[np.float64], r: NDArray[np.float64]) -> float:
        rp = p_mat @ p - target
        return float(r @ r + rp @ rp)

    cov = 0.5 * (covariance + covariance.T)
    w, v = np.linalg.eigh(cov)
    root = v * np.sqrt(np.clip(w, 0.0, None))[None, :]  # cov = root rootᵀ
    rows = _z0_rows(problem, cx)
    _, _, vt = np.linalg.svd(rows @ root, full_matrices=False)
    x0 = np.asarray(solution.x, dtype=float)
    c0 = cost(x0, solution.fun)
    out = []
    for k in range(starts):
        mode, sign = k // 2, 1.0 if k % 2 == 0 else -1.0
        if mode >= vt.shape[0]:
            break
        step = sd * (root @ vt[mode])
        try:
            s = refit(x0 + sign * step)
        except (ConvergenceError, np.linalg.LinAlgError, FloatingPointError):
            continue
        dz = rows @ (np.asarray(s.x) - x0)
        out.append(Basin(start=f"{'+' if sign > 0 else '-'}{mode + 1}",
                         delta_cost=cost(np.asarray(s.x), s.fun) - c0,
                         z0_difference=float(np.sqrt(np.mean(dz**2))),
                         misfit=float(np.sqrt(np.mean(np.asarray(s.fun) ** 2)))))  # fmt: skip
    return tuple(out)


def basin_warning(basins: tuple[Basin, ...], band: float) -> str | None:
    """The warning of a near basin (cost within :data:`BASIN_CHI2` of the fit's, or lower)
    whose z0 differs from the fit's by more than ``band`` [m] (the fit's median 95 % z0
    half-width), or None."""
    near = [b for b in basins if b.delta_cost <= BASIN_CHI2]
    if not near:
        return None
    worst = max(near, key=lambda b: b.z0_difference)
    if not worst.z0_difference > band:
        return None
    return (
        f"z0 ambiguous: a refit from the fit's weak z0 mode {worst.start} ended "
        f"{worst.delta_cost:+.1f} χ² units from the fit's cost with z0 differing by "
        f"{worst.z0_difference * 1e6:.0f} µm rms (the 95 % band: ±{band * 1e6:.0f} µm); the "
        "bench does not decide between them (the cost cannot: the lower one is no closer to "
        "the truth in issue 25's validation): read z0 as uncertain by that much, or add load "
        "cases (a full plan)"
    )


def check_basins(
    problem: _Problem,
    solution: Any,
    post: Any,
    prof: Any,
    starts: int,
    fit: Callable[..., Any],
    lam: float,
) -> tuple[tuple[Basin, ...], tuple[tuple[str, Any], ...], tuple[str, ...]]:
    """The basin check of :func:`~skisnow.identify.identify_ski` (``starts`` > 0): ``(basins,
    provenance details, warnings)``. ``post``, ``prof``: the fit's posterior and profiles
    (:mod:`skisnow.identify._bands`); ``fit(initial=None, start_parameters=p0,
    regularisation=lam)`` the fit's own refit at its λ ``lam``
    (:func:`~skisnow.identify._fit.fit_bench` with the fit's options)."""
    det = np.asarray(prof.z_determined, dtype=bool)
    if starts <= 0 or int(det.sum()) < 3:
        return (), (), ()
    pen = (solution.pen, solution.target)

    def refit(p0: NDArray[np.float64]) -> Any:
        return fit(initial=None, start_parameters=p0, regularisation=lam).solution

    basins = basin_check(problem, solution, post.covariance, pen, refit,
                         cx=np.asarray(prof.cx)[det], starts=starts)  # fmt: skip
    band = float(np.median(2.0 * np.asarray(prof.sd_z)[det]))
    warning = basin_warning(basins, band)
    near = [b for b in basins if b.delta_cost <= BASIN_CHI2]
    details = (
        ("basin_starts", f"{len(basins)} of {starts} ended"),
        ("basin_cost_range", f"{min((b.delta_cost for b in basins), default=0.0):+.1f}.."
                             f"{max((b.delta_cost for b in basins), default=0.0):+.1f}"),
        ("basin_z0_near_max_um", round(max((b.z0_difference for b in near), default=0.0) * 1e6,
                                       2)),
    )  # fmt: skip
    return basins, details, () if warning is None else (warning,)
