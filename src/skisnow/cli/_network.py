"""Commands for the camber network: train, predict (thin: parse, call skisnow.ski, render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from skisnow._errors import InputError
from skisnow.cli._app import app, report_domain_warnings, report_unconverged
from skisnow.cli._render import (
    JsonOption,
    emit_json,
    print_table,
    progress_bar,
    say,
)


def _resolve_model(model: str) -> Any:
    """A shipped ski name or the path of a model (``PATH``, ``PATH.npz`` or ``PATH.json``)."""
    from skisnow.network import load_network, shipped_network
    from skisnow.ski import SHIPPED_SKIS

    if model in SHIPPED_SKIS:
        return shipped_network(model)
    p = Path(model)
    base = p.with_suffix("") if p.suffix in (".npz", ".json") else p
    if not (base.with_name(base.name + ".npz").exists() or p.exists()):
        raise InputError(
            f"MODEL {model!r} is neither a shipped ski ({', '.join(SHIPPED_SKIS)}) nor a model "
            "file (PATH.npz + PATH.json written by `skisnow train`)"
        )
    return load_network(p)


@app.command()
def train(
    bench_file: Annotated[Path, typer.Argument(help="Bench table (.csv or .parquet), one ski.")],
    out: Annotated[Path, typer.Option("--out", help="Model path: writes OUT.npz + OUT.json.")],
    seed: int = typer.Option(0, "--seed", help="Seed: validation split, weights, subsample."),
    widths: str = typer.Option(
        "6,16,16,16,12,12",
        "--widths",
        help="Six layer widths: load, collapse1-3, camber1-2 (Kalliorinne et al. 2023, Figure 3).",
    ),
    adam_steps: int = typer.Option(600, "--adam-steps", help="Adam steps (first phase)."),
    lm_steps: int = typer.Option(200, "--lm-steps", help="Max Levenberg-Marquardt steps."),
    ensemble: int = typer.Option(1, "--ensemble", help="Number of members (spread = uncertainty)."),
    json_out: JsonOption = False,
) -> None:
    """Train the camber network h = f(x, m, x_m) on a bench file and save it."""
    from skisnow.bench import read_bench
    from skisnow.network import save_network, train_network

    widths_list = [w.strip() for w in widths.split(",")]
    if len(widths_list) != 6 or not all(w.isdigit() and int(w) >= 1 for w in widths_list):
        raise InputError(
            f"--widths: need six positive integers (load, collapse1-3, camber1-2), got {widths!r}"
        )
    for option, value, least in (
        ("--adam-steps", adam_steps, 0),
        ("--lm-steps", lm_steps, 0),
        ("--ensemble", ensemble, 1),
    ):
        if value < least:
            raise InputError(f"{option}: need an integer >= {least}, got {value}")
    data = read_bench(bench_file)
    with progress_bar("train") as bar:

        def progress(p: Any) -> None:
            bar(
                p.step,
                p.total,
                label=f"member {p.member + 1}/{p.n_members} {p.phase}",
                status=(
                    f"train rms {p.train_rms_um:.1f} µm · held-out mean {p.val_mean_um:.2f} µm, "
                    f"max {p.val_max_um:.1f} µm"
                ),
            )

        net = train_network(
            data,
            seed=seed,
            architecture=widths,
            adam_steps=adam_steps,
            lm_steps=lm_steps,
            ensemble=ensemble,
            progress=progress,
        )
    npz, js = save_network(net, out)
    err = net.metadata["validation_errors"]
    doc = {
        "ski": net.ski,
        "model": str(npz.with_suffix("")),
        "files": [str(npz), str(js)],
        "widths": list(net.architecture.widths),
        "members": len(net.members),
        "held_out_conditions": len(net.metadata["validation_conditions"]),
        "held_out_mean_error_um": err["mean_um"],
        "held_out_p95_error_um": err["p95_um"],
        "held_out_max_error_um": err["max_um"],
        "held_out_near_contact_mean_error_um": err["near_contact_mean_um"],
        "training_time_s": net.metadata["training_time_s"],
        "status": net.metadata["status"],
        "stopped_by": list(net.metadata["stopped_by"]),
    }
    from skisnow.network import training_converged

    converged, why = training_converged(net.metadata)
    doc["converged"] = converged
    doc["warnings"] = [] if why is None else [why]
    report_unconverged([] if why is None else [why], solved=True)  # false: exit 3
    if json_out:
        emit_json(doc)
        return
    print_table("Camber network trained", ["quantity", "value"], [[k, v] for k, v in doc.items()])


@app.command()
def predict(
    model: Annotated[str, typer.Argument(help="Model path (PATH.npz/.json) or a shipped ski.")],
    mass_kg: float = typer.Option(..., "--mass-kg", help="Load mass m [kg]."),
    load_position_mm: float = typer.Option(
        ..., "--load-position-mm", help="Load position x_m [mm] from the balance point."
    ),
    dx_mm: float = typer.Option(1.0, "--dx-mm", help="Output sampling step along the ski [mm]."),
    strict: bool = typer.Option(
        False, "--strict", help="Refuse loads outside the trained range (default: warn)."
    ),
    figure: Annotated[
        Path | None, typer.Option("--figure", help="Save a profile figure (png/pdf).")
    ] = None,
    json_out: JsonOption = False,
) -> None:
    """Predict the loaded camber profile h(x) with a trained network.

    Kalliorinne et al. (2023), eq. 1.
    """
    import warnings

    from skisnow._checks import check_memory, check_value
    from skisnow._errors import DomainWarning

    mass_kg = check_value(mass_kg, "mass", where="--mass-kg")
    load_position_mm = check_value(load_position_mm, "load_position", where="--load-position-mm")
    dx_mm = check_value(dx_mm, "step_along_ski", where="--dx-mm")
    net = _resolve_model(model)
    d = net.domain
    check_memory(
        (d.x_max - d.x_min) / (dx_mm * 1e-3) * 8 * 16,
        where=f"--dx-mm {dx_mm:g}",
        what=f"a profile sampled every {dx_mm:g} mm",
        hint="use a larger step",
    )
    k0 = int(np.ceil(d.x_min / (dx_mm * 1e-3) - 1e-9))
    k1 = int(np.floor(d.x_max / (dx_mm * 1e-3) + 1e-9))
    x = np.clip(np.arange(k0, k1 + 1) * dx_mm * 1e-3, d.x_min, d.x_max)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DomainWarning)
        try:
            h, spread = net.predict_with_spread(
                x, mass_kg, load_position_mm * 1e-3, on_domain_error="raise" if strict else "warn"
            )
        except InputError as exc:  # name the model file (a re-scaled model predicts metres)
            raise type(exc)(f"MODEL {model}: {exc}") from None
    notes = [str(w.message) for w in caught if issubclass(w.category, DomainWarning)]
    for n in notes:
        say(f"warning: {n}", style="yellow")
    report_domain_warnings(notes, shown=True)  # exit code 4, listed in --json
    from skisnow.ski import SHIPPED_SKIS, breitschaedel_contact, get_ski

    kick = get_ski(net.ski).kick_zone if net.ski in SHIPPED_SKIS else None
    i_min = int(np.argmin(np.where(np.abs(x) < 0.5 * (d.x_max - d.x_min) / 2, h, np.inf)))
    summary = {
        "ski": net.ski,
        "mass_kg": mass_kg,
        "load_position_mm": load_position_mm,
        "points": int(x.size),
        "camber_height_at_balance_point_mm": float(np.interp(0.0, x, h) * 1e3),
        "min_height_mid_ski_mm": float(h[i_min] * 1e3),
        # Breitschädel (2012): gap to the plane the ski rests on below 50 µm
        "length_below_50um_mm": float(np.sum(breitschaedel_contact(x, h, kick_zone=kick)) * dx_mm),
        # one member has no spread: null, not 0 µm (which would read as "exact"); the held-out
        # error the network was trained with says what a prediction is worth
        "max_ensemble_spread_um": float(spread.max() * 1e6) if len(net.members) > 1 else None,
        "members": len(net.members),
        **_held_out_errors(net.metadata),
        "in_trained_domain": not notes,
    }
    if figure is not None:
        _profile_figure(x, h, spread, summary, figure)
    if json_out:
        emit_json(
            {
                **summary,
                "warnings": notes,
                "x_mm": x * 1e3,
                "height_mm": h * 1e3,
                "spread_um": spread * 1e6 if len(net.members) > 1 else None,
            }
        )
        return
    print_table(
        "Predicted camber profile", ["quantity", "value"], list(summary.items()), floatfmt=".4g"
    )


def _held_out_errors(metadata: dict[str, Any]) -> dict[str, float | None]:
    """The network's error on its held-out bench conditions (recorded at training) [µm]."""
    err = metadata.get("validation_errors") or {}
    return {
        f"held_out_{k}_error_um": None if err.get(f"{k}_um") is None else float(err[f"{k}_um"])
        for k in ("mean", "p95", "max")
    }


def _profile_figure(
    x: np.ndarray, h: np.ndarray, spread: np.ndarray, summary: dict[str, Any], path: Path
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 3.2), layout="constrained")
    ax.plot(x * 1e3, h * 1e3, lw=1.2, label="network")
    if np.any(spread > 0):
        ax.fill_between(
            x * 1e3, (h - 2 * spread) * 1e3, (h + 2 * spread) * 1e3, alpha=0.3, label="±2 spread"
        )
    ax.axhline(0.05, color="0.5", lw=0.8, ls=":", label="50 µm (Breitschädel)")
    ax.set_xlabel("x from the balance point [mm]")
    ax.set_ylabel("camber height h [mm]")
    ax.set_title(
        f"{summary['ski']}: m = {summary['mass_kg']:g} kg at x_m = "
        f"{summary['load_position_mm']:g} mm"
    )
    ax.legend(fontsize=8)
    from skisnow._atomic import atomic_path

    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=150)
    plt.close(fig)
