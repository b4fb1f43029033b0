"""The ``micro-curves`` command: the micro curves of one or more bases on a snow (thin: parse,
call :func:`skisnow.multiscale.micro_curves`, render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from skisnow.cli._app import app
from skisnow.cli._media import SnowOption, SnowTemperatureOption
from skisnow.cli._render import JsonOption, console, emit_json, print_table, progress_bar


@app.command("micro-curves")
def micro_curves_command(
    base: Annotated[
        list[str],
        typer.Option("--base", help="Base texture(s): S1..S5, smooth or a topography file."),
    ],
    snow: SnowOption = None,
    snow_temperature_c: SnowTemperatureOption = None,
    film_cutoff_nm: Annotated[
        float, typer.Option("--film-cutoff-nm", help="Film cut-off of ⟨1/u⟩ in nm.")
    ] = 100.0,
    figure: Annotated[
        Path | None, typer.Option("--figure", help="Save the curves (png/svg by suffix).")
    ] = None,
    json_out: JsonOption = False,
) -> None:
    """The micro curves of each base on the snow: real-area fraction (flat ice and grains),
    mean and reciprocal separation over the nominal pressure (computed once, then cached)."""
    from skisnow._checks import check_value
    from skisnow._errors import InputError
    from skisnow.cli._media import resolve_base, resolve_snow
    from skisnow.multiscale import micro_curves

    s, _ = resolve_snow(snow, None, temperature_c=snow_temperature_c, required=False)
    if s is None:
        raise InputError("micro-curves needs --snow (a preset or a snow file)")
    uc = check_value(film_cutoff_nm, "film_cutoff", where="--film-cutoff-nm") * 1e-9
    bases = [resolve_base(b, s) for b in base]
    curves = []
    with progress_bar("micro curves", total=len(bases), disable=json_out) as bar:
        for k, b in enumerate(bases):
            curves.append(micro_curves(b, s))
            bar(k + 1)
    files = []
    if figure is not None:
        from skisnow.plot import plot_micro_curves, save_figure

        files = [str(p) for p in save_figure(plot_micro_curves(curves, film_cutoff=uc), figure)]
    docs = []
    for c in curves:
        d = c.as_dict()
        d["reciprocal_separation_per_um"] = (c.reciprocal_grid(uc) * 1e-6).tolist()
        d["film_cutoff_nm"] = uc * 1e9
        d["from_cache"] = c.from_cache
        docs.append(d)
    if json_out:
        emit_json({"snow": s.describe(), "curves": docs, "files": files,
                   "converged": all(d["converged"] for d in docs)})  # fmt: skip
        return
    console.print(f"snow {s.describe()}")
    for c, d in zip(curves, docs, strict=True):
        rows = [
            [p, fr, d["plastic_fraction"][i], d["mean_separation_um"][i],
             d["reciprocal_separation_per_um"][i]]
            for i, (p, fr) in enumerate(zip(d["pressure_kpa"], d["real_fraction"], strict=True))
        ]  # fmt: skip
        print_table(
            f"base {c.base} × snow {c.snow} (H = {c.hardness / 1e6:.3g} MPa, "
            f"{'from the cache' if c.from_cache else f'computed in {c.cpu_seconds:.1f} s CPU'})",
            ["p [kPa]", "real fraction", "plastic share", "ū [µm]", "⟨1/u⟩ [1/µm]"],
            rows,
        )
    for f in files:
        console.print(f"wrote {f}")
