"""``skisnow calibrate``: fit the shipped skis to the paper's captions (parse, call, print).

The options are those of the calibration program ``benchmarks/calibrate_skis.py`` (same names,
field units), which now runs this command; :func:`skisnow.calibrate.run_calibration` does the
work and prints its progress and tables.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer

from skisnow._errors import InputError
from skisnow.cli._app import app

_SKIS = ("classic", "skate")


@app.command()
def calibrate(
    ski: Annotated[
        list[str] | None,
        typer.Option("--ski", help="classic or skate (repeat for both; default both)."),
    ] = None,
    seed: Annotated[int, typer.Option("--seed", help="Seed of the differential evolution.")] = 0,
    generations: Annotated[
        int, typer.Option("--generations", help="Generations of the differential evolution.")
    ] = 30,
    popsize: Annotated[int, typer.Option("--popsize", help="Population per parameter.")] = 6,
    caption_only: Annotated[
        bool, typer.Option("--caption-only", help="No plausibility terms.")
    ] = False,
    shipped: Annotated[
        bool, typer.Option("--shipped", help="Only the table of the shipped skis.")
    ] = False,
    out: Annotated[Path, typer.Option("--out", help="Folder of the calibration records.")] = Path(
        "calibration"
    ),
    start: Annotated[
        list[str] | None,
        typer.Option(
            "--start",
            help="Start from a calibration JSON (a restart) or 'shipped' (the shipped ski "
            "sampled at the knots); repeat for a population around several starts.",
        ),
    ] = None,
    hinge_weight: Annotated[
        float, typer.Option("--hinge-weight", help="Weight of the hinges.")
    ] = 2.0,
    topology_weight: Annotated[
        float,
        typer.Option(
            "--topology-weight",
            help="Weight of the topology residuals (skate: rear grows 30->60 kg, front 1 then 2 "
            "patches; classic: middle patch at 60 kg / -70 mm), in patch-count units.",
        ),
    ] = 0.0,
    max_minutes: Annotated[
        float, typer.Option("--max-minutes", help="Stop the DE stage after this time [min].")
    ] = math.inf,
    ei_shape_weight: Annotated[
        float,
        typer.Option(
            "--ei-shape-weight",
            help="Weight of the EI shape hinges (unimodal log EI, neighbour steps <= 8x).",
        ),
    ] = 0.0,
    bench_topology: Annotated[
        bool,
        typer.Option(
            "--bench-topology",
            help="Skate: topology residuals also for the bench front patches (1 at 30 kg, 2 at "
            "65 kg) and the front mean pressure rising from 30 to 60 kg on 100 MPa.",
        ),
    ] = False,
    findings: Annotated[
        bool,
        typer.Option(
            "--findings",
            help="Skate: --bench-topology with the thresholds of the findings tests (rear "
            "growth >= 1.4x, front mean pressure rise >= 1.5x from 30 to 60 kg on 100 MPa) and "
            "the rear load share changing by <= 0.04 (paper 67 -> 71 %).",
        ),
    ] = False,
    front_pressure_growth_min: Annotated[
        float | None,
        typer.Option(
            "--front-pressure-growth-min",
            help="With --findings: the least front mean pressure rise 30->60 kg (default 1.5; "
            "the paper's is 2.1).",
        ),
    ] = None,
    polish_starts: Annotated[
        bool,
        typer.Option(
            "--polish-starts",
            help="Polish every --start by least squares before the DE (for starts resampled "
            "onto other knots).",
        ),
    ] = False,
    tag: Annotated[str, typer.Option("--tag", help="Suffix of the record name, e.g. _v2.")] = "",
    knots: Annotated[
        str,
        typer.Option(
            "--knots",
            help="Spline knots: default (the shipped skis'; 10 log-EI, 13 camber) or dense (19 "
            "log-EI, 26 camber); --start records are resampled onto them (PCHIP).",
        ),
    ] = "default",
    k_range: Annotated[
        tuple[float, float] | None,
        typer.Option(
            "--k-range",
            metavar="LO HI",
            help="Skate stiffness k limits [N/mm] (default the team means 225 251).",
        ),
    ] = None,
    sigma: Annotated[float, typer.Option("--sigma", help="Population spread (unit box).")] = 0.08,
    kick_gap_max: Annotated[
        float | None,
        typer.Option(
            "--kick-gap-max",
            metavar="MM",
            help="Classic: hinge on the largest gap left in the kick zone at twice the body "
            "weight (-80 mm) [mm]; off by default (chosen, not sourced: a real ski is flat "
            "there).",
        ),
    ] = None,
    write_shipped: Annotated[
        Path | None,
        typer.Option(
            "--write-shipped",
            help="Write the ski of this calibration record as the shipped ski file.",
        ),
    ] = None,
    ski_out: Annotated[
        Path | None,
        typer.Option(
            "--ski-out",
            help="With --write-shipped: write the ski file here instead (a candidate to try "
            "with --ski FILE before it ships).",
        ),
    ] = None,
    reproduction: Annotated[
        bool,
        typer.Option(
            "--reproduction",
            help="Fit a reproduction ski (<ski>-k22): the captions alone, within 10 % lengths "
            "and mean pressures, 3 points load shares (the shares Figs. 4 and 7 imply too).",
        ),
    ] = False,
) -> None:
    """Calibrate the shipped skis on the captions of Kalliorinne et al. (2023), Figs. 4-7.

    Differential evolution, then a least-squares polish, of a spline ski against the caption
    numbers through the paper's pipeline, with hinges on the practitioners' numbers; writes
    OUT/calibration_<ski>[_caption_only|_k22]<tag>.json. Takes minutes to hours.
    """
    from skisnow.calibrate import CalibrationRun, run_calibration

    bad = [s for s in ski or () if s not in _SKIS]
    if bad:
        raise InputError(f"--ski must be classic or skate, not {bad[0]!r}")
    if knots not in ("default", "dense"):
        raise InputError(f"--knots must be default or dense, not {knots!r}")
    run_calibration(
        CalibrationRun(
            skis=tuple(ski or ()), seed=seed, generations=generations, popsize=popsize,
            caption_only=caption_only, shipped=shipped, out=out, start=tuple(start or ()),
            hinge_weight=hinge_weight, topology_weight=topology_weight,
            max_minutes=max_minutes, ei_shape_weight=ei_shape_weight,
            bench_topology=bench_topology, findings=findings,
            front_pressure_growth_min=front_pressure_growth_min, polish_starts=polish_starts,
            tag=tag, knots=knots, k_range=k_range, sigma=sigma, kick_gap_max=kick_gap_max,
            write_shipped=write_shipped, ski_out=ski_out, reproduction=reproduction,
        )
    )  # fmt: skip
