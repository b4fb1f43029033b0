"""Identify a ski's bending stiffness EI(x) and free camber z0(x) from camber-bench data.

The forward model is the bench itself (Kalliorinne et al. 2023, §3.1, eq. 1 h = f(x, m, x_m)):
an Euler–Bernoulli beam with stiffness EI(x) and stress-free shape z0(x), free-floating in
unilateral contact with the rigid stone, loaded by m·g through the boot plate at x_m
(:mod:`skisnow.ski._beam`, same Hermite elements and exact LCP). All load cases of the bench
(every mass and load position) are fitted at once by nonlinear least squares:

    min_p  Σ_k Σ_i n_ki (h_model(x̄_ki; m_k, x_mk, p) - h̄_ki)² / σ²  +  λ ||D₂ θ_E||²
           + λ_z ||D₂ θ_z / z_ref||²

* Parameters p: log EI(x) = Σ_j θ_E,j B_j(x) and z0(x) = Σ_j θ_z,j B_j(x), cubic B-splines on
  uniform knots (EI > 0 and smooth by construction). A linear function added to z0 is invisible
  to the bench (the ski's rigid motion absorbs it): θ_z is restricted to the complement of the
  linear coefficient vectors, and the result is returned resting on the plane (z0 = 0 at the two
  support points of its lower convex hull), the convention of :class:`~skisnow.ski.Ski`.
* Data: each profile is averaged over bins of ``bin_width`` (x̄, h̄, count n); the weights n make
  this the least-squares fit of every sample. σ is the bench noise, estimated from the scatter
  inside the bins (model-free: the profile varies by < 0.1 µm across a 5 mm bin).
* Exact Jacobian by the tangent of the beam at its active set (no finite differences): with the
  contact nodes A fixed, the clamped equilibrium K(θ_E) u = f + E_A r, the gap conditions
  z0(x_A) + a + b x_A + w_A = 0 and the balances Σr = F, Σ r x = M are linear in (u, r, a, b);
  differentiating them gives, per load case, one banded solve per stiffness parameter
  (K⁻¹ ∂K/∂θ_j u) and one small KKT solve (the same matrix as the forward problem). The active
  set is piecewise constant in p, so this is the derivative wherever it is defined.
* Start: z0 from the lightest profile "unloaded" by the beam — its measured heights minus the
  deflection of the beam under the boot load and two point reactions at the centroids of the
  measured contact patches, or of the outermost patch on each side (lever rule) — at each trial
  constant EI (or, if that fits worse, the two lightest profiles extrapolated to zero load),
  continued along a straight line beyond the measured stations, and the constant EI that fits
  all profiles best on it (a grid of log EI, then a bounded scalar search). Then the shape of
  EI(x) from the differences between load cases, in which z0 cancels: with the contact
  reactions of the model the bending moments are statics, h_k − h_1 = ∫ (x − s)₊ ΔM_k / EI ds
  + a line, fitted in log EI; the start is re-made with it (z0 unloaded at the new EI, the
  level of log EI by a walk from the shape's own) and the contacts re-solved while the misfit
  falls, in sequences
  on the lightest third, half and all of the masses; the best start by misfit.
* Homotopy in the contact (only when the EI shape does not improve on the constant start: from
  a good start it pulls the fit away, at the largest λ of the grid and on the smoothed stone):
  with the exact unilateral contact the residuals have a kink at
  every switch of the contact set (the glide zones pressed flat on the stone switch node by
  node with µm changes of z0), and far from the solution the damped Gauss–Newton steps
  collapse. From the default start the fit therefore runs first on a smoothed stone (a softplus
  penalty of width ε; :mod:`skisnow.identify._smooth`): the light load cases (continuation
  in load), then all of them with ε = 10, 3, 1, 0.3, 0.1 µm, then on the exact contact.
* Globalisation (only when the fit ends above the noise: χ² above the discrepancy bound of
  its own residual degrees of freedom, dof + 2 (2 dof)^1/2, dof = n − tr(2H − H²) with H the
  influence matrix of the penalised linearisation; the warning keeps the margin
  :data:`AT_NOISE`): the stalled
  fits sit in a local minimum of the exact-contact misfit with the heaviest load's contact
  under the foot at the wrong node, in a stretch where the measured profile lies within the
  noise of the stone. The smoothed contact is restarted at the stalled fit (ε = 3 → 0.1 µm, a
  smoothing method for the complementarity, Chen & Mangasarian 1996, then on to 1 nm while the
  smoothed stone differs from the exact contact by more than the noise at the polished point),
  then the exact contact again, the lower misfit kept (:mod:`skisnow.identify._fit`, stage 5).
* Optimiser: Levenberg–Marquardt on the normal equations (Marquardt 1963) with the exact
  Jacobian, halving a rejected step along its direction before raising the damping (a kink of
  the contact set), and a stop when the Gauss–Newton step would lower the σ-normalised sum of
  squares by less than 0.01 (:func:`skisnow.identify._lm.levenberg_marquardt` says why not
  SciPy's ``least_squares``).
* Regularisation: λ on the second differences of log-EI coefficients, chosen by generalised
  cross-validation (GCV, Craven & Wahba 1979; Wahba 1990, §4.3) on the Gauss–Newton
  linearisation around ONE converged fit (at the geometric middle of the λ grid): for every λ of
  the grid the penalised linear step, its residual sum of squares and the trace of its
  influence matrix (a few 110 × 110 solves), then one warm-started fit at the chosen λ. λ_z is
  fixed small (z_ref = 1 mm, λ_z = 1): z0 is measured directly almost everywhere; the term only
  continues z0 smoothly over ends the bench did not measure.
* Resolution of z0 by the discrepancy principle (Morozov 1966): a fit that ends above the noise (χ²
  above the discrepancy bound of its own residual degrees of freedom, the restart's test above;
  formerly 1 + 2 (2 n)^-1/2 in the misfit: the twelve seed-1 rows of the identification table are
  the same with either) is refitted with the z0 knot spacing halved (2 n_camber - 3 coefficients:
  the coarse spline is exactly a spline of the fine basis, knot insertion, and starts the fine fit
  on the exact contact), while that stays within ``n_camber_max`` (default 200: one halving), and
  the refinement is kept only if it lowers the Bayesian information criterion χ² + k ln n (Schwarz
  1978). Diagnosis (the shipped skate of version 2, full sequence, started at the true ski): the
  misfit the model reaches is set by z0, not log EI — noise-free (residuals in µm) 5.5 µm rms at 100
  z0 coefficients, 1.8 at 150, 0.94 at 200, and 6.2 / 5.3 µm with 20 / 28 log-EI coefficients at 100
  z0 ones; at 5 µm noise 1.35 σ at 100, 0.98 σ at 197. Why not more: a second halving (391) on that
  bench lowered the misfit 1.25 -> 1.20 σ and made the held-out profiles worse (3.5 -> 11 µm); why
  BIC and not a χ²_k test: on the four-mass benches a refinement lowered χ² by 3.7 times its added
  parameters and made the held-out profiles worse (stiff test ski, 5 µm: 2.8 -> 7.3 µm).
* Uncertainty: the Gauss–Newton (sandwich) covariance of the penalised estimate,
  (JᵀJ + P)⁻¹ JᵀJ (JᵀJ + P)⁻¹ with σ-normalised residuals, propagated to log EI and to z0 (in
  the rest-on-the-plane gauge) at the stations of the identified ski. It is the noise-only
  (linearised) uncertainty; it does not include the bias of the regularisation.

Accuracy (``benchmarks/bench_identify.py --ski classic skate stiff --coverage user full
--noise-um 5 10 --max-nfev 40``, seed 1, and ``--seed 1 2 3 4 5`` for the spread; the README's
identification table has the numbers, now measured on 9444867 with the z0 refinement: the
skate's full sequences within 1.6 % of the contact results and at 5 µm at 1.25 σ, the classic's
full sequences at 0.99-1.03 σ with EI within 2.1 % and z0 within 2.4 µm, seeds 1-4; what
follows was measured on 6db6490, before it; the classic is the shipped classic of
version 2, bcb39eb: EI 57-6200 N m² with a stiff spot behind the foot, tip rising 31 mm; the
skate the shipped skate of version 2, 319a4fa). From the default start every four-mass bench
reaches the noise (30 benches: the classic, the skate of version 1 and the stiff ski, 5 and 10
µm, seeds 1-5: 0.96-1.18 σ, 10 needed the smoothed restart of the globalisation; the skate of
version 2 at 10 µm, seeds 1-5: 0.99-1.10 σ), and every full sequence at seed 1 but the skate's
at 5 µm (1.63 σ; 1.35 σ from the true ski), and the classic's full sequence at 5 and 10 µm,
seeds 1-4 (1.04-1.18 σ; at 5 µm, seed 2 and 10 µm, seed 4 the first fit stalls at 9.9 / 1.6 σ
and the smoothed restart brings it to the noise; fragile until the log-EI bound was lowered
to EI 1e7 N m²: the seed-2 bench made with noise 5e-6 instead of 5 * 1e-6, one ulp apart,
stalled at 16 σ with the tip overhang's EI at 7e10 N m², where the 10 kg case's smoothed Newton
wandered at the roundoff of the stiffness; now 1.03 σ, EI 0.6 %).
Targets (EI 5 % rms, z0 10 µm, held-out within
the noise, contact within 5 %, full sequence < 60 s) at seed 1: full sequences EI 0.8-4.7 %
(skate at 5 µm: 5.1 %), z0 2.5-10.6 µm (classic at 10 µm: missed narrowly), held-out 1.7-7.5 µm
(skate at 5 µm, 5.9 µm: missed), contact 0.5-6.7 % (skate: 6.70 / 6.71 %, missed), 9.4-25.8 s
(the classic's seeds 1-4 included, the other core busy); four-mass
benches EI 2.5-9.0 % (classic 9.0 / 8.9 %, skate at 10 µm 6.8 %, stiff at 10 µm 5.6 %: missed;
the classic 3.2-8.9 % over seeds at 10 µm), z0 2.8-61 µm (missed by all but the stiff ski at 5
µm), held-out 2.8-14.2 µm (classic at 10 µm missed: between the bench's masses its contact rolls
over glide-zone stations no bench load presses; at 50 kg the identified classic was 54-57 µm off
for seeds 1 and 5, at the bench's own masses 2-4 µm; the skate at 5 µm, 6.4 µm, missed too),
contact 2.9-5.3 % (classic at 10 µm missed; 0.9-7.1 % over seeds). Over noise seeds
(``benchmarks/bench_identify_uncertainty.py``) the four-mass classic's contact misses are its
noise (mean difference per quantity ≤ 2.6 %, seeds' standard deviation 2.0-3.9 %); the skate of
version 1 missed systematically (front length at 60 kg +8.35 ± 0.69 % from four masses), the z0
resolution at its glide hump: contact results on snow depend on z0 within a few µm over the few
centimetres of a contact zone; the z0 spline (``n_camber`` = 100 coefficients, ≈ 20 mm knots)
cannot follow a curvature jump there (the skate's glide hump): with noise-free data the skate's
contact lengths are 7.6 % off at 100 coefficients and 2.5 % at 200, but with 10 µm noise more
coefficients make the fit worse (measured at 150 and 200: a z0 smoothing chosen from the data
would be needed). Diagnosis (``benchmarks/bench_identify_contact.py``, measured on the skis
shipped at commit 0320ddc, classic of version 1): the misses are in the zone lengths (the mean
pressures follow them), mostly from z0: the true ski carrying the identified z0 misses by as
much as the identified ski, the true ski carrying the identified EI by 0.6-2.3 %; a Gaussian
bump of 1 µm (sd 20 mm) on the true z0 changes the contact results by 1.9-2.5 %, of 3 µm by
3.8-6.5 %. Refined z0 knots (6 mm in the bench's contact windows) with a curvature penalty
chosen by GCV removed the resolution floor without noise but with 10 µm noise made the user
benches worse, so they are not used.

This module holds the public entry point :func:`identify_ski` (input checks, the identified
:class:`~skisnow.ski.Ski` with its provenance); its result :class:`IdentificationResult` is in
:mod:`skisnow.identify._result`, the binned load cases in :mod:`skisnow.identify._cases`, the
spline parametrisation, forward model and Jacobian in :mod:`skisnow.identify._model`, the
smoothed contact of the homotopy in :mod:`skisnow.identify._smooth`, the fit (start, homotopy,
Levenberg–Marquardt, GCV, bands, restart) in :mod:`skisnow.identify._fit` and the modules it
names, the z0 resolution in :mod:`skisnow.identify._resolution`.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from skisnow._errors import InputError
from skisnow.identify._bands import identified_profiles
from skisnow.identify._cases import _bench_cases, load_cases
from skisnow.identify._fit import fit_bench
from skisnow.identify._model import _Problem
from skisnow.identify._noise import estimate_noise
from skisnow.identify._resolution import AT_NOISE, refine_resolution
from skisnow.identify._result import DEFAULT_LAMBDAS, IdentificationResult
from skisnow.ski import DEFAULT_BOOT_LENGTH, DEFAULT_N_ELEMENTS, Provenance, Ski

__all__ = ["IdentificationResult", "identify_ski"]


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
    n_stiffness: int = 14,
    n_camber: int = 100,
    n_camber_max: int = 200,
    bin_width: float = 0.005,
    element_length: float | None = None,
    noise: float | None = None,
    regularisation: float | None = None,
    lambdas: Sequence[float] = DEFAULT_LAMBDAS,
    initial: Ski | None = None,
    max_nfev: int = 60,
    continuation: Sequence[float] = (1 / 3, 2 / 3),
    progress: Callable[[str], None] | None = None,
    source: str = "",
) -> IdentificationResult:
    """Identify EI(x) and z0(x) of a ski from a camber-bench sequence (all load cases at once).

    Nonlinear least squares of the free-floating beam in unilateral contact with the bench stone
    (Kalliorinne et al. 2023, §3.1, eq. 1) against every profile of the bench; see the module
    docstring for the parametrisation, the exact Jacobian, the GCV choice of the regularisation
    and the Gauss–Newton uncertainty.

    Parameters
    ----------
    bench
        :class:`~skisnow.bench.BenchData` (any masses and load positions; profiles may miss the
        tip and the tail).
    ski
        Which ski of a multi-ski bench.
    name, kind, width, kick_zone
        Of the identified ski; default from the bench metadata (``kind``, ``width_mm``,
        ``kick_zone_mm``), else ``'<bench ski> (identified)'``, ``'classic'``, 44 mm, none.
    x_tail, x_tip
        Ends of the running surface [m] from the balance point; default the metadata's
        ``x_tail_mm``/``x_tip_mm``, else the measured extent. Beyond the measured extent, EI and
        z0 are continued smoothly (the regularisation) and carry wide bands.
    boot_length
        Length [m] of the bench's boot plate; default the metadata's ``boot_length_mm``, else
        :data:`~skisnow.ski._beam.DEFAULT_BOOT_LENGTH`.
    n_stiffness, n_camber
        Cubic B-spline coefficients of log EI and of z0 (of z0 the first resolution).
    n_camber_max
        Most z0 coefficients: a fit that ends above the noise (χ² above the discrepancy bound
        of its residual degrees of freedom, as for the restart) is refitted with the z0 knot
        spacing halved (2 n_camber - 3 coefficients, started at the coarse fit) while that stays
        within ``n_camber_max`` and lowers χ² significantly (the discrepancy principle,
        Morozov 1966; module docstring). ``n_camber_max`` below 2 n_camber - 3: no refinement.
    bin_width
        Profiles are averaged over bins of this width [m] (weights keep the full-data fit).
    element_length
        Beam element length [m] of the forward model; default the mesh of
        :func:`~skisnow.ski.solve_beam` (:data:`~skisnow.ski._beam.DEFAULT_N_ELEMENTS` elements
        over the running surface), on which the identified ski is then used: the nodal contact
        resolves contact positions to an element, and on another mesh the identified ski
        reproduces the bench µm worse (measured on a 1.95 m ski: 11.9 against 10.1 µm rms).
    noise
        Bench noise σ [m]; default estimated from the scatter inside the bins.
    regularisation
        λ; default chosen by GCV over ``lambdas`` (on the linearisation around one fit).
    initial
        A starting ski (the fit then goes to the exact contact directly); default z0 from the
        lightest profile unloaded by the beam and the constant EI that fits best on it, then
        the homotopy on the smoothed contact (module docstring).
    max_nfev
        Residual evaluations allowed to each stage of the fit (each homotopy stage, the fit at
        the middle of the λ grid, the fit at the chosen λ, and each stage of the smoothed
        restart of a fit that ends above the noise).
    continuation
        Fractions of the bench's masses fitted first, in turn (lightest first, on the smoothed
        contact of width 10 µm; default start only).
    progress
        Called with a short message after each stage.
    source
        Where the bench came from (file name), recorded in the provenance.

    Returns
    -------
    IdentificationResult
        The identified ski and the fit's record.

    Raises
    ------
    InputError
        Too little data (fewer than two load cases or profiles shorter than the spline
        resolution), bad options.
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
    for opt, val, lo in (
        ("n_stiffness", n_stiffness, 5),
        ("n_camber", n_camber, 6),
        ("n_camber_max", n_camber_max, 6),
    ):
        if not (isinstance(val, int) and val >= lo):
            raise InputError(f"{opt} must be an integer >= {lo}, got {val!r}")
    for opt, val in (("bin_width", bin_width), ("element_length", element_length or 0.005)):
        if not (np.isfinite(val) and 0 < val < 0.1):
            raise InputError(f"{opt} must be in (0, 0.1) m, got {val}")
    xmin = min(float(c[2].min()) for c in raw)
    xmax = max(float(c[2].max()) for c in raw)
    x_tail = float(md.get("x_tail_mm", xmin * 1e3)) * 1e-3 if x_tail is None else float(x_tail)
    x_tip = float(md.get("x_tip_mm", xmax * 1e3)) * 1e-3 if x_tip is None else float(x_tip)
    if not (x_tail < 0 < x_tip) or x_tail > xmin + 1e-9 or x_tip < xmax - 1e-9:
        raise InputError(
            f"the running surface [{x_tail * 1e3:g}, {x_tip * 1e3:g}] mm must contain the balance "
            f"point and the measured stations [{xmin * 1e3:g}, {xmax * 1e3:g}] mm"
        )
    if boot_length is None:
        boot_length = float(md.get("boot_length_mm", DEFAULT_BOOT_LENGTH * 1e3)) * 1e-3
    # the mesh of solve_beam by default: the nodal contact resolves positions to an element, so
    # the identified ski reproduces the bench best on the mesh it is then used with
    n_el = (
        DEFAULT_N_ELEMENTS
        if element_length is None
        else max(8, round((x_tip - x_tail) / element_length))
    )
    nodes = np.linspace(x_tail, x_tip, n_el + 1)

    cases, scatter, n_samples, _ = load_cases(raw, nodes, boot_length, bin_width)
    try:
        estimate = estimate_noise([(c[2], c[3]) for c in raw])
    except ValueError:
        raise InputError(
            f"bench of ski {label!r}: every profile needs at least 5 stations to estimate the "
            "noise"
        ) from None
    noise_warnings: list[str] = []
    if noise is None:
        sigma_cases = np.maximum(np.nan_to_num(estimate.sigma, nan=estimate.pooled), 1e-7)
        sigma = max(float(estimate.pooled), 1e-7)
    else:
        if not (np.isfinite(noise) and noise > 0):
            raise InputError(f"noise must be > 0 m, got {noise}")
        sigma = float(noise)
        sigma_cases = np.full(len(cases), sigma)
        ratio = sigma / max(float(estimate.pooled), 1e-12)
        if not 1 / 1.5 <= ratio <= 1.5:
            noise_warnings.append(
                f"noise misestimate: the given noise {sigma * 1e3:.4g} mm is {ratio:.2g} times "
                f"the noise the bench's profiles show ({estimate.pooled * 1e3:.4g} mm, from the "
                "scatter about local cubics); the fit's weights and bands follow the given value"
            )
    problem = _Problem(cases, nodes, n_stiffness, n_camber, sigma_cases)
    options = dict(
        regularisation=regularisation, lambdas=lambdas, max_nfev=max_nfev,
        continuation=continuation, say=say,
    )  # fmt: skip
    fitted = fit_bench(problem, cases, nodes, initial=initial, **options)
    # The z0 resolution by the discrepancy principle (Morozov 1966; Schwarz 1978)
    problem, fitted, resolution = refine_resolution(
        problem, fitted, cases, nodes, n_stiffness=n_stiffness, sigma=sigma_cases,
        n_camber_max=n_camber_max, options=options,
    )  # fmt: skip
    sol, lam, records, r = fitted.solution, fitted.regularisation, fitted.records, fitted.residuals

    # -- the identified ski
    ex, ei, sd_log_ei, cx, z_rest, sd_z = identified_profiles(
        problem, sol.x, fitted.covariance, x_tail, x_tip
    )
    seconds = time.perf_counter() - t_start
    rms = float(np.sqrt((float(r @ r) * sigma**2 + scatter) / n_samples))
    kz: Any = kick_zone
    if isinstance(kz, str):
        kz_mm = md.get("kick_zone_mm")
        kz = None if kz_mm is None else (float(kz_mm[0]) * 1e-3, float(kz_mm[1]) * 1e-3)
    kind_ = kind or md.get("kind") or ("classic" if kz is not None else "skate")
    masses = sorted({c.mass for c in cases})
    positions = sorted({round(c.position * 1e3, 6) for c in cases})
    identified = Ski(
        name=name or f"{label} (identified)",
        kind=kind_,
        x_tail=x_tail,
        x_tip=x_tip,
        width=float(md.get("width_mm", 44.0)) * 1e-3 if width is None else float(width),
        stiffness_x=ex,
        stiffness_values=ei,
        camber_x=cx,
        camber_values=z_rest,
        kick_zone=kz,
        stiffness_log_sd=sd_log_ei,
        camber_sd=sd_z,
        description=(
            f"Identified from the camber bench of ski {label!r}: {len(cases)} load cases "
            f"({len(masses)} masses {masses[0]:g}-{masses[-1]:g} kg at {len(positions)} "
            f"positions {positions[0]:g}..{positions[-1]:g} mm), stations "
            f"{xmin * 1e3:.0f}..{xmax * 1e3:.0f} mm. Bands: 95 % (Gauss-Newton, noise only)."
        ),
        provenance=Provenance(
            # the text identified ski files have carried (kept when identify_ski moved)
            method="identified from camber-bench data (skisnow.ski.identify_ski: nonlinear "
            "least squares of the beam on the bench stone, GCV regularisation)",
            data=(source or f"bench of ski {label!r}")
            + f"; {len(cases)} profiles, {n_samples} samples",
            sources=(
                "Kalliorinne, K., et al. (2023): the camber bench and its load sequence (§3.1)",
                "Craven, P., Wahba, G. (1979): generalized cross-validation",
                "Marquardt, D. W. (1963): the Levenberg-Marquardt method",
            ),
            created=time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            software=f"skisnow {_version()}",
            details=(
                ("lambda", lam),
                ("criterion", "given" if regularisation is not None else "gcv"),
                ("n_stiffness", n_stiffness),
                ("n_camber", problem.n_z),
                ("noise_mm", sigma * 1e3),
                ("residual_rms_mm", rms * 1e3),
                ("boot_length_mm", boot_length * 1e3),
                ("measured_x_mm", f"{xmin * 1e3:.1f}..{xmax * 1e3:.1f}"),
                ("seconds", round(seconds, 2)),
            ),
        ),
    )
    misfit = float(sol.misfit_rms)
    warn: tuple[str, ...] = ()
    if not misfit <= AT_NOISE:
        warn = (
            f"the fit ended at {misfit:.2f} σ, above the bench noise ({AT_NOISE:g} σ): the "
            "identified ski may be a local minimum, not the ski on the bench; load cases at "
            "more masses and load positions constrain it",
        )
    return IdentificationResult(
        ski=identified,
        regularisation=lam,
        criterion="given" if regularisation is not None else "gcv",
        gcv=tuple(records),
        noise=sigma,
        residual_rms=rms,
        n_cases=len(cases),
        n_samples=n_samples,
        n_parameters=problem.n_params,
        n_evaluations=int(sol.nfev),
        converged=bool(sol.status > 0),
        message=str(sol.message),
        seconds=seconds,
        misfit=misfit,
        warnings=tuple(noise_warnings) + warn,
        resolution=tuple(resolution),
        n_bins=problem.n_data,
    )


def _version() -> str:
    from skisnow import __version__

    return __version__
