"""The end-to-end demo command: the shipped skis on the bench, then their contact with snow."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Annotated, Any

import typer

from skisnow._errors import FileFormatError, InputError
from skisnow.cli._app import app
from skisnow.cli._render import JsonOption, SkiModelOption, console, emit_json

__all__ = ["run_contact_demo", "run_ski_demo"]


def run_ski_demo(out: Path, *, progress: bool = True) -> dict[str, Any]:
    """Bench both plausible skis, compute their metrics and draw their camber profiles into ``out``.

    Returns a document with the metrics and the files written.
    """
    from skisnow.bench import run_bench, write_bench
    from skisnow.cli._render import progress_bar
    from skisnow.cli._ski import metrics_documents
    from skisnow.plot import plot_camber_profiles, save_figure
    from skisnow.ski import PLAUSIBLE_SKIS

    out.mkdir(parents=True, exist_ok=True)
    files: list[str] = []
    docs = []
    for name in PLAUSIBLE_SKIS:
        with progress_bar(f"bench {name}", disable=not progress) as bar:
            data = run_bench(name, progress=bar)
        path = write_bench(data, out / f"bench_{name}.csv")  # CSV: no optional dependency
        files.append(str(path))
        docs.extend(metrics_documents(str(path), body_mass_kg=65.0, load_position_mm=-80.0))
    fig = plot_camber_profiles(PLAUSIBLE_SKIS)
    files.extend(str(p) for p in save_figure(fig, out / "camber_profiles", formats=("png",)))
    return {"output_dir": str(out), "files": files, "metrics": docs}


def network_or_beam() -> tuple[str, str]:
    """``('network', '')`` when both plausible skis have their pretrained network, else
    ``('beam', reason)``.

    Only a network that is not shipped falls back to the beam; a shipped model file that is
    corrupt, truncated or of another format version raises :class:`~skisnow.FileFormatError`
    (a broken installation must not pass silently as a beam demo).
    """
    from skisnow.network import shipped_network
    from skisnow.ski import PLAUSIBLE_SKIS

    try:
        for name in PLAUSIBLE_SKIS:
            shipped_network(name)
    except FileFormatError:
        raise
    except InputError as exc:  # no network shipped for this ski: say so, use the beam
        return "beam", f"shipped networks unavailable ({exc}); profiles from the beam"
    return "network", ""


#: The load cases of Kalliorinne et al. (2023), Figures 4–7: (figure, ski, m [kg], x_m [mm],
#: E_counter [MPa]).
PAPER_CASES: tuple[tuple[str, str, float, float, float], ...] = (
    ("fig4", "classic", 30, -120, 70_000),
    ("fig4", "skate", 30, -120, 70_000),
    ("fig5", "skate", 30, -120, 100),
    ("fig5", "skate", 60, -120, 100),
    ("fig6", "classic", 60, -210, 100),
    ("fig6", "classic", 60, -70, 100),
    ("fig7", "classic", 30, -120, 50),
    ("fig7", "classic", 30, -120, 200),
)


def run_contact_demo(
    out: Path,
    *,
    profile_source: str,
    workers: int | None = 0,
    n_points: int = 4096,
    masses: Any = None,
    snow_moduli: Any = None,
    progress: bool = True,
    ski_model: str = "rigid",
) -> dict[str, Any]:
    """The contact part of the demo: the analogues of the paper's Figures 4–7 (contact pictures),
    Figures 8–9 (maps of a sweep over load and snow, both skis), the explorer page of both skis
    and one HTML report per ski (linking the explorer).

    ONE sweep feeds the maps, the explorer and the reports: the paper's snow moduli (default
    ``snow_moduli`` 20–400 MPa in 20 MPa steps) and stations (``n_points`` 4096) with a coarser
    load step (``masses`` [kg], default 5–130 kg in 5 kg steps), at x_m = −120 mm, with the
    fields along the ski kept for the explorer: 1040 contact solves. The demo's explorer
    therefore moves the mass and the snow at −120 mm only; ``skisnow explore`` solves the
    paper's six load positions. ``skisnow sweep`` and ``examples/fig8_9_maps.py`` run the paper's
    1 kg steps. Figures are written as PNG (the reports carry their own SVG).
    ``ski_model='flexible'``: every case and map with the ski's beam bending on the snow.
    """
    import math

    import numpy as np

    from skisnow.cli._render import progress_bar
    from skisnow.explore import explorer_from_sweeps, explorer_spec_options, write_explorer
    from skisnow.pipeline import solve_case
    from skisnow.plot import plot_contact, save_figure, sweep_figures
    from skisnow.report import study_ski, write_report
    from skisnow.ski import PLAUSIBLE_SKIS
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep

    png = ("png",)
    out.mkdir(parents=True, exist_ok=True)
    files: list[str] = []
    cases = []
    for fig_no, ski, m, x_mm, e_mpa in PAPER_CASES:
        case = solve_case(ski, mass=m, load_position=x_mm * 1e-3, snow_modulus=e_mpa * 1e6,
                          profile_source=profile_source, n_points=n_points,
                          ski_model=ski_model)  # fmt: skip
        solution, zones = case.solution, case.zones
        stem = f"{fig_no}_{ski}_{m:g}kg_x{x_mm:g}mm_{e_mpa:g}MPa"
        snow = "stone" if e_mpa >= 10_000 else f"snow modulus {e_mpa:g} MPa"
        title = f"{ski}: {m:g} kg at {x_mm:g} mm from the balance point, {snow}"
        files += [str(p) for p in save_figure(plot_contact(solution, zones, title=title),
                                              out / stem, formats=png)]  # fmt: skip
        cases.append(
            {
                "figure": fig_no, "ski": ski, "mass_kg": m, "load_position_mm": x_mm,
                "snow_modulus_mpa": e_mpa, "converged": solution.converged,
                "profile_route": case.route, "merged": zones.merged,
                **{f"{z}_length_mm": zones[z].length * 1e3 for z in ("rear", "middle", "front")},
                **{f"{z}_mean_pressure_kpa": zones[z].mean_pressure / 1e3
                   for z in ("rear", "middle", "front")},
                **{f"{r.name}_length_mm": r.length * 1e3 for r in zones.footprint.regions},
                **{f"{r.name}_load_share": r.load_share for r in zones.footprint.regions},
            }
        )  # fmt: skip

    spec = SweepSpec(
        skis=tuple(PLAUSIBLE_SKIS),
        masses=np.arange(5.0, 131.0, 5.0) if masses is None else masses,
        load_positions=(-0.120,),
        snow_moduli=np.arange(20.0, 401.0, 20.0) * 1e6 if snow_moduli is None else snow_moduli,
        profile_source=profile_source,
        n_points=n_points,
        ski_model=ski_model,
        **explorer_spec_options(math.gcd(512, n_points)),  # the explorer's fields and zones
    )  # fmt: skip
    store = out / (f"maps_{profile_source}.zarr" if ski_model == "rigid" else "maps_flexible.zarr")
    with progress_bar("sweep (Figures 8-9)", disable=not progress, transient=False) as bar:
        run = run_sweep(spec, store, workers=workers, on_progress=bar)
    ds = open_sweep(store)
    files.append(str(store))
    # Figure 8: {ski}_x-120mm_area, Figure 9: {ski}_x-120mm_mean_pressure, and the load share
    kinds = ("area", "mean_pressure", "load_share")
    for stem, fig in sweep_figures(ds, load_positions_mm=[-120.0], kinds=kinds).items():
        files += [str(p) for p in save_figure(fig, out / stem, formats=png)]
    # The explorer page of both skis from the same sweep (nothing solved again)
    explorer = explorer_from_sweeps({ski_model: ds}, spec)
    page, _ = write_explorer(spec.skis, out / "explore.html", dataset=explorer)
    files.append(str(page))
    for ski in spec.skis:
        study = study_ski(ski, dataset=ds, profile_source=profile_source, n_points=n_points,
                          ski_model=ski_model)  # fmt: skip
        files.append(str(write_report(study, out, explorer=page.name)))
    return {
        "profile_source": profile_source,
        "ski_model": ski_model,
        "cases": cases,
        "sweep": {
            "store": str(store), "points": spec.n_points_total,
            "chunks_computed": len(run.computed), "chunks_reused": len(run.skipped),
            "wall_time_s": run.wall_time,
        },
        "files": files,
    }  # fmt: skip


#: What the side process of :func:`_warm_compiled_kernels` solves: one flexible and one rigid
#: case of the shipped classic, so that numba compiles (and caches) the kernels the demo needs.
_WARM_CODE = (
    "from skisnow.pipeline import solve_case\n"
    "for model in ('flexible', 'rigid'):\n"
    "    solve_case('classic', mass=60.0, load_position=-0.12, snow_modulus=100e6,\n"
    "               n_points=1024, ski_model=model)\n"
)


def _warm_compiled_kernels() -> subprocess.Popen | None:
    """Start a side process that compiles the contact solvers' numba kernels into numba's
    on-disk cache while the demo does its first, serial steps.

    A first run on a fresh install compiles them once (about 8 s of CPU, issue 29's kernels);
    done in a second process, that work uses the second core instead of delaying the demo,
    which then loads the kernels from the cache (or, if it gets there first, compiles them
    itself: the cache is written atomically, so a race costs CPU, never a wrong result). Later
    runs find the cache and the side process ends at once. Best effort: never an error.
    """
    try:
        return subprocess.Popen(
            [sys.executable, "-c", _WARM_CODE],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    except OSError:
        return None


@app.command()
def demo(
    out: Annotated[Path, typer.Option("--out", help="Output directory.")] = Path("skisnow-output"),
    json_out: JsonOption = False,
    workers: Annotated[
        int, typer.Option("--workers", help="Dask workers for the maps' sweep (0: in process).")
    ] = 0,
    ski_model: SkiModelOption = "rigid",
    profile_source: Annotated[
        str,
        typer.Option(
            "--profile-source",
            help="Loaded profiles of the rigid route: beam (the shipped skis themselves, the "
            "default) or network (their pretrained camber networks, which emulate the beam "
            "within 6-7 µm on average; the beam is used, with a note, where none is shipped).",
        ),
    ] = "beam",
) -> None:
    """Run the end-to-end demo on the shipped skis and say where the files went."""
    import time

    if profile_source not in ("beam", "network"):
        raise InputError(f"--profile-source must be beam or network, got {profile_source!r}")
    if ski_model not in ("rigid", "flexible"):
        raise InputError(f"--ski-model must be rigid or flexible, got {ski_model!r}")
    t0 = time.perf_counter()
    warm = _warm_compiled_kernels()
    try:
        doc, source = _demo_steps(out, json_out, workers, ski_model, profile_source)
    finally:
        if warm is not None and warm.poll() is None:
            warm.kill()
            warm.wait()
    doc["wall_time_s"] = time.perf_counter() - t0
    _print_demo(doc, json_out, ski_model, source)


def _demo_steps(
    out: Path, json_out: bool, workers: int, ski_model: str, profile_source: str
) -> tuple[dict[str, Any], str]:
    """The demo's work (the bench, the paper's cases, the maps, the explorer, the reports)."""
    doc = run_ski_demo(out, progress=not json_out)
    # the networks are loaded (and checked: a broken shipped model is an error, never a silent
    # switch) only when the demo uses them; the default beam route needs no JAX
    source, note = network_or_beam() if profile_source == "network" else ("beam", "")
    contact = run_contact_demo(
        out, profile_source=source, workers=workers, progress=not json_out, ski_model=ski_model
    )
    doc["contact"] = contact
    doc["files"] = doc["files"] + contact["files"]
    doc["note"] = note
    return doc, source


def _print_demo(doc: dict[str, Any], json_out: bool, ski_model: str, source: str) -> None:
    """The demo's answer: JSON, or the tables and where the files went."""
    from skisnow.cli._ski import print_metrics_table

    contact, note = doc["contact"], doc["note"]
    if json_out:
        emit_json(doc)
        return
    print_metrics_table(
        doc["metrics"],
        "Shipped skis on the virtual bench (65 kg skier, load at -80 mm from the balance point)",
    )
    rows = [
        (c["figure"], c["ski"], c["mass_kg"], c["load_position_mm"], c["snow_modulus_mpa"],
         c["rear_length_mm"], c["middle_length_mm"], c["front_length_mm"],
         "yes" if c["merged"] else "no")
        for c in contact["cases"]
    ]  # fmt: skip
    from skisnow.cli._render import print_table

    print_table(
        f"The paper's load cases (Figures 4-7), {ski_model} ski"
        + (f", {source} route" if ski_model == "rigid" else ""),
        ["figure", "ski", "mass [kg]", "load position [mm]", "snow modulus [MPa]",
         "rear [mm]", "middle [mm]", "front [mm]", "merged"],
        rows,
    )  # fmt: skip
    if note:
        console.print(f"note: {note}")
    sw = contact["sweep"]
    console.print(
        f"Maps sweep: {sw['points']} contact solves, {sw['chunks_computed']} chunks computed, "
        f"{sw['chunks_reused']} reused, {sw['wall_time_s']:.1f} s -> {sw['store']}"
    )
    console.print(f"Files written to {doc['output_dir']}/ in {doc['wall_time_s']:.1f} s:")
    for f in doc["files"]:
        console.print(f"  {f}")
