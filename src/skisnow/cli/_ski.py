"""Commands for the ski: skis, bench, metrics (thin: parse, call skisnow.ski, render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from skisnow._errors import InputError
from skisnow._values import parse_values
from skisnow.cli._app import app, report_converged
from skisnow.cli._render import JsonOption, emit_json, print_table, progress_bar


def resolve_profile_source(option: str, skis: list[str]) -> str:
    """``--profile-source auto``: the default route for every ski, whatever its name or file
    (:data:`skisnow.pipeline.DEFAULT_PROFILE_SOURCE`, the beam: the truth of a ski defined by
    EI(x) and z0(x)); other values pass through."""
    from skisnow.pipeline import DEFAULT_PROFILE_SOURCE

    del skis  # the route depends on no ski's name (issue 26)
    return DEFAULT_PROFILE_SOURCE if option == "auto" else option


def ski_summary_rows(skis: list[str] | None = None) -> list[dict[str, Any]]:
    """Key numbers of skis (default: the shipped ones) in field units (``skis`` and ``demo``)."""
    from skisnow.bench import closing_load
    from skisnow.ski import REPRODUCTION_SKIS, SHIPPED_SKIS, get_ski

    rows = []
    for name in SHIPPED_SKIS if skis is None else skis:
        ski = get_ski(name)
        kz = ski.kick_zone
        rows.append(
            {
                **ski.summary_mm(),
                # the reproduction skis match the paper's captions, not real skis (issue 30)
                "reproduction_ski": "YES" if name in REPRODUCTION_SKIS else "no",
                "kick_zone_mm": None if kz is None else [kz[0] * 1e3, kz[1] * 1e3],
                "free_camber_at_balance_point_mm": float(ski.free_camber(0.0)) * 1e3,
                "stiffness_at_balance_point_n_m2": float(ski.stiffness(0.0)),
                "closing_load_at_-80mm_kg": closing_load(ski, load_position=-0.080),
            }
        )
    return rows


@app.command()
def skis(
    show: Annotated[
        str | None,
        typer.Option("--show", help="Show one ski's passport: a shipped name or a ski file."),
    ] = None,
    figure: Annotated[
        Path | None,
        typer.Option("--figure", help="With --show: save the passport figure (png/svg/pdf)."),
    ] = None,
    out: Annotated[
        Path | None,
        typer.Option("--out", help="With --show: write the ski as a ski file (.json)."),
    ] = None,
    step_mm: Annotated[
        float, typer.Option("--step-mm", help="With --show: station spacing of the table [mm].")
    ] = 100.0,
    body_mass_kg: Annotated[
        float, typer.Option("--body-mass-kg", help="With --show: body mass of the metrics [kg].")
    ] = 65.0,
    load_position_mm: Annotated[
        float,
        typer.Option("--load-position-mm", help="With --show: load position of the metrics [mm]."),
    ] = -80.0,
    json_out: JsonOption = False,
) -> None:
    """List the shipped skis, or show one ski's passport (EI(x), z0(x), bands, metrics)."""
    if show is None:
        if figure is not None or out is not None:
            raise InputError("--figure and --out need --show SKI")
        _list_skis(json_out)
        return
    from skisnow.bench import ski_passport
    from skisnow.ski import get_ski, ski_to_document, write_ski

    ski = get_ski(show)
    if not (step_mm > 0):
        raise InputError(f"--step-mm must be > 0, got {step_mm:g}")
    pp = ski_passport(
        ski, step=step_mm * 1e-3, body_mass=body_mass_kg, load_position=load_position_mm * 1e-3
    )
    if out is not None:
        out.parent.mkdir(parents=True, exist_ok=True)
        write_ski(ski, out)
    if figure is not None:
        from skisnow.plot import plot_passport, save_figure

        fmt = figure.suffix.lower().lstrip(".")
        if fmt not in ("png", "svg", "pdf"):
            raise InputError(f"--figure {figure}: use a .png, .svg or .pdf file name")
        save_figure(plot_passport(ski), figure.with_suffix(""), formats=(fmt,))
    from skisnow.ski import uncertainty_note

    doc = ski_to_document(ski)
    summary = {k: doc[k] for k in ("name", "kind", "x_tail_mm", "x_tip_mm", "width_mm",
                                   "kick_zone_mm", "boot_plate_mm")}  # fmt: skip
    summary["length_mm"] = ski.length * 1e3
    summary["balance_point_from_tail_mm"] = -ski.x_tail * 1e3
    table = {k: v.tolist() for k, v in pp.table().items()}
    if json_out:
        emit_json(
            {
                "ski": summary,
                "stations": table,
                "metrics": pp.metrics,
                "provenance": doc["provenance"],
                "uncertainty": uncertainty_note(ski),
                "file": None if out is None else str(out),
                "figure": None if figure is None else str(figure),
            }
        )
        return

    def cell(value: Any) -> Any:
        return f"{value[0]:g} .. {value[1]:g}" if isinstance(value, list) else value

    print_table(f"Ski {ski.name}", ["", "value"], [[k, cell(v)] for k, v in summary.items()])
    cols = list(table)
    if not pp.has_bands:
        cols = ["x_mm", "ei_nm2", "z0_mm"]
    rows = [[table[c][i] for c in cols] for i in range(len(table["x_mm"]))]
    print_table("EI(x) and z0(x)" + (" with 95 % bands" if pp.has_bands else ""), cols, rows)
    if pp.metrics is not None:
        keys = [k for k in pp.metrics if k not in ("ski",)]
        print_table("Practitioners' metrics", ["metric", "value"],
                    [[k, pp.metrics[k]] for k in keys], floatfmt=".4g")  # fmt: skip
    prov = doc["provenance"]
    prov_rows = [["method", prov["method"]], ["data", prov["data"]],
                 ["created", prov["created_utc"]], ["software", prov["software"]]]  # fmt: skip
    prov_rows += [[k, v] for k, v in prov["details"].items()]
    prov_rows += [[f"source {i + 1}", s] for i, s in enumerate(prov["sources"])]
    prov_rows += [["uncertainty", uncertainty_note(ski)]]
    print_table("Provenance", ["", ""], prov_rows)


