"""Commands for maps over load and snow: sweep, plot, report."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from skisnow._errors import InputError
from skisnow._names import file_stem
from skisnow.cli._app import app, interrupted_by_user, report_unconverged
from skisnow.cli._intervals import SamplesOption, check_samples
from skisnow.cli._media import (
    BaseOption,
    FilmCutoffOption,
    ShearStrengthOption,
    SlidingSpeedOption,
    SnowOption,
    SnowTemperatureOption,
    ViscosityOption,
)
from skisnow.cli._render import (
    DaskWorkersOption,
    JsonOption,
    LoadPositionGridOption,
    MassGridOption,
    NPointsOption,
    ProfileSourceOption,
    SchedulerOption,
    SkiModelOption,
    SnowModulusGridOption,
    emit_json,
    print_table,
    progress_bar,
    say,
)
from skisnow.cli._ski import resolve_profile_source

#: The sweep's modulus axis when neither --snow-modulus-mpa nor --snow is given.
DEFAULT_SWEEP_MODULI = "20:400:20"


def sweep_snow(snow: str | None, grid: str | None, temperature_c: float | None, default: str):
    """(Snow or None, modulus-grid text) by the snow options' rule: --snow-modulus-mpa is the
    axis when given; with only --snow, the axis is its modulus."""
    from skisnow.cli._media import resolve_snow

    s, _ = resolve_snow(snow, None, temperature_c=temperature_c, required=False)
    if grid is None:
        grid = default if s is None else f"{s.modulus / 1e6:.12g}"
    return s, grid


def friction_overrides(**values: float | None) -> tuple[tuple[str, float], ...]:
    """The friction options as the sweep's (name, SI value) overrides."""
    from skisnow.cli._media import friction_parameters

    f = friction_parameters(**values)
    return tuple(
        (k, float(getattr(f, k)))
        for k in ("shear_strength", "viscosity", "sliding_speed", "film_cutoff")
        if getattr(f, k) is not None
    )


