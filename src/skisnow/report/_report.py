"""The HTML report of one ski: practitioner metrics, zones at standard loads, maps.

One self-contained file (inline CSS and SVG, no scripts, no external resources) that a service
technician can mail or open offline. It renders a :class:`skisnow.report.SkiStudy` and
computes nothing:

1. the ski and the practitioner metrics of the virtual bench (camber height, wax pocket,
   closing load, stiffness, Breitschädel contact lengths);
2. the apparent contact at the standard loads — half and full body weight at the load position,
   on several snows — per zone (length, mean and max pressure, load share, patches), with the
   contact pictures (Kalliorinne et al. 2023, Figures 5–7 style);
3. the maps over load and snow (Figures 8–9 style: area and mean pressure of the rear and front
   zones versus mass, one line per snow modulus, Breitschädel line) and the load partitioning.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from skisnow.report._html import Figure, Link, Section, Table, render_page


def _metrics_section(study: Any) -> Section:
    s = study.ski
    doc = study.metrics.as_field_units()
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
            f"Virtual bench of the ski '{s.name}' (beam model), skier body mass "
            f"{study.body_mass:g} kg, load at {study.load_position * 1e3:g} mm from the balance "
            "point. Half/full: "
            "half and full body weight on the ski.",
        ),
        (info, Table(["metric", "value"], rows, floatfmt=".4g")),
    )


def _standard_loads(study: Any) -> Section:
    rows = []
    for case in study.cases:
        label = "half" if case.mass < study.body_mass else "full"
        merged = " (merged: = region)" if case.zones.merged else ""
        for zname in ("rear", "middle", "front", *case.zones.footprint.names):
            z = case.zones[zname]
            if z.patches == 0 and zname in ("rear", "middle", "front"):
                continue
            region = zname not in ("rear", "middle", "front")
            rows.append(
                (
                    f"{label} ({case.mass:g} kg)",
                    case.snow_modulus / 1e6,
                    (zname.replace("_", " ") + " (region)") if region else zname + merged,
                    z.length * 1e3,
                    z.area * 1e4,
                    z.mean_pressure / 1e3,
                    z.max_pressure / 1e3,
                    z.load_share * 100,
                    z.patches,
                    "yes" if case.converged else "NO",
                )
            )
    table = Table(
        [
            "load", "snow modulus [MPa]", "zone / region", "contact [mm]", "area [cm²]",
            "mean p [kPa]", "max p [kPa]", "load share [%]", "patches", "converged",
        ],
        rows,
        floatfmt=".3g",
    )  # fmt: skip
    first = study.cases[0]
    iv_text, iv_items = _uncertainty(study)
    return Section(
        "Contact at the standard loads",
        (
            (
                f"Loaded profile from the {study.profile_source}, pressed as a rigid body; "
                if getattr(study, "ski_model", "rigid") == "rigid"
                else "Flexible ski: the beam (EI(x), z0(x)) bending on the snow, solved with it; "
            )
            + "contact on elastic snow with force "
            "and moment balance (Kalliorinne et al. 2023, eq. 2–3), equivalent modulus E' of the "
            f"ski base and the snow (eq. 2), {first.model} model, {study.n_points} stations "
            "along the ski. Zones are the paper's (whole contact patches); once the patches "
            "merge across the kick zone they are the regions and say so. Regions are fixed by "
            "the ski (rear glide: tail to the rear kick-zone mark; kick zone; front glide; "
            "without a kick zone, rear and front of the balance point) and never jump.",
            iv_text,
        ),
        (table, *iv_items, *_contact_figures(study)),
    )


def _uncertainty(study: Any) -> tuple[str, tuple[Table, ...]]:
    """The 95 % intervals of the standard cases of an identified ski, or a line saying that the
    ski carries no uncertainty (its numbers are the ski as given, not exact)."""
    if not study.intervals:
        s = study.ski
        from skisnow.ski import uncertainty_note

        why = ("intervals not computed (no posterior samples asked for)" if s.has_posterior
               else uncertainty_note(s))  # fmt: skip
        return why, ()
    rows = []
    for case, iv in zip(study.cases, study.intervals, strict=True):
        label = "half" if case.mass < study.body_mass else "full"
        for zone in ("rear", "middle", "front", "total", "kick"):

            def rng(q: str, f: float, iv=iv, zone=zone) -> str:
                lo, hi = iv.interval(f"{zone}.{q}")
                return "—" if np.isnan(lo) else f"{lo * f:.3g} – {hi * f:.3g}"

            rows.append((f"{label} ({case.mass:g} kg)", case.snow_modulus / 1e6, zone,
                         rng("length", 1e3), rng("area", 1e4), rng("mean_pressure", 1e-3),
                         rng("max_pressure", 1e-3), rng("load_share", 100.0)))  # fmt: skip
    first = study.intervals[0]
    worst = max(iv.worst_mc_error() for iv in study.intervals)
    note = (
        f"95 % intervals of the answers above from {first.samples} samples of the identified "
        "ski's posterior (Laplace posterior of log EI and z0 in its file), each solved as the "
        "case; an interval is the samples' 2.5–97.5 % quantiles, extended to hold the estimate. "
        f"Monte Carlo error of the ends ≤ {100 * worst:.0f} % of the width."
    )
    table = Table(
        ["load", "snow modulus [MPa]", "zone", "contact [mm]", "area [cm²]", "mean p [kPa]",
         "max p [kPa]", "load share [%]"],
        rows,
        floatfmt=".3g",
    )  # fmt: skip
    return note, (table,)


def _rigid_vs_flexible(study: Any) -> Section | None:
    """The standard loads by both ski models, side by side (rigid − flexible differences)."""
    if not study.other_cases:
        return None
    by_model = {study.ski_model: study.cases, ("flexible" if study.ski_model == "rigid"
                else "rigid"): study.other_cases}  # fmt: skip
    rows = []
    for rigid, flex in zip(by_model["rigid"], by_model["flexible"], strict=True):
        label = "half" if rigid.mass < study.body_mass else "full"
        for zname in ("total", "kick"):
            zr, zf = rigid.zones[zname], flex.zones[zname]
            if zr.patches == 0 and zf.patches == 0:
                continue
            rows.append((
                f"{label} ({rigid.mass:g} kg)", rigid.snow_modulus / 1e6, zname,
                zr.length * 1e3, zf.length * 1e3, zr.mean_pressure / 1e3, zf.mean_pressure / 1e3,
                zr.max_pressure / 1e3, zf.max_pressure / 1e3, zr.load_share * 100,
                zf.load_share * 100, zr.penetration * 1e6, zf.penetration * 1e6,
            ))  # fmt: skip
    table = Table(
        ["load", "snow E [MPa]", "zone", "length rigid [mm]", "length flexible [mm]",
         "mean p rigid [kPa]", "mean p flexible [kPa]", "max p rigid [kPa]",
         "max p flexible [kPa]", "share rigid [%]", "share flexible [%]",
         "penetration rigid [µm]", "penetration flexible [µm]"],
        rows,
        floatfmt=".3g",
    )  # fmt: skip
    return Section(
        "The rigid-profile method against the flexible ski",
        (
            "Rigid: the loaded profile measured on the stone, pressed into the snow as a rigid "
            "body (Kalliorinne et al. 2023); flexible: the beam (EI(x), z0(x)) and the snow "
            "solved together. 'kick' is the contact between the kick-zone marks (where the grip "
            "wax touches). Where the two differ, the paper's method is approximate (its §3.2).",
        ),
        (table,),
    )


def _contact_figures(study: Any) -> list[Figure]:
    """Contact pictures (profile, pressure, deformed snow) at half and full body weight on the
    median snow of the table."""
    from skisnow.plot import plot_contact

    snows = sorted({c.snow_modulus for c in study.cases})
    e_pick = snows[(len(snows) - 1) // 2]
    figures = []
    for case in study.cases:
        if case.snow_modulus != e_pick:
            continue
        m, e = case.mass, case.snow_modulus
        fig = plot_contact(
            case.solution,
            case.zones,
            title=f"{case.label}: {m:g} kg at {case.load_position * 1e3:g} mm from the balance "
            f"point, snow modulus {e / 1e6:g} MPa",
        )
        figures.append(Figure.of(fig, f"{case.label} ski, {m:g} kg, snow {e / 1e6:g} MPa."))
    return figures


#: Captions of the maps, by kind of :func:`skisnow.plot.sweep_figures`.
_MAP_CAPTIONS = {
    "area": "Apparent contact area of the rear and front zones versus load, one line per snow "
    "modulus; thick black: Breitschädel (50 µm above the plane the ski rests on) estimate "
    "(cf. paper Figure 8).",
    "mean_pressure": "Mean apparent pressure of the rear and front zones versus load "
    "(cf. paper Figure 9).",
    "load_share": "How the load is shared between the zones.",
}


def _maps_section(study: Any) -> Section:
    from skisnow.plot import sweep_figures

    ds, ski = study.maps, study.ski.name
    positions = ds["load_position_mm"].values
    pos_mm = float(positions[np.argmin(np.abs(positions - study.load_position * 1e3))])
    if ds.sizes["mass_kg"] < 2:  # a curve over the load of one point: empty axes
        return Section("Maps over load and snow", (
            f"The maps run over the load: one mass ({float(ds['mass_kg'].values[0]):g} kg) "
            "draws none; give --mass-kg two masses or more (default 5:130:5).",), ())  # fmt: skip
    figures = sweep_figures(ds, skis=[ski], load_positions_mm=[pos_mm], kinds=tuple(_MAP_CAPTIONS))
    items = [
        Figure.of(fig, _MAP_CAPTIONS[kind])
        for kind, fig in zip(_MAP_CAPTIONS, figures.values(), strict=True)
    ]
    n_bad = int((~ds["converged"].sel(ski=ski).values).sum())
    note = (
        f"Sweep of {ds.sizes['mass_kg']} masses × {ds.sizes['snow_modulus_mpa']} snow moduli at "
        f"the load at {pos_mm:g} mm from the balance point ({ds.attrs.get('profile_source', '?')} "
        "route, "
        f"{ds.attrs.get('ski_model', 'rigid')} ski); "
        f"{n_bad} points without a converged solution (drawn as gaps)."
    )
    return Section("Maps over load and snow", (note,), items)


def _explorer_section(explorer: str) -> Section:
    return Section(
        "Interactive explorer",
        (
            "Move the mass, the load position and the snow modulus and watch the contact: the "
            "ski base and the deformed snow, the pressure with its zones, the zone table and the "
            "maps with the current point marked. One self-contained page beside this report "
            "(no server, no network).",
        ),
        (Link(explorer, f"Open the explorer ({explorer})"),),
    )


def build_report(
    study: Any,
    *,
    cycles: Sequence[Any] = (),
    fleet: Any = None,
    explorer: str | None = None,
    real_cases: Sequence[Any] = (),
) -> str:
    """The report of a :class:`skisnow.report.SkiStudy` as an HTML string.

    ``cycles``: load cycles of the ski (:func:`skisnow.workflows.run_cycle` Datasets, e.g. the
    stride at the athlete's weight); ``fleet``: a :class:`skisnow.workflows.FleetComparison`
    when several skis are compared; ``explorer``: the file name of an explorer page
    (:mod:`skisnow.explore`) beside the report, linked; ``real_cases``: cases solved with a
    textured base and a snow (:attr:`skisnow.pipeline.Case.real`), the real contact. Each adds
    its section.
    """
    from skisnow import __version__
    from skisnow.report._passport import passport_section
    from skisnow.report._workflows import cycle_section, fleet_section

    name = study.ski.name
    sections = [_metrics_section(study), passport_section(study.ski), _standard_loads(study)]
    comparison = _rigid_vs_flexible(study)
    sections += [comparison] if comparison is not None else []
    sections.append(_maps_section(study))
    if real_cases:
        from skisnow.report._multiscale import real_contact_section

        sections.append(real_contact_section(real_cases))
    sections += [cycle_section(ds) for ds in cycles]
    if fleet is not None:
        sections.append(fleet_section(fleet))
    if explorer is not None:
        sections.append(_explorer_section(explorer))
    return render_page(
        f"skisnow report: {name} ski",
        f"How the {name} ski meets the snow — body mass {study.body_mass:g} kg, load at "
        f"{study.load_position * 1e3:g} mm from the balance point",
        sections,
        footer=f"skisnow {__version__}. Method: Kalliorinne et al., Lubricants 11 (2023) "
        "(camber under load, half-space contact with force and moment balance, zones, "
        "Breitschädel criterion). Self-contained page: no scripts, no external resources.",
    )


def write_report(
    study: Any,
    out_dir: str | Path,
    *,
    cycles: Sequence[Any] = (),
    fleet: Any = None,
    explorer: str | None = None,
    real_cases: Sequence[Any] = (),
) -> Path:
    """Write ``{out_dir}/{ski}_report.html`` of a :class:`skisnow.report.SkiStudy` (with the
    optional ``cycles`` and ``fleet`` sections of :func:`build_report`); return its path."""
    from skisnow._atomic import atomic_write
    from skisnow._names import file_stem

    # a ski's name is a label, never a path: sanitised, the page stays inside out_dir
    path = Path(out_dir) / f"{file_stem(study.ski.name)}_report.html"
    return atomic_write(
        path,
        build_report(study, cycles=cycles, fleet=fleet, explorer=explorer, real_cases=real_cases),
    )  # a killed run leaves no half page
