"""Bench planning: the uncertainty of :func:`~skisnow.identify.identify_ski` predicted before
measuring.

For a (true or provisional) ski and a bench plan (masses × load positions, measured stations,
noise σ) the Gauss–Newton / Fisher information of the identification at that ski: the exact
Jacobian J of :class:`~skisnow.identify._model._Problem` (the same binned load cases,
spline parametrisation, beam mesh and penalty rows the fit uses; σ-normalised residuals, so
F = JᵀJ is the Fisher information of the spline parameters for Gaussian noise; Bard 1974, §7-5;
Seber & Wild 2003, §2.1-2.2 and §5.2). Two predictions:

* without regularisation: the Cramér–Rao bound F⁻¹ of an unbiased estimator (on the range of
  F: a quantity with a component in the null space of F is not identifiable from the plan);
* with the regularisation of the fit (the penalty rows P of λ): the linearised penalised
  estimate around the ski, δ̂ = -(F + PᵀP)⁻¹ (Jᵀ(r₀ - e) + PᵀP p), with the sandwich covariance
  (F + PᵀP)⁻¹ F (F + PᵀP)⁻¹ (the one of the identified ski's bands) and the mean error from the
  penalty and from the splines' representation of the ski (r₀: the residuals of the ski's own
  spline projection against its exact bench profiles). λ is chosen like the fit chooses it, by
  generalised cross-validation (Craven & Wahba 1979), here its expectation over the noise,
  n E[RSS] / (n - edf)², with E[RSS] = |(I - S) r₀ - J (F + PᵀP)⁻¹ PᵀP p|² + tr((I - S)²),
  S = J (F + PᵀP)⁻¹ Jᵀ.

Reported as the issue's error measures: EI as the rms over x_ei (default -450…+400 mm) of the
standard deviation of log EI (≈ relative EI), z0 as the rms over the measured stations (20 mm
in from each end) of the standard deviation of z0 modulo its least-squares line. The
prediction is first order (linearised at the ski, the contact set of the ski fixed): it holds
where the fit reaches the noise near the ski; it does not see local minima of the fit.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from skisnow._errors import InputError
from skisnow.identify._cases import load_cases
from skisnow.identify._lm import levenberg_marquardt, parameter_bounds
from skisnow.identify._model import _design, _Problem
from skisnow.identify._result import DEFAULT_LAMBDAS
from skisnow.identify._start import _camber_fit
from skisnow.ski import DEFAULT_BOOT_LENGTH, DEFAULT_N_ELEMENTS, Ski

__all__ = ["BenchPlanPrediction", "predict_identification_uncertainty"]

#: Relative eigenvalue (of the Jacobi-scaled Fisher matrix) below which a direction of the
#: parameters counts as not informed by the plan (the numerical null space).
NULL_TOLERANCE = 1e-10
#: Relative size of a quantity's component in that null space above which it is not
#: identifiable (its Cramér–Rao bound is infinite).
ESTIMABLE_TOLERANCE = 1e-6


@dataclass(frozen=True, kw_only=True)
class BenchPlanPrediction:
    """Predicted accuracy of :func:`~skisnow.identify.identify_ski` on a bench plan (SI units).

    Attributes
    ----------
    masses, load_positions
        The plan: masses [kg] at every load position [m].
    stations
        Measured window [m] (first, last station).
    noise
        Bench noise σ [m] of one sample.
    n_cases, n_bins, n_parameters
        Load cases, data bins (of all cases) and spline parameters.
    rank
        Numerical rank of the Fisher information JᵀJ (:data:`NULL_TOLERANCE`);
        ``n_parameters - rank`` is the dimension of its null space.
    ei_sd_crb, z0_sd_crb
        Cramér–Rao bound (no regularisation): rms over ``ei_window`` of the standard deviation
        of log EI [-] (≈ relative EI), and rms over the stations of the standard deviation of
        z0 modulo a line [m]; ``inf`` when not identifiable.
    ei_identifiable, z0_identifiable
        Whether EI over ``ei_window`` / z0 over the stations lie in the range of JᵀJ (no
        component in its null space).
    regularisation
        λ of the regularised prediction (given, or by expected GCV over the fit's grid).
    ei_sd, z0_sd
        With the regularisation: the same rms standard deviations of the penalised estimate
        (sandwich covariance; the bands of the identified ski).
    ei_bias, z0_bias
        With the regularisation: rms over the same stations of the mean error (penalty and
        spline representation of the ski) [-] / [m].
    gcv
        ``((λ, expected GCV, edf, ei_sd, z0_sd, ei_bias, z0_bias), ...)`` over the λ grid.
    ei_window
        Where EI is assessed [m].
    """

    masses: tuple[float, ...]
    load_positions: tuple[float, ...]
    stations: tuple[float, float]
    noise: float
    n_cases: int
    n_bins: int
    n_parameters: int
    rank: int
    ei_sd_crb: float
    z0_sd_crb: float
    ei_identifiable: bool
    z0_identifiable: bool
    regularisation: float
    ei_sd: float
    z0_sd: float
    ei_bias: float
    z0_bias: float
    gcv: tuple[tuple[float, float, float, float, float, float, float], ...]
    ei_window: tuple[float, float]

    @property
    def null_dimension(self) -> int:
        """Dimension of the null space of the Fisher information (directions no data see)."""
        return self.n_parameters - self.rank

    @property
    def ei_rms(self) -> float:
        """Expected rms error of log EI with the regularisation: √(bias² + sd²) [-]."""
        return float(np.hypot(self.ei_sd, self.ei_bias))

    @property
    def z0_rms(self) -> float:
        """Expected rms error of z0 modulo a line with the regularisation [m]."""
        return float(np.hypot(self.z0_sd, self.z0_bias))


def _rms_sd(g: NDArray[np.float64], cov: NDArray[np.float64]) -> float:
    """√(mean_i var(g_i · p)) for rows g of linear functionals and the covariance of p."""
    return float(np.sqrt(max(np.mean(np.einsum("ij,jk,ik->i", g, cov, g)), 0.0)))


def _rms(v: NDArray[np.float64]) -> float:
    return float(np.sqrt(np.mean(v**2)))


def plan_problem(
    ski: Ski,
    bench: Any,
    noise: float,
    *,
    stations: tuple[float, float] | None = None,
    bin_width: float = 0.005,
    n_stiffness: int = 14,
    n_camber: int = 100,
    boot_length: float = DEFAULT_BOOT_LENGTH,
    n_elements: int = DEFAULT_N_ELEMENTS,
) -> _Problem:
    """The identification's bench model of a bench (:class:`~skisnow.bench.BenchData` of ``ski``)
    cut to the open interval ``stations`` [m]: its load cases binned as
    :func:`~skisnow.identify.identify_ski` bins them, on the mesh of ``ski``'s running surface."""
    from skisnow.identify._cases import _bench_cases

    if stations is not None:
        t = bench.table
        keep = (t["x_mm"] > stations[0] * 1e3) & (t["x_mm"] < stations[1] * 1e3)
        bench = type(bench)(table=t[keep].reset_index(drop=True), metadata=bench.metadata)
    raw = _bench_cases(bench, ski.name)
    nodes = np.linspace(ski.x_tail, ski.x_tip, n_elements + 1)
    cases, _, _, _ = load_cases(raw, nodes, boot_length, bin_width)
    return _Problem(cases, nodes, n_stiffness, n_camber, noise)


def ski_parameters(problem: _Problem, ski: Ski) -> NDArray[np.float64]:
    """The spline parameters of ``ski`` in ``problem``: log EI and z0 projected at the nodes, as
    :func:`~skisnow.identify.identify_ski` projects its ``initial`` ski."""
    nodes = problem.nodes
    theta_e = np.linalg.lstsq(_design(problem.t_e, nodes), np.log(ski.stiffness(nodes)),
                              rcond=None)[0]  # fmt: skip
    return np.concatenate([theta_e, _camber_fit(problem, nodes) @ ski.free_camber(nodes)])


def fit_parameters(problem: _Problem, p0: NDArray[np.float64], lam: float, *, max_nfev: int = 30):
    """The fit's Levenberg–Marquardt (exact contact, penalty of λ, the fit's bounds) from
    ``p0``: the result with ``x``, ``fun`` (σ-normalised residuals) and ``jac``."""
    pen = problem.penalty(lam)

    def residuals(pp: NDArray[np.float64], jacobian: bool):
        r, j = problem.evaluate(pp, jacobian=jacobian)
        return r, j, pen

    lower, upper = parameter_bounds(problem)
    return levenberg_marquardt(residuals, p0, lower, upper, max_nfev=max_nfev, tol=1e-3)


def predict_identification_uncertainty(
    ski: Ski,
    masses: Sequence[float],
    load_positions: Sequence[float],
    noise: float,
    *,
    stations: tuple[float, float] | None = None,
    dx: float = 1e-3,
    bin_width: float = 0.005,
    n_stiffness: int = 14,
    n_camber: int = 100,
    regularisation: float | None = None,
    lambdas: Sequence[float] = DEFAULT_LAMBDAS,
    boot_length: float = DEFAULT_BOOT_LENGTH,
    n_elements: int = DEFAULT_N_ELEMENTS,
    ei_window: tuple[float, float] = (-0.45, 0.40),
    linearisation: str = "fit",
    max_nfev: int = 30,
) -> BenchPlanPrediction:
    """Predict the uncertainty of :func:`~skisnow.identify.identify_ski` for a bench plan.

    The Gauss–Newton (Fisher information) covariance of the identification's spline parameters
    at ``ski`` (Bard 1974, §7-5; Seber & Wild 2003, §2.1, §5.2): from the exact Jacobian of the
    bench model (the same load cases, bins, splines, mesh and penalty as the fit), the
    Cramér–Rao bound of an unbiased estimator (no regularisation; a quantity outside the range of
    the Fisher information is not identifiable), and the covariance and mean error of the
    penalised estimate at λ (given, or chosen by the expected GCV score over ``lambdas``). First
    order: it assumes the fit ends at the noise near ``ski`` (module docstring).

    Parameters
    ----------
    ski
        The ski (true or provisional) at which the bench model is linearised.
    masses
        Masses [kg] of the plan, each at every load position.
    load_positions
        Load positions [m] from the balance point (negative behind).
    noise
        Standard deviation σ [m] of the bench noise of one sample.
    stations
        First and last measured station [m] (profiles cut to the open interval, as
        ``benchmarks/bench_identify.py`` cuts its user bench); default the whole ski.
    dx
        Sampling step of the bench [m] (samples per bin weight the bins).
    bin_width, n_stiffness, n_camber, lambdas
        As in :func:`~skisnow.identify.identify_ski`.
    regularisation
        λ of the log-EI smoothness; default the λ of ``lambdas`` with the smallest expected GCV.
    boot_length, n_elements
        Boot plate length [m] and beam elements (the bench's and the fit's mesh).
    ei_window
        Where the EI error is assessed [m] (the issue's: between the glide zones).
    linearisation
        Where the model is linearised: ``'fit'`` (default) the noise-free fit of the plan's bench
        from the ski's spline projection at the middle of the λ grid (as the fit's own GCV
        linearises around its fit at that λ; the point the noisy fits scatter about — the
        projection at the nodes is not the best spline for the bench: the classic's log EI is
        3.4 % rms off between the glide zones there, its full bench at 2 σ misfit at 10 µm);
        ``'projection'`` the projection itself (the same point for every plan: then adding
        load cases adds to the Fisher information exactly).
    max_nfev
        Evaluations of that noise-free fit (Levenberg–Marquardt, the fit's own).

    Returns
    -------
    BenchPlanPrediction
        Predicted rms standard deviations (Cramér–Rao and regularised), mean errors, the rank.

    Raises
    ------
    InputError
        An empty plan, a non-positive noise or mass, stations outside the ski.
    """
    ms = tuple(sorted({float(m) for m in masses}))
    ps = tuple(sorted({float(p) for p in load_positions}))
    if not ms or not ps:
        raise InputError("a bench plan needs at least one mass and one load position")
    if any(not (np.isfinite(m) and m > 0) for m in ms):
        raise InputError(f"masses must be > 0 kg, got {list(ms)}")
    if not (np.isfinite(noise) and noise > 0):
        raise InputError(f"noise must be > 0 m, got {noise}")
    lo, hi = (
        (ski.x_tail, ski.x_tip) if stations is None else (float(stations[0]), float(stations[1]))
    )
    if not (ski.x_tail <= lo < hi <= ski.x_tip) or hi - lo < 0.2:
        raise InputError(
            f"stations [{lo * 1e3:g}, {hi * 1e3:g}] mm must lie on the ski "
            f"[{ski.x_tail * 1e3:g}, {ski.x_tip * 1e3:g}] mm and span at least 200 mm"
        )
    for p in ps:
        if not (ski.x_tail < p < ski.x_tip):
            raise InputError(f"load position {p * 1e3:g} mm is not on the ski")
    if linearisation not in ("fit", "projection"):
        raise InputError(f"linearisation must be 'fit' or 'projection', got {linearisation!r}")
    grid = [float(regularisation)] if regularisation is not None else [float(v) for v in lambdas]
    if not grid or any(not (np.isfinite(v) and v >= 0) for v in grid):
        raise InputError(f"regularisation / lambdas must be finite and >= 0, got {grid}")

    from skisnow.bench import run_bench

    # the fit's beam: contact resolved between nodes (issue 25)
    bench = run_bench(ski, masses=ms, load_positions=ps, dx=dx, boot_length=boot_length,
                      n_elements=n_elements, contact="continuous")  # fmt: skip
    problem = plan_problem(
        ski, bench, noise, stations=None if stations is None else (lo, hi),
        bin_width=bin_width, n_stiffness=n_stiffness, n_camber=n_camber,
        boot_length=boot_length, n_elements=n_elements,
    )  # fmt: skip
    lam0 = float(np.sqrt(max(grid) * max(min(grid), 1e-12))) if len(grid) > 1 else grid[0]
    p_ski = ski_parameters(problem, ski)
    if linearisation == "fit":
        sol = fit_parameters(problem, p_ski, lam0, max_nfev=max_nfev)
        p_ski, r0, jac = sol.x, sol.fun, sol.jac
    else:
        r0, jac = problem.evaluate(p_ski, jacobian=True)
    fisher = jac.T @ jac
    n_e, n_par, n_bins = problem.n_e, problem.n_params, r0.size

    # -- the quantities: log EI over the window, z0 modulo a line over the stations
    x_ei = np.linspace(ei_window[0], ei_window[1], 86)
    g_e = np.zeros((x_ei.size, n_par))
    g_e[:, :n_e] = _design(problem.t_e, x_ei)
    x_z = np.linspace(lo + 0.02, hi - 0.02, 400)
    line = np.stack([np.ones_like(x_z), x_z], axis=1)
    q_line, _ = np.linalg.qr(line)
    bz = _design(problem.t_z, x_z) @ problem.q_z
    g_z = np.zeros((x_z.size, n_par))
    g_z[:, n_e:] = bz - q_line @ (q_line.T @ bz)
    true_log_ei = np.log(ski.stiffness(x_ei))
    true_z = ski.free_camber(x_z)
    true_z = true_z - q_line @ (q_line.T @ true_z)

    # -- Cramér–Rao bound on the range of the Fisher information (Jacobi-scaled for the rank)
    scale = np.sqrt(np.diag(fisher))
    scale = np.where(scale > 0, scale, 1.0)
    w, v = np.linalg.eigh(fisher / np.outer(scale, scale))
    informed = w > NULL_TOLERANCE * float(w.max())
    rank = int(informed.sum())
    v_in, v_null = v[:, informed], v[:, ~informed]
    cov_crb = (v_in / scale[:, None]) @ np.diag(1.0 / w[informed]) @ (v_in / scale[:, None]).T

    def estimable(g: NDArray[np.float64]) -> bool:
        gs = g / scale[None, :]  # functionals on the scaled parameters
        out = np.linalg.norm(gs @ v_null) if v_null.size else 0.0
        return bool(out <= ESTIMABLE_TOLERANCE * np.linalg.norm(gs))

    ei_ok, z0_ok = estimable(g_e), estimable(g_z)
    ei_crb = _rms_sd(g_e, cov_crb) if ei_ok else float("inf")
    z0_crb = _rms_sd(g_z, cov_crb) if z0_ok else float("inf")

    # -- with the regularisation: sandwich covariance, mean error, expected GCV
    records = []
    for lam in grid:
        pen, target = problem.penalty(lam)
        ptp = pen.T @ pen
        a_inv = np.linalg.pinv(fisher + ptp)
        cov = a_inv @ fisher @ a_inv
        mean_step = -a_inv @ (jac.T @ r0 + ptp @ p_ski - pen.T @ target)
        p_mean = p_ski + mean_step
        ei_bias = _rms(g_e[:, :n_e] @ p_mean[:n_e] - true_log_ei)
        z_mean = _design(problem.t_z, x_z) @ (problem.q_z @ p_mean[n_e:])
        z0_bias = _rms(z_mean - q_line @ (q_line.T @ z_mean) - true_z)
        s_mat = a_inv @ fisher  # tr(S) = tr(A⁻¹F), tr(S²) = tr((A⁻¹F)²)
        edf = float(np.trace(s_mat))
        resid_mean = r0 + jac @ mean_step
        rss = float(resid_mean @ resid_mean) + n_bins - 2 * edf + float(np.trace(s_mat @ s_mat))
        score = n_bins * rss / max(n_bins - edf, 1.0) ** 2
        records.append((lam, score, edf, _rms_sd(g_e, cov), _rms_sd(g_z, cov), ei_bias, z0_bias))
    best = min(records, key=lambda rec: rec[1])
    return BenchPlanPrediction(
        masses=ms,
        load_positions=ps,
        stations=(lo, hi),
        noise=float(noise),
        n_cases=len(problem.cases),
        n_bins=n_bins,
        n_parameters=n_par,
        rank=rank,
        ei_sd_crb=ei_crb,
        z0_sd_crb=z0_crb,
        ei_identifiable=ei_ok,
        z0_identifiable=z0_ok,
        regularisation=best[0],
        ei_sd=best[3],
        z0_sd=best[4],
        ei_bias=best[5],
        z0_bias=best[6],
        gcv=tuple(records),
        ei_window=(float(ei_window[0]), float(ei_window[1])),
    )