@app.command()
def sweep(
    ski: Annotated[
        list[str], typer.Option("--ski", help="Ski name or ski file .json (repeat for several).")
    ],
    out: Annotated[Path, typer.Option("--out", help="Zarr store (resumed if it exists).")],
    mass_kg: MassGridOption = "5:130:1",
    load_position_mm: LoadPositionGridOption = "-120",
    snow_modulus_mpa: SnowModulusGridOption = None,  # type: ignore[assignment]
    # the snow, base and friction options, defined once in cli/_media.py; Typer needs them
    # listed in each command's own signature
    snow: SnowOption = None,
    snow_temperature_c: SnowTemperatureOption = None,
    base: BaseOption = None,
    shear_strength_mpa: ShearStrengthOption = None,
    viscosity_mpa_s: ViscosityOption = None,
    sliding_speed_m_s: SlidingSpeedOption = None,
    film_cutoff_nm: FilmCutoffOption = None,
    scheduler: SchedulerOption = None,
    workers: DaskWorkersOption = None,
    model: Annotated[str, typer.Option("--model", help="Contact model: strip or surface.")] = (
        "strip"
    ),
    profile_source: ProfileSourceOption = "auto",
    ski_model: SkiModelOption = "rigid",
    n_points: NPointsOption = 4096,
    netcdf: Annotated[
        Path | None, typer.Option("--netcdf", help="Also export the finished sweep to NetCDF.")
    ] = None,
    json_out: JsonOption = False,
) -> None:
    """Sweep the contact over ski × mass × load position × snow modulus into a Zarr store.

    Interrupted sweeps resume: run the same command again and only missing chunks are computed.
    With --base and --snow the real contact per zone and point is stored too (default modulus
    axis 20:400:20 MPa; with --snow alone, its modulus).
    """
    from skisnow._checks import check_grid_points, check_option_values
    from skisnow.constants import MM, MPA
    from skisnow.sweep import (
        SweepSpec,
        open_sweep,
        parse_values,
        run_sweep,
        save_netcdf,
        unconverged_points,
    )

    # Every input is checked BEFORE anything is created: a typo never poisons --out.
    check_grid_points(n_points, where="--points")
    if workers is not None and workers < 0:
        raise InputError(f"--workers: need >= 0 (0: no Dask), got {workers}")
    from skisnow.ski import get_ski
    from skisnow.sweep import MODELS, PROFILE_SOURCES

    for name in ski:
        try:
            get_ski(name)
        except InputError as exc:
            raise type(exc)(f"--ski: {exc}") from None
    if model not in MODELS:
        raise InputError(f"--model: {model!r} is not one of {', '.join(MODELS)}")
    if profile_source not in (*PROFILE_SOURCES, "auto"):
        raise InputError(
            f"--profile-source: {profile_source!r} is not one of {', '.join(PROFILE_SOURCES)}, auto"
        )
    import json

    from skisnow.cli._media import resolve_base
    from skisnow.snow import snow_record

    snow_obj, snow_modulus_mpa = sweep_snow(
        snow, snow_modulus_mpa, snow_temperature_c, DEFAULT_SWEEP_MODULI
    )
    texture = resolve_base(base, snow_obj)
    real: dict = {}
    if texture is not None:
        real = {
            "base": base,
            "snow": json.dumps(snow_record(snow_obj), sort_keys=True),
            "friction": friction_overrides(
                shear_strength_mpa=shear_strength_mpa,
                viscosity_mpa_s=viscosity_mpa_s,
                sliding_speed_m_s=sliding_speed_m_s,
                film_cutoff_nm=film_cutoff_nm,
            ),
        }
    spec = SweepSpec(
        skis=tuple(ski),
        masses=check_option_values(parse_values(mass_kg, name="--mass-kg"), "mass", "--mass-kg"),
        load_positions=check_option_values(
            parse_values(load_position_mm, name="--load-position-mm"),
            "load_position",
            "--load-position-mm",
        )
        * MM,
        snow_moduli=check_option_values(
            parse_values(snow_modulus_mpa, name="--snow-modulus-mpa"),
            "snow_modulus",
            "--snow-modulus-mpa",
        )
        * MPA,
        model=model,
        profile_source=resolve_profile_source(profile_source, ski),
        n_points=n_points,
        ski_model=ski_model,
        **real,
    )
    if spec.base:  # the micro curves once, here (the workers read them from the cache)
        spec.micro_curves()
    n_chunks = len(spec.chunks())
    from skisnow._checks import check_memory
    from skisnow._resources import check_solves

    what = f"a sweep of {spec.n_points_total:,} points"
    check_solves(spec.n_points_total, where="--ski x --mass-kg x --load-position-mm x "
                 "--snow-modulus-mpa", what=what, hint="use coarser grids")  # fmt: skip
    check_memory(spec.n_points_total * len(spec.zones) * 10 * 8, where="the sweep's grid",
                 what=f"{what} read back", hint="use coarser grids")  # fmt: skip
    # the bar starts with the first finished chunk (not before the store checks)
    bar = progress_bar(f"sweep {out.name}", transient=False)
    try:
        run = run_sweep(spec, out, scheduler=scheduler, workers=workers, on_progress=bar)
    except (KeyboardInterrupt, SystemError) as exc:
        # Say what was kept, and exit 130 (interrupted), as `skisnow --help` promises.
        if not interrupted_by_user(exc):  # a SystemError not caused by Ctrl-C is a bug
            raise
        bar.close()
        done = bar.completed
        typer.echo(
            f"skisnow: sweep interrupted (Ctrl-C); {done:g} chunks of this run are safely in "
            f"{out}; run the same command again to compute only the rest",
            err=True,
        )
        raise typer.Exit(130) from None
    finally:
        bar.close()
    exported = None
    ds = open_sweep(out)
    unconverged, not_carried = unconverged_points(ds)  # also those solved by Dask workers
    report_unconverged(unconverged, solved=True)  # exit 3, the first named
    if netcdf is not None:
        exported = save_netcdf(ds, netcdf)
    doc = {
        "store": str(out),
        "netcdf": None if exported is None else str(exported),
        "points": spec.n_points_total,
        "profile_route": "flexible" if spec.ski_model == "flexible" else spec.profile_source,
        "chunks": n_chunks,
        "computed_chunks": len(run.computed),
        "skipped_chunks": len(run.skipped),
        "computed": [list(k) for k in run.computed],
        "unconverged_points": len(unconverged),
        "points_not_carried": not_carried,
        "workers": run.workers,
        "wall_time_s": run.wall_time,
        "compute_time_s": run.compute_time,
    }
    if json_out:
        emit_json(doc)
        return
    rows = [
        ("store", str(out)),
        ("contact solves", spec.n_points_total),
        ("profile route", doc["profile_route"]),
        ("chunks computed / already done", f"{len(run.computed)} / {len(run.skipped)}"),
        ("workers", run.workers),
        ("wall time [s]", f"{run.wall_time:.2f}"),
    ]
    if exported is not None:
        rows.append(("NetCDF", str(exported)))
    print_table("sweep", ["", "value"], rows)


