"""Commands for the apparent contact: contact (thin: parse, call skisnow.pipeline, render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from skisnow._errors import InputError
from skisnow.cli._app import app, report_converged, report_domain_warnings
from skisnow.cli._intervals import SamplesOption
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
    JsonOption,
    ProfileSourceOption,
    SkiModelOption,
    console,
    emit_json,
    print_table,
    say,
)
from skisnow.materials import BASE
from skisnow.pipeline import DEFAULT_N_POINTS, MODELS, PROFILE_SOURCES, SKI_MODELS

__all__ = ["footprint_records", "patch_record", "real_rows", "zone_record"]

_ZONES = ("rear", "middle", "front", "total")


def zone_record(zone: Any, *, pressures: bool = True) -> dict[str, Any]:
    """One zone in field units (mm, cm², kPa, µm)."""
    rec: dict[str, Any] = {
        "length_mm": zone.length * 1e3,
        "area_cm2": zone.area * 1e4,
        "patches": zone.patches,
        "start_mm": zone.start * 1e3,
        "end_mm": zone.end * 1e3,
    }
    if pressures:
        rec |= {
            "mean_pressure_kpa": zone.mean_pressure * 1e-3,
            "max_pressure_kpa": zone.max_pressure * 1e-3,
            "load_share": zone.load_share,
            "penetration_um": zone.penetration * 1e6,
        }
    return rec


def patch_record(patch: Any) -> dict[str, Any]:
    """One contact patch (:class:`skisnow.contact.Patch`) in field units."""
    return {
        "start_mm": patch.start * 1e3,
        "end_mm": patch.end * 1e3,
        "length_mm": patch.length * 1e3,
        "area_cm2": patch.area * 1e4,
        "load_n": patch.force,
        "load_share": patch.load_share,
        "mean_pressure_kpa": patch.mean_pressure * 1e-3,
        "max_pressure_kpa": patch.max_pressure * 1e-3,
        "penetration_um": patch.penetration * 1e6,
        "regions": list(patch.regions),
    }


def footprint_records(zones: Any) -> dict[str, Any]:
    """The two views that never jump, in field units: ``regions`` (fixed by the ski) and
    ``patches``, with ``merged`` (the paper's zones are the regions) and the region marks."""
    fp = zones.footprint
    return {
        "merged": zones.merged,
        "region_rule": fp.rule,
        "region_marks_mm": [m * 1e3 for m in fp.marks],
        "regions": {
            name: zone_record(zones[name]) | {"load_n": zones[name].force} for name in fp.names
        },
        "patches": [patch_record(p) for p in fp.patches],
    }


@app.command()
def contact(
    ski: Annotated[
        str | None,
        typer.Option("--ski", help="Shipped ski name (classic, skate) or a ski file (.json)."),
    ] = None,
    profile: Annotated[
        Path | None,
        typer.Option("--profile", help="CSV of a rigid loaded profile: columns x_mm,height_mm."),
    ] = None,
    mass_kg: Annotated[float, typer.Option("--mass-kg", help="Load m in kg (W = m·g).")] = ...,  # type: ignore[assignment]
    load_position_mm: Annotated[
        float,
        typer.Option(
            "--load-position-mm", help="x_m in mm from the balance point, + toward the tip."
        ),
    ] = ...,  # type: ignore[assignment]
    snow_modulus_mpa: Annotated[
        float | None,
        typer.Option(
            "--snow-modulus-mpa",
            help="Elastic modulus of the snow in MPa (or --snow; with --snow it overrides).",
        ),
    ] = None,
    # the snow, base and friction options, defined once in cli/_media.py; Typer needs them
    # listed in each command's own signature
    snow: SnowOption = None,
    snow_temperature_c: SnowTemperatureOption = None,
    base: BaseOption = None,
    shear_strength_mpa: ShearStrengthOption = None,
    viscosity_mpa_s: ViscosityOption = None,
    sliding_speed_m_s: SlidingSpeedOption = None,
    film_cutoff_nm: FilmCutoffOption = None,
    model: Annotated[
        str, typer.Option("--model", help="strip (1D, fast) or surface (2D grid across).")
    ] = "strip",
    width_mm: Annotated[
        float | None,
        typer.Option(
            "--width-mm",
            help="With --profile: the ski's width in mm (default 44). With --ski the ski's own "
            "width is used.",
        ),
    ] = None,
    ski_model: SkiModelOption = "rigid",
    profile_source: ProfileSourceOption = "auto",
    base_modulus_mpa: Annotated[
        float, typer.Option("--base-modulus-mpa", help="Ski base modulus in MPa (eq. 2).")
    ] = BASE.modulus / 1e6,
    points: Annotated[
        int,
        typer.Option(
            "--points",
            help="With --ski: stations from tail to tip, both ends included (skisnow.pipeline).",
        ),
    ] = DEFAULT_N_POINTS,
    n_across: Annotated[
        int, typer.Option("--n-across", help="Cells across the width (surface model).")
    ] = 16,
    samples: SamplesOption = 200,
    json_out: JsonOption = False,
    figure: Annotated[
        Path | None, typer.Option("--figure", help="Save a figure (png/svg/pdf by suffix).")
    ] = None,
    fields_out: Annotated[
        Path | None,
        typer.Option(
            "--fields-out",
            help="Write x_mm,pressure_kpa,gap_um,snow_displacement_um,region,patch (CSV).",
        ),
    ] = None,
) -> None:
    """Apparent contact of a loaded ski with elastic snow: force and moment balance (eq. 2–3).

    With --base (a texture) and --snow, also the real contact along the ski, side by side with
    the apparent one, and the friction proxies with their assumptions. An identified ski (a
    ski file with bands) gives every zone's answers a 95 % interval (--samples).
    """
    from skisnow.cli._intervals import (
        check_samples,
        no_uncertainty_note,
        print_intervals,
        uncertainty_doc,
    )
    from skisnow.cli._media import friction_parameters, resolve_base, resolve_snow
    from skisnow.contact import read_profile, write_fields
    from skisnow.pipeline import solve_case

    snow_obj, snow_modulus = resolve_snow(snow, snow_modulus_mpa, temperature_c=snow_temperature_c)

    if (ski is None) == (profile is None):
        raise InputError("give exactly one of --ski NAME or --profile FILE")
    if ski is not None and width_mm is not None:
        raise InputError(
            "--width-mm goes with --profile only: with --ski the ski's own width is used"
        )
    if profile is not None:
        width_mm = 44.0 if width_mm is None else width_mm
    if ski_model not in SKI_MODELS:
        raise InputError(f"--ski-model must be one of {', '.join(SKI_MODELS)}, got {ski_model!r}")
    if ski_model == "flexible" and profile is not None:
        raise InputError(
            "--ski-model flexible needs --ski (the beam's EI(x) and z0(x)); a --profile is a "
            "rigid profile"
        )
    if ski is not None:
        from skisnow.ski import get_ski

        try:
            get_ski(ski)
        except InputError as exc:
            raise type(exc)(f"--ski: {exc}") from None
        from skisnow.cli._ski import resolve_profile_source

        profile_source = resolve_profile_source(profile_source, [ski])
    from skisnow._checks import check_grid_points, check_value

    for name, quantity, value in (
        ("--mass-kg", "mass", mass_kg),
        ("--load-position-mm", "load_position", load_position_mm),
        ("--width-mm", "width", width_mm),
        ("--base-modulus-mpa", "base_modulus", base_modulus_mpa),
        ("--n-across", "cells_across", n_across),
    ):
        if value is not None:
            check_value(value, quantity, where=name)
    check_grid_points(points, where="--points")
    check_samples(samples)
    check_grid_points(points * n_across if model == "surface" else points, where="--n-across")
    if model not in MODELS:
        raise InputError(f"--model must be one of {', '.join(MODELS)}, got {model!r}")
    if ski is not None and profile_source not in PROFILE_SOURCES:
        raise InputError(
            f"--profile-source must be one of {', '.join(PROFILE_SOURCES)}, got {profile_source!r}"
        )
    # the case in SI units (the flexible figure draws the rigid route of the same case beside it)
    texture = resolve_base(base, snow_obj)
    if texture is not None and base_modulus_mpa != BASE.modulus / 1e6:
        from skisnow.materials import Material
        from skisnow.multiscale import make_base

        macro = Material(name="ski base", modulus=base_modulus_mpa * 1e6, poisson=BASE.poisson)
        texture = make_base(base, material=macro)
    same_case: dict[str, Any] = {
        "mass": mass_kg,
        "load_position": load_position_mm * 1e-3,
        "model": model,
        "n_points": points,
        "base": base_modulus_mpa * 1e6 if texture is None else texture,
        "n_across": n_across,
    }
    same_case |= {"snow": snow_obj} if snow_obj is not None else {"snow_modulus": snow_modulus}
    if texture is not None:
        same_case["friction"] = friction_parameters(
            shear_strength_mpa=shear_strength_mpa,
            viscosity_mpa_s=viscosity_mpa_s,
            sliding_speed_m_s=sliding_speed_m_s,
            film_cutoff_nm=film_cutoff_nm,
        )
    elif any(
        v is not None
        for v in (shear_strength_mpa, viscosity_mpa_s, sliding_speed_m_s, film_cutoff_nm)
    ):
        raise InputError(
            "--shear-strength-mpa, --viscosity-mpa-s, --sliding-speed-m-s and --film-cutoff-nm "
            "go with --base (the real contact)"
        )
    snow_modulus_mpa = snow_modulus * 1e-6
    case = solve_case(
        ski,
        **same_case,
        profile_source=profile_source,
        profile=None if profile is None else read_profile(profile),
        width=None if width_mm is None else width_mm * 1e-3,
        label=None if profile is None else Path(str(profile)).name,
        ski_model=ski_model,
    )
    sol, zones = case.solution, case.zones
    iv = None
    if samples and case.ski is not None and case.ski.has_posterior:
        from skisnow.pipeline import case_intervals

        iv = case_intervals(case, samples=samples, base=base_modulus_mpa * 1e6, n_across=n_across)
    topology = None if iv is None else iv.topology_note()  # the samples' patch topologies
    for note in (*case.warnings, *([topology] if topology else [])):
        say(f"warning: {note}", style="yellow")
    # exit code 3 when unconverged, 4 outside a model's domain (the last note of an unconverged
    # case is the solver's own, the others are domain warnings)
    report_converged(case.converged)
    report_domain_warnings(case.warnings[: len(case.warnings) - (not case.converged)], shown=True)
    if fields_out is not None:
        write_fields(sol, fields_out, zones)
    if figure is not None and case.real is not None:
        from skisnow.plot import plot_real_contact, save_figure

        save_figure(plot_real_contact(case), figure)
    elif figure is not None:
        from skisnow.plot import plot_contact, save_figure

        reference = None
        if ski_model == "flexible":  # the rigid route of the same case, drawn beside it
            reference = solve_case(ski, **same_case, profile_source="beam").solution
        fig = plot_contact(
            sol,
            zones,
            title=f"{case.label} ({ski_model} ski): {mass_kg:g} kg at x_m = "
            f"{load_position_mm:g} mm, snow {snow_modulus_mpa:g} MPa",
            reference=reference,
            label=(
                "bent ski base (flexible)" if ski_model == "flexible" else "ski base (positioned)"
            ),
            reference_label="rigid profile (paper's method)",
        )
        save_figure(fig, figure)

    doc: dict[str, Any] = {
        "ski": ski,
        "profile": None if profile is None else str(profile),
        "profile_source": profile_source if ski is not None and ski_model == "rigid" else None,
        "profile_route": case.route,
        "ski_model": ski_model,
        "model": model,
        "mass_kg": mass_kg,
        "load_position_mm": load_position_mm,
        "snow_modulus_mpa": snow_modulus_mpa,
        "equivalent_modulus_mpa": case.modulus * 1e-6,
        "width_mm": case.width * 1e3,
        "points": case.n_points,
    }
    for name in _ZONES:
        doc[name] = zone_record(zones[name])
    # the grip-wax metric: contact between the kick-zone marks, whatever patch it belongs to
    doc["kick"] = zone_record(zones.kick)
    doc |= footprint_records(zones)
    doc["breitschaedel"] = {
        name: zone_record(zones.breitschaedel[name], pressures=False) for name in _ZONES
    }
    doc |= {
        "translation_um": sol.translation * 1e6,
        "rotation_rad": sol.rotation,
        "converged": sol.converged,
        "iterations": sol.iterations,
        "residual": sol.residual,
        "force_residual": sol.force_residual,
        "moment_residual": sol.moment_residual,
        "warnings": [*case.warnings, *([topology] if topology else [])],
        "uncertainty": uncertainty_doc(iv, note=no_uncertainty_note(case.ski, samples)),
    }
    if case.flexible is not None:
        doc["ski_penetration_um"] = case.flexible.penetration * 1e6
    if snow_obj is not None:
        from skisnow.snow import snow_record

        doc["snow"] = snow_record(snow_obj)
    if case.real is not None:
        summary = case.real_summary()
        doc["base"] = {"name": case.texture.name, "source": case.texture.source}
        doc["real"] = {name: s.as_dict() for name, s in summary.items()}
        doc["friction"] = case.real.friction_estimate()
    if json_out:
        emit_json(doc)
        return
    region_names = [n.replace("_", " ") for n in doc["regions"]]
    rows = [
        [
            name,
            doc[name]["length_mm"],
            doc[name]["area_cm2"],
            doc[name]["mean_pressure_kpa"],
            doc[name]["max_pressure_kpa"],
            doc[name]["load_share"],
            doc[name]["patches"],
            doc["breitschaedel"][name]["length_mm"],
        ]
        for name in _ZONES
    ]
    merged_note = " — merged footprint: zones = regions" if zones.merged else ""
    print_table(
        f"Apparent contact: {ski or profile}, {mass_kg:g} kg at {load_position_mm:g} mm from "
        f"the balance point, snow {snow_modulus_mpa:g} MPa ({model}, {case.route} route)"
        f"{merged_note}",
        [
            "zone",
            "length [mm]",
            "area [cm²]",
            "mean p [kPa]",
            "max p [kPa]",
            "load share",
            "patches",
            "Breitschädel [mm]",
        ],
        rows,
    )
    print_table(
        f"By region (fixed by the ski: {doc['region_rule']} at "
        f"{', '.join(f'{m:+.0f}' for m in doc['region_marks_mm'])} mm)",
        ["region", "contact [mm]", "area [cm²]", "load [N]", "load share", "mean p [kPa]",
         "max p [kPa]"],
        [[label, r["length_mm"], r["area_cm2"], r["load_n"], r["load_share"],
          r["mean_pressure_kpa"], r["max_pressure_kpa"]]
         for label, r in zip(region_names, doc["regions"].values(), strict=True)],
    )  # fmt: skip
    print_table(
        "By patch (every contiguous contact patch)",
        ["patch", "from [mm]", "to [mm]", "length [mm]", "load share", "max p [kPa]", "regions"],
        [[str(k), p["start_mm"], p["end_mm"], p["length_mm"], p["load_share"],
          p["max_pressure_kpa"], " + ".join(r.replace("_", " ") for r in p["regions"])]
         for k, p in enumerate(doc["patches"], start=1)],
    )  # fmt: skip
    if iv is not None:
        print_intervals(iv, f"Uncertainty of {ski}")
    else:
        console.print(doc["uncertainty"]["note"])
    status = "converged" if sol.converged else "NOT converged"
    console.print(
        f"δ = {doc['translation_um']:.2f} µm, θ = {sol.rotation:.3e} rad, {status} in "
        f"{sol.iterations} iterations (E' = {case.modulus * 1e-6:.1f} MPa)"
    )
    if snow_obj is not None:
        console.print(f"snow {snow_obj.describe()}")
    if case.real is not None:
        _print_real(case)


def real_rows(summary: dict[str, Any]) -> list[list[Any]]:
    """Rows of the side-by-side table: apparent and real contact per region and patch."""
    rows = []
    for name, s in summary.items():
        rows.append(
            [
                name.replace("_", " "),
                s.apparent_area * 1e4,
                s.load / s.apparent_area * 1e-3 if s.apparent_area > 0 else None,
                s.real_area * 1e6,
                s.real_area_grains * 1e6,
                100 * s.real_fraction,
                s.mean_separation * 1e6,
                s.reciprocal_separation,
                s.dry_force,
                s.viscous_force,
            ]
        )
    return rows


def _print_real(case: Any) -> None:
    """The real contact of a case beside its apparent contact, then µ with its assumptions."""
    r = case.real
    summary = case.real_summary()
    print_table(
        f"Apparent and real contact: base {r.base} × snow {r.snow} (regions fixed by the ski, "
        "then every contact patch)",
        [
            "region/patch",
            "apparent [cm²]",
            "mean p [kPa]",
            "real [mm²]",
            "real, grains [mm²]",
            "real [%]",
            "mean sep. [µm]",
            "∫1/u dA [m]",
            "τ·A_r [N]",
            "η·v·∫1/u [N]",
        ],
        real_rows(summary),
    )
    est = r.friction_estimate()
    console.print(
        f"µ = F/W ≈ {est['mu']:.3g} with a dry real contact (τ·A_r {est['dry_force_n']:.3g} N "
        f"+ viscous {est['viscous_force_n']:.3g} N over W = {est['load_n']:.4g} N), "
        f"≈ {est['mu_lubricated']:.3g} if the contact spots are sheared through the film"
    )
    console.print(f"assumptions: {est['assumptions']}")
    console.print(
        "note: the plastic real area is W·s/H whatever the camber (s: the texture's slope "
        "factor); the camber acts through the separation, its reciprocal and the elastic rims"
    )
