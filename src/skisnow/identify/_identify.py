"""Identify a ski's bending stiffness EI(x) and free camber z0(x) from camber-bench data.

The forward model is the bench itself (Kalliorinne et al. 2023, §3.1, eq. 1 h = f(x, m, x_m)):
an Euler–Bernoulli beam with stiffness EI(x) and stress-free shape z0(x), free-floating in
unilateral contact with the rigid stone, loaded by m·g through the boot plate at x_m, the
contact resolved between the nodes (:func:`skisnow.ski.solve_point_contact`: the ski does not
dip through the stone anywhere). All load cases of the bench are fitted at once:

    min_p  Σ_k Σ_i w_ki n_ki (h_model(x̄_ki; m_k, x_mk, p) - h̄_ki)² / σ_k²  +  |P p - t|²

* Parameters p: log EI(x) and z0(x) as cubic B-splines on uniform knots (``n_stiffness``
  coefficients, ~50 mm knots by default; z0 without its linear part, which the bench cannot
  see, knots at the station spacing within 10-20 mm by default).
* Data: profiles averaged over bins of ``bin_width`` (x̄, h̄, count n), h_model(x̄) read as the
  same mean of the model at the bin's stations (:func:`skisnow.identify._model._bin_average`);
  σ_k the noise of each
  load case from the scatter about local cubics of its deviation from the other profiles at the
  same stations, where the free camber cancels (:mod:`skisnow.identify._noise`, any station
  spacing); w the Huber weights of outlying bins (:mod:`skisnow.identify._robust`).
* Penalty P p - t: the smoothness of log EI (λ by GCV), a weak trend term, and a proper prior
  on the level of log EI and on z0 (:mod:`skisnow.identify._model`).
* The fit (:mod:`skisnow.identify._fit`): a start from the load differences, the smoothed
  contact from a far start, Levenberg–Marquardt with the exact Jacobian, GCV, the smoothed
  restart of a fit above the noise, the z0 resolution by the discrepancy principle.
* Then the discretisation error of the forward model (:mod:`skisnow.identify._mesh_error`), the
  Laplace posterior with the prior and that error (:mod:`skisnow.identify._bands`): bands, the
  stations the bench determines, the posterior's modes; and what the result is worth
  (:mod:`skisnow.identify._diagnosis`).

How the method came about, what was tried and measured: ``docs/theory/identification.md``.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from skisnow._errors import ConvergenceError, InputError
from skisnow._parallel import single_threaded_blas
from skisnow.identify._bands import (
    UNDERSMOOTHING,
    band_scale,
    bands_detail,
    discrepancy_covariance,
    discrepancy_rms,
    identified_profiles,
    posterior,
    smoothing_bias,
)
from skisnow.identify._cases import _bench_cases, load_cases
from skisnow.identify._diagnosis import correlated_excess, diagnose
from skisnow.identify._edges import EDGE_SCALE, edge_refit
from skisnow.identify._fit import fit_bench
from skisnow.identify._mesh_error import mesh_error
from skisnow.identify._model import _Problem
from skisnow.identify._noise import estimate_noise
from skisnow.identify._prior import PopulationPrior
from skisnow.identify._resolution import refine_resolution
from skisnow.identify._result import DEFAULT_LAMBDAS, IdentificationResult, _span, _version
from skisnow.identify._robust import robust_refit
from skisnow.ski import DEFAULT_BOOT_LENGTH, Provenance, Ski

__all__ = ["DEFAULT_ELEMENT_LENGTH", "IdentificationResult", "identify_ski"]

#: Default element length [m] of the identification's beam: with the contact resolved between
#: nodes, 10 mm elements reproduce the loaded heights within 0.2 µm of 1.25 mm ones (five skis,
#: four load cases each; the fit reports the difference at its result, ``mesh_error``).
DEFAULT_ELEMENT_LENGTH = 0.010


def _camber_coefficients(raw: list, length: float) -> int:
    """z0 coefficients for knots at the median station spacing, within 10-20 mm: a base's
    waviness of 15 µm on a 60 mm wavelength needs them (issue 25's ski, shop bench at 5 µm,
    started at the true ski: 20 mm knots left z0 16.8 µm off with 10 % of its stations
    within their band, 10 mm knots 3.3 µm and 99 %)."""
    spacing = float(np.median(np.concatenate([np.diff(np.sort(c[2])) for c in raw])))
    knot = float(np.clip(spacing, 0.010, 0.020))
    return max(6, round(length / knot) + 3)


# One BLAS thread: the fit's products are small (JᵀJ of ~250 parameters, 250 × 250 solves) and a
# second OpenBLAS thread's spinning waits cost far more on a shared machine (measured on ski 6's
# shop bench at load 5.6-7.3: 6.4 s CPU, 12.4 s wall on one thread; 25.3 s CPU, 82.6 s wall on
# OpenBLAS's default two; docs/validation/identification-uncertainty.md, "Fifth pass: time").
@single_threaded_blas()
def identify_ski(
    bench: Any,
    *,
    ski: str | None = None,
    name: str | None = None,
    kind: str | None = None,
    x_tail: float | None = None,
    x_tip: float | None = None,
    width: float | None = None,
    kick_zone: tuple[float, float] | str | None = "bench",
    boot_length: float | None = None,
    n_stiffness: int = 60,
    n_camber: int | None = None,
    n_camber_max: int = 400,
    bin_width: float = 0.005,
    element_length: float | None = None,
    noise: float | None = None,
    regularisation: float | None = None,
    lambdas: Sequence[float] = DEFAULT_LAMBDAS,
    initial: Ski | None = None,
    max_nfev: int = 60,
    continuation: Sequence[float] = (1 / 3, 2 / 3),
    robust: bool = True,
    criterion: str = "gcv",
    smoothing_bands: bool = True,
    discrepancy_bands: bool = False,
    bands: str = "laplace",
    stiffness_penalty: str = "quadratic",
    edge_scale: float = EDGE_SCALE,
    prior: PopulationPrior | None = None,
    progress: Callable[[str], None] | None = None,
    source: str = "",
) -> IdentificationResult:
    """Identify EI(x) and z0(x) of a ski from a camber-bench sequence (all load cases at once).

    Nonlinear least squares of the free-floating beam in unilateral contact with the bench stone
    (Kalliorinne et al. 2023, §3.1, eq. 1) against every profile of the bench, with a Huber loss
    for outliers, the Laplace posterior for the bands and the stations the bench determines
    (module docstring).

    Parameters
    ----------
    bench
        :class:`~skisnow.bench.BenchData` (any masses and load positions, stations 1-20 mm
        apart; profiles may miss the tip and the tail).
    ski
        Which ski of a multi-ski bench.
    name, kind, width, kick_zone
        Of the identified ski; default from the bench metadata (``kind``, ``width_mm``,
        ``kick_zone_mm``), else ``'<bench ski> (identified)'``, ``'classic'``, 44 mm, none.
    x_tail, x_tip
        Ends of the running surface [m] from the balance point; default the metadata's
        ``x_tail_mm``/``x_tip_mm``, else the measured extent.
    boot_length
        Length [m] of the bench's boot plate; default the metadata's ``boot_length_mm``, else
        :data:`~skisnow.ski.DEFAULT_BOOT_LENGTH`.
    n_stiffness, n_camber
        Cubic B-spline coefficients of log EI and of z0 (of z0 the first resolution; default
        knots at the median station spacing, within 10-20 mm).
    n_camber_max
        Most z0 coefficients: a fit that ends above the noise is refitted with the z0 knot
        spacing halved while that stays within ``n_camber_max`` (the discrepancy principle,
        Morozov 1966; :mod:`skisnow.identify._resolution`).
    bin_width
        Profiles are averaged over bins of this width [m] (weights keep the full-data fit), and
        so is the model (its mean at each bin's stations).
    element_length
        Beam element length [m] of the forward model (default :data:`DEFAULT_ELEMENT_LENGTH`);
        its discretisation error at the fit is reported (``mesh_error``).
    noise
        Bench noise σ [m] of every load case; default estimated per load case from the data.
    regularisation
        λ; default chosen by GCV over ``lambdas``.
    initial
        A starting ski; default from the lightest profile and the load differences.
    max_nfev
        Residual evaluations allowed to each stage of the fit.
    continuation
        Fractions of the bench's masses fitted first, in turn, when the start has no EI shape.
    robust
        Huber weights for bins beyond the noise's extreme (:mod:`skisnow.identify._robust`).
    criterion
        How λ is chosen over ``lambdas``: ``'gcv'`` (generalised cross-validation, Craven &
        Wahba 1979), ``'evidence'`` (the Laplace evidence, type-II maximum likelihood, MacKay
        1992) or ``'case-cv'`` (leave-one-load-case-out cross-validation with the
        one-standard-error rule, Rice & Silverman 1991; :mod:`skisnow.identify._cv`); all on
        the Gauss–Newton linearisation. GCV is the default: on the calibration skis of issue
        25 the evidence chose λ 10-100 times larger and its bands covered EI at 72 % of the
        determined stations against GCV's 88 % (both with the smoothing bias at λ / 100); on
        the full plans of issue 25's ski and ski 1001 case-cv chose λ 1e4-1e5 and did not
        lower the EI error (docs/validation/identification-uncertainty.md).
    discrepancy_bands
        Add the covariance of a smooth model discrepancy (:func:`~skisnow.identify._bands.
        discrepancy_covariance`, Kennedy & O'Hagan 2001) of the fit's own stated excess over
        the noise (the diagnosis's δ, :func:`~skisnow.identify._bands.discrepancy_rms`) over
        150 mm; nothing when the fit is at the noise (δ = 0). Off by default: it lifts the z0
        coverage by 2-5 points only (held-out skis 37-45 %, skis 5-24 70-77 %; issue 25's
        seventh pass, docs/validation/identification-uncertainty.md): what moves z0 is common
        to all load cases, which the fit absorbs and the residuals do not show, and the misses
        are a nonlinear trade of z0 against EI that no band at the fit sees.
    bands
        ``'laplace'`` (the posterior's 2 sd, default) or ``'conformal'``: its widths scaled by
        the split-conformal factors at the determined stations (:func:`~skisnow.identify.
        _bands.calibrated_scale`; ×1.33 log EI, ×4.66 z0, calibrated on seeded skis 1-14):
        z0 covered at 99-100 % of the determined stations of other skis, above the 90-98 %
        target, so an option (issue 25's eighth pass). Not with ``discrepancy_bands``.
    smoothing_bands
        Add the estimated smoothing bias to the bands (:func:`~skisnow.identify._bands.
        smoothing_bias`: the step to the fit at min(λ / 100, min(lambdas)), a rule calibrated
        on seeded skis 1-4 and validated on others).
    stiffness_penalty, edge_scale
        The smoothness penalty of log EI: ``'quadratic'`` (λ |D₂ θ|², the default) or
        ``'huber'`` (edge-preserving: the Huber loss of scale ``edge_scale``, in the prior's
        standard deviations, on the smoothness rows √λ D₂ θ of the log-EI coefficients, by
        reweighting from the quadratic fit at its λ; ``'huber-gcv'`` chooses λ again by GCV at
        each reweighting; :mod:`skisnow.identify._edges`). An option: on the calibration skis
        it did not lower the EI error (docs/validation/identification-uncertainty.md).
    prior
        An opt-in population prior (:func:`~skisnow.identify.population_prior`) in place of
        the smoothness penalty and its λ: the fit is then the Bayes-linear estimate under that
        population, only as good as the population is like the ski (a modelling choice; its
        provenance is recorded; docs/validation/identification-uncertainty.md, eighth pass).
    progress
        Called with a short message after each stage.
    source
        Where the bench came from (file name), recorded in the provenance.

    Returns
    -------
    IdentificationResult
        The identified ski and the fit's record (``converged``, ``warnings`` and ``causes``:
        what the result is worth).

    Raises
    ------
    InputError
        Too little data or bad options.
    ConvergenceError
        The fit could not be carried out (no contact solution at any start: the bench's
        profiles are not those of one ski on the stone).
    """
    t_start = time.perf_counter()
    say = progress or (lambda _msg: None)
    from skisnow.bench import BenchData

    if not isinstance(bench, BenchData):
        raise InputError(f"bench must be a skisnow.bench.BenchData, got {type(bench).__name__}")
    label = bench.ski_name(ski)
    md = bench.metadata if bench.metadata.get("ski") == label else {}
    raw = _bench_cases(bench, label)
    if len(raw) < 2:
        raise InputError(f"bench of ski {label!r}: need at least 2 load cases, got {len(raw)}")
    xmin = min(float(c[2].min()) for c in raw)
    xmax = max(float(c[2].max()) for c in raw)
    x_tail = float(md.get("x_tail_mm", xmin * 1e3)) * 1e-3 if x_tail is None else float(x_tail)
    x_tip = float(md.get("x_tip_mm", xmax * 1e3)) * 1e-3 if x_tip is None else float(x_tip)
    if stiffness_penalty not in ("quadratic", "huber", "huber-gcv"):
        raise InputError(
            "stiffness_penalty must be 'quadratic', 'huber' or 'huber-gcv', got "
            f"{stiffness_penalty!r}"
        )
    if not (np.isfinite(edge_scale) and edge_scale > 0):
        raise InputError(f"edge_scale must be > 0, got {edge_scale}")
    if prior is not None and (stiffness_penalty != "quadratic" or regularisation is not None):
        raise InputError("prior replaces the smoothness penalty: no regularisation or edges")
    plain = smoothing_bands and not discrepancy_bands and prior is None
    scale = band_scale(bands, calibrated_on=plain)
    if criterion not in ("gcv", "evidence", "case-cv"):
        raise InputError(f"criterion must be 'gcv', 'evidence' or 'case-cv', got {criterion!r}")
    if n_camber is None:
        n_camber = _camber_coefficients(raw, x_tip - x_tail)
    for opt, val, lo in (
        ("n_stiffness", n_stiffness, 5),
        ("n_camber", n_camber, 6),
        ("n_camber_max", n_camber_max, 6),
    ):
        if not (isinstance(val, int) and val >= lo):
            raise InputError(f"{opt} must be an integer >= {lo}, got {val!r}")
    element_length = DEFAULT_ELEMENT_LENGTH if element_length is None else element_length
    for opt, val in (("bin_width", bin_width), ("element_length", element_length)):
        if not (np.isfinite(val) and 0 < val < 0.1):
            raise InputError(f"{opt} must be in (0, 0.1) m, got {val}")
    if not (x_tail < 0 < x_tip) or x_tail > xmin + 1e-9 or x_tip < xmax - 1e-9:
        raise InputError(
            f"the running surface [{x_tail * 1e3:g}, {x_tip * 1e3:g}] mm must contain the balance "
            f"point and the measured stations [{xmin * 1e3:g}, {xmax * 1e3:g}] mm"
        )
    if boot_length is None:
        boot_length = float(md.get("boot_length_mm", DEFAULT_BOOT_LENGTH * 1e3)) * 1e-3
    n_el = max(8, round((x_tip - x_tail) / element_length))
    nodes = np.linspace(x_tail, x_tip, n_el + 1)

    cases, _, n_samples, _ = load_cases(raw, nodes, boot_length, bin_width)
    try:
        estimate = estimate_noise([(c[2], c[3]) for c in raw])
    except ValueError:
        raise InputError(
            f"bench of ski {label!r}: every profile needs at least 5 stations to estimate the noise"
        ) from None
    # the standard error of the estimated noise's log (its 95 % interval is ±1.96 of them)
    lo, hi = estimate.interval
    noise_log_se = float(np.log(hi / lo)) / (2 * 1.96) if lo > 0 else 0.0
    if noise is None:
        sigma_cases = np.maximum(np.nan_to_num(estimate.sigma, nan=estimate.pooled), 1e-7)
    else:
        if not (np.isfinite(noise) and noise > 0):
            raise InputError(f"noise must be > 0 m, got {noise}")
        sigma_cases = np.full(len(cases), float(noise))
    problem = _Problem(cases, nodes, n_stiffness, n_camber, sigma_cases, prior)
    options = dict(
        regularisation=1.0 if prior is not None else regularisation, lambdas=lambdas,
        max_nfev=max_nfev, continuation=continuation, say=say, criterion=criterion,
    )  # fmt: skip
    try:
        fitted = fit_bench(problem, cases, nodes, initial=initial, **options)
        # the z0 resolution by the discrepancy principle (Morozov 1966; Schwarz 1978)
        problem, fitted, resolution = refine_resolution(
            problem, fitted, cases, nodes, n_stiffness=n_stiffness, sigma=sigma_cases,
            n_camber_max=n_camber_max, options=options,
        )  # fmt: skip
        outliers: tuple = ()
        if robust:

            def refit(p: Any, lam: float) -> Any:
                return fit_bench(problem, cases, nodes, initial=None, start_parameters=p,
                                 **{**options, "regularisation": lam})  # fmt: skip

            fitted, outliers = robust_refit(problem, fitted, refit, say)
        if stiffness_penalty != "quadratic":
            gcv_again = stiffness_penalty == "huber-gcv"

            def refit_edges(p: Any, lam: float) -> Any:
                opts = {**options, "regularisation": None if gcv_again else lam}
                return fit_bench(problem, cases, nodes, initial=None, start_parameters=p, **opts)

            fitted = edge_refit(problem, fitted, refit_edges, say, edge_scale)
    except (np.linalg.LinAlgError, FloatingPointError) as exc:
        raise ConvergenceError(
            f"bench of ski {label!r}: the fit broke down ({exc}); the profiles do not fit one "
            "ski on the stone under growing loads (check the masses and load positions of the "
            "bench file)",
            result=None,
        ) from None
    sol, lam = fitted.solution, fitted.regularisation
    # the discretisation error of the forward model at the fit, then the posterior with it
    merr = mesh_error(problem, sol.x, raw, boot_length=boot_length, bin_width=bin_width)
    smooth_bias = None
    if smoothing_bands and lam > 0:
        lam_under = min(lam / UNDERSMOOTHING, min(float(v) for v in lambdas))
        smooth_bias = smoothing_bias(sol, problem.penalty(lam_under))
    post = posterior(sol, merr.residual_change, smooth_bias)
    contacts = np.concatenate([c for c in problem.contacts if c.size] or [np.zeros(1)])
    bent = (float(contacts.min()), float(contacts.max()))
    prof = identified_profiles(problem, sol.x, post, x_tail, x_tip, bent=bent,
                               measured=(xmin, xmax), scale=scale)  # fmt: skip
    r = sol.fun
    chi2 = float(r @ r)
    case_misfit = []
    start = 0
    for c in cases:
        rk = r[start : start + c.x.size]
        start += c.x.size
        case_misfit.append((c.mass, c.position, float(np.sqrt(np.mean(rk**2)))))
    masses = sorted({c.mass for c in cases})
    positions = sorted({round(c.position * 1e3, 6) for c in cases})
    # the part of the excess over the noise correlated between neighbouring bins (σ² units);
    # the excess itself, δ, is the diagnosis's (what σ_eff² = σ² + δ² allows, up to the cap)
    corr2 = correlated_excess(r, [c.x.size for c in cases])
    # per load case, the bins' positions and σ-normalised residual weights (a bin of c
    # stations weighs √c): they turn δ into the height of a smooth error (and are the
    # discrepancy's rows)
    rows = [(c.x, c.w * problem.bin_weights[k] / problem.sigma_cases[k])
            for k, c in enumerate(problem.cases)]  # fmt: skip
    height_scale = discrepancy_rms(1.0, rows)
    diag = diagnose(
        chi2=chi2, bound=fitted.chi2_bound, misfit=float(sol.misfit_rms), lm_status=sol.status,
        noise=problem.sigma, noise_given=noise, noise_data=float(estimate.pooled),
        dof=fitted.chi2_dof, noise_se=0.0 if noise is not None else noise_log_se,
        case_misfits=case_misfit, mesh_rms=merr.rms, element_length=merr.element_length,
        ei_x=prof.ex, ei_determined=prof.ei_determined, bent=bent,
        cases=[(c.mass, c.position) for c in cases], correlated2=corr2, n_bins=r.size,
        height_scale=height_scale,
    )  # fmt: skip
    disc_rms = 0.0
    if discrepancy_bands and diag.delta > 0:
        # the fit's own stated excess δ as a smooth discrepancy (the diagnosis's δ: the stations
        # a bench determines do not depend on it, so the profiles are only re-banded)
        disc_rms = diag.delta * height_scale
        disc = discrepancy_covariance(sol, rows, rms=disc_rms)
        post = posterior(sol, merr.residual_change, smooth_bias, disc)
        prof = identified_profiles(
            problem, sol.x, post, x_tail, x_tip, bent=bent, measured=(xmin, xmax)
        )
    for w in outliers:
        say(f"outlier: {w.mass:g} kg at {w.load_position * 1e3:g} mm, x = {w.x * 1e3:.0f} mm")
    seconds = time.perf_counter() - t_start
    rms = float(np.sqrt(chi2 / max(r.size, 1))) * problem.sigma
    kz: Any = kick_zone
    if isinstance(kz, str):
        kz_mm = md.get("kick_zone_mm")
        kz = None if kz_mm is None else (float(kz_mm[0]) * 1e-3, float(kz_mm[1]) * 1e-3)
    kind_ = kind or md.get("kind") or ("classic" if kz is not None else "skate")
    bias_note = ", smoothing bias" if smooth_bias is not None else ""
    how = "prior" if prior is not None else "given" if regularisation is not None else criterion
    band_note = bands_detail(bands, smoothing=smooth_bias is not None, discrepancy=disc_rms)
    span_e = _span(prof.ex, prof.ei_determined)
    span_z = _span(prof.cx, prof.z_determined)
    identified = Ski(
        name=name or f"{label} (identified)",
        kind=kind_,
        x_tail=x_tail,
        x_tip=x_tip,
        width=float(md.get("width_mm", 44.0)) * 1e-3 if width is None else float(width),
        stiffness_x=prof.ex,
        stiffness_values=prof.ei,
        camber_x=prof.cx,
        camber_values=prof.z_rest,
        kick_zone=kz,
        stiffness_log_sd=prof.sd_log_ei,
        camber_sd=prof.sd_z,
        stiffness_determined=tuple(prof.ei_determined),
        camber_determined=tuple(prof.z_determined),
        stiffness_modes=prof.modes_log_ei,
        camber_modes=prof.modes_z0,
        description=(
            f"Identified from the camber bench of ski {label!r}: {len(cases)} load cases "
            f"({len(masses)} masses {masses[0]:g}-{masses[-1]:g} kg at {len(positions)} "
            f"positions {positions[0]:g}..{positions[-1]:g} mm), stations "
            f"{xmin * 1e3:.0f}..{xmax * 1e3:.0f} mm. Bands: 95 % of the Laplace posterior "
            f"{'(widths scaled by conformal factors) ' if bands == 'conformal' else ''}"
            f"(noise, prior, discretisation error{bias_note}); determined by the bench: "
            f"EI {span_e}, "
            f"z0 {span_z} (elsewhere the prior's width)."
        ),
        provenance=Provenance(
            method="identified from camber-bench data (skisnow.identify.identify_ski: nonlinear "
            "least squares of the beam on the bench stone, contact resolved between nodes, GCV "
            "regularisation, Huber loss, Laplace posterior)",
            data=(source or f"bench of ski {label!r}")
            + f"; {len(cases)} profiles, {n_samples} samples",
            sources=(
                "Kalliorinne, K., et al. (2023): the camber bench and its load sequence (§3.1)",
                "Craven, P., Wahba, G. (1979): generalized cross-validation",
                "Wahba, G. (1983): Bayesian confidence intervals for the smoothing spline",
                "Marquardt, D. W. (1963): the Levenberg-Marquardt method",
                "Huber, P. J. (1964): robust estimation of a location parameter",
                "Eubank, R. L., Speckman, P. L. (1993): confidence bands in nonparametric "
                "regression (the smoothing bias in the bands)",
            ),
            created=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            software=f"skisnow {_version()}",
            details=(
                ("lambda", lam),
                ("criterion", how),
                ("stiffness_penalty", stiffness_penalty if prior is None else prior.description),
                ("n_stiffness", n_stiffness),
                ("n_camber", problem.n_z),
                ("noise_mm", problem.sigma * 1e3),
                ("residual_rms_mm", rms * 1e3),
                ("misfit_sigma", round(float(sol.misfit_rms), 4)),
                ("converged", diag.converged),
                ("boot_length_mm", boot_length * 1e3),
                ("measured_x_mm", f"{xmin * 1e3:.1f}..{xmax * 1e3:.1f}"),
                ("determined_ei_mm", span_e),
                ("determined_z0_mm", span_z),
                ("element_length_mm", merr.element_length * 1e3),
                # null when it could not be estimated (a ski file holds finite numbers only)
                ("mesh_error_rms_um", round(merr.rms * 1e6, 4) if np.isfinite(merr.rms) else None),
                ("mesh_error_max_um", round(merr.max * 1e6, 4) if np.isfinite(merr.max) else None),
                ("model_error_rms_um", round(diag.delta * height_scale * 1e6, 4)),
                ("outliers", len(outliers)),
                ("bands", band_note),
                ("seconds", round(seconds, 2)),
            ),
        ),
    )
    return IdentificationResult(
        ski=identified,
        regularisation=lam,
        criterion=how,
        gcv=tuple(fitted.records),
        noise=problem.sigma,
        residual_rms=rms,
        n_cases=len(cases),
        n_samples=n_samples,
        n_parameters=problem.n_params,
        n_evaluations=int(sol.nfev),
        converged=diag.converged,
        message=str(sol.message),
        seconds=seconds,
        misfit=float(sol.misfit_rms),
        warnings=diag.warnings,
        resolution=tuple(resolution),
        n_bins=problem.n_data,
        chi2_bound=float(fitted.chi2_bound),
        noise_cases=tuple(
            (m, p, float(s), float(f))
            for (m, p, f), s in zip(case_misfit, problem.sigma_cases, strict=True)
        ),
        mesh_error=(merr.rms, merr.max, merr.element_length),
        outliers=tuple((o.mass, o.load_position, o.x, o.residual, o.z) for o in outliers),
        posterior_inflation=post.inflation,
        causes=diag.causes,
        model_error=(diag.delta * height_scale, diag.delta),
    )
