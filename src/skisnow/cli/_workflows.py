"""Technician workflows on a fleet: the ``compare`` and ``pairs`` commands.

Thin: they parse, call :mod:`skisnow.workflows` and render. This module also holds the options
and the CSV writer shared with the ``cycle`` command (:mod:`skisnow.cli._workflows_cycle`).
"""

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
from skisnow.cli._fleet_table import comparison_rows
from skisnow.cli._intervals import GLIDE_NOTE, SamplesOption
from skisnow.cli._media import (
    FilmCutoffOption,
    ShearStrengthOption,
    SlidingSpeedOption,
    SnowOption,
    SnowTemperatureOption,
    ViscosityOption,
    friction_parameters,
    resolve_snow,
)
from skisnow.cli._render import (
    JsonOption,
    _jsonable,
    console,
    emit_json,
    print_table,
    progress_bar,
    say,
    show,
)

_SNOW = typer.Option(
    None,
    "--snow-modulus-mpa",
    help="Young's modulus of the snow in MPa (or --snow; with --snow it overrides).",
)
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


def friction_assumptions(friction: object, snow: object) -> str:
    """The friction parameters as a sentence (resolved on ``snow``)."""
    import warnings

    from skisnow._errors import DomainWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DomainWarning)
        h = snow.hardness  # type: ignore[attr-defined]
    return friction.resolve(temperature_c=snow.temperature_c, hardness=h).assumptions()  # type: ignore[attr-defined]


def _check_fleet(skis: Sequence[str]) -> None:
    """A fleet names each ski once (``pairs classic classic`` would pair a ski with itself)."""
    twice = sorted({s for s in skis if list(skis).count(s) > 1})
    if twice:
        raise InputError(
            f"SKIS: {', '.join(repr(s) for s in twice)} given twice; name each ski of the fleet "
            "once (two skis of the same content are compared as two, tied)"
        )


def _report_failures(failures: Sequence[tuple[str, str]]) -> None:
    for spec, message in failures:
        say(f"not compared: {spec}: {message}", style="bold red")


# ------------------------------------------------------------------------------- compare


