"""Technician workflows: compare, pairs, cycle (thin: parse, call skisnow.workflows, render)."""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from skisnow._atomic import atomic_path
from skisnow._errors import InputError
from skisnow._values import parse_values
from skisnow.cli._app import EXIT_INPUT, app, report_converged, run_annotations
from skisnow.cli._render import (
    JsonOption,
    _jsonable,
    console,
    emit_json,
    err_console,
    print_table,
    progress_bar,
)

_SNOW = typer.Option(..., "--snow-modulus-mpa", help="Young's modulus of the snow in MPa.")
_BODY = typer.Option(..., "--body-mass-kg", help="The athlete's body mass in kg.")
_POS = typer.Option(
    -120.0,
    "--load-position-mm",
    help="Load position x_m in mm from the balance point (+ toward the tip); default -120, the "
    "paper's reference.",
)
_POINTS = typer.Option(4096, "--points", help="Stations along each ski.")
_OUT = typer.Option(None, "--out", help="Folder for the CSV tables and the figures.")
_MODEL = typer.Option(
    "rigid", "--ski-model", help="rigid (the paper's rigid loaded profile) or flexible."
)


def write_csv(path: Path, records: Sequence[dict[str, Any]]) -> Path:
    """Write records as a CSV table (header = the keys of the first record; NaN → empty)."""
    keys = list(records[0]) if records else []
    with atomic_path(path) as tmp, tmp.open("w", newline="", encoding="utf-8") as fh:
        writer = csv.DictWriter(fh, fieldnames=keys)
        writer.writeheader()
        for rec in records:
            writer.writerow({k: "" if (v := _jsonable(rec[k])) is None else v for k in keys})
    return path


def _check_positive(name: str, value: float) -> None:
    if not (np.isfinite(value) and value > 0):
        raise InputError(f"{name} must be a positive number, got {value:g}")


def _report_failures(failures: Sequence[tuple[str, str]]) -> None:
    for spec, message in failures:
        err_console.print(f"[bold red]not compared[/]: {spec}: {message}")


# ------------------------------------------------------------------------------- compare

_SIDE_BY_SIDE = (
    ("camber_half_mm", "camber at ½ BW [mm]"),
    ("camber_full_mm", "camber at 1 BW [mm]"),
    ("pocket_0.1mm_half_mm", "wax pocket (0.1 mm) at ½ BW [mm]"),
    ("closing_load_kg", "closing load [kg]"),
    ("stiffness_n_per_mm", "stiffness [N/mm]"),
)
_CONTACT_ROWS = (
    ("length_mm", "length [mm]"),
    ("area_cm2", "area [cm²]"),
    ("mean_pressure_kpa", "mean p [kPa]"),
    ("peak_pressure_kpa", "peak p [kPa]"),
    ("load_share", "load share"),
)


def comparison_rows(records: Sequence[dict[str, Any]]) -> list[list[Any]]:
    """The side-by-side table: one row per quantity, one column per ski (field units)."""
    rows: list[list[Any]] = [["route", *[r["profile_route"] for r in records]]]
    rows += [[label, *[r[key] for r in records]] for key, label in _SIDE_BY_SIDE]
    for load, tag in (("half", "½ BW"), ("full", "1 BW")):
        for zone in ("rear", "middle", "front", "total", "kick"):
            for key, label in _CONTACT_ROWS:
                rows.append(
                    [f"{tag} {zone} {label}", *[r[f"{load}_{zone}_{key}"] for r in records]]
                )
        rows.append([f"{tag} grip wax touches", *[r[f"{load}_kick_contact"] for r in records]])
    return rows


