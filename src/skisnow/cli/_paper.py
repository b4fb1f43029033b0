"""``skisnow captions``: the paper's caption numbers against skisnow's (parse, call, render)."""

from __future__ import annotations

import typer

from skisnow.cli._app import app
from skisnow.cli._render import JsonOption, console, emit_json, print_table


@app.command()
def captions(
    ski: str = typer.Option(
        "all", "--ski", help="Which shipped ski's captions: classic, skate or all."
    ),
    json_out: JsonOption = False,
) -> None:
    """Kalliorinne et al. (2023) Figs. 4-7 captions against the shipped skis (fitted numbers).

    Each case runs the paper's pipeline: the loaded ski on the rigid plane (virtual bench), its
    rigid profile pressed into the half-space (strip model, E_base 900 MPa, ν 0.3, force and
    moment balance). Lengths in mm, mean pressures in kPa, load shares in %.
    """
    from skisnow._errors import InputError
    from skisnow.paper import TOLERANCES, caption_table
    from skisnow.ski import get_ski

    if ski not in ("classic", "skate", "all"):
        raise InputError(f"--ski must be classic, skate or all, not {ski!r}")
    kinds = ("classic", "skate") if ski == "all" else (ski,)
    rows = caption_table({k: get_ski(k) for k in kinds})
    records = [r.as_dict() for r in rows]
    if json_out:
        emit_json(
            {
                "tolerances": {
                    "length_pct": TOLERANCES.length * 100,
                    "mean_pressure_pct": TOLERANCES.pressure * 100,
                    "load_share_points": TOLERANCES.share * 100,
                    "patches": "exact where the paper states them",
                },
                "all_within_tolerance": all(r.ok for r in rows),
                "rows": records,
            }
        )
        return

    def pct(v: float | None) -> str | None:
        return None if v is None else f"{v:+.0f}"

    table = [
        [
            d["case"],
            d["zone"],
            d["paper_length_mm"],
            d["length_mm"],
            pct(d["length_error_pct"]),
            d["paper_mean_pressure_kpa"],
            d["mean_pressure_kpa"],
            pct(d["pressure_error_pct"]),
            d["paper_load_share_pct"],
            d["load_share_pct"],
            "—" if d["paper_patches"] is None else str(d["paper_patches"]),
            str(d["patches"]),
            "yes" if d["ok"] else "NO",
        ]
        for d in records
    ]
    print_table(
        "Kalliorinne et al. (2023) captions vs skisnow (fitted: a calibration, not a validation)",
        [
            "case",
            "zone",
            "paper [mm]",
            "skisnow [mm]",
            "Δ [%]",
            "paper [kPa]",
            "skisnow [kPa]",
            "Δ [%]",
            "paper share [%]",
            "skisnow share [%]",
            "paper patches",
            "patches",
            "within",
        ],
        table,
        floatfmt=".1f",
    )
    n_ok = sum(r.ok for r in rows)
    console.print(
        f"{n_ok}/{len(rows)} zones within ±{TOLERANCES.length:.0%} length, "
        f"±{TOLERANCES.pressure:.0%} pressure, ±{TOLERANCES.share * 100:.0f} points share, "
        "exact patch counts"
    )
