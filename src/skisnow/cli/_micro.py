"""Commands for the real contact: topo, grind, bearing, rank (thin: parse, call skisnow.micro,
render)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from skisnow._errors import InputError
from skisnow._values import parse_values, sorted_unique
from skisnow.cli._app import app, report_domain_warnings
from skisnow.cli._render import JsonOption, console, emit_json, print_table, progress_bar

__all__ = ["parse_grain_range"]


def parse_grain_range(text: str) -> np.ndarray:
    """``START:STOP:STEP`` (inclusive, µm), a list or one value → sorted unique diameters [m]."""
    from skisnow._checks import check_option_values

    values = np.round(parse_values(text, name="--grain-um"), 6)
    check_option_values(values, "grain", "--grain-um")
    return sorted_unique(values, name="--grain-um", unit="µm", positive=True) * 1e-6


def _load(source: str, pixel_um: float | None, height_unit: str, *, seed: int = 0) -> Any:
    from skisnow import micro

    path = Path(source)
    if not path.exists() and source.strip().upper() in micro.PRESETS:
        return micro.grind_preset(source, seed=seed)
    from skisnow._checks import check_value

    pixel = None if pixel_um is None else check_value(pixel_um, "pixel", where="--pixel-um") * 1e-6
    return micro.read_topography(path, pixel_size=pixel, height_unit=height_unit)


def _check_form(form: str) -> None:
    if form not in ("mean", "plane", "polynomial"):
        raise InputError(f"--form: {form!r} unknown; valid: mean, plane, polynomial")


def _cutoff(cutoff_um: float) -> float | None:
    """--cutoff-um [µm] → the low-pass cut-off [m] (0: no filter)."""
    from skisnow._checks import check_value

    check_value(cutoff_um, "cutoff", where="--cutoff-um")
    return cutoff_um * 1e-6 if cutoff_um > 0 else None


def _roughness_record(r: Any) -> dict[str, Any]:
    return {
        "Sa_um": r.Sa * 1e6,
        "Sq_um": r.Sq * 1e6,
        "Sdq": r.Sdq,
        "Ssk": r.Ssk,
        "Sku": r.Sku,
        "Ra_um": r.Ra * 1e6,
        "Rz_um": r.Rz * 1e6,
        "Rt_um": r.Rt * 1e6,
    }


_PIXEL = typer.Option("--pixel-um", help="Pixel size [µm] of .npy / text matrices.")
_HUNIT = typer.Option("--height-unit", help="Height unit of .npy / text matrices (m, um, nm).")
_FORM = typer.Option("--form", help="Form removal: mean, plane or polynomial.")
_CUTOFF = typer.Option("--cutoff-um", help="Fourier low-pass cut-off wavelength [µm]; 0 = none.")


@app.command()
def topo(
    file: Annotated[str, typer.Argument(help="Topography file (or preset S1..S5).")],
    cutoff_um: Annotated[float, _CUTOFF] = 33.0,
    form: Annotated[str, _FORM] = "plane",
    pixel_um: Annotated[float | None, _PIXEL] = None,
    height_unit: Annotated[str, _HUNIT] = "m",
    json_out: JsonOption = False,
    figure: Annotated[
        Path | None, typer.Option("--figure", help="Save the height map (PNG/SVG by suffix).")
    ] = None,
) -> None:
    """Roughness parameters of a topography (Sa, Sq, Sdq, Ssk, Sku; Ra, Rz across the ski)."""
    from skisnow import micro

    _cutoff(cutoff_um)  # checked before the file is read
    _check_form(form)
    t = _load(file, pixel_um, height_unit)
    r = micro.roughness(t, cutoff=_cutoff(cutoff_um), form=form)
    # the slope statistics of a map with holes depend on how the holes are treated
    spread = micro.sdq_spread(micro.prepare(t, cutoff=_cutoff(cutoff_um), form=form))
    doc = {
        "source": t.source,
        "grid": list(t.shape),
        "pixel_um": [t.dx * 1e6, t.dy * 1e6],
        "size_um": [t.size[0] * 1e6, t.size[1] * 1e6],
        "missing_pixels": t.n_missing,
        "form": form,
        "cutoff_um": cutoff_um if cutoff_um > 0 else None,
        "parameters": _roughness_record(r),
        "Sdq_holes": None if spread is None else spread.as_dict(),
    }
    if figure is not None:
        from skisnow.plot import save_figure, topography_figure

        doc["figures"] = [
            str(p)
            for p in save_figure(
                topography_figure(
                    micro.prepare(t, cutoff=_cutoff(cutoff_um), form=form), title=t.source
                ),
                figure,
            )
        ]
    if json_out:
        emit_json(doc)
        return
    console.print(
        f"{t.source}: {t.shape[0]} × {t.shape[1]} px, pixel {t.dx * 1e6:.4g} × "
        f"{t.dy * 1e6:.4g} µm, {t.n_missing} missing; form {form}, cut-off "
        f"{cutoff_um if cutoff_um > 0 else 'none'} µm"
    )
    rows: list[list[Any]] = [[k, v] for k, v in doc["parameters"].items()]
    if spread is not None:  # Sdq to the digits it is worth
        rows = [[k, f"{v:#.{spread.digits}g}" if k == "Sdq" else v] for k, v in rows]
    print_table("roughness", ["parameter", "value"], rows, floatfmt=".4g")
    if spread is not None:
        ways = ", ".join(f"{k} {v:.4g}" for k, v in spread.values.items())
        console.print(
            f"note: Sdq of a map with {spread.missing} missing pixels depends on how the holes "
            f"are treated: {spread.low:.4g} to {spread.high:.4g} ({100 * spread.relative:.1f} % "
            f"of the value; {ways}); printed: undefined pairs skipped, to "
            f"{spread.digits} significant digit{'s' * (spread.digits != 1)}; the filled map "
            "is the smoothest surface meeting the holes' rims, so for any surface under the "
            f"holes Sdq ≥ {spread.values['filled']:.4g}"
        )
    for p in doc.get("figures", []):
        console.print(f"figure: {p}")


@app.command()
def grind(
    preset: Annotated[
        str, typer.Argument(help="Preset S1..S5 (the five structures of Scherge et al. (2021)).")
    ],
    out: Annotated[Path, typer.Option("--out", help="Output file: .x3p, .npy, .txt or .csv.")],
    size_um: Annotated[
        float, typer.Option("--size-um", help="Side of the square map [µm].")
    ] = 1000.0,
    pixel_um: Annotated[float, typer.Option("--pixel-um", help="Pixel size [µm].")] = 1.0,
    seed: Annotated[int, typer.Option("--seed", help="Random seed (grit, depth jitter).")] = 0,
    json_out: JsonOption = False,
) -> None:
    """Write a synthetic grinding structure (seeded)."""
    from skisnow import micro
    from skisnow._checks import check_memory, check_value

    pixel_um = check_value(pixel_um, "pixel", where="--pixel-um")
    size_um = check_value(size_um, "map_size", where="--size-um")
    n = size_um / pixel_um
    check_memory(
        n * n * 8 * 8,
        where=f"--size-um {size_um:g} --pixel-um {pixel_um:g}",
        what=f"a map of {n:.3g} × {n:.3g} pixels",
        hint="use a smaller map or larger pixels",
    )
    t = micro.grind_preset(preset, size=size_um * 1e-6, dx=pixel_um * 1e-6, seed=seed)
    path = micro.write_topography(t, out)
    spec = micro.PRESETS[preset.strip().upper()]
    doc = {
        "preset": spec.name,
        "description": spec.description,
        "out": str(path),
        "grid": list(t.shape),
        "pixel_um": pixel_um,
        "seed": seed,
    }
    if json_out:
        emit_json(doc)
        return
    console.print(
        f"{spec.name} ({spec.description}): {t.shape[0]} × {t.shape[1]} px at {pixel_um} µm "
        f"→ {path}"
    )
    if path.suffix.lower() in (".npy", ".txt", ".csv"):
        console.print(f"(read it back with --pixel-um {pixel_um}; heights are in m)")


@app.command()
def bearing(
    source: Annotated[str, typer.Argument(help="Topography file or preset S1..S5.")],
    temperature_c: Annotated[
        float, typer.Option("--temperature-c", help="Snow temperature [°C].")
    ] = -2.0,
    pressure_kpa: Annotated[
        float, typer.Option("--pressure-kpa", help="Macroscopic pressure [kPa].")
    ] = 20.0,
    grain_um: Annotated[
        str, typer.Option("--grain-um", help="Grain diameters [µm]: START:STOP:STEP or list.")
    ] = "450:750:10",
    hardness_model: Annotated[
        str, typer.Option("--hardness-model", help="Ice hardness: poirier or makkonen.")
    ] = "poirier",
    cutoff_um: Annotated[float, _CUTOFF] = 33.0,
    form: Annotated[str, _FORM] = "plane",
    stride: Annotated[int, typer.Option("--stride", help="Raster step [pixels].")] = 1,
    workers: Annotated[int, typer.Option("--workers", help="Threads (grain sizes).")] = 2,
    pixel_um: Annotated[float | None, _PIXEL] = None,
    height_unit: Annotated[str, _HUNIT] = "m",
    seed: Annotated[int, typer.Option("--seed", help="Seed of a preset.")] = 0,
    json_out: JsonOption = False,
    figure: Annotated[
        Path | None, typer.Option("--figure", help="Save A_fr(D) (PNG/SVG by suffix).")
    ] = None,
) -> None:
    """Bearing model of ice grains (eq. 5–9): A_fr(D), grain-averaged ⟨A_fr⟩ (eq. 13), regime."""
    import warnings

    from skisnow import micro
    from skisnow._checks import check_value
    from skisnow._errors import DomainWarning

    check_value(temperature_c, "temperature", where="--temperature-c")
    check_value(pressure_kpa, "pressure", where="--pressure-kpa")
    for option, value in (("--stride", stride), ("--workers", workers)):
        if value < 1:
            raise InputError(f"{option}: need an integer >= 1, got {value}")
    _cutoff(cutoff_um)
    _check_form(form)
    if hardness_model not in ("poirier", "makkonen"):
        raise InputError(f"--hardness-model: {hardness_model!r} unknown; valid: poirier, makkonen")
    diameters = parse_grain_range(grain_um)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DomainWarning)
        regime = micro.deformation_regime(temperature_c, model=hardness_model)
    notes = [str(w.message) for w in caught]
    pressure = pressure_kpa * 1e3
    if pressure >= regime.ice_hardness:  # p/H >= 1: no bearing model (eq. 5-9 need p < H)
        raise InputError(
            f"--pressure-kpa: {pressure_kpa:g} kPa is not below the ice hardness at "
            f"{temperature_c:g} °C ({regime.ice_hardness * 1e-3:.0f} kPa, {hardness_model}): the "
            "flat base would bear on the ice over its whole area (p/H >= 1); a ski presses the "
            "snow at tens to hundreds of kPa (was the pressure given in Pa?)"
        )
    t = micro.prepare(
        _load(source, pixel_um, height_unit, seed=seed), cutoff=_cutoff(cutoff_um), form=form
    )
    if not regime.bearing_model_applies:
        notes.append("the base is softer than the ice here: the bearing model does not apply")
    report_domain_warnings(notes, shown=not json_out)  # exit code 4, listed in --json
    with progress_bar("bearing model", total=diameters.size, disable=json_out) as bar:
        sweep = micro.bearing_sweep(
            t,
            diameters=diameters,
            pressure=pressure,
            hardness=regime.ice_hardness,
            stride=stride,
            workers=workers,
            progress=bar,
        )
    averaged = (
        micro.grain_average(sweep.diameters, sweep.fractional_area) if diameters.size >= 2 else None
    )
    doc: dict[str, Any] = {
        "source": t.source,
        "temperature_c": temperature_c,
        "pressure_kpa": pressure_kpa,
        "regime": {
            "yielding": regime.yielding,
            "ice_hardness_mpa": regime.ice_hardness * 1e-6,
            "base_hardness_mpa": regime.base_hardness * 1e-6,
            "hardness_model": hardness_model,
        },
        "flat_base_fractional_area": pressure / regime.ice_hardness,
        "grains": [
            {
                "diameter_um": round(float(d) * 1e6, 6),
                "fractional_area": a,
                "fractional_area_std": s,
                "mean_penetration_um": pm * 1e6,
                "max_penetration_um": px * 1e6,
                "positions": int(n),
            }
            for d, a, s, pm, px, n in zip(
                sweep.diameters,
                sweep.fractional_area,
                sweep.fractional_area_std,
                sweep.mean_penetration,
                sweep.max_penetration,
                sweep.n_positions,
                strict=True,
            )
        ],
        "grain_averaged_fractional_area": averaged,
        "stride": stride,
        "notes": notes,
    }
    if figure is not None:
        from skisnow.plot import bearing_figure, save_figure

        fig = bearing_figure(
            sweep.diameters,
            sweep.fractional_area,
            reference=pressure / regime.ice_hardness,
            grain_density=micro.PAPER_GRAIN_FIT,
            title=t.source,
        )
        doc["figures"] = [str(p) for p in save_figure(fig, figure)]
    if json_out:
        emit_json(doc)
        return
    console.print(
        f"{t.source}: T = {temperature_c} °C, H_ice = {regime.ice_hardness * 1e-6:.3g} MPa "
        f"({hardness_model}), H_UHMWPE = {regime.base_hardness * 1e-6:.3g} MPa → the "
        f"{regime.yielding} yields; p = {pressure_kpa} kPa; flat base p/H = "
        f"{pressure / regime.ice_hardness:.5g}"
    )
    print_table(
        "bearing model (eq. 5–9)",
        ["D [µm]", "A_fr", "std", "mean δ [µm]", "max δ [µm]", "positions"],
        [
            [
                g["diameter_um"],
                g["fractional_area"],
                g["fractional_area_std"],
                g["mean_penetration_um"],
                g["max_penetration_um"],
                g["positions"],
            ]
            for g in doc["grains"]
        ],
        floatfmt=".5g",
    )
    if averaged is not None:
        console.print(f"grain-averaged ⟨A_fr⟩ (eq. 13, seed f(D)): {averaged:.6g}")
    for n in notes:
        console.print(f"note: {n}")
    for p in doc.get("figures", []):
        console.print(f"figure: {p}")


@app.command()
def rank(
    table: Annotated[
        Path | None,
        typer.Argument(help="CSV: structure, glide_time_s, descriptor columns (e.g. A_fr)."),
    ] = None,
    paper_tables: Annotated[
        bool,
        typer.Option(
            "--paper-tables", help="Recompute Scherge et al.'s (2021) Table 4 r from its Table 3."
        ),
    ] = False,
    alpha: Annotated[float, typer.Option("--alpha", help="Significance level.")] = 0.05,
    json_out: JsonOption = False,
) -> None:
    """Rank structures by glide time; Pearson r of every descriptor (eq. 10) with significance."""
    from skisnow import micro

    if table is None and not paper_tables:
        raise InputError("give a TABLE.csv or --paper-tables")
    doc: dict[str, Any] = {}
    if table is not None:
        from skisnow._checks import check_value

        check_value(alpha, "alpha", where="--alpha")
        rt = micro.read_rank_table(table, alpha=alpha)
        doc["structures"] = [
            {"structure": s, "glide_time_s": t, "rank": r}
            for s, t, r in zip(rt.structures, rt.glide_times, rt.ranks, strict=True)
        ]
        doc["critical_r"] = rt.critical_r
        doc["alpha"] = alpha
        doc["correlations"] = [
            {
                "descriptor": c.name,
                "r": c.r,
                "p_value": c.p_value,
                "significant": c.significant,
                "descriptor_ranks": micro.rank(rt.descriptors[c.name]).tolist(),
            }
            for c in rt.correlations
        ]
    if paper_tables:
        doc["paper_table4"] = micro.table4_comparison()
    if json_out:
        emit_json(doc)
        return
    if table is not None:
        print_table(
            f"ranking ({table})",
            ["structure", "glide time [s]", "rank"],
            [[s["structure"], s["glide_time_s"], s["rank"]] for s in doc["structures"]],
            floatfmt=".4g",
        )
        print_table(
            f"Pearson r with glide time (n = {len(doc['structures'])}, |r| > "
            f"{doc['critical_r']:.3f} significant at α = {alpha})",
            ["descriptor", "r", "p", "significant"],
            [
                [c["descriptor"], c["r"], c["p_value"], "yes" if c["significant"] else "no"]
                for c in doc["correlations"]
            ],
            floatfmt=".3f",
        )
    if paper_tables:
        print_table(
            "Scherge et al. (2021), Table 4: r recomputed from Table 3 glide times vs published",
            ["parameter", "r published", "r (averages)", "p", "r (runs)", "difference"],
            [
                [
                    r["parameter"],
                    r["r_published"],
                    r["r_from_averages"],
                    r["p_value"],
                    r["r_from_runs"],
                    r["difference"],
                ]
                for r in doc["paper_table4"]
            ],
            floatfmt=".3f",
        )
