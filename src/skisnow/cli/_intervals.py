"""The intervals of an identified ski's answers at the CLI: the ``--samples`` option, the JSON
section ``uncertainty`` and the table (thin: :func:`skisnow.pipeline.case_intervals` computes).
"""

from __future__ import annotations

from typing import Annotated, Any

import typer

from skisnow._errors import InputError
from skisnow._names import printable
from skisnow.pipeline import DEFAULT_SAMPLES, INTERVAL_ZONES

GLIDE_NOTE = (
    "values within 1.1 % of each other tie: the relative variation of glide measured by a "
    "skitester on snow, 0.6-1.1 % (Lemmettylä et al. 2021), the worse end; a smaller predicted "
    "difference no glide test could confirm"
)

__all__ = [
    "GLIDE_NOTE",
    "UNIT_KEYS",
    "SamplesOption",
    "check_samples",
    "cycle_uncertainty_doc",
    "fleet_intervals",
    "interval_text",
    "no_uncertainty_note",
    "print_cycle_uncertainty",
    "print_fleet_uncertainty",
    "print_intervals",
    "tie_test_doc",
    "uncertainty_doc",
]

SamplesOption = Annotated[
    int,
    typer.Option(
        "--samples",
        help="Posterior samples of an identified ski for the 95 % intervals of the answers "
        f"(default {DEFAULT_SAMPLES}: Monte Carlo error of the ends ~7.5 % of the width; 0: "
        "no intervals). A ski without bands has none.",
    ),
]

#: quantity of :data:`skisnow.pipeline.ZONE_QUANTITIES` -> (key in field units, factor from SI)
UNIT_KEYS: dict[str, tuple[str, float]] = {
    "length": ("length_mm", 1e3),
    "area": ("area_cm2", 1e4),
    "mean_pressure": ("mean_pressure_kpa", 1e-3),
    "max_pressure": ("max_pressure_kpa", 1e-3),
    "load_share": ("load_share", 1.0),
}

WHY_ENOUGH = (
    "the ends of each interval are sample quantiles; their Monte Carlo standard error "
    "(bootstrap) is given as a fraction of the interval's width; at the default 200 samples the "
    "ends move by about 7.5 % (worst 10 %) of the width from seed to seed on an identified "
    "classic (benchmarks/bench_interval_samples.py), small beside the width itself; raise "
    "--samples to shrink it as 1/sqrt(samples)"
)


def check_samples(samples: int) -> None:
    """``--samples`` is 0 (no intervals) or at least 2 (an interval needs two samples)."""
    if samples == 1:
        raise InputError("--samples: give 0 (no intervals) or at least 2 posterior samples, got 1")


def no_uncertainty_note(ski: Any, samples: int) -> str:
    """Why an answer carries no interval (said, never implied by a bare number)."""
    if ski is None:
        return "no uncertainty recorded: a given profile carries no bands"
    if ski.has_posterior and samples == 0:
        return "intervals not computed (--samples 0); the ski carries its posterior"
    from skisnow.ski import uncertainty_note

    return uncertainty_note(ski) + " (in a ranking its values count as exact)"


def uncertainty_doc(iv: Any, *, note: str | None = None, zones=INTERVAL_ZONES) -> dict[str, Any]:
    """The ``uncertainty`` section of a JSON document, field units (``note`` when ``iv`` is
    ``None``: why there is none)."""
    if iv is None:
        return {"recorded": False, "note": note or "no uncertainty recorded"}
    out: dict[str, Any] = {
        "recorded": True,
        "method": "posterior samples of the identified ski (the posterior's modes in its file: "
        "the Laplace posterior's, and the bootstrap replicates' when identified with "
        "--bootstrap; its bands detail says which), each solved as the case; interval = "
        "sample quantiles, extended to hold the estimate",
        "level": iv.level,
        "samples": iv.samples,
        "seed": iv.seed,
        "failed_samples": iv.failed,
        "unconverged_samples": iv.unconverged,
        "mc_error_of_ends_max_fraction_of_width": iv.worst_mc_error(),
        "why_enough": WHY_ENOUGH,
        "intervals": {},
    }
    if iv.sample_topologies:
        from skisnow.pipeline import topology_text

        out["patch_topology"] = {
            "estimate": topology_text(iv.topology),
            "sample_shares": iv.topology_shares(),
            "warning": iv.topology_note(),
        }
    for zone in zones:
        rec = {}
        for q, (key, f) in UNIT_KEYS.items():
            name = f"{zone}.{q}"
            if name in iv.low:
                rec[key] = [iv.low[name] * f, iv.high[name] * f]
        out["intervals"][zone] = rec
    return out


def interval_text(low: float, high: float, fmt: str = ".3g") -> str:
    """``'low – high'`` (``'—'`` when undefined)."""
    if low != low or high != high:  # NaN: undefined (no contact in the zone)
        return "—"
    return f"{low:{fmt}} – {high:{fmt}}"


