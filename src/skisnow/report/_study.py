"""What the report of one ski shows, computed in one place: :func:`study_ski`.

The practitioners' metrics of the virtual bench (Breitschädel 2012), the cases at the standard
loads (half and full body weight on several snows, each a :func:`~skisnow.pipeline.solve_case`)
and the maps over load and snow (a resumable sweep, Kalliorinne et al. 2023, Figures 8–9).
:mod:`skisnow.report` only renders the :class:`SkiStudy` this returns.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from skisnow._errors import InputError
from skisnow.pipeline import DEFAULT_N_POINTS, Case, resolve_ski, solve_case

#: Snows of the standard-load table [Pa]: soft new snow to hard old machine-made snow
#: (Kalliorinne et al. 2023, §3.2: 50–350 MPa for machine-made snow after Lintzén & Edeskär).
STANDARD_SNOWS: tuple[float, ...] = (50e6, 100e6, 200e6, 400e6)
#: Default grid of the report's maps: masses [kg] and snow moduli [Pa].
MAP_MASSES: tuple[float, ...] = tuple(float(m) for m in range(5, 131, 5))
MAP_MODULI: tuple[float, ...] = tuple(float(e) * 1e6 for e in range(20, 401, 40))


@dataclass(frozen=True, kw_only=True, eq=False)
class SkiStudy:
    """Everything the report of one ski shows (SI units).

    Attributes
    ----------
    ski
        The :class:`~skisnow.ski.Ski`.
    body_mass, load_position
        The skier's mass [kg] and the load position x_m [m].
    metrics
        :class:`~skisnow.bench.SkiMetrics` of the virtual bench (beam) at ``body_mass``.
    cases
        The standard loads: half then full body weight, each on every snow (ascending).
    maps
        The sweep over load and snow (:func:`skisnow.sweep.open_sweep`) holding the ski.
    profile_source, n_points
        Where the loaded profiles came from and the stations along the ski.
    ski_model
        ``'rigid'`` (the paper's method) or ``'flexible'`` (the beam bent on the snow).
    other_cases
        The same standard loads with the other ski model (``()`` when not asked for): the
        rigid-profile method of Kalliorinne et al. (2023) against the flexible ski.
    intervals
        One :class:`~skisnow.pipeline.Intervals` per case of ``cases`` (95 % intervals from the
        posterior samples of an identified ski, :func:`~skisnow.pipeline.case_intervals`);
        ``()`` when the ski carries no posterior or no samples were asked for.
    samples
        The posterior samples asked for (0: none).
    """

    ski: Any
    body_mass: float
    load_position: float
    metrics: Any = field(repr=False)
    cases: tuple[Case, ...] = field(repr=False)
    maps: Any = field(repr=False)
    profile_source: str
    n_points: int
    ski_model: str = "rigid"
    other_cases: tuple[Case, ...] = field(default=(), repr=False)
    intervals: tuple[Any, ...] = field(default=(), repr=False)
    samples: int = 0


def standard_cases(
    ski: Any,
    *,
    body_mass: float,
    load_position: float,
    snows: Sequence[float] = STANDARD_SNOWS,
    profile_source: str = "beam",
    n_points: int = DEFAULT_N_POINTS,
    ski_model: str = "rigid",
    masses: Sequence[float] | None = None,
) -> tuple[Case, ...]:
    """The cases at the standard loads: half and full body weight at ``load_position`` on every
    snow of ``snows`` [Pa] (ascending), each solved by :func:`solve_case` (``masses`` [kg]
    replaces the two loads)."""
    return tuple(
        solve_case(
            ski,
            mass=m,
            load_position=load_position,
            snow_modulus=e,
            profile_source=profile_source,
            n_points=n_points,
            ski_model=ski_model,
        )
        for m in ((0.5 * body_mass, body_mass) if masses is None else masses)
        for e in sorted(float(v) for v in snows)
    )


def study_ski(
    ski: Any,
    *,
    body_mass: float = 60.0,
    load_position: float = -0.12,
    snows: Sequence[float] = STANDARD_SNOWS,
    dataset: Any = None,
    store: str | Path | None = None,
    masses: Sequence[float] = MAP_MASSES,
    map_moduli: Sequence[float] = MAP_MODULI,
    profile_source: str = "beam",
    n_points: int = DEFAULT_N_POINTS,
    workers: int | None = 0,
    scheduler: str | None = None,
    ski_model: str = "rigid",
    compare_models: bool = True,
    progress: Callable[..., None] | None = None,
    samples: int = 0,
) -> SkiStudy:
    """Compute what the report of ``ski`` shows (see the module docstring).

    Parameters
    ----------
    ski
        A :class:`~skisnow.ski.Ski` or a name :func:`skisnow.ski.get_ski` accepts.
    body_mass, load_position
        The skier's mass [kg]; the load position x_m [m] of the cases and the maps.
    snows
        Snow moduli of the standard-load cases [Pa].
    dataset
        A sweep (:func:`skisnow.sweep.open_sweep`) that holds the ski; else the maps' sweep
        (``masses`` [kg] × ``map_moduli`` [Pa] at ``load_position``) is run into ``store``
        (resumable: a second study of the same ski reuses it) with ``workers`` or
        ``scheduler`` (:func:`skisnow.sweep.run_sweep`).
    profile_source, n_points
        Loaded profiles of the cases and the maps (:func:`solve_case`).
    ski_model
        ``'rigid'`` or ``'flexible'`` for the cases and the maps (:func:`solve_case`).
    compare_models
        Also solve the standard loads with the other ski model (:attr:`SkiStudy.other_cases`),
        so that the report shows how far the rigid-profile method is from the flexible ski.
    progress
        ``progress(done, total, status=...)`` after each map chunk and each standard case (a
        progress bar: the maps of the default grid take about a minute).
    samples
        Posterior samples for the 95 % intervals of the standard cases of an identified ski
        (:attr:`SkiStudy.intervals`; 0 or a ski without posterior: none).
    """
    from skisnow.bench import ski_metrics
    from skisnow.ski import SHIPPED_SKIS, get_ski, ski_to_json
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep

    s = resolve_ski(ski)
    n_cases = 2 * len(tuple(snows)) * (2 if compare_models else 1)
    state = {"maps": 0, "maps_total": 0, "cases": 0}

    def tick(status: str) -> None:
        if progress is not None:
            total = state["maps_total"] + n_cases
            progress(state["maps"] + state["cases"], total, status=status)

    def on_chunk(done: int, total: int, *_: Any) -> None:
        state["maps"], state["maps_total"] = done, total
        tick("maps over load and snow")

    if dataset is None:
        if store is None:
            raise InputError("study_ski: give a sweep (dataset=) or a Zarr store to run it into")
        # the ski's definition travels with the spec: the content decides, never the name
        shipped = s.name in SHIPPED_SKIS and get_ski(s.name) == s
        spec = SweepSpec(
            skis=(s.name,),
            ski_files=() if shipped else ((s.name, ski_to_json(s)),),
            masses=tuple(masses),
            load_positions=(load_position,),
            snow_moduli=tuple(map_moduli),
            profile_source=profile_source,
            n_points=n_points,
            ski_model=ski_model,
        )
        run_sweep(spec, store, workers=workers, scheduler=scheduler, on_progress=on_chunk)
        dataset = open_sweep(store)
    kwargs = dict(body_mass=body_mass, load_position=load_position, snows=snows,
                  profile_source=profile_source, n_points=n_points)  # fmt: skip
    other = "flexible" if ski_model == "rigid" else "rigid"

    def cases(model: str) -> tuple[Case, ...]:
        out = []
        for m in (0.5 * body_mass, body_mass):
            for e in sorted(float(v) for v in snows):
                out.append(standard_cases(s, ski_model=model, **{**kwargs, "snows": (e,)},
                                          masses=(m,))[0])  # fmt: skip
                state["cases"] += 1
                tick(f"standard loads ({model})")
        return tuple(out)

    from skisnow.pipeline import case_intervals

    main = cases(ski_model)
    intervals = ()
    if samples and s.has_posterior:
        intervals = tuple(case_intervals(c, samples=samples) for c in main)
    return SkiStudy(
        ski=s,
        body_mass=float(body_mass),
        load_position=float(load_position),
        metrics=ski_metrics(s, body_mass=body_mass, load_position=load_position),
        cases=main,
        intervals=intervals,
        samples=int(samples),
        other_cases=cases(other) if compare_models else (),
        maps=dataset,
        profile_source=profile_source,
        n_points=int(n_points),
        ski_model=ski_model,
    )