@app.command()
def compare(
    skis: Annotated[list[str], typer.Argument(help="Skis: shipped names, ski files, bench files.")],
    body_mass_kg: float = _BODY,
    snow_modulus_mpa: float = _SNOW,
    ski_model: str = _MODEL,
    load_position_mm: float = _POS,
    criterion: Annotated[
        str,
        typer.Option(
            "--criterion",
            help="Ranking criterion: mean-pressure, peak-pressure, contact-length, kick-share, "
            "rear-share, closing-load (see README, 'Technician workflows').",
        ),
    ] = "mean-pressure",
    snow_range_mpa: Annotated[
        str,
        typer.Option(
            "--snow-range-mpa",
            help="Snow moduli in MPa for the ranking across snow: start:stop:step or a list.",
        ),
    ] = "20,30,50,75,100,150,200,300,400",
    points: int = _POINTS,
    out: Path | None = _OUT,
    json_out: JsonOption = False,
) -> None:
    """Compare a fleet side by side at ½ and 1 body weight; rank it on one snow and across snow.

    A ski that cannot be read is named on stderr and left out; the others are compared (exit 2,
    bad input, when any was left out).
    """
    from skisnow.workflows import CRITERIA, compare_fleet, rank_across_snow

    _check_positive("--body-mass-kg", body_mass_kg)
    _check_positive("--snow-modulus-mpa", snow_modulus_mpa)
    if criterion not in CRITERIA:
        raise InputError(f"--criterion must be one of {', '.join(CRITERIA)}, got {criterion!r}")
    moduli = parse_values(snow_range_mpa, name="--snow-range-mpa")
    if moduli.size < 2 or np.any(moduli <= 0):
        raise InputError("--snow-range-mpa needs at least two positive moduli in MPa")
    with progress_bar("compare", disable=json_out) as update:
        cmp = compare_fleet(
            skis,
            body_mass=body_mass_kg,
            snow_modulus=snow_modulus_mpa * 1e6,
            load_position=load_position_mm * 1e-3,
            ski_model=ski_model,  # type: ignore[arg-type]
            n_points=points,
            progress=update,
        )
    _report_failures(cmp.failures)
    for entry in cmp.entries:
        for case in entry.cases.values():
            report_converged(case.converged)
    if not cmp.entries:
        raise InputError("no ski of the fleet could be compared")
    crit = CRITERIA[criterion]
    records = cmp.records()
    ranking = cmp.ranking(criterion)
    with progress_bar("ranking across snow", disable=json_out) as update:
        snow = rank_across_snow(cmp, criterion, moduli * 1e6, n_points=points, progress=update)
    snow_records = [
        {
            "snow_modulus_mpa": float(e * 1e-6),
            **{f"{s}_{crit.column}": float(snow.values[i, j]) for i, s in enumerate(snow.skis)},
            **{f"{s}_rank": int(snow.ranks[i, j]) for i, s in enumerate(snow.skis)},
            "best": snow.winners()[j],
        }
        for j, e in enumerate(snow.snow_moduli)
    ]
    changes = [
        {
            "between_mpa": [lo * 1e-6, hi * 1e-6],
            "order_before": list(before),
            "order_after": list(after),
        }
        for lo, hi, before, after in snow.changes
    ]
    notes = [e.route_note for e in cmp.entries if e.route_note]
    files: list[str] = []
    if out is not None:
        from skisnow.plot import plot_fleet, plot_snow_ranking, save_figure

        files += [str(write_csv(out / "comparison.csv", records))]
        files += [str(write_csv(out / "ranking.csv", ranking))]
        files += [str(write_csv(out / "snow_ranking.csv", snow_records))]
        files += [str(p) for p in save_figure(plot_fleet(cmp), out / "fleet")]
        files += [str(p) for p in save_figure(plot_snow_ranking(snow), out / "snow_ranking")]
    doc = {
        **run_annotations(),
        "body_mass_kg": body_mass_kg,
        "snow_modulus_mpa": snow_modulus_mpa,
        "load_position_mm": load_position_mm,
        "ski_model": ski_model,
        "skis": records,
        "criterion": {
            "name": crit.name,
            "column": crit.column,
            "better": crit.better,
            "description": crit.description,
        },
        "ranking": ranking,
        "snow_ranking": snow_records,
        "order_changes": changes,
        "notes": notes,
        "failures": [{"ski": s, "error": m} for s, m in cmp.failures],
        "files": files,
    }
    if json_out:
        emit_json(doc)
    else:
        labels = [r["ski"] for r in records]
        print_table(
            f"Fleet: {body_mass_kg:g} kg at {load_position_mm:g} mm on {snow_modulus_mpa:g} MPa "
            f"snow ({ski_model})",
            ["quantity", *labels],
            comparison_rows(records),
        )
        print_table(
            f"Ranking by {crit.name} ({crit.column}, {crit.better} is better)",
            ["rank", "ski", crit.column],
            [[r["rank"], r["ski"], r[crit.column]] for r in ranking],
        )
        console.print(f"criterion: {crit.description}")
        print_table(
            f"Best ski by {crit.name} across snow",
            ["snow [MPa]", "order (best first)"],
            [
                [
                    rec["snow_modulus_mpa"],
                    " > ".join(sorted(snow.skis, key=lambda s, r=rec: r[f"{s}_rank"])),
                ]
                for rec in snow_records
            ],
        )
        if not changes:
            console.print("the order does not change over the snow range")
        for c in changes:
            console.print(
                f"order changes between {c['between_mpa'][0]:g} and {c['between_mpa'][1]:g} MPa"
            )
        for note in notes:
            console.print(f"note: {note}")
        for f in files:
            console.print(f"wrote {f}")
    if cmp.failures:
        raise typer.Exit(EXIT_INPUT)