@app.command()
def compare(
    skis: Annotated[list[str], typer.Argument(help="Skis: shipped names, ski files, bench files.")],
    body_mass_kg: float = _BODY,
    snow_modulus_mpa: float | None = _SNOW,
    # the snow, base and friction options, defined once in cli/_media.py; Typer needs them
    # listed in each command's own signature
    snow: SnowOption = None,
    snow_temperature_c: SnowTemperatureOption = None,
    base: Annotated[
        list[str] | None,
        typer.Option(
            "--base",
            help="Base texture(s) to rank with the skis (repeat: --base S1 --base S3); S1..S5, "
            "smooth or a topography file; needs --snow.",
        ),
    ] = None,
    proxy: Annotated[
        str,
        typer.Option(
            "--proxy",
            help="Real-contact proxy that ranks skis × bases: mu, mu-lubricated, viscous, dry, "
            "real-area, real-area-flat, reciprocal.",
        ),
    ] = "viscous",
    shear_strength_mpa: ShearStrengthOption = None,
    viscosity_mpa_s: ViscosityOption = None,
    sliding_speed_m_s: SlidingSpeedOption = None,
    film_cutoff_nm: FilmCutoffOption = None,
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
    samples: SamplesOption = 200,
    out: Path | None = _OUT,
    json_out: JsonOption = False,
) -> None:
    """Compare a fleet side by side at ½ and 1 body weight; rank it on one snow and across snow.

    An identified ski's contact answers carry 95 % intervals (--samples); skis whose intervals
    overlap tie in the ranking (a tie within uncertainty); glide proxies tie within the
    glide-test precision (1.1 %, Lemmettylä et al. 2021).

    A ski that cannot be read is named on stderr and left out; the others are compared (exit 2,
    bad input, when any was left out).
    """
    from skisnow.cli._intervals import check_samples, fleet_intervals, print_fleet_uncertainty
    from skisnow.workflows import CRITERIA, PROXIES, compare_fleet, rank_across_snow

    _check_positive("--body-mass-kg", body_mass_kg)
    _check_fleet(skis)
    check_samples(samples)
    if ski_model not in ("rigid", "flexible"):
        raise InputError(f"--ski-model must be rigid or flexible, got {ski_model!r}")
    snow_obj, e = resolve_snow(snow, snow_modulus_mpa, temperature_c=snow_temperature_c)
    snow_modulus_mpa = e * 1e-6
    if base and snow_obj is None:
        raise InputError("--base: the real contact needs --snow (a preset or a snow file)")
    if proxy not in PROXIES:
        raise InputError(f"--proxy must be one of {', '.join(PROXIES)}, got {proxy!r}")
    friction = friction_parameters(
        shear_strength_mpa=shear_strength_mpa,
        viscosity_mpa_s=viscosity_mpa_s,
        sliding_speed_m_s=sliding_speed_m_s,
        film_cutoff_nm=film_cutoff_nm,
    )
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
            samples=samples,
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
        snow = rank_across_snow(cmp, criterion, moduli * 1e6, n_points=points, progress=update,
                                samples=samples)  # fmt: skip
    snow_records = [
        {
            "snow_modulus_mpa": float(e * 1e-6),
            **{f"{s}_{crit.column}": float(snow.values[i, j]) for i, s in enumerate(snow.skis)},
            **{f"{s}_rank": int(snow.ranks[i, j]) for i, s in enumerate(snow.skis)},
            **(
                {}
                if snow.intervals is None
                else {
                    f"{s}_{crit.column}_{end}": float(snow.intervals[i, j, k])
                    for i, s in enumerate(snow.skis)
                    for k, end in enumerate(("low", "high"))
                }
            ),
            "best": snow.winners()[j],
            "order": snow.order_text(j),
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
    topology = [*cmp.topology_warnings(criterion), *snow.warnings]  # patch-based: not comparable
    intervals = fleet_intervals(cmp, samples)
    real_records, real_ranking = [], []
    if base:
        from skisnow.workflows import rank_real, real_table

        with progress_bar("real contact (micro curves per base)", disable=json_out):
            real_records = real_table(
                {e.ski.label: e.cases["full"].solution for e in cmp.entries},
                list(base),
                snow_obj,
                friction=friction,
            )
        real_ranking = rank_real(real_records, proxy)
    files: list[str] = []
    if out is not None:
        from skisnow.plot import plot_fleet, plot_snow_ranking, save_figure

        files += [str(write_csv(out / "comparison.csv", records))]
        if real_records:
            files += [str(write_csv(out / "real_contact.csv", real_records))]
            files += [str(write_csv(out / "real_ranking.csv", real_ranking))]
        files += [str(write_csv(out / "ranking.csv", ranking))]
        files += [str(write_csv(out / "intervals.csv", intervals))]
        files += [str(write_csv(out / "snow_ranking.csv", snow_records))]
        files += [str(p) for p in save_figure(plot_fleet(cmp), out / "fleet")]
        files += [str(p) for p in save_figure(plot_snow_ranking(snow), out / "snow_ranking")]
    doc = {
        **(ann := run_annotations()),
        "warnings": [*ann["warnings"], *topology],
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
        "intervals": intervals,
        "snow_ranking": snow_records,
        "order_changes": changes,
        "real_contact": real_records,
        "real_ranking": {
            "proxy": proxy,
            "tie_rule": GLIDE_NOTE,
            "description": PROXIES[proxy].description,
            "ranking": real_ranking,
        }
        if real_records
        else None,
        "snow": None if snow_obj is None else snow_obj.describe(),
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
            comparison_rows(records, load_position_mm=load_position_mm),
        )
        print_table(
            f"Ranking by {crit.name} ({crit.column}, {crit.better} is better)",
            ["rank", "ski", crit.column],
            [
                [f"{r['rank']}=" if r["tied"] else str(r["rank"]), r["ski"], r[crit.column]]
                for r in ranking
            ],
        )
        console.print(f"criterion: {crit.description}")
        print_fleet_uncertainty(ranking, crit.column, intervals)
        print_table(
            f"Best ski by {crit.name} across snow",
            ["snow [MPa]", "order (best first)"],
            [[rec["snow_modulus_mpa"], rec["order"]] for rec in snow_records],
        )
        if real_records:
            p = PROXIES[proxy]
            print_table(
                f"Skis × bases at {body_mass_kg:g} kg on {snow_obj.name} snow by {p.name} "
                f"({p.better} is better)",
                ["rank", "ski", "base", p.column, "real [mm²]", "viscous [N]", "µ dry", "µ lub."],
                [
                    [
                        f"{r['rank']}=" if r["ties_with"] else str(r["rank"]),
                        r["ski"],
                        r["base"],
                        r[p.column],
                        *next(
                            [q["real_area_mm2"], q["viscous_force_n"], q["mu"], q["mu_lubricated"]]
                            for q in real_records
                            if (q["ski"], q["base"]) == (r["ski"], r["base"])
                        ),
                    ]
                    for r in real_ranking
                ],
            )
            console.print(f"proxy: {p.description}")
            console.print(f"n= : a tie within the glide-test precision ({GLIDE_NOTE})")
            console.print(f"assumptions: {friction_assumptions(friction, snow_obj)}")
        if not changes:
            console.print("the order does not change over the snow range")
        for c in changes:
            console.print(
                f"order changes between {c['between_mpa'][0]:g} and {c['between_mpa'][1]:g} MPa"
            )
        for note in notes:
            show(f"note: {note}")
        for w in topology:
            say(f"warning: {w}", style="yellow")
        for f in files:
            show(f"wrote {f}")
    if cmp.failures:
        raise typer.Exit(EXIT_INPUT)


# ------------------------------------------------------------------------------- pairs


@app.command()
def pairs(
    skis: Annotated[list[str], typer.Argument(help="Skis: shipped names, ski files, bench files.")],
    body_mass_kg: float = _BODY,
    snow_modulus_mpa: float | None = _SNOW,
    # the snow, base and friction options, defined once in cli/_media.py; Typer needs them
    # listed in each command's own signature
    snow: SnowOption = None,
    load_position_mm: float = _POS,
    points: int = _POINTS,
    out: Path | None = _OUT,
    json_out: JsonOption = False,
) -> None:
    """Pair a fleet: the minimum-weight matching of the camber, stiffness and contact distance."""
    from skisnow.cli._intervals import tie_test_doc
    from skisnow.workflows import (
        CAMBER_TOLERANCE,
        CONTACT_TOLERANCE,
        POOR_MATCH_DISTANCE,
        STIFFNESS_TOLERANCE,
        match_pairs,
    )

    _check_positive("--body-mass-kg", body_mass_kg)
    _check_fleet(skis)
    snow_modulus_mpa = resolve_snow(snow, snow_modulus_mpa)[1] * 1e-6
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
    report_converged(result.converged)  # the contact terms' solves (``converged`` of --json)
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
            "poor_match": result.poor((a, b, d)),
            "worst": worst is not None and (a, b) == worst[:2],
            "tie_within_uncertainty": d.within_uncertainty,
            "tie_test": tie_test_doc(d.uncertainty_test),
            "compared_mm": None if d.compared is None else [v * 1e3 for v in d.compared],
        }
        for a, b, d in result.pairs
    ]
    pair_warnings = result.messages()  # the identifications' warnings, ties above the tolerance
    definition = (
        f"d = sqrt((rms dz0 / {CAMBER_TOLERANCE * 1e3:g} mm)^2 + (rms dlnEI / "
        f"{STIFFNESS_TOLERANCE:g})^2 + (load moved / {CONTACT_TOLERANCE:g})^2); load moved = "
        f"half the integral of |q_a - q_b| over the load, at {body_mass_kg:g} kg on "
        f"{snow_modulus_mpa:g} MPa snow, load at {load_position_mm:g} mm from the balance point; "
        f"a poor match: d > {POOR_MATCH_DISTANCE:g} (the skis differ by more than the "
        "tolerances); the worst: the poor match of largest d; camber and stiffness compared "
        "only where both skis are determined by their data (identified skis); a tie within "
        "uncertainty: the camber and stiffness differences within the skis' simultaneous 95 % "
        "band (largest difference in units of the combined band sd against its 95 % quantile "
        "under the skis' posteriors, the sup-t band)"
    )
    matrix = [
        {"ski": s, **{t: float(result.distances[i, j]) for j, t in enumerate(result.skis)}}
        for i, s in enumerate(result.skis)
    ]
    files: list[str] = []
    if out is not None:
        from skisnow.plot import plot_pairs, save_figure

        files.append(str(write_csv(out / "pairs.csv", records)))
        files.append(str(write_csv(out / "distances.csv", matrix)))
        fig = plot_pairs(result, threshold=POOR_MATCH_DISTANCE)
        files += [str(p) for p in save_figure(fig, out / "pairs")]
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
                "warnings": pair_warnings,
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
                    ("WORST" if r["worst"] else ("poor" if r["poor_match"] else ""))
                    + (" (tie within uncertainty)" if r["tie_within_uncertainty"] else ""),
                ]
                for r in records
            ],
        )
        console.print(definition)
        for a, b, d in result.pairs:
            if d.uncertainty_test is not None:
                show(f"{a} / {b}: {d.uncertainty_test.text()}")
        for w in pair_warnings:
            show(f"warning: {w}")
        if result.spare:
            show(f"spare (odd fleet): {result.spare}")
        for f in files:
            show(f"wrote {f}")
    if result.failures:
        raise typer.Exit(EXIT_INPUT)