def _list_skis(json_out: bool) -> None:
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
    ski: Annotated[
        str, typer.Argument(help="Shipped ski name (see `skisnow skis`) or a ski file (.json).")
    ],
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
    json_out: JsonOption = False,
) -> None:
    """Run the virtual camber bench on a shipped ski and write the bench table."""
    from skisnow._checks import check_memory, check_option_values, check_value
    from skisnow.bench import run_bench, write_bench
    from skisnow.ski import get_ski

    sk = get_ski(ski)
    dx_mm = check_value(dx_mm, "step_along_ski", where="--dx-mm")
    noise_mm = check_value(noise_mm, "noise", where="--noise-mm")
    check_memory(
        sk.length / (dx_mm * 1e-3) * 8 * 16,
        where=f"--dx-mm {dx_mm:g}",
        what=f"sampling a {sk.length * 1e3:g} mm ski every {dx_mm:g} mm",
        hint="use a larger step",
    )
    if out.suffix.lower() not in (".csv", ".parquet"):
        raise InputError(f"--out {out}: use a .csv or .parquet file name")
    masses = check_option_values(
        parse_values(mass_kg, name="--mass-kg"), "mass", "--mass-kg"
    ).tolist()
    positions = (
        check_option_values(
            parse_values(load_position_mm, name="--load-position-mm"),
            "load_position",
            "--load-position-mm",
        )
        * 1e-3
    ).tolist()
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
    from skisnow._checks import check_value
    from skisnow.bench import read_bench, ski_metrics
    from skisnow.ski import SHIPPED_SKIS

    body_mass_kg = check_value(body_mass_kg, "mass", where="--body-mass-kg")
    load_position_mm = check_value(load_position_mm, "load_position", where="--load-position-mm")
    kw = {"body_mass": body_mass_kg, "load_position": load_position_mm * 1e-3}
    if source in SHIPPED_SKIS:
        docs = [ski_metrics(source, **kw).as_field_units()]
        report_converged(True)  # solve_beam raises ConvergenceError unless each solve converged
        return docs
    path = Path(source)
    if not path.exists():
        raise InputError(
            f"{source!r} is neither a shipped ski ({', '.join(SHIPPED_SKIS)}) nor an existing "
            "ski file (.json) or bench file (.csv or .parquet)"
        )
    if path.suffix.lower() == ".json":
        docs = [ski_metrics(str(path), **kw).as_field_units()]
        report_converged(True)  # as above; from a bench nothing is solved: converged stays null
        return docs
    data = read_bench(path)
    try:
        return [ski_metrics(data, ski=name, **kw).as_field_units() for name in data.skis]
    except InputError as exc:  # name the file the bench came from
        raise type(exc)(f"{path}: {exc}") from None


def print_metrics_table(docs: list[dict[str, Any]], title: str) -> None:
    """Render metrics documents as one table: a row per metric, a column per ski."""
    keys = [k for k in docs[0] if k != "ski"]
    rows = [[k, *[d[k] for d in docs]] for k in keys]
    print_table(title, ["metric", *[d["ski"] for d in docs]], rows, floatfmt=".4g")


@app.command()
def metrics(
    source: str = typer.Argument(
        ..., help="A shipped ski name, a ski file (.json) or a bench file (.csv/.parquet)."
    ),
    body_mass_kg: float = typer.Option(65.0, "--body-mass-kg", help="Skier's body mass [kg]."),
    load_position_mm: float = typer.Option(
        -80.0, "--load-position-mm", help="Load position from the balance point [mm]."
    ),
    json_out: JsonOption = False,
) -> None:
    """Practitioners' metrics: camber, wax pocket, closing load, stiffness, contact lengths."""
    docs = metrics_documents(source, body_mass_kg=body_mass_kg, load_position_mm=load_position_mm)
    if json_out:
        emit_json({"metrics": docs})
        return
    print_metrics_table(docs, f"Ski metrics ({body_mass_kg:g} kg body mass)")