# ------------------------------------------------------------------------------- pairs


@app.command()
def pairs(
    skis: Annotated[list[str], typer.Argument(help="Skis: shipped names, ski files, bench files.")],
    body_mass_kg: float = _BODY,
    snow_modulus_mpa: float = _SNOW,
    load_position_mm: float = _POS,
    points: int = _POINTS,
    out: Path | None = _OUT,
    json_out: JsonOption = False,
) -> None:
    """Pair a fleet: the minimum-weight matching of the camber, stiffness and contact distance."""
    from skisnow.workflows import (
        CAMBER_TOLERANCE,
        CONTACT_TOLERANCE,
        STIFFNESS_TOLERANCE,
        match_pairs,
    )

    _check_positive("--body-mass-kg", body_mass_kg)
    _check_positive("--snow-modulus-mpa", snow_modulus_mpa)
    with progress_bar("pairs", disable=json_out) as update:
        result = match_pairs(
            skis,
            body_mass=body_mass_kg,
            snow_modulus=snow_modulus_mpa * 1e6,
            load_position=load_position_mm * 1e-3,
            n_points=points,
            progress=update,
        )
    _report_failures(result.failures)
    worst = result.worst
    records = [
        {
            "ski_a": a,
            "ski_b": b,
            "distance": d.total,
            "camber_term": d.camber,
            "stiffness_term": d.stiffness,
            "contact_term": d.contact,
            "camber_rms_um": d.camber_rms * 1e6,
            "stiffness_rms_percent": d.stiffness_rms * 100,
            "load_moved_percent": d.load_moved * 100,
            "worst": worst is not None and (a, b) == worst[:2],
        }
        for a, b, d in result.pairs
    ]
    definition = (
        f"d = sqrt((rms dz0 / {CAMBER_TOLERANCE * 1e3:g} mm)^2 + (rms dlnEI / "
        f"{STIFFNESS_TOLERANCE:g})^2 + (load moved / {CONTACT_TOLERANCE:g})^2); load moved = "
        f"half the integral of |q_a - q_b| over the load, at {body_mass_kg:g} kg on "
        f"{snow_modulus_mpa:g} MPa snow"
    )
    matrix = [
        {"ski": s, **{t: float(result.distances[i, j]) for j, t in enumerate(result.skis)}}
        for i, s in enumerate(result.skis)
    ]
    files: list[str] = []
    if out is not None:
        files.append(str(write_csv(out / "pairs.csv", records)))
        files.append(str(write_csv(out / "distances.csv", matrix)))
    if json_out:
        emit_json(
            {
                **run_annotations(),
                "distance": definition,
                "pairs": records,
                "spare": result.spare,
                "total_distance": result.total,
                "distances": matrix,
                "failures": [{"ski": s, "error": m} for s, m in result.failures],
                "files": files,
            }
        )
    else:
        print_table(
            "Pairs (minimum-weight matching, networkx), best first",
            ["ski A", "ski B", "distance", "camber", "stiffness", "contact", "flag"],
            [
                [
                    r["ski_a"],
                    r["ski_b"],
                    r["distance"],
                    r["camber_term"],
                    r["stiffness_term"],
                    r["contact_term"],
                    "WORST" if r["worst"] else "",
                ]
                for r in records
            ],
        )
        console.print(definition)
        if result.spare:
            console.print(f"spare (odd fleet): {result.spare}")
        for f in files:
            console.print(f"wrote {f}")
    if result.failures:
        raise typer.Exit(EXIT_INPUT)


# ------------------------------------------------------------------------------- cycle


