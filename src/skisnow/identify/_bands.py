"""The uncertainty of a fit: GCV of its linearisation, the posterior, the bands and what is
determined.

λ by generalised cross-validation on the Gauss–Newton linearisation at a fit (Craven & Wahba
1979; Wahba 1990, §4.3). The bands are the Laplace approximation of the posterior of the
penalised fit read as a Bayesian estimate (Wahba 1978, 1983; Nychka 1988): the penalty is a
Gaussian prior with precision PᵀP (smoothness of log EI at the chosen λ, a proper ridge on the
level of log EI and on z0: :data:`~skisnow.identify._model.PRIOR_LOG_EI_SD`,
:data:`~skisnow.identify._model.PRIOR_Z0_SD`), the residuals are σ-normalised, so the posterior
covariance of the parameters is (JᵀJ + PᵀP)⁻¹, inflated by χ²/dof when the fit ends above the
noise. Unlike the noise-only sandwich (JᵀJ + PᵀP)⁻¹ JᵀJ (JᵀJ + PᵀP)⁻¹ of the fit before issue 25
(4-34 times too narrow), it contains the prior's variance, which is the size of the bias the
penalty may cause (Wahba 1983: the Bayesian intervals of a smoothing spline at its GCV λ cover
the truth at about their nominal rate on average over the stations, Nychka 1988, though not at
every station). The discretisation error of the forward model, estimated by a finer solve
(:mod:`skisnow.identify._mesh_error`), adds its parameter shift (JᵀJ + PᵀP)⁻¹ Jᵀ δ as a bias.

A station is *determined by the bench* where the data shrink the prior's variance to below a
quarter (posterior standard deviation below half the prior's), and, for the stiffness, where the
bench bends the ski: between the outermost contact points of its load cases (beyond them no
load case carries a bending moment). Elsewhere the band is the prior's width.

On request (``identify_ski(bands='conformal')``) the widths at the determined stations are
multiplied by factors measured on independent benches of skis with a known truth
(:func:`calibrated_scale`: split-conformal calibration by conformal risk control, one unit per
ski), and the posterior's modes alike: what a band at one fit cannot see (the basin a fit
landed in) is then at least counted, at the price of widths set by the worst calibration skis.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from skisnow.identify._lm import _LmResult
from skisnow.identify._model import _design, _Problem
from skisnow.ski import lower_hull_bracket

__all__ = [
    "BAND_METHODS",
    "CONFORMAL_SCALE_EI",
    "CONFORMAL_SCALE_Z0",
    "LAPLACE_BANDS",
    "LAPLACE_Z0_UNDERCOVER",
    "Posterior",
    "band_scale",
    "bands_detail",
    "calibrated_scale",
    "discrepancy_covariance",
    "discrepancy_rms",
    "identified_profiles",
    "posterior",
    "smoothing_bias",
]

#: Posterior over prior standard deviation below which a station is determined by the bench.
DETERMINED_RATIO = 0.5

#: Largest z0 band written [m] (the plausible range of a ski file's camber band).
_Z0_SD_CAP = 9.99e-3

#: Stations of the identified ski: EI every 20 mm, z0 every 5 mm.
_EI_STEP, _Z0_STEP = 0.02, 0.005

#: The modes kept of the posterior (its square root at the stations, by singular values of its
#: correlation form): those that carry 99.5 % of its variance, at most this many (at 40 the
#: shipped classic's shop bench kept a median 95 % of its EI band, at 60 98 %; the ski file
#: grows from 0.52 to 0.77 MB).
MAX_MODES = 60

#: The ``bands`` detail of an identified ski's provenance: which method made its bands and what
#: they are known to be worth (the default, Laplace, bands under-cover z0; the coverage measured
#: on independent benches, docs/validation/identification-uncertainty.md, sixth and seventh
#: passes: held-out skis 35-40 %, seeded skis 5-24 68-79 %).
LAPLACE_BANDS = "Laplace posterior, 95 % = 2 sd"
LAPLACE_Z0_UNDERCOVER = (
    "; its z0 bands are known to under-cover: the truth inside them at 35-79 % of the "
    "determined stations of independent benches of held-out and seeded skis (shop plans, "
    "5-10 µm; target 90-98 %); a parametric bootstrap (--bootstrap 8) widens them (79-94 %), "
    "the conformal widths (--bands conformal, z0 x4.66) to 95.7-100 % (one fit in 28 at 83 %)"
)


#: The conformal calibration of the Laplace bands (:func:`calibrated_scale`): the Laplace
#: posterior's standard deviations at the determined stations multiplied by these factors (EI:
#: of log EI; z0). Calibrated, not validated: conformal risk control at alpha = 0.10 on the seeded
#: plausible skis 1-14 (``skisnow.bench.random_ski``), one unit per ski, its independent reference
#: benches (``skisnow.bench.reference_bench``, 1 mm finite differences) of the shop plan at 5 and
#: 10 µm noise, the fits identify_ski's defaults; exact factors 1.324 (EI) and 4.659 (z0),
#: rounded up (benchmarks/bench_band_conformal.py; docs/validation/identification-uncertainty.md,
#: eighth pass, with the predictions on other skis and plans).
CONFORMAL_ALPHA = 0.10
CONFORMAL_SCALE_EI = 1.33
CONFORMAL_SCALE_Z0 = 4.66
CONFORMAL_SET = "seeded skis 1-14, shop plan, 5 and 10 µm"
#: What the conformal bands are known to be worth: the eighth pass's predictions, the shop rows
#: re-measured on fresh fits of the tenth pass (the code had moved since the eighth pass's fits).
CONFORMAL_COVERAGE = (
    "; measured on independent benches of other skis (seeded skis 15-24, held-out 1001-1003 "
    "and issue 25's ski; shop and full plans, 5-10 µm): the truth inside them at 95.7-100 % "
    "of the determined stations for z0 (shop, re-measured; one fit of 28 at 83 %; full plans "
    "99.9-100 %: wider than most skis need) and 92-98 % for EI (shop; full plans 80-93 %)"
)


def calibrated_scale(
    normalised_errors: Sequence[NDArray[np.float64]], *, alpha: float = 0.10, level: float = 2.0
) -> float:
    """The factor k by which a band of ``level`` standard deviations must be widened so that,
    on a new unit exchangeable with the calibration units, the expected share of its stations
    outside the widened band is at most ``alpha``: conformal risk control (Angelopoulos, Bates,
    Fisch, Lei & Schuster 2024, "Conformal risk control", Theorem 1; the split-conformal
    calibration of Vovk, Gammerman & Shafer 2005, and Angelopoulos & Bates 2023, §2, with a
    bounded loss in place of a 0/1 miss).

    ``normalised_errors``: per calibration unit (one ski: its independent reference benches,
    never the fit's forward model) the errors |estimate - truth| / sd at its determined
    stations. The loss of a unit at factor k is the share L_i(k) of its stations with error
    > ``level`` k, non-increasing in k and in [0, 1]; the factor is the smallest k with

        (Σ_i L_i(k) + 1) / (n + 1) <= alpha,

    searched over the steps of the L_i (the errors / ``level``).

    Why a unit is a ski, not a station: stations of one fit are strongly correlated (a fit
    landing in the wrong basin misses z0 at most of its stations at once), so only whole skis
    are exchangeable; pooling stations as if independent would claim a precision the
    calibration set does not have.

    Guarantee: E[L_{n+1}(k)] <= alpha, the expectation over the calibration skis and the new
    ski, i.e. the *average over skis* of the share of determined stations covered is at least
    1 - alpha; nothing is said about one ski (a ski whose fit lands far off may stay covered at
    a few %), nor about skis unlike the calibration set (other plans, noise, shapes). The
    guarantee is one-sided: the over-coverage is only bounded by E[L] >= alpha - 2/(n + 1)
    (Theorem 2, for continuous losses), vacuous for n < 2/alpha - 1. With a loss bounded by 1
    the rule needs n >= 1/alpha - 1 units (9 at alpha = 0.10, 19 at 0.05); with fewer it
    returns ``inf``.
    """
    units = [np.sort(np.asarray(e, dtype=float).ravel()) for e in normalised_errors]
    units = [e for e in units if e.size]
    n = len(units)
    if not (0.0 < alpha < 1.0) or level <= 0.0:
        raise ValueError(f"alpha must be in (0, 1) and level > 0, got {alpha!r}, {level!r}")
    if n == 0 or (1.0 / (n + 1)) > alpha:
        return float("inf")
    cand = np.unique(np.concatenate([[0.0], *units])) / level
    risk = np.zeros(cand.size)
    for e in units:
        risk += 1.0 - np.searchsorted(e, level * cand, side="right") / e.size
    ok = (risk + 1.0) / (n + 1) <= alpha * (1.0 + 1e-12)
    return float(cand[np.argmax(ok)])


#: The bands :func:`~skisnow.identify.identify_ski` can write (``bands=``).
BAND_METHODS = ("laplace", "conformal")


def band_scale(bands: str, *, calibrated_on: bool = True) -> tuple[float, float]:
    """The factors (log EI, z0) on the Laplace posterior's standard deviations of the band
    method ``bands`` (:data:`BAND_METHODS`); the conformal factors only on the fits and bands
    they were calibrated on (``calibrated_on``: the default penalty, the smoothing bias, no
    discrepancy term, no population prior)."""
    from skisnow._errors import InputError

    if bands not in BAND_METHODS:
        raise InputError(f"bands must be one of {', '.join(BAND_METHODS)}, got {bands!r}")
    if bands == "conformal" and not calibrated_on:
        raise InputError(
            "bands='conformal' scales the default bands (the smoothness penalty with the "
            "smoothing bias, no discrepancy term, no population prior): its factors are "
            "calibrated on those only"
        )
    return (CONFORMAL_SCALE_EI, CONFORMAL_SCALE_Z0) if bands == "conformal" else (1.0, 1.0)


def bands_detail(bands: str, *, smoothing: bool, discrepancy: float = 0.0) -> str:
    """The ``bands`` detail of an identified ski's provenance: the method that made its bands
    (``bands``, with the smoothing bias, with a discrepancy of ``discrepancy`` m rms) and what
    they are known to be worth."""
    k_e, k_z = band_scale(bands)
    text = LAPLACE_BANDS
    if bands == "conformal":
        text = (f"Laplace posterior, widths scaled ×{k_e:g} (log EI) and ×{k_z:g} (z0) at the "
                "determined stations (split-conformal calibration, conformal risk control at "
                f"{100 * CONFORMAL_ALPHA:g} %, on 14 independent benches: {CONFORMAL_SET}; "
                "Angelopoulos et al. 2024), 95 % = 2 sd")  # fmt: skip
    if smoothing:
        text += ", with the estimated smoothing bias"
    if discrepancy > 0:
        text += (f", with a model discrepancy of the fit's own excess {discrepancy * 1e6:.2g} µm "
                 f"rms over {DISCREPANCY_LENGTH * 1e3:g} mm (Kennedy & O'Hagan 2001)")  # fmt: skip
    return text + (CONFORMAL_COVERAGE if bands == "conformal" else LAPLACE_Z0_UNDERCOVER)


def _penalised_step(sol: _LmResult, pen):
    """The penalised Gauss–Newton step at ``sol`` with the penalty rows ``pen`` (or
    ``(rows, target)``), shared by :func:`_gcv` and :func:`_evidence`:
    ``(r, JᵀJ, PᵀP, A = JᵀJ + PᵀP, A⁺, δ̂, r + J δ̂, P (p + δ̂) - t)``."""
    pen, target = pen if isinstance(pen, tuple) else (pen, np.zeros(pen.shape[0]))
    j, r, p = sol.jac, sol.fun, sol.x
    jtj = sol.jtj
    ptp = pen.T @ pen
    a = jtj + ptp
    a_inv = np.linalg.pinv(a)
    step = -a_inv @ (j.T @ r + ptp @ p - pen.T @ target)
    return r, jtj, ptp, a, a_inv, step, r + j @ step, pen @ (p + step) - target


def _gcv(sol: _LmResult, pen, lam: float):
    """GCV of the Gauss–Newton linearisation at ``sol`` with the penalty rows ``pen`` of λ
    (or ``(rows, target)``): ``(λ, GCV, misfit rms / σ, edf, step)`` (Craven & Wahba 1979;
    Wahba 1990, §4.3)."""
    r, jtj, _, _, a_inv, step, rl, _ = _penalised_step(sol, pen)
    rss = float(rl @ rl)
    edf = float(np.trace(a_inv @ jtj))
    n = r.size
    gcv = n * rss / max(n - edf, 1.0) ** 2
    return lam, gcv, float(np.sqrt(rss / n)), edf, step


def _evidence(sol: _LmResult, pen, lam: float):
    """Minus the log evidence (marginal likelihood) of λ on the Gauss–Newton linearisation at
    ``sol``, up to a constant: ``(λ, -log Z, misfit rms / σ, edf, step)`` like :func:`_gcv`.

    Type-II maximum likelihood (empirical Bayes; MacKay 1992, eq. 2.19 of "Bayesian
    interpolation"; Wahba 1985's generalised maximum likelihood): with σ-normalised residuals
    r + J δ and the Gaussian prior of the penalty rows P p - t (precision PᵀP, proper: the
    ridges on the level of log EI and on z0), the evidence of λ is

        -2 log Z(λ) = |r + J δ̂|² + |P p̂ - t|² + log det(JᵀJ + PᵀP) - log det(PᵀP),

    δ̂ the penalised step and p̂ = p + δ̂. Unlike GCV it weighs the prior's own scale against the
    data (the Occam factor det(PᵀP)^1/2 / det(JᵀJ + PᵀP)^1/2), so that the chosen prior is one
    the fitted ski is a typical draw of: the condition under which the Laplace bands cover the
    truth at their nominal rate on average over the stations (Nychka 1988)."""
    r, jtj, ptp, a, a_inv, step, rl, rp = _penalised_step(sol, pen)
    rss = float(rl @ rl)
    edf = float(np.trace(a_inv @ jtj))
    logdet_a = np.linalg.slogdet(a)[1]
    logdet_p = np.linalg.slogdet(ptp)[1]
    score = 0.5 * (rss + float(rp @ rp) + logdet_a - logdet_p)
    return lam, float(score), float(np.sqrt(rss / r.size)), edf, step


@dataclass(frozen=True, kw_only=True, eq=False)
class Posterior:
    """The Laplace posterior of a fit: ``covariance`` of the parameters (σ-normalised data),
    ``prior`` the prior's covariance, ``inflation`` the factor χ²/dof applied (>= 1), ``dof``
    the residual degrees of freedom, ``bias`` the parameter shift of the model's discretisation
    error (added to the covariance as ``bias biasᵀ``)."""

    covariance: NDArray[np.float64]
    prior: NDArray[np.float64]
    inflation: float
    dof: float
    bias: NDArray[np.float64]
    #: the estimated smoothing bias (parameter shift to the undersmoothed fit), added to the
    #: covariance as ``smoothing smoothingᵀ``; zero if not estimated
    smoothing: NDArray[np.float64] | None = None
    #: the parameter covariance of the model discrepancy (:func:`discrepancy_covariance`),
    #: added to the covariance; None if not estimated
    discrepancy: NDArray[np.float64] | None = None


def posterior(
    sol: _LmResult,
    model_error: NDArray[np.float64] | None = None,
    smoothing: NDArray[np.float64] | None = None,
    discrepancy: NDArray[np.float64] | None = None,
) -> Posterior:
    """The Laplace posterior of the penalised fit ``sol`` (module docstring); ``model_error``
    the σ-normalised residual change of a finer forward model (the discretisation error);
    ``smoothing`` the estimated smoothing bias of the parameters (:func:`smoothing_bias`),
    added as a rank-one term."""
    jtj = sol.jtj
    ptp = sol.pen.T @ sol.pen
    cov = np.linalg.pinv(jtj + ptp)
    prior = np.linalg.pinv(ptp)
    n = sol.fun.size
    dof = float(n - np.trace(cov @ jtj))
    chi2 = float(sol.fun @ sol.fun)
    inflation = max(1.0, chi2 / max(dof, 1.0))
    bias = np.zeros(cov.shape[0])
    if model_error is not None and model_error.size == n:
        bias = cov @ (sol.jac.T @ model_error)
    total = inflation * cov + np.outer(bias, bias)
    if smoothing is not None:
        total = total + np.outer(smoothing, smoothing)
    if discrepancy is not None:
        total = total + discrepancy
    return Posterior(covariance=total, prior=prior, inflation=inflation, dof=dof, bias=bias,
                     smoothing=smoothing, discrepancy=discrepancy)  # fmt: skip


#: The model discrepancy allowed for in the bands (:func:`discrepancy_covariance`): rms [m] and
#: correlation length [m] of a smooth error of the bench model against the real bench. A
#: calibration, not a validation: 1 µm is the disagreement of the fit's beam with the
#: independent 1 mm reference bench measured on the seeded skis 1-4 (noise-free benches fitted
#: at 0.3-1.45 µm rms; the true ski against the bench 1.41 µm on ski 2, 0.1-2.6 µm per load
#: case), 150 mm its correlation length (where the autocorrelation of the true ski's residuals
#: falls to e^-1/2: 0.08-0.20 m on skis 2, 6 and 12); the coverage is measured on other skis.
DISCREPANCY_RMS = 1.0e-6
DISCREPANCY_LENGTH = 0.15


def discrepancy_rms(
    excess: float, rows: list[tuple[NDArray[np.float64], NDArray[np.float64]]]
) -> float:
    """The height rms [m] of a discrepancy whose σ-normalised residuals carry, on average over
    the bins, the excess ``excess``² (σ² units; the diagnosis's δ² = (χ² - dof) / n,
    :class:`~skisnow.identify._diagnosis.Diagnosis`): ``excess`` / (mean weight²)^1/2 with
    ``rows`` as in :func:`discrepancy_covariance` (a bin of c stations at noise σ_k has the
    weight √c / σ_k, so on a bench of one station per bin and one noise it is δ σ)."""
    w = np.concatenate([wk for _, wk in rows]) if rows else np.ones(1)
    return float(excess) / float(np.sqrt(max(float(np.mean(w**2)), 1e-300)))


def discrepancy_covariance(
    sol: _LmResult,
    rows: list[tuple[NDArray[np.float64], NDArray[np.float64]]],
    *,
    rms: float = DISCREPANCY_RMS,
    length: float = DISCREPANCY_LENGTH,
) -> NDArray[np.float64]:
    """The parameter covariance caused by a smooth model discrepancy: a Gaussian process of
    standard deviation ``rms`` and squared-exponential correlation of ``length`` in the heights
    of each load case, independent between load cases (the model-discrepancy term of Kennedy &
    O'Hagan 2001, propagated through the linearised fit): A⁻¹ Jᵀ W Σ_d W J A⁻¹ with A = JᵀJ +
    PᵀP. ``rows``: per load case, in the order of the residuals, the bins' positions x [m] and
    their residual weights (the σ-normalised residual is weight × height error). The fit's own
    stated excess over the noise gives ``rms`` by :func:`discrepancy_rms` (what
    ``identify_ski(discrepancy_bands=True)`` uses).

    Why: white noise averages out over the stations, a smooth model error does not; on weakly
    determined directions (a smooth bowl of z0 traded against EI) a discrepancy of 0.2 σ rms,
    invisible in the misfit, moved z0 by 3-7 posterior standard deviations (docs/validation/
    identification-uncertainty.md)."""
    j = sol.jac
    a_inv = np.linalg.pinv(sol.jtj + sol.pen.T @ sol.pen)
    middle = np.zeros((j.shape[1], j.shape[1]))
    start = 0
    for x, w in rows:
        jk = w[:, None] * j[start : start + x.size]
        start += x.size
        kern = rms**2 * np.exp(-0.5 * ((x[:, None] - x[None, :]) / length) ** 2)
        middle += jk.T @ kern @ jk
    return a_inv @ middle @ a_inv


#: The undersmoothed fit whose difference from the chosen one estimates the smoothing bias:
#: λ divided by this factor (:func:`smoothing_bias`).
UNDERSMOOTHING = 100.0


def smoothing_bias(sol: _LmResult, pen_under) -> NDArray[np.float64]:
    """The smoothing bias of the fit ``sol`` estimated by the difference to an undersmoothed
    fit: the penalised Gauss–Newton step from ``sol`` with the penalty rows ``pen_under`` (λ
    divided by :data:`UNDERSMOOTHING`), a plug-in estimate of the bias of a penalised
    estimator (Eubank & Speckman 1993; Hall 1992 on undersmoothing for intervals).

    Why: the Laplace posterior contains the prior's variance, which is the size of the bias
    only when the true ski is a typical draw of the smoothness prior; a ski's stiffness is
    smooth with a few sharp steps (laminate ends, the binding plate), which a stationary
    Gaussian prior at the λ chosen for the smooth majority calls improbable, and the bands
    then miss the truth at and around the steps (measured, docs/validation/
    identification-uncertainty.md). The step to the undersmoothed fit is noisy (its expected
    square is the bias² plus the variance gained by undersmoothing), so the term errs on the
    wide side."""
    return _gcv(sol, pen_under, 0.0)[4]


@dataclass(frozen=True, kw_only=True, eq=False)
class Profiles:
    """EI and z0 of a fit at the identified ski's stations, with their bands."""

    ex: NDArray[np.float64]
    ei: NDArray[np.float64]
    sd_log_ei: NDArray[np.float64]
    ei_determined: NDArray[np.bool_]
    cx: NDArray[np.float64]
    z_rest: NDArray[np.float64]
    sd_z: NDArray[np.float64]
    z_determined: NDArray[np.bool_]
    #: the posterior's square root at the stations: (k, EI stations) of log EI, (k, z0
    #: stations) of z0 [m]; samples are the fit plus Σ_i ξ_i mode_i with ξ_i ~ N(0, 1)
    modes_log_ei: NDArray[np.float64]
    modes_z0: NDArray[np.float64]


def identified_profiles(
    problem: _Problem,
    parameters: NDArray[np.float64],
    post: Posterior,
    x_tail: float,
    x_tip: float,
    *,
    bent: tuple[float, float],
    measured: tuple[float, float],
    scale: tuple[float, float] = (1.0, 1.0),
) -> Profiles:
    """EI and z0 of the fitted parameters with their standard deviations, what the bench
    determines (module docstring; ``bent``: the span between the outermost contact points of
    the load cases [m], ``measured``: the first and last station [m]) and the posterior's
    modes.

    ``scale``: factors (log EI, z0) on the posterior's standard deviations at the determined
    stations (:data:`CONFORMAL_SCALE_EI`, :data:`CONFORMAL_SCALE_Z0` for the calibrated
    bands), applied to the modes' station rows alike, so that samples spread as the bands say:
    the posterior D C D with D the diagonal of the factors (the correlations kept). What is
    determined is decided on the unscaled posterior; elsewhere the band stays the prior's.

    EI [N m²] and the standard deviation of log EI at stations ``ex`` 20 mm apart, z0 [m]
    resting on the plane (zero at the two support points of its lower convex hull) and its
    standard deviation at stations ``cx`` 5 mm apart; where not determined, the prior's.
    """
    n_e = problem.n_e
    theta_e, theta_z = problem.split(parameters)
    ex = np.unique(np.concatenate([np.arange(x_tail, x_tip, _EI_STEP), [x_tip]]))
    ei = problem.ei_at(theta_e, ex)
    be = np.zeros((ex.size, parameters.size))
    be[:, :n_e] = _design(problem.t_e, ex)
    cx = np.unique(np.concatenate([np.arange(x_tail, x_tip, _Z0_STEP), [x_tip]]))
    zc = problem.z0_at(theta_z, cx)
    i, j = lower_hull_bracket(cx, zc, 0.0)
    s1, s2 = cx[i], cx[j]
    line = zc[i] + (zc[j] - zc[i]) * (cx - s1) / (s2 - s1)
    z_rest = np.maximum(zc - line, 0.0)
    bz = _design(problem.t_z, cx)
    bz_g = bz - (np.outer((s2 - cx) / (s2 - s1), bz[i]) + np.outer((cx - s1) / (s2 - s1), bz[j]))
    tz = np.zeros((cx.size, parameters.size))
    tz[:, n_e:] = bz_g @ problem.q_z

    def sd(rows: NDArray[np.float64], cov: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", rows, cov, rows), 0.0))

    sd_e, prior_e = sd(be, post.covariance), sd(be, post.prior)
    sd_zz, prior_z = sd(tz, post.covariance), sd(tz, post.prior)
    # what the data determine: the posterior without the smoothing-bias term (that term says
    # how far the smoothing may have moved the fit, not how much the data know)
    data_cov = post.covariance
    if post.smoothing is not None:
        data_cov = data_cov - np.outer(post.smoothing, post.smoothing)
    if post.discrepancy is not None:
        data_cov = data_cov - post.discrepancy
    det_e = (sd(be, data_cov) < DETERMINED_RATIO * prior_e) & (ex >= bent[0]) & (ex <= bent[1])
    det_z = (sd(tz, data_cov) < DETERMINED_RATIO * prior_z) & (cx >= measured[0])
    det_z &= cx <= measured[1]
    k_e, k_z = (float(f) for f in scale)
    if not (k_e > 0.0 and k_z > 0.0 and np.isfinite(k_e) and np.isfinite(k_z)):
        raise ValueError(f"band scale factors must be finite and > 0, got {scale!r}")
    sd_e = np.where(det_e, k_e * sd_e, np.maximum(sd_e, prior_e))
    # the prior's width where not determined, capped at the ski file's plausible camber band
    # (10 mm, skisnow._quantities 'camber_sd': a camber is 0-5 mm, so 10 mm says "unknown")
    sd_zz = np.minimum(np.where(det_z, k_z * sd_zz, np.maximum(sd_zz, prior_z)), _Z0_SD_CAP)
    # the posterior's square root at the stations, by singular values of its correlation form:
    # each station's row divided by its own standard deviation first, so that log EI
    # (dimensionless, ~0.01-0.3) and z0 (metres, ~1e-6-1e-5) count alike — unscaled, the SVD
    # kept log EI's directions and dropped most of z0's (the modes' z0 spread was a median 0.48
    # of its band on the shipped classic's shop bench; issue 25, seventh pass)
    rows = np.concatenate([be, tz])
    w, v = np.linalg.eigh(0.5 * (post.covariance + post.covariance.T))
    root = rows @ (v * np.sqrt(np.maximum(w, 0.0)))  # (stations, n_params)
    norm = np.sqrt(np.sum(root**2, axis=1))
    norm = np.where(norm > 0.0, norm, 1.0)
    u, s, _ = np.linalg.svd(root / norm[:, None], full_matrices=False)
    share = np.cumsum(s**2) / max(float(np.sum(s**2)), 1e-300)
    k = int(min(MAX_MODES, np.searchsorted(share, 0.995) + 1))
    modes = (norm[:, None] * (u[:, :k] * s[:k])).T  # (k, stations)
    # the calibrated factors on the determined stations' rows (D C D: correlations kept)
    modes = modes * np.concatenate([np.where(det_e, k_e, 1.0), np.where(det_z, k_z, 1.0)])
    return Profiles(
        ex=ex, ei=ei, sd_log_ei=sd_e, ei_determined=det_e, cx=cx, z_rest=z_rest, sd_z=sd_zz,
        z_determined=det_z, modes_log_ei=modes[:, : ex.size], modes_z0=modes[:, ex.size :],
    )  # fmt: skip
