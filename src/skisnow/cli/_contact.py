"""Commands for the apparent contact: contact (thin: parse, call skisnow.contact, render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from skisnow._errors import InputError
from skisnow.cli._app import app
from skisnow.cli._render import console, emit_json, print_table
from skisnow.constants import STANDARD_GRAVITY
from skisnow.materials import BASE

__all__ = ["zone_record"]

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


@app.command()
def contact(
    ski: Annotated[
        str | None, typer.Option("--ski", help="Shipped ski name (classic, skate).")
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
        float, typer.Option("--snow-modulus-mpa", help="Elastic modulus of the snow in MPa.")
    ] = ...,  # type: ignore[assignment]
    model: Annotated[
        str, typer.Option("--model", help="strip (1D, fast) or surface (2D grid across).")
    ] = "strip",
    width_mm: Annotated[float, typer.Option("--width-mm", help="Ski width in mm.")] = 44.0,
    profile_source: Annotated[
        str,
        typer.Option(
            "--profile-source",
            help="With --ski: network (shipped pretrained, default) or beam (virtual ski).",
        ),
    ] = "network",
    base_modulus_mpa: Annotated[
        float, typer.Option("--base-modulus-mpa", help="Ski base modulus in MPa (eq. 2).")
    ] = BASE.modulus / 1e6,
    points: Annotated[
        int, typer.Option("--points", help="Stations along the ski (with --ski).")
    ] = 2048,
    n_across: Annotated[
        int, typer.Option("--n-across", help="Cells across the width (surface model).")
    ] = 16,
    json_out: Annotated[
        bool, typer.Option("--json", help="Print one JSON document to stdout, nothing else.")
    ] = False,
    figure: Annotated[
        Path | None, typer.Option("--figure", help="Save a figure (png/svg/pdf by suffix).")
    ] = None,
    fields_out: Annotated[
        Path | None,
        typer.Option(
            "--fields-out", help="Write x_mm,pressure_kpa,gap_um,snow_displacement_um (CSV)."
        ),
    ] = None,
) -> None:
    """Apparent contact of a loaded ski with elastic snow: force and moment balance (eq. 2–3)."""
    from skisnow.contact import (
        contact_zones,
        effective_modulus,
        snow,
        solve_contact,
    )
    from skisnow.contact._io import read_profile, write_fields

    if (ski is None) == (profile is None):
        raise InputError("give exactly one of --ski NAME or --profile FILE")
    if model not in ("strip", "surface"):
        raise InputError(f"--model must be strip or surface, got {model!r}")
    if profile_source not in ("beam", "network"):
        raise InputError(f"--profile-source must be beam or network, got {profile_source!r}")
    for name, value in (
        ("--mass-kg", mass_kg),
        ("--snow-modulus-mpa", snow_modulus_mpa),
        ("--width-mm", width_mm),
        ("--base-modulus-mpa", base_modulus_mpa),
    ):
        if not np.isfinite(value) or value <= 0:
            raise InputError(f"{name} must be a positive number, got {value:g}")
    if points < 16:
        raise InputError(f"--points must be at least 16, got {points}")
    xm = load_position_mm * 1e-3
    kick_zone = None
    if ski is not None:
        from skisnow.ski import camber_profile, get_ski

        ski_obj = get_ski(ski)
        kick_zone = ski_obj.kick_zone
        edges = np.linspace(ski_obj.x_tail, ski_obj.x_tip, points + 1)
        x, h = camber_profile(
            ski,
            mass=mass_kg,
            load_position=xm,
            x=0.5 * (edges[1:] + edges[:-1]),
            source=profile_source,  # type: ignore[arg-type]
        )
    else:
        assert profile is not None
        x, h = read_profile(profile)
    e_prime = effective_modulus(snow(snow_modulus_mpa * 1e6), base_modulus_mpa * 1e6)
    sol = solve_contact(
        x,
        h,
        load=mass_kg * STANDARD_GRAVITY,
        load_position=xm,
        modulus=e_prime,
        model=model,  # type: ignore[arg-type]
        width=width_mm * 1e-3,
        n_across=n_across,
    )
    zones = contact_zones(sol, kick_zone=kick_zone)
    if fields_out is not None:
        write_fields(sol, fields_out)
    if figure is not None:
        from skisnow.plot._contact import plot_contact

        label = ski if ski is not None else Path(str(profile)).name
        fig = plot_contact(
            sol,
            zones,
            title=f"{label}: {mass_kg:g} kg at x_m = {load_position_mm:g} mm, "
            f"snow {snow_modulus_mpa:g} MPa",
        )
        figure.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(figure)

    doc: dict[str, Any] = {
        "ski": ski,
        "profile": None if profile is None else str(profile),
        "profile_source": profile_source if ski is not None else None,
        "model": model,
        "mass_kg": mass_kg,
        "load_position_mm": load_position_mm,
        "snow_modulus_mpa": snow_modulus_mpa,
        "equivalent_modulus_mpa": e_prime * 1e-6,
        "width_mm": width_mm,
        "points": int(x.size),
    }
    for name in _ZONES:
        doc[name] = zone_record(zones[name])
    # the grip-wax metric: contact between the kick-zone marks, whatever patch it belongs to
    doc["kick"] = zone_record(zones.kick)
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
    }
    if json_out:
        emit_json(doc)
        return
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
    print_table(
        f"Apparent contact: {ski or profile}, {mass_kg:g} kg at {load_position_mm:g} mm, "
        f"snow {snow_modulus_mpa:g} MPa ({model})",
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
    status = "converged" if sol.converged else "NOT converged"
    console.print(
        f"δ = {doc['translation_um']:.2f} µm, θ = {sol.rotation:.3e} rad, {status} in "
        f"{sol.iterations} iterations (E' = {e_prime * 1e-6:.1f} MPa)"
    )