def cycle_records(ds: Any) -> list[dict[str, Any]]:
    """One record per frame, field units (s, N, mm, kPa)."""
    recs = []
    for i, t in enumerate(ds["time"].values):
        rec: dict[str, Any] = {
            "t_s": float(t),
            "force_n": float(ds["load"].values[i]),
            "load_position_mm": float(ds["load_position"].values[i] * 1e3),
            "loaded": bool(ds["loaded"].values[i]),
        }
        for j, zone in enumerate(ds["zone"].values):
            rec[f"{zone}_length_mm"] = float(ds["length"].values[i, j] * 1e3)
            rec[f"{zone}_area_cm2"] = float(ds["area"].values[i, j] * 1e4)
            rec[f"{zone}_mean_pressure_kpa"] = float(ds["mean_pressure"].values[i, j] * 1e-3)
            rec[f"{zone}_peak_pressure_kpa"] = float(ds["max_pressure"].values[i, j] * 1e-3)
            rec[f"{zone}_load_share"] = float(ds["load_share"].values[i, j])
        rec["kick_contact"] = bool(ds["kick_contact"].values[i])
        rec["converged"] = bool(ds["converged"].values[i])
        recs.append(rec)
    return recs


def summary_record(ds: Any) -> dict[str, Any]:
    """The kick-zone contact summary of a cycle in field units."""
    from skisnow.workflows import kick_contact_summary

    s = kick_contact_summary(ds)
    return {
        "history": ds.attrs["history"],
        "route": ds.attrs["route"],
        "kick_contact_time_s": s["contact_time"],
        "loaded_time_s": s["loaded_time"],
        "kick_fraction_of_loaded": s["fraction_of_loaded"],
        "first_touch_s": s["first_touch"],
        "last_touch_s": s["last_touch"],
        "touch_downs": s["episodes"],
        "max_kick_share": s["max_kick_share"],
        "max_kick_length_mm": s["max_kick_length"] * 1e3,
        "peak_force_n": float(np.max(ds["load"].values)),
        "peak_pressure_kpa": float(np.nanmax(ds["max_pressure"].values, initial=0.0) * 1e-3),
    }


