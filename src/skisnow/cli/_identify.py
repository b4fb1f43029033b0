"""``skisnow identify``: EI(x) and z0(x) of a ski from its camber-bench file (thin: parse, call
:func:`skisnow.identify.identify_ski`, write the ski file, render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from skisnow._errors import InputError
from skisnow.cli._app import app, report_converged
from skisnow.cli._render import (
    JsonOption,
    NStiffnessOption,
    RegularisationOption,
    emit_json,
    print_table,
)
from skisnow.cli._render import say as _say


@app.command()
def identify(
    bench_file: Annotated[Path, typer.Argument(help="Bench table (.csv or .parquet).")],
    out: Annotated[Path, typer.Option("--out", help="The identified ski file (.json).")],
    ski: Annotated[
        str | None, typer.Option("--ski", help="Which ski of a multi-ski bench.")
    ] = None,
    name: Annotated[str | None, typer.Option("--name", help="Name of the identified ski.")] = None,
    x_tail_mm: Annotated[
        float | None,
        typer.Option("--x-tail-mm", help="Tail end of the running surface [mm] (default: file)."),
    ] = None,
    x_tip_mm: Annotated[
        float | None,
        typer.Option("--x-tip-mm", help="Tip end of the running surface [mm] (default: file)."),
    ] = None,
    noise_mm: Annotated[
        float | None,
        typer.Option("--noise-mm", help="Bench noise [mm] (default: estimated from the data)."),
    ] = None,
    regularisation: RegularisationOption = None,
    n_stiffness: NStiffnessOption = 60,
    n_camber: Annotated[
        int | None,
        typer.Option(
            "--n-camber",
            help="Spline coefficients of z0(x) (default: knots at the station spacing, 10-20 mm).",
        ),
    ] = None,
    mesh_mm: Annotated[
        float | None,
        typer.Option(
            "--mesh-mm",
            help="Element length of the fit's beam [mm] (default 10; contact resolved between "
            "nodes; the discretisation error is estimated and reported).",
        ),
    ] = None,
    max_nfev: Annotated[
        int, typer.Option("--max-nfev", help="Evaluation limit of each stage of the fit.")
    ] = 60,
    bands: Annotated[
        str,
        typer.Option(
            "--bands",
            help="laplace: the Laplace posterior's 2 sd (z0 known to under-cover, 35-79 %); "
            "conformal: its widths scaled x1.33 (EI) and x4.66 (z0) by a split-conformal "
            "calibration on 14 seeded skis (z0 covered at 99-100 % on other skis, above the "
            "90-98 % target). Not with --bootstrap.",
        ),
    ] = "laplace",
    bootstrap: Annotated[
        int,
        typer.Option(
            "--bootstrap",
            help="Widen the z0 bands by a parametric bootstrap of this many replicates (each "
            "one identification from the default start, run in --bootstrap-workers processes; "
            "0: the Laplace bands only, whose z0 bands under-cover; 8 calibrated).",
        ),
    ] = 0,
    bootstrap_workers: Annotated[
        int | None,
        typer.Option(
            "--bootstrap-workers",
            help="Processes the bootstrap's replicates run in (0: in this process; unset: one "
            "per core).",
        ),
    ] = None,
    figure: Annotated[
        Path | None,
        typer.Option("--figure", help="Save the passport figure (png/svg/pdf by suffix)."),
    ] = None,
    json_out: JsonOption = False,
) -> None:
    """Identify EI(x) and z0(x) from a whole bench sequence (beam on the stone, least squares)."""
    from skisnow._parallel import default_workers
    from skisnow.bench import read_bench
    from skisnow.identify import bootstrap_bands, identify_ski
    from skisnow.ski import write_ski

    if bootstrap == 1:
        raise InputError("--bootstrap must be 0 (none) or at least 2 replicates, got 1")
    if bands not in ("laplace", "conformal"):
        raise InputError(f"--bands must be one of laplace, conformal, got {bands!r}")
    if bands != "laplace" and bootstrap:
        raise InputError(
            "--bands conformal with --bootstrap: choose one (the bootstrap widens the Laplace "
            "bands; the conformal factors are calibrated without it)"
        )
    if out.suffix.lower() != ".json":
        raise InputError(f"--out {out}: the identified ski is written as a ski file (.json)")
    bench = read_bench(bench_file)
    accepted = _accepted_implausible(bench_file)
    from skisnow._checks import check_memory

    # the fit's Jacobian: one row per bench sample, one column per spline coefficient
    rows = len(bench.table)
    n_coef = n_stiffness + (n_camber or 200)
    check_memory(8.0 * rows * n_coef * 4, where="--n-stiffness, --n-camber",
                 what=f"a fit of {rows:,} samples x {n_coef} coefficients",
                 hint="use fewer coefficients")  # fmt: skip

    def say(msg: str) -> None:
        if not json_out:
            _say(msg, style="dim")

    options = dict(
        ski=ski,
        name=name,
        x_tail=None if x_tail_mm is None else x_tail_mm * 1e-3,
        x_tip=None if x_tip_mm is None else x_tip_mm * 1e-3,
        noise=None if noise_mm is None else noise_mm * 1e-3,
        regularisation=regularisation,
        n_stiffness=n_stiffness,
        n_camber=n_camber,
        element_length=None if mesh_mm is None else mesh_mm * 1e-3,
        max_nfev=max_nfev,
    )
    res = identify_ski(bench, progress=say, source=str(bench_file), bands=bands, **options)
    if bootstrap:
        jobs = default_workers() if bootstrap_workers is None else max(1, bootstrap_workers)
        say(f"bootstrap: {bootstrap} replicate benches, each identified again ({jobs} processes)")
        res = bootstrap_bands(res, bench, replicates=bootstrap, jobs=jobs,
                              **{k: v for k, v in options.items() if k != "name"})  # fmt: skip
    write_ski(res.ski, out)
    if figure is not None:
        from skisnow.plot import plot_passport, save_figure

        fmt = figure.suffix.lower().lstrip(".")
        if fmt not in ("png", "svg", "pdf"):
            raise InputError(f"--figure {figure}: use a .png, .svg or .pdf file name")
        save_figure(plot_passport(res.ski), figure.with_suffix(""), formats=(fmt,))
    warns, causes = list(res.warnings), list(res.causes)
    if accepted is not None:  # the data themselves, named before the fit's own causes
        causes.insert(0, "implausible bench")
        warns.insert(0, f"implausible bench accepted with --allow-implausible: {accepted} A "
                     "misfit above the noise may come from these data, not from the causes "
                     "named below.")  # fmt: skip
    n_boot = res.bootstrap[0] if res.bootstrap else 0
    doc = {
        "ski": res.ski.name,
        "file": str(out),
        "load_cases": res.n_cases,
        "samples": res.n_samples,
        "parameters": res.n_parameters,
        "noise_mm": res.noise * 1e3,
        "residual_rms_mm": res.residual_rms * 1e3,
        "regularisation": res.regularisation,
        "criterion": res.criterion,
        "converged": res.converged,
        "misfit_rms_sigma": res.misfit,
        "chi2_bound": res.chi2_bound,
        "causes": causes,
        "mesh_mm": res.mesh_error[2] * 1e3,
        "mesh_error_rms_um": res.mesh_error[0] * 1e6,
        "mesh_error_max_um": res.mesh_error[1] * 1e6,
        "model_error_rms_um": res.model_error[0] * 1e6,
        "determined_ei_mm": res.ski.provenance.detail("determined_ei_mm"),
        "determined_z0_mm": res.ski.provenance.detail("determined_z0_mm"),
        "bands": res.ski.provenance.detail("bands"),
        "bootstrap_replicates": n_boot,
        "outliers": [
            {
                "mass_kg": m,
                "load_position_mm": p * 1e3,
                "x_mm": x * 1e3,
                "residual_mm": d * 1e3,
                "sigma": z,
            }
            for m, p, x, d, z in res.outliers
        ],
        "noise_per_case": [
            {"mass_kg": m, "load_position_mm": p * 1e3, "noise_mm": s * 1e3, "misfit_sigma": f}
            for m, p, s, f in res.noise_cases
        ],
        "message": res.message,
        "warnings": warns,
        "seconds": res.seconds,
        "gcv": [
            {"lambda": lam, "gcv": g, "misfit_rms_sigma": m, "edf": e} for lam, g, m, e in res.gcv
        ],
    }
    report_converged(res.converged)  # exit code 3 when not (the warnings name the cause)
    if json_out:
        emit_json(doc)
        return
    for w in warns:
        _say(f"warning: {w}", style="yellow")
    skip = ("gcv", "warnings", "outliers", "noise_per_case")
    rows = [[k, v] for k, v in doc.items() if k not in skip]
    print_table("Identified ski (passport: skisnow skis --show FILE)", ["", "value"], rows)
    print_table(
        "Regularisation (GCV)",
        ["lambda", "GCV", "misfit rms / σ", "edf"],
        [[g["lambda"], g["gcv"], g["misfit_rms_sigma"], g["edf"]] for g in doc["gcv"]],
    )


def _accepted_implausible(path: Path) -> str | None:
    """What the strict bench checks would have refused in ``path`` when --allow-implausible
    let it through (``None``: nothing, or the override not given)."""
    from skisnow._checks import allow_implausible, implausible_allowed
    from skisnow._errors import ImplausibleValueError
    from skisnow.bench import read_bench

    if not implausible_allowed():
        return None
    with allow_implausible(False):
        try:
            read_bench(path)
        except ImplausibleValueError as exc:
            return str(exc).split(" If you really mean it")[0]
    return None
