"""One case end to end: ski → loaded profile → apparent contact → zones (:func:`solve_case`).

The chain of Kalliorinne et al. (2023), §3: the loaded camber profile h = f(x, m, x_m) (eq. 1),
pressed as a rigid body free to translate and rotate about the load point (force and moment
balance, eq. 3) into an elastic half-space of equivalent modulus E' (eq. 2), and the contact
grouped into rear / middle / front zones with the Breitschädel (2012) 50 µm estimate beside
them. This module is the only place the chain is written; the sweep's chunk function, the
``skisnow contact`` command, the report, the demo and the examples all call :func:`solve_case`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._checks import positive_finite  # the one positive-and-finite rule
from skisnow._errors import DomainWarning, InputError, UnsupportedLoadError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.pipeline._plausible import pressure_notes
from skisnow.pipeline._profiles import (
    DEFAULT_N_POINTS,
    DEFAULT_PROFILE_SOURCE,
    _check_source,
    loaded_profiles,
    resolve_ski,
    stations,
)
from skisnow.pipeline._record import note_implausible, note_solved, note_unconverged

if TYPE_CHECKING:
    from skisnow.contact import (
        ContactSolution,
        FlexibleSolution,
        Material,
        Zone,
        ZoneMetrics,
    )
    from skisnow.multiscale import Base, FrictionParameters, MicroCurves, RealContact, RealSummary
    from skisnow.ski import Ski
    from skisnow.snow import Snow

#: Contact models of :func:`skisnow.contact.solve_contact` a case may use.
MODELS: tuple[str, ...] = ("strip", "surface")
#: Ski models: ``'rigid'`` (the paper's method: the profile loaded on the stone pressed into the
#: snow as a rigid body) or ``'flexible'`` (the free beam bending on the snow,
#: :func:`skisnow.contact.solve_flexible`).
SKI_MODELS: tuple[str, ...] = ("rigid", "flexible")
#: Default tolerance of the contact solver (relative pressure change between iterations).
DEFAULT_TOL: float = 1e-8


@dataclass(frozen=True, kw_only=True, eq=False)
class Case:
    """One solved case (SI units): its inputs, loaded profile, contact and zones.

    Attributes
    ----------
    ski
        The :class:`~skisnow.ski.Ski`, or ``None`` for a bare profile (:func:`solve_case` with
        ``ski=None``).
    label
        The ski's name, or what the caller named the bare profile.
    mass, load_position, snow_modulus
        m [kg], x_m [m] from the balance point (positive toward the tip), E_counter [Pa].
    model, profile_source, n_points
        Contact model, where the profile came from (``'network'``, ``'beam'`` or ``'given'``),
        stations along the ski.
    modulus, width, kick_zone
        E' of eq. 2 [Pa], the width of the ski [m], the kick zone that defines the middle zone.
    x, height
        The loaded profile (stations [m], camber height h [m]): for the rigid ski the profile
        loaded on the stone; for the flexible ski the ski bent on the snow, in the frame of the
        binding (z0 + bending; ``flexible.shape`` is its position on the snow).
    ski_model
        ``'rigid'`` or ``'flexible'`` (:data:`SKI_MODELS`).
    flexible
        The :class:`~skisnow.contact.FlexibleSolution` (bent ski, beam and snow fields) of a
        flexible case, ``None`` for a rigid one.
    solution
        The :class:`~skisnow.contact.ContactSolution`.
    zones
        The :class:`~skisnow.contact.ZoneMetrics` (rear / middle / front / total and the
        Breitschädel estimate, :attr:`breitschaedel`).
    converged
        Whether the contact solver reached its tolerance.
    warnings
        Texts of what the caller should know: the camber network used outside its trained
        domain (:class:`~skisnow.DomainWarning`), an apparent pressure more than the snow can
        bear or beyond a small strain (:func:`skisnow.pipeline._plausible.pressure_notes`), a
        solve that did not converge (always last).
    snow
        The :class:`~skisnow.snow.Snow` when the case was given one (``None`` with a bare
        ``snow_modulus``).
    texture
        The :class:`~skisnow.multiscale.Base` when a textured base was asked for.
    real
        The real contact along the ski (:class:`~skisnow.multiscale.RealContact`) when a
        textured base and a snow were given; :meth:`real_summary` per region and patch.
    """

    ski: Ski | None = field(repr=False)
    label: str
    mass: float
    load_position: float
    snow_modulus: float
    model: str
    profile_source: str
    n_points: int
    modulus: float
    width: float
    kick_zone: tuple[float, float] | None
    x: NDArray[np.float64] = field(repr=False)
    height: NDArray[np.float64] = field(repr=False)
    solution: ContactSolution = field(repr=False)
    zones: ZoneMetrics = field(repr=False)
    converged: bool
    warnings: tuple[str, ...] = ()
    ski_model: str = "rigid"
    flexible: FlexibleSolution | None = field(default=None, repr=False)
    snow: Snow | None = field(default=None, repr=False)
    texture: Base | None = field(default=None, repr=False)
    real: RealContact | None = field(default=None, repr=False)

    @property
    def route(self) -> str:
        """The profile route of this case, as every output states it: ``'network'`` or
        ``'beam'`` (the rigid ski's loaded profile), ``'flexible'`` (beam and snow solved
        together) or ``'given'`` (a profile the caller gave)."""
        return "flexible" if self.ski_model == "flexible" else self.profile_source

    @property
    def breitschaedel(self) -> dict[str, Zone]:
        """The Breitschädel (2012) 50 µm contact estimate per zone (lengths and areas)."""
        return self.zones.breitschaedel

    def station_masks(self) -> dict[str, np.ndarray]:
        """Station masks of the regions fixed by the ski and of every contact patch (see
        :func:`skisnow.pipeline._real.station_masks`)."""
        from skisnow.pipeline._real import station_masks

        return station_masks(self)

    def real_summary(self) -> dict[str, RealSummary]:
        """The real contact per region and patch and in total (needs a base with a texture
        and a snow: :attr:`real`)."""
        if self.real is None:
            raise InputError(
                f"case {self.label!r} has no real contact: solve it with base= (a texture: "
                "'S1'..'S5', 'smooth', a topography file) and snow="
            )
        return self.real.summarize(self.station_masks())


def _check_inputs(mass: Any, load_position: Any, model: str) -> tuple[float, float]:
    m = positive_finite("mass [kg]", mass)
    xm = float(load_position)
    if not math.isfinite(xm):
        raise InputError(f"load_position [m]: need a finite value, got {load_position!r}")
    if model not in MODELS:
        raise InputError(f"model: {model!r} is not one of {MODELS}")
    return m, xm


def _given_profile(profile: tuple[ArrayLike, ArrayLike], label: str, mass: float):
    x = np.asarray(profile[0], dtype=float)
    h = np.asarray(profile[1], dtype=float)
    if x.ndim != 1 or h.shape != x.shape or x.size < 16:
        raise InputError(
            f"profile: need (x, h) as two 1-D arrays of the same length >= 16, got shapes "
            f"{x.shape} and {h.shape}"
        )
    if not np.all(np.isfinite(h)):
        # the sweep's batched beam profiles mark a load the ski cannot carry by a NaN row
        raise UnsupportedLoadError(f"no loaded profile of {label} at m = {mass:g} kg")
    return x, h


def _noted(case: Case, implausible: list[str]) -> Case:
    """``case``, its non-convergence and implausible results recorded (:mod:`._record`)."""
    label = (
        f"{case.label} {case.mass:g} kg at {case.load_position * 1e3:g} mm on "
        f"{case.snow_modulus / 1e6:g} MPa"
    )
    note_solved(label)
    if not case.converged:
        note_unconverged(label)
    for note in implausible:
        note_implausible(f"{label}: {note}")
    return case


def solve_case(
    ski: Ski | str | None,
    *,
    mass: float,
    load_position: float,
    snow_modulus: float | None = None,
    model: str = "strip",
    profile_source: str = DEFAULT_PROFILE_SOURCE,
    n_points: int = DEFAULT_N_POINTS,
    base: Material | float | Base | str | None = None,
    poisson: float = 0.3,
    start: ArrayLike | None = None,
    profile: tuple[ArrayLike, ArrayLike] | None = None,
    width: float | None = None,
    label: str | None = None,
    n_across: int = 16,
    tol: float = DEFAULT_TOL,
    workers: int | None = None,
    ski_model: str = "rigid",
    snow: Snow | str | None = None,
    friction: FrictionParameters | None = None,
    curves: MicroCurves | None = None,
    cache_dir: str | None = None,
) -> Case:
    """Solve one case end to end: ski → loaded profile → contact → zones.

    The loaded camber profile h = f(x, m, x_m) (Kalliorinne et al. 2023, eq. 1; the shipped
    network or the beam) on the stations of the grid convention of
    :mod:`skisnow.pipeline` (``n_points`` stations from tail to tip, ends included), pressed
    as a rigid body with force and moment balance about x_m (eq. 3) into elastic snow of
    equivalent modulus E' (eq. 2), then grouped into zones with the Breitschädel (2012) 50 µm
    estimate (:func:`skisnow.contact.contact_zones`).

    Parameters
    ----------
    ski
        A :class:`~skisnow.ski.Ski` or a name :func:`skisnow.ski.get_ski` accepts; its width
        and kick zone are used. ``None``: a bare ``profile`` of a ski of ``width`` (no kick
        zone).
    mass
        Load m [kg] (W = m·g₀).
    load_position
        x_m [m] from the balance point, positive toward the tip.
    snow_modulus
        E_counter of the snow [Pa] (Poisson ratio ``poisson``); or give ``snow``.
    model
        ``'strip'`` (1-D, fast) or ``'surface'`` (2-D grid of ``n_across`` cells across).
    profile_source
        ``'beam'`` (default: the virtual ski's beam, the truth of a ski defined by EI(x) and
        z0(x); :data:`skisnow.pipeline.DEFAULT_PROFILE_SOURCE`) or ``'network'`` (the shipped
        camber network, an emulator of the beam, for a ski whose content is a shipped one's).
    n_points
        Stations along the ski.
    base
        The ski base: a :class:`~skisnow.contact.Material` or a modulus [Pa] (Poisson ratio
        ``poisson``); default :data:`skisnow.contact.BASE` (UHMWPE, 900 MPa, ν = 0.3). A base
        with a texture — a :class:`~skisnow.multiscale.Base`, a grind ``'S1'``..``'S5'``,
        ``'smooth'`` or a topography file — also asks for the real contact (with ``snow``).
    poisson
        ν of the snow (and of a base given as a number).
    start
        A pressure field [Pa] to start the contact iteration from (warm start, e.g. the
        solution of a slightly lighter load); it changes the iterations, not the answer.
    profile
        A precomputed loaded profile ``(x, h)`` [m] (the sweep's batched network profiles, a
        measured profile); replaces computing it. A NaN height means the ski cannot carry the
        load (:class:`~skisnow.UnsupportedLoadError`).
    width
        Ski width [m], only with ``ski=None`` (a known ski has its own width).
    label
        Name of a bare profile (default ``'profile'``).
    n_across, tol, workers
        Passed to :func:`skisnow.contact.solve_contact` (cells across the width for 'surface',
        tolerance, FFT threads).
    ski_model
        ``'rigid'`` (default, the paper's method: the loaded profile pressed into the snow as a
        rigid body) or ``'flexible'``: the ski's beam (EI(x), z0(x)) and the snow solved
        together (:func:`skisnow.contact.solve_flexible`); needs a ski (shipped or a ski file),
        not a network or a bare profile, and ignores ``profile_source``.

    snow
        The snow: a :class:`~skisnow.snow.Snow`, a preset (``'fine-grained'``...) or a snow
        file; gives E_counter and ν (then leave ``snow_modulus`` unset) and, with a textured
        ``base``, the temperature and grains of the real contact.
    friction
        :class:`~skisnow.multiscale.FrictionParameters` of the proxies (default: the cited
        defaults).
    curves
        Precomputed :class:`~skisnow.multiscale.MicroCurves` of this base × snow (sweeps pass
        them to skip the cache look-up).
    cache_dir
        Directory of the micro-curve cache (default: :func:`skisnow.multiscale.cache_dir`).

    Returns
    -------
    Case
        Inputs, profile, contact solution, zones, converged flag and warnings; with a textured
        base and a snow, the real contact along the ski (:attr:`Case.real`).

    Raises
    ------
    InputError
        Invalid input (the message names the argument).
    UnsupportedLoadError
        The profile cannot carry the load (e.g. the contact would reach an end of the ski).
    """
    from skisnow.contact import BASE, contact_zones, effective_modulus, solve_contact
    from skisnow.pipeline._real import case_real, resolve_media

    m, xm = _check_inputs(mass, load_position, model)
    if ski_model not in SKI_MODELS:
        raise InputError(f"ski_model: {ski_model!r} is not one of {SKI_MODELS}")
    media = resolve_media(snow_modulus, snow, base)
    e = media.snow_modulus
    real_kw = {"friction": friction, "curves": curves, "cache_dir": cache_dir}
    if ski_model == "flexible":
        return _flexible_case(
            ski, m, xm, media, model=model, n_points=n_points, poisson=poisson,
            start=start, profile=profile, width=width, n_across=n_across, tol=tol,
            workers=workers, real_kw=real_kw,
        )  # fmt: skip
    notes: list[str] = []
    if ski is None:
        if profile is None or width is None:
            raise InputError("solve_case(ski=None) needs a profile=(x, h) and a width [m]")
        s, name = None, label or "profile"
        ski_width = positive_finite("width [m]", width)
        kick_zone, source = None, "given"
        x, h = _given_profile(profile, name, m)
    else:
        s = resolve_ski(ski)
        name = s.name
        if width is not None:
            raise InputError(
                f"width: the ski {s.name!r} has its own width ({s.width * 1e3:g} mm); give "
                "width only with ski=None and a bare profile"
            )
        ski_width, kick_zone = s.width, s.kick_zone
        _check_source(profile_source)
        source = profile_source
        if profile is not None:
            x, h = _given_profile(profile, name, m)
        else:
            x = stations(s, n_points)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", DomainWarning)
                _, heights = loaded_profiles(
                    s, (m,), xm, profile_source=source, n_points=n_points, missing="raise"
                )
            for w in caught:
                if issubclass(w.category, DomainWarning):
                    notes.append(str(w.message))
                else:
                    warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
            h = heights[0]
    # The rigid ski on elastic snow (eq. 2-3); the flexible ski replaces this step and the
    # profile above by one coupled solve (_flexible_case).
    counter_base = BASE if media.base_material is None else media.base_material
    modulus = effective_modulus(media.counter, counter_base, poisson=poisson)
    solution = solve_contact(
        x,
        h,
        load=m * STANDARD_GRAVITY,
        load_position=xm,
        modulus=modulus,
        model=model,  # type: ignore[arg-type]
        width=ski_width,
        n_across=n_across,
        initial_pressure=start,
        tol=tol,
        workers=workers,
    )
    zones = contact_zones(solution, kick_zone=kick_zone)
    real = case_real(solution, media, notes, real_kw)
    # a derived quantity checked where it is computed (before the solver's note, kept last)
    implausible = pressure_notes(solution.pressure, zones, modulus=modulus, snow=media.snow or e)
    notes += implausible
    if not solution.converged:
        notes.append(
            f"contact solver did not converge in {solution.iterations} iterations "
            f"(residual {solution.residual:.3g}): {solution.message}"
        )
    return _noted(
        Case(
            ski=s,
            label=name,
            mass=m,
            load_position=xm,
            snow_modulus=e,
            model=model,
            profile_source=source,
            n_points=int(x.size),
            modulus=float(modulus),
            width=float(ski_width),
            kick_zone=kick_zone,
            x=x,
            height=h,
            solution=solution,
            zones=zones,
            converged=bool(solution.converged),
            warnings=tuple(notes),
            snow=media.snow,
            texture=media.base,
            real=real,
        ),
        implausible,
    )


#: Physical range of the snow (counter-surface) modulus of a flexible case [Pa]: from the
#: softest snow to stone; outside it the value is a unit slip (MPa given as Pa).
SNOW_MODULUS_LIMITS: tuple[float, float] = (1e6, 1e12)


def _flexible_case(
    ski: Any,
    m: float,
    xm: float,
    media: Any,
    *,
    model: str,
    n_points: int,
    poisson: float,
    start: ArrayLike | None,
    profile: Any,
    width: float | None,
    n_across: int,
    tol: float,
    workers: int | None,
    real_kw: dict[str, Any],
) -> Case:
    """The flexible ski on elastic snow: beam and half-space in one solve (no loaded profile)."""
    from skisnow.contact import BASE, contact_zones, effective_modulus, solve_flexible
    from skisnow.pipeline._real import case_real

    if ski is None or profile is not None:
        raise InputError(
            "ski_model='flexible' needs a ski (EI(x) and z0(x): a shipped ski or a ski file), "
            "not a bare or precomputed profile"
        )
    if width is not None:
        raise InputError("width: a flexible case uses the ski's own width")
    e = media.snow_modulus
    lo, hi = SNOW_MODULUS_LIMITS
    if not lo <= e <= hi:
        raise InputError(
            f"snow_modulus [Pa]: {e:g} lies outside the physical range {lo:g}..{hi:g} Pa "
            "(snow 20–400 MPa, stone 70 GPa)"
        )
    s = resolve_ski(ski)
    x = stations(s, n_points)
    base = media.base_material
    modulus = effective_modulus(media.counter, BASE if base is None else base, poisson=poisson)
    flex = solve_flexible(
        x,
        s.free_camber(x),
        s.stiffness(x),
        load=m * STANDARD_GRAVITY,
        load_position=xm,
        modulus=modulus,
        width=s.width,
        model=model,  # type: ignore[arg-type]
        n_across=n_across,
        initial_pressure=start,
        tol=tol,
        workers=workers,
        raise_on_failure=False,
    )
    solution = flex.contact
    notes: list[str] = []
    real = case_real(solution, media, notes, real_kw)
    zones = contact_zones(solution, kick_zone=s.kick_zone)
    implausible = pressure_notes(solution.pressure, zones, modulus=modulus, snow=media.snow or e)
    notes += implausible
    if not flex.converged:
        notes.append(f"flexible solve did not converge: {solution.message}")
    height = solution.height if solution.height.ndim == 1 else solution.height[:, 0]
    return _noted(
        Case(
            ski=s,
            label=s.name,
            mass=m,
            load_position=xm,
            snow_modulus=e,
            model=model,
            profile_source="beam",
            n_points=int(x.size),
            modulus=float(modulus),
            width=float(s.width),
            kick_zone=s.kick_zone,
            x=x,
            height=np.asarray(height),
            solution=solution,
            zones=zones,
            converged=bool(flex.converged),
            warnings=tuple(notes),
            ski_model="flexible",
            flexible=flex,
            snow=media.snow,
            texture=media.base,
            real=real,
        ),
        implausible,
    )
