"""The ``skisnow cycle`` command: the contact over a load cycle, frame by frame.

Thin, as the other workflow commands (:mod:`skisnow.cli._workflows`, whose options and CSV writer
it shares): it parses a load history (a CSV file or a built-in stride template), calls
:func:`skisnow.workflows.run_cycle` (the contact of Kalliorinne et al. 2023, eq. 2–3, at every
frame, warm-started) and renders the per-frame table, the kick-zone contact summary, CSV files and
figures. Field units in every option and column (kg, mm, MPa, kPa, s, N).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from skisnow._atomic import atomic_path
from skisnow._errors import InputError
from skisnow.cli._app import app, report_converged, run_annotations
from skisnow.cli._media import (
    BaseOption,
    FilmCutoffOption,
    ShearStrengthOption,
    SlidingSpeedOption,
    SnowOption,
    SnowTemperatureOption,
    ViscosityOption,
    friction_parameters,
    resolve_base,
    resolve_snow,
)
from skisnow.cli._render import JsonOption, emit_json, print_table, progress_bar, show
from skisnow.cli._workflows import _MODEL, _OUT, _POINTS, _SNOW, write_csv


def cycle_records(ds: Any) -> list[dict[str, Any]]:
    """One record per frame, field units (s, N, mm, kPa)."""
    recs = []
    for i, t in enumerate(ds["time"].values):
        rec: dict[str, Any] = {
            "t_s": float(t),
            "force_n": float(ds["load"].values[i]),
            "load_position_mm": float(ds["load_position"].values[i] * 1e3),
            "loaded": bool(ds["loaded"].values[i]),
        }
        for j, zone in enumerate(ds["zone"].values):
            rec[f"{zone}_length_mm"] = float(ds["length"].values[i, j] * 1e3)
            rec[f"{zone}_area_cm2"] = float(ds["area"].values[i, j] * 1e4)
            rec[f"{zone}_mean_pressure_kpa"] = float(ds["mean_pressure"].values[i, j] * 1e-3)
            rec[f"{zone}_peak_pressure_kpa"] = float(ds["max_pressure"].values[i, j] * 1e-3)
            rec[f"{zone}_load_share"] = float(ds["load_share"].values[i, j])
        rec["kick_contact"] = bool(ds["kick_contact"].values[i])
        if "viscous_force" in ds:
            rec["real_area_mm2"] = float(ds["real_area"].values[i] * 1e6)
            rec["reciprocal_separation_m"] = float(ds["reciprocal_separation"].values[i])
            rec["dry_force_n"] = float(ds["dry_force"].values[i])
            rec["viscous_force_n"] = float(ds["viscous_force"].values[i])
            rec["lubricated_force_n"] = float(ds["lubricated_force"].values[i])
        rec["converged"] = bool(ds["converged"].values[i])
        recs.append(rec)
    return recs


def real_record(ds: Any) -> dict[str, Any]:
    """The friction proxies over the cycle in field units (:func:`real_cycle_summary`)."""
    from skisnow.workflows import real_cycle_summary

    s = real_cycle_summary(ds)
    return {
        "mean_real_area_mm2": s["mean_real_area"] * 1e6,
        "mean_dry_force_n": s["mean_dry_force"],
        "mean_viscous_force_n": s["mean_viscous_force"],
        "mean_lubricated_force_n": s["mean_lubricated_force"],
        "viscous_impulse_ns": s["viscous_force_impulse"],
        "load_impulse_ns": s["load_impulse"],
        "mu": s["mu"],
        "mu_lubricated": s["mu_lubricated"],
    }


def summary_record(ds: Any) -> dict[str, Any]:
    """The kick-zone contact summary of a cycle in field units."""
    from skisnow.workflows import kick_contact_summary

    s = kick_contact_summary(ds)
    # a ski without a kick zone (a skate) has no grip wax: its kick values are absent (None:
    # a dash in text, an empty CSV cell, JSON null), not a contact time of 0 s
    kick = bool(ds.attrs.get("kick_zone"))
    return {
        "history": ds.attrs["history"],
        "route": ds.attrs["route"],
        "kick_contact_time_s": s["contact_time"] if kick else None,
        "loaded_time_s": s["loaded_time"],
        "kick_fraction_of_loaded": s["fraction_of_loaded"] if kick else None,
        "first_touch_s": s["first_touch"] if kick else None,
        "last_touch_s": s["last_touch"] if kick else None,
        "touch_downs": s["episodes"] if kick else None,
        "time_resolution_s": s["resolution"],  # one frame interval: what the times are worth
        "max_kick_share": s["max_kick_share"] if kick else None,
        "max_kick_length_mm": s["max_kick_length"] * 1e3 if kick else None,
        "peak_force_n": float(np.max(ds["load"].values)),
        "peak_pressure_kpa": float(np.nanmax(ds["max_pressure"].values, initial=0.0) * 1e-3),
    }


@app.command()
def cycle(
    ski: Annotated[str, typer.Argument(help="A shipped ski name, a ski file or a bench file.")],
    snow_modulus_mpa: float | None = _SNOW,
    # the snow, base and friction options, defined once in cli/_media.py; Typer needs them
    # listed in each command's own signature
    snow: SnowOption = None,
    snow_temperature_c: SnowTemperatureOption = None,
    base: BaseOption = None,
    shear_strength_mpa: ShearStrengthOption = None,
    viscosity_mpa_s: ViscosityOption = None,
    sliding_speed_m_s: SlidingSpeedOption = None,
    film_cutoff_nm: FilmCutoffOption = None,
    load_history: Annotated[
        Path | None,
        typer.Option(
            "--load-history",
            help="CSV with columns t_s, force_n or mass_kg, load_position_mm.",
        ),
    ] = None,
    template: Annotated[
        str | None,
        typer.Option(
            "--template",
            help="Built-in cycle: diagonal, double_poling, skate_g3, or all (the stride table).",
        ),
    ] = None,
    body_mass_kg: Annotated[
        float | None, typer.Option("--body-mass-kg", help="Body mass in kg (with --template).")
    ] = None,
    cycle_s: Annotated[
        float | None, typer.Option("--cycle-s", help="Cycle time in s (template's default).")
    ] = None,
    frames: Annotated[
        int | None,
        typer.Option("--frames", help="Frames over the cycle (template: 100; file: its rows)."),
    ] = None,
    profile_source: Annotated[
        str,
        typer.Option(
            "--profile-source",
            help="auto (= beam, the default route of every ski), beam, or network (the shipped "
            "camber network, inside its trained domain only).",
        ),
    ] = "auto",
    ski_model: str = _MODEL,
    points: int = _POINTS,
    out: Path | None = _OUT,
    animation: Annotated[
        Path | None,
        typer.Option("--animation", help="Write an animation (.gif, or .mp4 with ffmpeg)."),
    ] = None,
    animation_speed: Annotated[
        float,
        typer.Option(
            "--animation-speed",
            help="Playback speed of the animation: 1 = real time (default), 0.25 = slow "
            "motion; printed on every frame.",
        ),
    ] = 1.0,
    show_template: Annotated[
        bool, typer.Option("--show-template", help="Print the template's knots and source.")
    ] = False,
    samples: Annotated[
        int,
        typer.Option(
            "--samples",
            help="Posterior samples of an identified ski for the 95 % intervals of the cycle's "
            "summary (default 100: each sample runs the whole cycle; the Monte Carlo error of "
            "the ends is reported; 0: no intervals). A ski without bands has none.",
        ),
    ] = 100,
    json_out: JsonOption = False,
) -> None:
    """The contact over a load cycle, frame by frame (warm-started): zones, pressures, and when
    and for how long the grip wax touches the snow (with 95 % intervals for an identified ski)."""
    from skisnow.cli._intervals import (
        check_samples,
        cycle_uncertainty_doc,
        no_uncertainty_note,
        print_cycle_uncertainty,
    )
    from skisnow.workflows import (
        TEMPLATES,
        cycle_intervals,
        read_load_history,
        resolve_ski,
        run_cycle,
        template_history,
    )

    if (load_history is None) == (template is None):
        raise InputError("give exactly one of --load-history FILE or --template NAME")
    snow_obj, e = resolve_snow(snow, snow_modulus_mpa, temperature_c=snow_temperature_c)
    snow_modulus_mpa = e * 1e-6
    texture = resolve_base(base, snow_obj)
    friction = friction_parameters(
        shear_strength_mpa=shear_strength_mpa,
        viscosity_mpa_s=viscosity_mpa_s,
        sliding_speed_m_s=sliding_speed_m_s,
        film_cutoff_nm=film_cutoff_nm,
    )
    if ski_model not in ("rigid", "flexible"):
        raise InputError(f"--ski-model must be rigid or flexible, got {ski_model!r}")
    if not (np.isfinite(animation_speed) and animation_speed > 0):
        raise InputError(f"--animation-speed must be a positive number, got {animation_speed!r}")
    if frames is not None and frames < 2:
        raise InputError(f"--frames must be at least 2, got {frames}")
    check_samples(samples)
    histories = []
    if template is not None:
        names = list(TEMPLATES) if template == "all" else [template]
        if template != "all" and template not in TEMPLATES:
            raise InputError(
                f"--template must be one of {', '.join(TEMPLATES)} or all, got {template!r}"
            )
        if body_mass_kg is None:
            raise InputError("--template needs --body-mass-kg")
        if show_template:
            for name in names:
                tpl = TEMPLATES[name]
                print_table(
                    f"{tpl.technique}: {tpl.duration:g} s — {tpl.citation}",
                    ["phase", "force [BW]", "load_position_mm"],
                    [[k["phase"], k["force_bw"], k["load_position_mm"]] for k in tpl.knots()],
                )
        for name in names:
            histories.append(
                (
                    name,
                    template_history(
                        name, body_mass=body_mass_kg, n_frames=frames or 100, duration=cycle_s
                    ),
                )
            )
    else:
        assert load_history is not None
        h = read_load_history(load_history)
        histories.append((load_history.stem, h.resample(frames) if frames else h))
    from skisnow._checks import check_memory
    from skisnow._resources import check_solves

    n_frames = sum(h.time.size for _, h in histories)
    where = "--frames" if frames or template is not None else f"--load-history {load_history}"
    check_solves(n_frames, where=where, what=f"{n_frames:,} frames",
                 hint="resample it with --frames, or cut it into cycles")  # fmt: skip
    per_frame = 7 * 8 * 8 + (2 * 8 * points if animation is not None else 0)
    check_memory(n_frames * per_frame, where=where, what=f"{n_frames:,} frames of {points} "
                 "stations", hint="use fewer --frames")  # fmt: skip
    results, uncertainty = [], {}
    fs = resolve_ski(ski)  # once (a bench file is identified once for every cycle)
    for name, history in histories:
        with progress_bar(f"cycle {name}", disable=json_out) as update:
            ds = run_cycle(
                fs,
                history,
                snow_modulus=snow_modulus_mpa * 1e6,
                profile_source=profile_source,  # type: ignore[arg-type]
                n_points=points,
                keep_fields=animation is not None,
                ski_model=ski_model,  # type: ignore[arg-type]
                progress=update,
                base=texture,
                snow=snow_obj,
                friction=friction,
            )
        report_converged(bool(ds["converged"].all()))
        results.append((name, ds))
        with progress_bar(f"intervals {name}", disable=json_out or not fs.ski.has_posterior):
            iv = cycle_intervals(fs, history, ds, snow_modulus=snow_modulus_mpa * 1e6,
                                 samples=samples, n_points=points, ski_model=ski_model)  # fmt: skip
        uncertainty[name] = cycle_uncertainty_doc(iv, no_uncertainty_note(fs.ski, samples))
    files: list[str] = []
    for name, ds in results:
        # the same names for one cycle as for several: cycle_<name>.csv, .nc, .png, .svg
        suffix = f"_{name}"
        if out is not None:
            from skisnow.plot import plot_cycle, save_figure

            files.append(str(write_csv(out / f"cycle{suffix}.csv", cycle_records(ds))))
            with atomic_path(out / f"cycle{suffix}.nc") as tmp:
                ds.to_netcdf(tmp)  # the whole Dataset (SI units in the attributes)
            files.append(str(out / f"cycle{suffix}.nc"))
            files += [str(p) for p in save_figure(plot_cycle(ds), out / f"cycle{suffix}")]
        if animation is not None:
            from skisnow.plot import animate_cycle

            many = len(results) > 1
            target = animation.with_name(f"{animation.stem}{suffix if many else ''}"
                                         f"{animation.suffix}")  # fmt: skip
            with (
                progress_bar(f"animation {name}", disable=json_out) as update,
                atomic_path(target) as tmp,
            ):
                animate_cycle(ds, tmp, speed=animation_speed, progress=update)
            files.append(str(target))
    summaries = [{"cycle": name, **summary_record(ds)} for name, ds in results]
    real = [{"cycle": name, **real_record(ds)} for name, ds in results if "viscous_force" in ds]
    notes = [ds.attrs["route_note"] for _, ds in results if ds.attrs["route_note"]]
    if out is not None:
        files.append(str(write_csv(out / "cycle_summary.csv", summaries)))
    if json_out:
        emit_json(
            {
                **run_annotations(),
                "ski": results[0][1].attrs["ski"],
                "snow_modulus_mpa": snow_modulus_mpa,
                "summaries": summaries,
                "uncertainty": uncertainty,
                "real_contact": real,
                "friction_assumptions": results[0][1].attrs.get("friction", ""),
                "notes": notes,
                "sources": {name: ds.attrs["history_source"] for name, ds in results},
                "frames": {name: cycle_records(ds) for name, ds in results},
                "files": files,
            }
        )
        return
    for note in notes:
        show(f"note: {note}", style="bold yellow")
    print_table(
        f"{'Kick-zone contact' if results[0][1].attrs.get('kick_zone') else 'Contact'} over "
        f"the cycle: {results[0][1].attrs['ski']} on "
        f"{snow_modulus_mpa:g} MPa snow",
        [
            "cycle",
            "route",
            "wax touches [s]",
            "loaded [s]",
            "fraction",
            "first [s]",
            "last [s]",
            "touch-downs",
            "max kick share",
            "peak force [N]",
        ],
        [
            [
                s["cycle"],
                s["route"],
                s["kick_contact_time_s"],
                s["loaded_time_s"],
                s["kick_fraction_of_loaded"],
                s["first_touch_s"],
                s["last_touch_s"],
                s["touch_downs"],
                s["max_kick_share"],
                s["peak_force_n"],
            ]
            for s in summaries
        ],
    )
    for s in summaries:  # what the times are worth (more frames: --frames)
        show(f"{s['cycle']}: times resolved to one frame interval, {s['time_resolution_s']:.3g} s")
    for name, doc in uncertainty.items():
        print_cycle_uncertainty(name, doc)
    if real:
        print_table(
            f"Friction proxies over the stride: base {results[0][1].attrs['base']} × snow "
            f"{results[0][1].attrs['snow']} (time means over the cycle)",
            ["cycle", "real area [mm²]", "τ·A_r [N]", "η·v·∫1/u [N]", "µ dry", "µ lubricated"],
            [
                [r["cycle"], r["mean_real_area_mm2"], r["mean_dry_force_n"],
                 r["mean_viscous_force_n"], r["mu"], r["mu_lubricated"]]
                for r in real
            ],
        )  # fmt: skip
        show(f"assumptions: {results[0][1].attrs['friction']}")
    for name, ds in results:
        if ds.attrs["history_source"] and template is not None:
            show(f"{name}: {ds.attrs['history_source']}")
    for f in files:
        show(f"wrote {f}")
