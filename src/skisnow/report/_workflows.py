"""Report sections of the technician workflows: a load cycle (the stride) and a fleet table.

They render results of :mod:`skisnow.workflows` (a cycle's Dataset from
:func:`~skisnow.workflows.run_cycle`, a :class:`~skisnow.workflows.FleetComparison`); they
compute nothing but the cycle's kick-contact summary.
"""

from __future__ import annotations

from typing import Any

from skisnow.report._html import Figure, Section, Table

__all__ = ["cycle_section", "fleet_section"]


def cycle_section(ds: Any) -> Section:
    """The contact over a load cycle: the figure over time and when the grip wax touches."""
    from skisnow.plot import plot_cycle
    from skisnow.workflows import kick_contact_summary

    s = kick_contact_summary(ds)
    a = ds.attrs
    rows: list[tuple[str, Any]] = [
        ("cycle", a["history"]),
        ("profile route", a["route"]),
        ("snow modulus [MPa]", a["snow_modulus"] * 1e-6),
        ("peak force on the ski [N]", float(ds["load"].max())),
        ("ski loaded [s]", s["loaded_time"]),
    ]
    kick = bool(a.get("kick_zone"))  # a skate has no kick zone: no grip-wax rows
    if kick:
        rows[4:4] = [("grip wax touches [s]", s["contact_time"])]
        rows += [
            ("first / last touch [s]", f"{s['first_touch']:.3g} / {s['last_touch']:.3g}"),
            ("touch-downs", s["episodes"]),
            ("largest load share between the kick marks [%]", 100 * s["max_kick_share"]),
        ]
    table = Table(["quantity", "value"], rows, floatfmt=".3g")
    notes = [
        f"Each of the {ds.sizes['time']} frames is one load case (Kalliorinne et al. 2023, "
        "§3.1: a stride followed as a sequence of load cases), solved warm-started from the "
        "previous frame. Load history: " + (a["history_source"] or a["history"]) + ".",
    ]
    if a.get("route_note"):
        notes.append(a["route_note"] + ".")
    caption = (
        "Load and centre of pressure, zone lengths, mean and peak pressures and load shares "
        "over the cycle" + ("; shaded: the grip wax touches the snow." if kick else ".")
    )
    return Section(
        f"Contact over a cycle: {a['history']}",
        tuple(notes),
        (table, Figure.of(plot_cycle(ds), caption)),
    )


def fleet_section(comparison: Any, *, criterion: str = "mean-pressure") -> Section:
    """The fleet side by side (metrics and contact at half and full body weight) and its
    ranking by ``criterion``."""
    from skisnow.plot import plot_fleet
    from skisnow.workflows import CRITERIA

    records = comparison.records()
    labels = [r["ski"] for r in records]
    rows: list[list[Any]] = []
    for key, label in (
        ("camber_half_mm", "camber at ½ BW [mm]"),
        ("closing_load_kg", "closing load [kg]"),
        ("stiffness_n_per_mm", "stiffness [N/mm]"),
    ):
        rows.append([label, *[r[key] for r in records]])
    # the kick-zone rows only when a ski of the fleet has a kick zone (a skate ski's: "—")
    kick = any(r["full_kick_contact"] is not None for r in records)
    zones = ("rear", "front", "kick", "total") if kick else ("rear", "front", "total")
    per_load = [(f"{z}_length_mm", f"{z} length [mm]") for z in zones]
    per_load += [
        ("total_mean_pressure_kpa", "mean p [kPa]"),
        ("total_peak_pressure_kpa", "peak p [kPa]"),
        ("rear_load_share", "rear load share"),
    ]
    if kick:
        per_load.append(("kick_load_share", "kick-zone load share"))
    for load, tag in (("half", "½ BW"), ("full", "1 BW")):
        for key, label in per_load:
            rows.append([f"{tag} {label}", *[r[f"{load}_{key}"] for r in records]])
    crit = CRITERIA[criterion]
    ranking = comparison.ranking(criterion)

    def interval(r: dict[str, Any]) -> str:
        iv = r["interval"]
        return "no uncertainty recorded" if iv is None else f"{iv[0]:.4g} – {iv[1]:.4g}"

    rank_table = Table(
        ["rank", "ski", f"{crit.column} ({crit.better} is better)", "95 % interval"],
        [(f"{r['rank']}=" if r["tied"] else r["rank"], r["ski"], r[crit.column], interval(r))
         for r in ranking],
        floatfmt=".4g",
    )  # fmt: skip
    notes = (
        f"Body mass {comparison.body_mass:g} kg, load at {comparison.load_position * 1e3:g} mm "
        "from the balance point "
        f"on {comparison.snow_modulus * 1e-6:g} MPa snow ({comparison.ski_model} ski). Ranking "
        f"criterion: {crit.description}. n= : a tie (equal values, or for identified skis "
        "overlapping 95 % intervals: a tie within uncertainty).",
    )
    figure = Figure.of(
        plot_fleet(comparison),
        "Loaded profiles and pressures of the fleet, full body weight solid, half dashed.",
    )
    return Section(
        "The fleet side by side",
        notes,
        (Table(["quantity", *labels], rows, floatfmt=".4g"), rank_table, figure),
    )
