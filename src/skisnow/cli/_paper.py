"""``skisnow captions``: the paper's caption numbers against skisnow's (parse, call, render)."""

from __future__ import annotations

import importlib.util
import math

import typer

from skisnow.cli._app import app
from skisnow.cli._render import JsonOption, console, emit_json, err_console, print_table


def _tolerance_doc(tol) -> dict:  # type: ignore[no-untyped-def]
    return {
        "length_pct": tol.length * 100,
        "mean_pressure_pct": tol.pressure * 100,
        "load_share_points": tol.share * 100,
        "implied_shares": tol.implied_shares,
        "patches": "exact where the paper states them",
    }


@app.command()
def captions(
    ski: str = typer.Option(
        "all",
        "--ski",
        help="Which shipped ski's captions: classic, skate, classic-k22, skate-k22 or all.",
    ),
    route: str = typer.Option(
        "both",
        "--route",
        help="Profile route: network (the paper's: the camber network trained on the ski's "
        "bench), beam (the beam on the rigid plane it emulates) or both.",
    ),
    json_out: JsonOption = False,
) -> None:
    """Kalliorinne et al. (2023) Figs. 4-7 captions against the shipped skis (fitted numbers).

    Each case runs the paper's pipeline: the loaded ski's profile (camber network or beam on
    the rigid plane), pressed as a rigid body into the half-space (strip model, E_base 900 MPa,
    ν 0.3, force and moment balance). Lengths in mm, mean pressures in kPa, load shares in %.
    The plausible skis (classic, skate) are held to ±20 % / ±25 % / ±5 points, the reproduction
    skis (classic-k22, skate-k22) to ±10 % / ±10 % / ±3 points including the shares Figs. 4
    and 7 imply.
    """
    from skisnow._errors import InputError
    from skisnow.paper import ROUTES, caption_table, tolerances_of
    from skisnow.ski import SHIPPED_SKIS, get_ski

    if ski not in (*SHIPPED_SKIS, "all"):
        raise InputError(f"--ski must be one of {', '.join(SHIPPED_SKIS)} or all, not {ski!r}")
    if route not in (*ROUTES, "both"):
        raise InputError(f"--route must be network, beam or both, not {route!r}")
    names = SHIPPED_SKIS if ski == "all" else (ski,)
    routes = ROUTES if route == "both" else (route,)
    warnings: list[str] = []
    if route == "both" and importlib.util.find_spec("jax") is None:
        # the default asks for both routes; without the network extra, the beam route alone
        routes = ("beam",)
        warnings.append(
            "network route left out: the camber network needs the 'network' extra "
            "(uv sync --extra network); --route network asks for it explicitly"
        )
        if not json_out:
            err_console.print(f"[yellow]warning:[/yellow] {warnings[-1]}")
    by_route = {r: caption_table(list(names), route=r) for r in routes}
    if json_out:
        emit_json(
            {
                "routes": list(routes),
                "warnings": warnings,
                "tolerances": {n: _tolerance_doc(tolerances_of(get_ski(n))) for n in names},
                "within": {
                    n: {
                        r: [sum(x.ok for x in rows if x.ski == n), sum(x.ski == n for x in rows)]
                        for r, rows in by_route.items()
                    }
                    for n in names
                },
                "all_within_tolerance": all(x.ok for rows in by_route.values() for x in rows),
                "rows": [x.as_dict() for rows in by_route.values() for x in rows],
            }
        )
        return

    def fmt(value: float | None, spec: str) -> str:
        return "—" if value is None or not math.isfinite(value) else format(value, spec)

    def cell(paper: float | None, got: list[float], spec: str) -> str:
        """``paper / route 1 / route 2`` in one cell."""
        return " / ".join([fmt(paper, spec), *(fmt(g, spec) for g in got)])

    for name in names:
        rows = {r: [x for x in by_route[r] if x.ski == name] for r in routes}
        keyed = {r: {(x.case.label, x.zone): x for x in rows[r]} for r in routes}
        keys = list(dict.fromkeys(k for r in routes for k in keyed[r]))  # case order kept
        table = []
        for key in keys:
            per = [keyed[r].get(key) for r in routes]
            x = next(p for p in per if p is not None)
            paper = x.paper
            share = None if x.paper_share is None else 100 * x.paper_share
            share_txt = (
                f"({share:.0f})" if x.share_implied and share is not None else fmt(share, ".0f")
            )
            table.append(
                [
                    x.case.label.replace(f" {x.case.ski} ", " "),
                    x.zone,
                    cell(None if paper is None else paper.length * 1e3,
                         [p.length * 1e3 if p else math.nan for p in per], ".1f"),
                    cell(None if paper is None else paper.mean_pressure * 1e-3,
                         [p.mean_pressure * 1e-3 if p else math.nan for p in per], ".1f"),
                    " / ".join([share_txt, *(fmt(p.load_share * 100 if p else None, ".0f")
                                             for p in per)]),
                    " / ".join([fmt(None if paper is None else paper.patches, "d"),
                                *(str(p.patches) if p else "0" for p in per)]),
                    " / ".join("—" if p is None else "yes" if p.ok else "NO" for p in per),
                ]
            )  # fmt: skip
        tol = tolerances_of(get_ski(name))
        order = " / ".join(["paper", *routes])
        print_table(
            f"{name}: Kalliorinne et al. (2023) captions, each cell {order} "
            "(fitted numbers: a calibration, not a validation; (share) = implied by "
            "length × pressure)",
            ["case", "zone", "length [mm]", "mean p [kPa]", "share [%]", "patches",
             f"within ({', '.join(routes)})"],
            table,
        )  # fmt: skip
        counts = ", ".join(f"{r} {sum(x.ok for x in rows[r])}/{len(rows[r])}" for r in routes)
        implied = ", implied shares too" if tol.implied_shares else ""
        console.print(
            f"{name}: zones within ±{tol.length:.0%} length, ±{tol.pressure:.0%} pressure, "
            f"±{tol.share * 100:.0f} points share{implied}, exact patch counts: {counts}"
        )
