"""Commands for the ski: skis, bench, metrics (thin: parse, call skisnow.ski, render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from skisnow._errors import InputError
from skisnow._values import parse_values
from skisnow.cli._app import app
from skisnow.cli._render import emit_json, print_table, progress_bar

_JSON = typer.Option(False, "--json", help="Print one JSON document to stdout, nothing else.")


def ski_summary_rows() -> list[dict[str, Any]]:
    """Key numbers of the shipped skis in field units (used by ``skis`` and ``demo``)."""
    from skisnow.ski import SHIPPED_SKIS, closing_load, get_ski

    rows = []
    for name in SHIPPED_SKIS:
        ski = get_ski(name)
        kz = ski.kick_zone
        rows.append(
            {
                "ski": name,
                "kind": ski.kind,
                "length_mm": ski.length * 1e3,
                "width_mm": ski.width * 1e3,
                "x_tail_mm": ski.x_tail * 1e3,
                "x_tip_mm": ski.x_tip * 1e3,
                "kick_zone_mm": None if kz is None else [kz[0] * 1e3, kz[1] * 1e3],
                "free_camber_at_balance_point_mm": float(ski.free_camber(0.0)) * 1e3,
                "stiffness_at_balance_point_n_m2": float(ski.stiffness(0.0)),
                "closing_load_at_-80mm_kg": closing_load(ski, load_position=-0.080),
            }
        )
    return rows


@app.command()
def skis(json_out: bool = _JSON) -> None:
    """List the shipped virtual skis and their key numbers."""
    rows = ski_summary_rows()
    if json_out:
        emit_json({"skis": rows})
        return

    def cell(value: Any) -> Any:
        if isinstance(value, list):
            return f"{value[0]:g} .. {value[1]:g}"
        return value

    keys = [k for k in rows[0] if k != "ski"]
    table_rows = [[k, *[cell(r[k]) for r in rows]] for k in keys]
    print_table("Shipped virtual skis", ["", *[r["ski"] for r in rows]], table_rows, floatfmt=".4g")


@app.command()
def bench(
    ski: Annotated[str, typer.Argument(help="Shipped ski name (see `skisnow skis`).")],
    out: Annotated[Path, typer.Option("--out", help="Output file, .csv or .parquet.")],
    mass_kg: str = typer.Option("5:130:5", "--mass-kg", help="Masses: start:stop:step or a,b,c."),
    load_position_mm: str = typer.Option(
        "-240:-40:40",
        "--load-position-mm",
        help="Load positions from the balance point (negative = behind): start:stop:step or a,b.",
    ),
    noise_mm: float = typer.Option(0.0, "--noise-mm", help="Height noise std [mm] (e.g. 0.01)."),
    seed: int | None = typer.Option(None, "--seed", help="Seed of the noise."),
    dx_mm: float = typer.Option(1.0, "--dx-mm", help="Sampling step along the ski [mm]."),
    json_out: bool = _JSON,
) -> None:
    """Run the virtual camber bench on a shipped ski and write the bench table."""
    from skisnow.io import write_bench
    from skisnow.ski import get_ski, run_bench

    sk = get_ski(ski)
    if out.suffix.lower() not in (".csv", ".parquet"):
        raise InputError(f"--out {out}: use a .csv or .parquet file name")
    masses = parse_values(mass_kg, name="--mass-kg").tolist()
    positions = (parse_values(load_position_mm, name="--load-position-mm") * 1e-3).tolist()
    with progress_bar(f"bench {ski}", total=len(set(masses)) * len(set(positions))) as bar:
        data = run_bench(
            sk,
            masses=masses,
            load_positions=positions,
            dx=dx_mm * 1e-3,
            noise=noise_mm * 1e-3,
            seed=seed,
            progress=bar,
        )
    out.parent.mkdir(parents=True, exist_ok=True)
    write_bench(data, out)
    n_profiles = len(data.conditions)
    doc = {"ski": ski, "file": str(out), "rows": len(data.table), "profiles": n_profiles}
    if json_out:
        emit_json(doc)
        return
    print_table("Virtual bench", list(doc), [list(doc.values())])


def metrics_documents(
    source: str, *, body_mass_kg: float, load_position_mm: float
) -> list[dict[str, Any]]:
    """Metrics (field units) of a shipped ski or of every ski in a bench file."""
    from skisnow.io import read_bench
    from skisnow.ski import SHIPPED_SKIS, ski_metrics

    kw = {"body_mass": body_mass_kg, "load_position": load_position_mm * 1e-3}
    if source in SHIPPED_SKIS:
        return [ski_metrics(source, **kw).as_field_units()]
    path = Path(source)
    if not path.exists():
        raise InputError(
            f"{source!r} is neither a shipped ski ({', '.join(SHIPPED_SKIS)}) nor an existing "
            "bench file (.csv or .parquet)"
        )
    data = read_bench(path)
    return [ski_metrics(data, ski=name, **kw).as_field_units() for name in data.skis]


def print_metrics_table(docs: list[dict[str, Any]], title: str) -> None:
    """Render metrics documents as one table: a row per metric, a column per ski."""
    keys = [k for k in docs[0] if k != "ski"]
    rows = [[k, *[d[k] for d in docs]] for k in keys]
    print_table(title, ["metric", *[d["ski"] for d in docs]], rows, floatfmt=".4g")


@app.command()
def metrics(
    source: str = typer.Argument(..., help="A shipped ski name or a bench file (.csv/.parquet)."),
    body_mass_kg: float = typer.Option(65.0, "--body-mass-kg", help="Skier's body mass [kg]."),
    load_position_mm: float = typer.Option(
        -80.0, "--load-position-mm", help="Load position from the balance point [mm]."
    ),
    json_out: bool = _JSON,
) -> None:
    """Practitioners' metrics: camber, wax pocket, closing load, stiffness, contact lengths."""
    docs = metrics_documents(source, body_mass_kg=body_mass_kg, load_position_mm=load_position_mm)
    if json_out:
        emit_json({"metrics": docs})
        return
    print_metrics_table(docs, f"Ski metrics ({body_mass_kg:g} kg body mass)")
