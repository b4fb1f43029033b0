"""The HTML report of one ski: practitioner metrics, zones at standard loads, maps.

One self-contained file (inline CSS and SVG, no scripts, no external resources) that a service
technician can mail or open offline. Contents:

1. the ski and the practitioner metrics of the virtual bench (``skisnow.ski.ski_metrics``: camber
   height, wax pocket, closing load, stiffness, Breitschädel contact lengths);
2. the apparent contact at the standard loads — half and full body weight at the load position,
   on several snows — per zone (length, mean and max pressure, load share, patches), with the
   contact pictures (Kalliorinne et al. 2023, Figures 5–7 style);
3. the maps over load and snow (Figures 8–9 style: area and mean pressure of the rear and front
   zones versus mass, one line per snow modulus, Breitschädel line) and the load partitioning,
   from a sweep (run here into a resumable Zarr store, or given).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from skisnow.report._html import Figure, Section, Table, render_page

#: Snows of the standard-load table [Pa]: soft new snow to hard old machine-made snow (§3.2:
#: 50–350 MPa for machine-made snow after Lintzén & Edeskär).
STANDARD_SNOWS: tuple[float, ...] = (50e6, 100e6, 200e6, 400e6)
#: Default grid of the report's maps.
MAP_MASSES: tuple[float, ...] = tuple(float(m) for m in range(5, 131, 5))
MAP_MODULI: tuple[float, ...] = tuple(float(e) * 1e6 for e in range(20, 401, 40))


def _metrics_section(ski: str, body_mass: float, load_position: float) -> Section:
    from skisnow.ski import get_ski, ski_metrics

    s = get_ski(ski)
    doc = ski_metrics(ski, body_mass=body_mass, load_position=load_position).as_field_units()
    rows = [(k, v) for k, v in doc.items() if k not in ("ski",)]
    info = Table(
        ["property", "value"],
        [
            ("kind", s.kind),
            ("running length [mm]", (s.x_tip - s.x_tail) * 1e3),
            ("width [mm]", s.width * 1e3),
            ("tail / tip from balance point [mm]", f"{s.x_tail * 1e3:g} / {s.x_tip * 1e3:g}"),
            (
                "kick zone [mm]",
                "—"
                if s.kick_zone is None
                else f"{s.kick_zone[0] * 1e3:g} … {s.kick_zone[1] * 1e3:g}",
            ),
        ],
        floatfmt=".4g",
    )
    return Section(
        "The ski and its practitioner metrics",
        (
            f"Virtual bench of the shipped ski '{ski}' (beam model), skier body mass "
            f"{body_mass:g} kg, load at x_m = {load_position * 1e3:g} mm. Half/full: half and "
            "full body weight on the ski.",
        ),
        (info, Table(["metric", "value"], rows, floatfmt=".4g")),
    )


def _standard_loads(
    ski: str,
    *,
    body_mass: float,
    load_position: float,
    snows: Sequence[float],
    profile_source: str,
    n_points: int,
) -> tuple[Section, list[tuple[float, float, Any, Any]]]:
    from skisnow.pipeline import solve_case

    masses = (body_mass / 2, body_mass)
    rows = []
    solutions = []
    for m, label in zip(masses, ("half", "full"), strict=True):
        for e in sorted(float(v) for v in snows):
            case = solve_case(
                ski, mass=m, load_position=load_position, snow_modulus=e,
                profile_source=profile_source, n_points=n_points,
            )  # fmt: skip
            solution, zones = case.solution, case.zones
            solutions.append((m, e, solution, zones))
            for zname in ("rear", "middle", "front"):
                z = zones[zname]
                if z.patches == 0:
                    continue
                rows.append(
                    (
                        f"{label} ({m:g} kg)",
                        e / 1e6,
                        zname,
                        z.length * 1e3,
                        z.area * 1e4,
                        z.mean_pressure / 1e3,
                        z.max_pressure / 1e3,
                        z.load_share * 100,
                        z.patches,
                        "yes" if solution.converged else "NO",
                    )
                )
    table = Table(
        [
            "load",
            "snow E [MPa]",
            "zone",
            "length [mm]",
            "area [cm²]",
            "mean p [kPa]",
            "max p [kPa]",
            "load share [%]",
            "patches",
            "converged",
        ],
        rows,
        floatfmt=".3g",
    )
    section = Section(
        "Contact at the standard loads",
        (
            f"Loaded profile from the {profile_source}; contact on elastic snow with force and "
            "moment balance (Kalliorinne et al. 2023, eq. 2–3), ski base 900 MPa, ν = 0.3, "
            f"strip model, {n_points} stations along the ski.",
        ),
        (table,),
    )
    return section, solutions


def _contact_figures(ski: str, solutions: list[tuple[float, float, Any, Any]]) -> list[Figure]:
    """Contact pictures (profile, pressure, deformed snow) at the standard loads, if the contact
    area's plotting module is available."""
    try:
        from skisnow.plot._contact import plot_contact  # the contact engineer's pictures
    except ImportError:
        return []
    from skisnow.plot._style import figure_svg

    figures = []
    # half and full body weight on the median snow of the table
    snows = sorted({e for _, e, _, _ in solutions})
    e_pick = snows[(len(snows) - 1) // 2]
    pick = {(m, e) for m, e, _, _ in solutions if e == e_pick}
    for m, e, sol, zones in solutions:
        if (m, e) not in pick:
            continue
        fig = plot_contact(sol, zones, title=f"{ski}: m = {m:g} kg, E_counter = {e / 1e6:g} MPa")
        figures.append(Figure(figure_svg(fig), f"{ski} ski, {m:g} kg, snow {e / 1e6:g} MPa."))
    return figures


def _maps_section(ds: Any, ski: str, load_position: float) -> Section:
    from skisnow.plot._maps import plot_load_share, plot_zone_map
    from skisnow.plot._style import figure_svg

    pos_mm = float(
        ds["load_position_mm"].values[np.argmin(np.abs(ds["load_position_mm"].values
                                                      - load_position * 1e3))]
    )  # fmt: skip
    items = []
    for variable, caption in (
        ("area_cm2", "Apparent contact area of the rear and front zones versus load, one line per "
         "snow modulus; thick black: Breitschädel (h < 50 µm) estimate (cf. paper Figure 8)."),
        ("mean_pressure_kpa", "Mean apparent pressure of the rear and front zones versus load "
         "(cf. paper Figure 9)."),
    ):  # fmt: skip
        fig = plot_zone_map(ds, variable=variable, ski=ski, load_position_mm=pos_mm)
        items.append(Figure(figure_svg(fig), caption))
    fig = plot_load_share(ds, ski=ski, load_position_mm=pos_mm)
    items.append(Figure(figure_svg(fig), "How the load is shared between the zones."))
    n_bad = int((~ds["converged"].sel(ski=ski).values).sum())
    note = (
        f"Sweep of {ds.sizes['mass_kg']} masses × {ds.sizes['snow_modulus_mpa']} snow moduli at "
        f"x_m = {pos_mm:g} mm ({ds.attrs.get('profile_source', '?')} profiles); "
        f"{n_bad} points without a converged solution (drawn as gaps)."
    )
    return Section("Maps over load and snow", (note,), items)


def build_report(
    ski: str,
    *,
    dataset: Any,
    body_mass: float = 60.0,
    load_position: float = -0.12,
    snows: Sequence[float] = STANDARD_SNOWS,
    profile_source: str = "network",
    n_points: int = 4096,
) -> str:
    """The report of ``ski`` as an HTML string; ``dataset`` is a sweep (``open_sweep``) that
    contains the ski."""
    from skisnow import __version__

    sections = [_metrics_section(ski, body_mass, load_position)]
    loads, solutions = _standard_loads(
        ski,
        body_mass=body_mass,
        load_position=load_position,
        snows=snows,
        profile_source=profile_source,
        n_points=n_points,
    )
    figures = _contact_figures(ski, solutions)
    if figures:
        loads = Section(loads.title, loads.paragraphs, (*loads.items, *figures))
    sections.append(loads)
    sections.append(_maps_section(dataset, ski, load_position))
    return render_page(
        f"skisnow report: {ski} ski",
        f"How the {ski} ski meets the snow — body mass {body_mass:g} kg, load at "
        f"{load_position * 1e3:g} mm from the balance point",
        sections,
        footer=f"skisnow {__version__}. Method: Kalliorinne et al., Lubricants 11 (2023) "
        "(camber under load, half-space contact with force and moment balance, zones, "
        "Breitschädel criterion). Self-contained page: no scripts, no external resources.",
    )


def write_report(
    ski: str,
    *,
    out_dir: str | Path,
    body_mass: float = 60.0,
    load_position: float = -0.12,
    snows: Sequence[float] = STANDARD_SNOWS,
    dataset: Any = None,
    masses: Sequence[float] = MAP_MASSES,
    map_moduli: Sequence[float] = MAP_MODULI,
    profile_source: str = "network",
    n_points: int = 4096,
    workers: int | None = 0,
    scheduler: str | None = None,
) -> Path:
    """Write ``{out_dir}/{ski}_report.html`` and return its path.

    Without ``dataset`` the maps' sweep (``masses`` × ``map_moduli`` at ``load_position``) is run
    into ``{out_dir}/{ski}_maps_{profile_source}.zarr`` — resumable, and reused by the next
    report of the same ski.
    """
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    if dataset is None:
        spec = SweepSpec(
            skis=(ski,),
            masses=tuple(masses),
            load_positions=(load_position,),
            snow_moduli=tuple(map_moduli),
            profile_source=profile_source,
            n_points=n_points,
        )
        store = out_dir / f"{ski}_maps_{profile_source}.zarr"
        run_sweep(spec, store, workers=workers, scheduler=scheduler)
        dataset = open_sweep(store)
    text = build_report(
        ski,
        dataset=dataset,
        body_mass=body_mass,
        load_position=load_position,
        snows=snows,
        profile_source=profile_source,
        n_points=n_points,
    )
    path = out_dir / f"{ski}_report.html"
    path.write_text(text, encoding="utf-8")
    return path
