"""``skisnow captions``: the paper's caption numbers against skisnow's (parse, call, render)."""

from __future__ import annotations

import math

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

    def pair(paper: float | None, ours: float, error: float | None, fmt: str) -> str:
        """``paper / skisnow (±Δ %)``, a dash where the paper states nothing."""
        left = "—" if paper is None else format(paper, fmt)
        right = "—" if ours is None or not math.isfinite(ours) else format(ours, fmt)
        tail = "" if error is None or not math.isfinite(error) else f" ({error:+.0f}%)"
        return f"{left} / {right}{tail}"

    table = [
        [
            d["case"],
            d["zone"],
            pair(d["paper_length_mm"], d["length_mm"], d["length_error_pct"], ".1f"),
            pair(d["paper_mean_pressure_kpa"], d["mean_pressure_kpa"], d["pressure_error_pct"],
                 ".1f"),
            pair(d["paper_load_share_pct"], d["load_share_pct"], None, ".0f"),
            pair(d["paper_patches"], d["patches"], None, "d"),
            "yes" if d["ok"] else "NO",
        ]
        for d in records
    ]  # fmt: skip
    # paper and skisnow side by side in one cell (as the README's table): the table fits a
    # 120-column terminal instead of spreading 13 columns
    print_table(
        "Kalliorinne et al. (2023) captions vs skisnow, each cell paper / skisnow (Δ)\n"
        "(fitted: a calibration, not a validation)",
        ["case", "zone", "length [mm]", "mean p [kPa]", "share [%]", "patches", "within"],
        table,
    )
    n_ok = sum(r.ok for r in rows)
    console.print(
        f"{n_ok}/{len(rows)} zones within ±{TOLERANCES.length:.0%} length, "
        f"±{TOLERANCES.pressure:.0%} pressure, ±{TOLERANCES.share * 100:.0f} points share, "
        "exact patch counts"
    )