@app.command()
def cycle(
    ski: Annotated[str, typer.Argument(help="A shipped ski name, a ski file or a bench file.")],
    snow_modulus_mpa: float = _SNOW,
    load_history: Annotated[
        Path | None,
        typer.Option(
            "--load-history",
            help="CSV with columns t_s, force_n or mass_kg, load_position_mm.",
        ),
    ] = None,
    template: Annotated[
        str | None,
        typer.Option(
            "--template",
            help="Built-in cycle: diagonal, double_poling, skate_g3, or all (the stride table).",
        ),
    ] = None,
    body_mass_kg: Annotated[
        float | None, typer.Option("--body-mass-kg", help="Body mass in kg (with --template).")
    ] = None,
    cycle_s: Annotated[
        float | None, typer.Option("--cycle-s", help="Cycle time in s (template's default).")
    ] = None,
    frames: Annotated[
        int | None,
        typer.Option("--frames", help="Frames over the cycle (template: 100; file: its rows)."),
    ] = None,
    profile_source: Annotated[
        str,
        typer.Option(
            "--profile-source",
            help="auto (network inside its trained domain, else beam), network or beam.",
        ),
    ] = "auto",
    ski_model: str = _MODEL,
    points: int = _POINTS,
    out: Path | None = _OUT,
    animation: Annotated[
        Path | None,
        typer.Option("--animation", help="Write an animation (.gif, or .mp4 with ffmpeg)."),
    ] = None,
    show_template: Annotated[
        bool, typer.Option("--show-template", help="Print the template's knots and source.")
    ] = False,
    json_out: JsonOption = False,
) -> None:
    """The contact over a load cycle, frame by frame (warm-started): zones, pressures, and when
    and for how long the grip wax touches the snow."""
    from skisnow.workflows import TEMPLATES, read_load_history, run_cycle, template_history

    if (load_history is None) == (template is None):
        raise InputError("give exactly one of --load-history FILE or --template NAME")
    _check_positive("--snow-modulus-mpa", snow_modulus_mpa)
    if ski_model not in ("rigid", "flexible"):
        raise InputError(f"--ski-model must be rigid or flexible, got {ski_model!r}")
    if frames is not None and frames < 2:
        raise InputError(f"--frames must be at least 2, got {frames}")
    histories = []
    if template is not None:
        names = list(TEMPLATES) if template == "all" else [template]
        if template != "all" and template not in TEMPLATES:
            raise InputError(
                f"--template must be one of {', '.join(TEMPLATES)} or all, got {template!r}"
            )
        if body_mass_kg is None:
            raise InputError("--template needs --body-mass-kg")
        if show_template:
            for name in names:
                tpl = TEMPLATES[name]
                print_table(
                    f"{tpl.technique}: {tpl.duration:g} s — {tpl.citation}",
                    ["phase", "force [BW]", "load_position_mm"],
                    [[k["phase"], k["force_bw"], k["load_position_mm"]] for k in tpl.knots()],
                )
        for name in names:
            histories.append(
                (
                    name,
                    template_history(
                        name, body_mass=body_mass_kg, n_frames=frames or 100, duration=cycle_s
                    ),
                )
            )
    else:
        assert load_history is not None
        h = read_load_history(load_history)
        histories.append((load_history.stem, h.resample(frames) if frames else h))
    results = []
    for name, history in histories:
        with progress_bar(f"cycle {name}", disable=json_out) as update:
            ds = run_cycle(
                ski,
                history,
                snow_modulus=snow_modulus_mpa * 1e6,
                profile_source=profile_source,  # type: ignore[arg-type]
                n_points=points,
                keep_fields=animation is not None,
                ski_model=ski_model,  # type: ignore[arg-type]
                progress=update,
            )
        report_converged(bool(ds["converged"].all()))
        results.append((name, ds))
    files: list[str] = []
    for name, ds in results:
        suffix = f"_{name}" if len(results) > 1 else ""
        if out is not None:
            from skisnow.plot import plot_cycle, save_figure

            files.append(str(write_csv(out / f"cycle{suffix}.csv", cycle_records(ds))))
            with atomic_path(out / f"cycle{suffix}.nc") as tmp:
                ds.to_netcdf(tmp)  # the whole Dataset (SI units in the attributes)
            files.append(str(out / f"cycle{suffix}.nc"))
            files += [str(p) for p in save_figure(plot_cycle(ds), out / f"cycle{suffix}")]
        if animation is not None:
            from skisnow.plot import animate_cycle

            target = animation.with_name(f"{animation.stem}{suffix}{animation.suffix}")
            with (
                progress_bar(f"animation {name}", disable=json_out) as update,
                atomic_path(target) as tmp,
            ):
                animate_cycle(ds, tmp, progress=update)
            files.append(str(target))
    summaries = [{"cycle": name, **summary_record(ds)} for name, ds in results]
    notes = [ds.attrs["route_note"] for _, ds in results if ds.attrs["route_note"]]
    if out is not None:
        files.append(str(write_csv(out / "cycle_summary.csv", summaries)))
    if json_out:
        emit_json(
            {
                **run_annotations(),
                "ski": results[0][1].attrs["ski"],
                "snow_modulus_mpa": snow_modulus_mpa,
                "summaries": summaries,
                "notes": notes,
                "sources": {name: ds.attrs["history_source"] for name, ds in results},
                "frames": {name: cycle_records(ds) for name, ds in results},
                "files": files,
            }
        )
        return
    for note in notes:
        console.print(f"[bold yellow]note[/]: {note}")
    print_table(
        f"Kick-zone contact over the cycle: {results[0][1].attrs['ski']} on "
        f"{snow_modulus_mpa:g} MPa snow",
        [
            "cycle",
            "route",
            "wax touches [s]",
            "loaded [s]",
            "fraction",
            "first [s]",
            "last [s]",
            "touch-downs",
            "max kick share",
            "peak force [N]",
        ],
        [
            [
                s["cycle"],
                s["route"],
                s["kick_contact_time_s"],
                s["loaded_time_s"],
                s["kick_fraction_of_loaded"],
                s["first_touch_s"],
                s["last_touch_s"],
                s["touch_downs"],
                s["max_kick_share"],
                s["peak_force_n"],
            ]
            for s in summaries
        ],
    )
    for name, ds in results:
        if ds.attrs["history_source"] and template is not None:
            console.print(f"{name}: {ds.attrs['history_source']}")
    for f in files:
        console.print(f"wrote {f}")