@app.command()
def plot(
    store: Annotated[Path, typer.Argument(help="A sweep's Zarr store.")],
    out: Annotated[Path, typer.Option("--out", help="Directory for the figures.")] = Path(
        "skisnow-figures"
    ),
    formats: Annotated[str, typer.Option("--formats", help="Comma-separated formats.")] = (
        "png,svg"
    ),
    json_out: JsonOption = False,
) -> None:
    """Draw the maps of a sweep (area, mean pressure, length, load share vs mass per snow)."""
    from skisnow.plot import save_figure, sweep_figures
    from skisnow.sweep import open_sweep

    ds = open_sweep(store)
    kinds = [f.strip() for f in formats.split(",") if f.strip()]
    paths = [
        p
        for stem, fig in sweep_figures(ds).items()
        for p in save_figure(fig, out / stem, formats=kinds)
    ]
    if json_out:
        emit_json({"figures": [str(p) for p in paths]})
        return
    print_table(f"figures of {store}", ["file"], [(str(p),) for p in paths])


@app.command()
def report(
    ski: Annotated[str, typer.Argument(help="Shipped ski name or ski file (.json).")],
    out: Annotated[Path, typer.Option("--out", help="Directory for the report.")] = Path(
        "skisnow-report"
    ),
    body_mass_kg: Annotated[
        float,
        typer.Option(
            "--body-mass-kg", help="Skier's body mass in kg (default 60; stated in the report)."
        ),
    ] = 60.0,
    load_position_mm: Annotated[
        float, typer.Option("--load-position-mm", help="Load position x_m (mm).")
    ] = -120.0,
    workers: DaskWorkersOption = 0,
    profile_source: ProfileSourceOption = "auto",
    scheduler: SchedulerOption = None,
    mass_kg: MassGridOption = "5:130:5",
    snow_modulus_mpa: SnowModulusGridOption = None,  # type: ignore[assignment]
    n_points: NPointsOption = 4096,
    stride: Annotated[
        str,
        typer.Option(
            "--stride",
            help="Load cycle shown at the body mass: auto (diagonal for a classic ski, skate_g3 "
            "for a skate ski), diagonal, double_poling, skate_g3 or none.",
        ),
    ] = "auto",
    compare_with: Annotated[
        list[str] | None,
        typer.Option(
            "--compare-with", help="Another ski (name or file) for the fleet table; repeatable."
        ),
    ] = None,
    day_snow_mpa: Annotated[
        float | None,
        typer.Option(
            "--day-snow-mpa",
            help="Snow modulus (MPa) of the stride and the fleet comparison (default: the "
            "--snow's modulus, else 100).",
        ),
    ] = None,
    # the snow, base and friction options, defined once in cli/_media.py; Typer needs them
    # listed in each command's own signature
    snow: SnowOption = None,
    snow_temperature_c: SnowTemperatureOption = None,
    base: BaseOption = None,
    ski_model: SkiModelOption = "rigid",
    explorer: Annotated[
        bool,
        typer.Option(
            "--explorer/--no-explorer",
            help="Also write the ski's interactive explorer page beside the report (default "
            "grid: 26 masses x 6 positions x 10 moduli) and link it from the report.",
        ),
    ] = False,
    samples: SamplesOption = 200,
    json_out: JsonOption = False,
) -> None:
    """Write one self-contained HTML report of a ski (metrics, zones at standard loads, maps,
    the contact over a stride, a fleet table with --compare-with, a linked explorer page
    with --explorer, and the real contact with --base and --snow)."""
    # every option and every ski checked before anything is computed or written
    from skisnow._resources import check_solves
    from skisnow.cli._media import resolve_base, resolve_snow
    from skisnow.pipeline import PROFILE_SOURCES, SKI_MODELS
    from skisnow.report import study_ski, write_report
    from skisnow.ski import SHIPPED_SKIS, get_ski
    from skisnow.sweep import parse_values
    from skisnow.workflows import TEMPLATES

    snow_obj, _ = resolve_snow(snow, None, temperature_c=snow_temperature_c, required=False)
    texture = resolve_base(base, snow_obj)
    if day_snow_mpa is None:
        day_snow_mpa = 100.0 if snow_obj is None else snow_obj.modulus / 1e6
    if snow_modulus_mpa is None:
        snow_modulus_mpa = "20:400:40"

    if stride not in ("auto", "none", *TEMPLATES):
        raise InputError(f"--stride must be auto, none or one of {', '.join(TEMPLATES)}, "
                         f"got {stride!r}")  # fmt: skip
    if ski_model not in SKI_MODELS:
        raise InputError(f"--ski-model must be one of {', '.join(SKI_MODELS)}, got {ski_model!r}")
    if profile_source not in (*PROFILE_SOURCES, "auto"):
        raise InputError(f"--profile-source must be one of {', '.join(PROFILE_SOURCES)}, auto; "
                         f"got {profile_source!r}")  # fmt: skip
    try:
        get_ski(ski)
    except InputError as exc:
        raise type(exc)(f"SKI: {exc}") from None
    for other in compare_with or ():
        if other not in SHIPPED_SKIS and not Path(other).is_file():
            raise InputError(f"--compare-with {other!r}: neither a shipped ski "
                             f"({', '.join(SHIPPED_SKIS)}) nor an existing file")  # fmt: skip
    if len(set([ski, *(compare_with or ())])) != 1 + len(compare_with or ()):
        raise InputError("--compare-with: each ski once (a ski compared with itself says nothing)")
    check_samples(samples)
    n_maps = len(parse_values(mass_kg, name="--mass-kg")) * len(
        parse_values(snow_modulus_mpa, name="--snow-modulus-mpa"))  # fmt: skip
    check_solves(n_maps, where="--mass-kg x --snow-modulus-mpa", what=f"maps of {n_maps} points",
                 hint="use coarser grids")  # fmt: skip
    source = resolve_profile_source(profile_source, [ski])
    # output names from the ski's name: a label made safe, never a path (stays inside --out)
    stem = file_stem(Path(ski).stem if ski.lower().endswith(".json") else ski)
    if not json_out:
        say(
            f"report of {ski}: skier body mass {body_mass_kg:g} kg (--body-mass-kg), load at "
            f"{load_position_mm:g} mm from the balance point, {source} route"
        )
    with progress_bar("report", disable=json_out) as bar:
        study = study_ski(
            ski,
            store=out / (f"{stem}_maps_{source}.zarr" if ski_model == "rigid"
                         else f"{stem}_maps_flexible.zarr"),
            body_mass=body_mass_kg,
            load_position=load_position_mm * 1e-3,
            workers=workers,
            scheduler=scheduler,
            profile_source=source,
            masses=tuple(parse_values(mass_kg, name="--mass-kg")),
            map_moduli=tuple(parse_values(snow_modulus_mpa, name="--snow-modulus-mpa") * 1e6),
            n_points=n_points,
            ski_model=ski_model,
            progress=bar,
            samples=samples,
        )  # fmt: skip
    from skisnow.sweep import unconverged_points

    report_unconverged(unconverged_points(study.maps)[0], solved=True)  # the maps (any worker)
    from skisnow.workflows import TEMPLATES, compare_fleet, run_cycle, template_history

    cycles = []
    if stride == "auto":
        stride = "diagonal" if study.ski.kind == "classic" else "skate_g3"
    if stride != "none":
        history = template_history(stride, body_mass=body_mass_kg)
        with progress_bar(f"stride {stride}", disable=json_out) as bar:
            cycles.append(
                run_cycle(
                    ski,
                    history,
                    snow_modulus=day_snow_mpa * 1e6,
                    n_points=n_points,
                    progress=bar,
                    ski_model=ski_model,  # type: ignore[arg-type]
                )
            )
    fleet = None
    if compare_with:
        fleet = compare_fleet(
            [ski, *compare_with],
            body_mass=body_mass_kg,
            snow_modulus=day_snow_mpa * 1e6,
            load_position=load_position_mm * 1e-3,
            n_points=n_points,
            ski_model=ski_model,  # type: ignore[arg-type]
            samples=samples,
        )
        for spec, message in fleet.failures:
            say(f"not compared: {spec}: {message}", style="bold red")
    explorer_name = None
    if explorer:
        from skisnow.explore import write_explorer

        explorer_name = f"{stem}_explore.html"
        with progress_bar("explorer", disable=json_out) as bar:
            write_explorer([ski], out / explorer_name, profile_source=source,
                           ski_models=(ski_model,), workers=workers, scheduler=scheduler,
                           progress=bar)  # fmt: skip
    real_cases = []
    if texture is not None:
        from skisnow.pipeline import solve_case

        for case in study.cases:  # the standard loads again, with the grind on the snow
            real_cases.append(
                solve_case(
                    ski, mass=case.mass, load_position=case.load_position,
                    snow=snow_obj.replace(modulus=case.snow_modulus), base=texture,
                    profile_source=case.profile_source, n_points=n_points, ski_model=ski_model,
                )
            )  # fmt: skip
    path = write_report(
        study, out, cycles=cycles, fleet=fleet, explorer=explorer_name, real_cases=real_cases
    )
    if json_out:
        emit_json({"report": str(path), "explorer": explorer_name and str(out / explorer_name)})
        return
    rows = [(ski, str(path))] + ([(ski, str(out / explorer_name))] if explorer_name else [])
    print_table("report", ["ski", "file"], rows)
