"""The ``explore`` command: one self-contained interactive HTML page over load and snow."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated

import typer

from skisnow.cli._app import app, report_unconverged
from skisnow.cli._media import SnowOption, SnowTemperatureOption
from skisnow.cli._render import (
    DaskWorkersOption,
    JsonOption,
    LoadPositionGridOption,
    MassGridOption,
    ProfileSourceOption,
    SchedulerOption,
    SnowModulusGridOption,
    emit_json,
    err_console,
    progress_bar,
)


@app.command()
def explore(
    ski: Annotated[list[str], typer.Argument(help="Ski names (one or more).")],
    out: Annotated[Path, typer.Option("--out", help="The HTML page to write.")] = Path(
        "explore.html"
    ),
    mass_kg: MassGridOption = "5:130:5",
    load_position_mm: LoadPositionGridOption = "-240:-40:40",
    snow_modulus_mpa: SnowModulusGridOption = None,  # type: ignore[assignment]
    stations: Annotated[
        int, typer.Option("--stations", help="Display stations along the ski (divides 4096).")
    ] = 512,
    profile_source: ProfileSourceOption = "auto",
    ski_model: Annotated[
        str,
        typer.Option(
            "--ski-model",
            help="rigid (the paper's rigid profile), flexible (beam and snow together) or both "
            "(a switch on the page).",
        ),
    ] = "rigid",
    workers: DaskWorkersOption = None,
    scheduler: SchedulerOption = None,
    store: Annotated[
        Path | None,
        typer.Option(
            "--store",
            help="Keep the sweep's Zarr stores in this directory (an interrupted build resumes; "
            "default: a temporary directory).",
        ),
    ] = None,
    base: Annotated[
        list[str] | None,
        typer.Option(
            "--base",
            help="Base texture(s) for the real contact, a selector on the page (repeat: --base "
            "S1 --base S3); needs --snow.",
        ),
    ] = None,
    snow: SnowOption = None,
    snow_temperature_c: SnowTemperatureOption = None,
    json_out: JsonOption = False,
) -> None:
    """Write an interactive explorer page: sliders for mass, load position and snow modulus.

    The page opens from disk in any browser, with no server and no network; it holds the contact
    of every grid point (zones, pressures, the ski base and the deformed snow).
    """
    from skisnow._errors import InputError
    from skisnow.cli._media import resolve_base, resolve_snow
    from skisnow.cli._ski import resolve_profile_source
    from skisnow.explore import ExplorerGrid, write_explorer
    from skisnow.sweep import parse_values

    snow_obj, _ = resolve_snow(snow, None, temperature_c=snow_temperature_c, required=False)
    for b in base or ():
        resolve_base(b, snow_obj)  # checked before any solve
    if snow_modulus_mpa is None:
        snow_modulus_mpa = "40:400:40" if snow_obj is None else f"{snow_obj.modulus / 1e6:.12g}"
    if ski_model not in ("rigid", "flexible", "both"):
        raise InputError(f"--ski-model: {ski_model!r} is not rigid, flexible or both")
    grid = ExplorerGrid(
        masses=tuple(parse_values(mass_kg, name="--mass-kg")),
        load_positions=tuple(1e-3 * parse_values(load_position_mm, name="--load-position-mm")),
        snow_moduli=tuple(1e6 * parse_values(snow_modulus_mpa, name="--snow-modulus-mpa")),
        n_display=stations,
    )
    from skisnow._checks import check_memory
    from skisnow._resources import check_solves

    twice = sorted({s for s in ski if ski.count(s) > 1})
    if twice:
        raise InputError(f"SKI: {', '.join(map(repr, twice))} given twice; give each ski once")
    from skisnow.pipeline import PROFILE_SOURCES

    if profile_source not in (*PROFILE_SOURCES, "auto"):
        raise InputError(f"--profile-source must be one of {', '.join(PROFILE_SOURCES)}, auto; "
                         f"got {profile_source!r}")  # fmt: skip
    n_models = 2 if ski_model == "both" else 1
    points = len(ski) * n_models * len(grid.masses) * len(grid.load_positions) * len(
        grid.snow_moduli)  # fmt: skip
    what = f"a page of {points:,} points ({len(grid.masses)} masses x "
    what += f"{len(grid.load_positions)} positions x {len(grid.snow_moduli)} moduli)"
    check_solves(points, where="--mass-kg x --load-position-mm x --snow-modulus-mpa", what=what,
                 hint="use coarser grids")  # fmt: skip
    # per point: 3 curves (float64 in memory, float32 stored) and the zone codes on the
    # display stations, 7 zones x 7 metrics; twice for the page's copy
    check_memory(2 * points * (grid.n_display * 37 + 7 * 7 * 8), where="--mass-kg x "
                 "--load-position-mm x --snow-modulus-mpa x --stations", what=what,
                 hint="use coarser grids or fewer --stations")  # fmt: skip
    source = resolve_profile_source(profile_source, list(ski))
    start = time.perf_counter()
    with progress_bar("explorer", transient=False) as bar:
        out, ds = write_explorer(
            ski,
            out,
            grid,
            profile_source=source,
            ski_models=("rigid", "flexible") if ski_model == "both" else (ski_model,),
            store=store,
            workers=workers,
            scheduler=scheduler,
            progress=bar,
            bases=tuple(base or ()),
            snow=snow_obj,
        )
    seconds = time.perf_counter() - start
    size_mb = out.stat().st_size / 1e6
    n_ok, n_all = int(ds["converged"].sum()), int(ds["converged"].size)
    from skisnow.sweep import unconverged_points

    unconverged, not_carried = unconverged_points(ds)
    report_unconverged(unconverged, solved=True)  # exit 3, the first named
    if json_out:
        emit_json(
            {
                "path": str(out),
                "size_mb": size_mb,
                "seconds": seconds,
                "points": n_all,
                "profile_route": {
                    m: ("flexible" if m == "flexible" else source)
                    for m in ds.attrs.get("ski_models", [])
                },
                # a map's corner whose load the ski cannot carry is not solved (shown greyed)
                "points_converged": n_ok,
                "points_not_carried": not_carried,
                "unconverged_points": len(unconverged),
                "converged": not unconverged,
            }
        )
    else:
        err_console.print(
            f"wrote {out} ({size_mb:.2f} MB, {n_all} points, {n_ok} converged, {not_carried} "
            f"not carried, {seconds:.1f} s, {source} route for the rigid ski)"
        )