def print_intervals(iv: Any, title: str, *, zones=INTERVAL_ZONES) -> None:
    """One table: a row per zone, the 95 % interval of each answer (field units)."""
    from skisnow.cli._render import console, print_table

    rows = []
    for zone in zones:
        row = [zone]
        for q, (_, f) in UNIT_KEYS.items():
            row.append(interval_text(iv.low[f"{zone}.{q}"] * f, iv.high[f"{zone}.{q}"] * f))
        rows.append(row)
    print_table(
        f"{printable(title)}: {100 * iv.level:g} % intervals from {iv.samples} posterior samples",
        ["zone", "length [mm]", "area [cm²]", "mean p [kPa]", "max p [kPa]", "load share"],
        rows,
    )
    console.print(
        f"Monte Carlo error of the interval ends ≤ {100 * iv.worst_mc_error():.0f} % of the "
        f"width; {iv.failed} sample(s) could not carry the load, {iv.unconverged} unconverged"
    )


def fleet_intervals(cmp: Any, samples: int) -> list[dict[str, Any]]:
    """One record per ski of a comparison: the 95 % intervals of its contact columns (field
    units, ``<column>_low``/``_high``; NaN and a note for a ski without bands)."""
    from skisnow.cli._fleet_table import ZONE_ROWS
    from skisnow.workflows import interval_records

    columns = [
        f"{load}_{zone}_{q}"
        for load in ("half", "full")
        for zone in ZONE_ROWS
        if zone in INTERVAL_ZONES
        for q in ("length_mm", "area_cm2", "mean_pressure_kpa", "peak_pressure_kpa",
                  "load_share")
    ]  # fmt: skip
    notes = [no_uncertainty_note(e.ski.ski, samples) for e in cmp.entries]
    return interval_records(cmp.entries, columns, notes=notes)


def print_fleet_uncertainty(
    ranking: list[dict[str, Any]], column: str, records: list[dict[str, Any]]
) -> None:
    """Under the ranking: each ski's interval of the criterion (or why none), and the ties."""
    from skisnow.cli._render import console

    for rec in records:
        lo, hi = rec.get(f"{column}_low", float("nan")), rec.get(f"{column}_high", float("nan"))
        if lo == lo:
            console.print(
                f"{printable(rec['ski'])}: {column} in {interval_text(lo, hi)} (95 %, "
                f"{rec['samples']} posterior samples)"
            )
        else:
            console.print(f"{printable(rec['ski'])}: {printable(rec['uncertainty'])}")
    if any(r.get("not_comparable_with") for r in ranking):
        console.print(
            "n= : not comparable by this criterion (different patch topologies, see the "
            "warnings; compare the regions' shares instead)"
        )
    if any(r["within_uncertainty"] for r in ranking):
        console.print("n= : a tie within uncertainty (the skis' 95 % intervals overlap)")
    elif any(r["tied"] for r in ranking):
        console.print("n= : a tie (equal values; skis with the same content always tie)")


#: cycle answer (:data:`skisnow.workflows.CYCLE_QUANTITIES`) -> (key in field units, factor)
CYCLE_KEYS: dict[str, tuple[str, float]] = {
    "kick_contact_time": ("kick_contact_time_s", 1.0),
    "kick_fraction_of_loaded": ("kick_fraction_of_loaded", 1.0),
    "max_kick_share": ("max_kick_share", 1.0),
    "max_kick_length": ("max_kick_length_mm", 1e3),
    "mean_total_length": ("mean_total_length_mm", 1e3),
    "peak_pressure": ("peak_pressure_kpa", 1e-3),
    "mean_rear_share": ("mean_rear_share", 1.0),
}


def cycle_uncertainty_doc(iv: Any, note: str) -> dict[str, Any]:
    """The ``uncertainty`` section of one cycle (field units), or why there is none."""
    doc = uncertainty_doc(iv, note=note, zones=())
    if iv is not None:
        doc["method"] = doc["method"].replace("each solved as the case", "each run over the cycle")
        doc["intervals"] = {
            key: [iv.low[q] * f, iv.high[q] * f] for q, (key, f) in CYCLE_KEYS.items()
        }
        doc["estimates"] = {key: iv.estimate[q] * f for q, (key, f) in CYCLE_KEYS.items()}
    return doc


def print_cycle_uncertainty(name: str, doc: dict[str, Any]) -> None:
    """One line per answer of a cycle with its interval (or why none)."""
    from skisnow.cli._render import console

    if not doc["recorded"]:
        console.print(f"{printable(name)}: {printable(doc['note'])}")
        return
    parts = [f"{k} {interval_text(*v)}" for k, v in doc["intervals"].items()]
    mc = 100 * doc["mc_error_of_ends_max_fraction_of_width"]
    console.print(
        f"{printable(name)}: {100 * doc['level']:g} % intervals from {doc['samples']} posterior "
        "samples "
        f"(Monte Carlo error of the ends ≤ {mc:.0f} % of the width): {'; '.join(parts)}"
    )


def tie_test_doc(test: Any) -> dict[str, Any] | None:
    """The "same ski?" test of a pair in the JSON document (``None``: no bands)."""
    if test is None:
        return None
    return {
        "statistic": test.statistic,
        "critical_value": test.critical,
        "level": test.level,
        "method": test.method,
        "draws": test.draws,
        "p_value": None if test.p_value != test.p_value else test.p_value,
        "worst": test.worst[0],
        "worst_at_mm": test.worst[1] * 1e3,
        "verdict": test.text(),
    }
