"""Rendering the explorer: one self-contained HTML file (inline script, inline data, no server,
no network). The browser code is a small hand-written script (``explorer.js``, canvas drawing):
a plotting library's bundle would be larger than the data of the default grid."""

from __future__ import annotations

import base64
import re
from collections.abc import Callable, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from skisnow._names import html_text, script_json
from skisnow.explore._pack import pack

CURVES = ("pressure_kpa", "base_um", "snow_um")
ARRAYS = (
    "zone_code",
    "length_mm",
    "area_cm2",
    "mean_pressure_kpa",
    "max_pressure_kpa",
    "load_share",
    "patches",
    "converged",
    "x_mm",
)


def _nearest(values: list[float], target: float) -> int:
    return int(np.argmin(np.abs(np.asarray(values, dtype=float) - target)))


def display_name(label: str) -> str:
    """A ski's name on a page: a shipped name as is, a ski file by its file name only (a page
    never shows the local folders of whoever made it)."""
    return Path(str(label)).name


def _style() -> dict[str, Any]:
    """The one palette of the figures (:mod:`skisnow.plot`), embedded in the page's data so the
    page and the figures cannot drift apart."""
    from skisnow.plot import MAP_CMAP, ZONE_COLORS, ZONE_LABELS, cmap_stops

    return {"palette": dict(ZONE_COLORS), "labels": dict(ZONE_LABELS),
            "cmap": cmap_stops(MAP_CMAP, 11), "cmap_name": MAP_CMAP}  # fmt: skip


def render_explorer(ds: Any, *, title: str = "skisnow explorer", subtitle: str = "") -> str:
    """The explorer page of dataset ``ds`` (from :func:`skisnow.explore.explorer_dataset`).

    The page opens at the point nearest to 60 kg, 120 mm behind the balance point and 100 MPa
    (the paper's Figure 5–6 cases).
    """
    curves = {k: np.asarray(ds[k].values, dtype=float) for k in CURVES}
    arrays = {k: np.asarray(ds[k].values) for k in ARRAYS}
    real = "real_fraction_percent" in ds
    if real:  # the real contact: the separation spans µm to mm, so it travels as log10(µm)
        curves["real_fraction_percent"] = np.asarray(ds["real_fraction_percent"].values, float)
        with np.errstate(divide="ignore", invalid="ignore"):
            curves["separation_log10_um"] = np.log10(np.asarray(ds["separation_um"].values, float))
        for k in ("real_area_grains_mm2", "viscous_force_n", "mu", "mu_lubricated"):
            arrays[k] = np.asarray(ds[k].values)
    manifest, blob = pack(curves, arrays)
    grid = {
        "ski": [display_name(s) for s in ds["ski"].values],
        "model": [str(s) for s in ds["model"].values],
        "base": [str(s) for s in ds["base"].values] if "base" in ds.dims else [""],
        "mass_kg": [float(v) for v in ds["mass_kg"].values],
        "load_position_mm": [float(v) for v in ds["load_position_mm"].values],
        "snow_modulus_mpa": [float(v) for v in ds["snow_modulus_mpa"].values],
    }
    source = str(ds.attrs.get("profile_source", "beam"))
    kick = ds["kick_zone_mm"].values if "kick_zone_mm" in ds else np.full((len(grid["ski"]), 2),
                                                                          np.nan)  # fmt: skip
    meta = {
        "grid": grid,
        "arrays": manifest,
        "n_stations": int(ds.sizes["station"]),
        "real": bool(real),
        "snow": str(ds.attrs.get("snow", "")),
        "skisnow_version": ds.attrs.get("skisnow_version", ""),
        "zones": [str(z) for z in ds["zone"].values],
        "kick_zone_mm": [None if np.isnan(k).any() else [float(k[0]), float(k[1])] for k in kick],
        "route": {m: ("flexible" if m == "flexible" else source) for m in grid["model"]},
        **_style(),
    }
    note = (
        "Lengths, areas and pressures of the half-space contact (Kalliorinne et al. 2023, "
        "eq. 2–3) at the grid point shown; curves are block means on "
        f"{meta['n_stations']} stations, peak pressures come from the full-resolution solve."
    )
    page = resources.files("skisnow.explore").joinpath("explorer.html").read_text("utf-8")
    script = resources.files("skisnow.explore").joinpath("explorer.js").read_text("utf-8")
    replacements = {
        "__TITLE__": html_text(title),
        "__SUBTITLE__": html_text(subtitle),
        "__NOTE__": html_text(note),
        "__MASS0__": str(_nearest(grid["mass_kg"], 60.0)),
        "__POS0__": str(_nearest(grid["load_position_mm"], -120.0)),
        "__MOD0__": str(_nearest(grid["snow_modulus_mpa"], 100.0)),
        # names come from files: no text may end the <script> block or open a comment in it
        "__META__": script_json(meta),
        "__BLOB__": base64.b64encode(blob).decode("ascii"),
        "__SCRIPT__": script,
    }
    # one pass: a replacement's text (a ski named "__META__") is never replaced again
    pattern = re.compile("|".join(re.escape(k) for k in replacements))
    return pattern.sub(lambda m: replacements[m.group()], page)


# The keyword options of explorer_dataset, repeated on purpose: it passes them on, and its
# signature documents them where a reader looks (no **kwargs to unpack in the docs).
def write_explorer(
    skis: Sequence[Any],
    path: str | Path,
    grid: Any = None,
    *,
    profile_source: str = "beam",
    ski_models: Sequence[str] = ("rigid",),
    store: str | Path | None = None,
    workers: int | None = 0,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    dataset: Any = None,
    bases: Sequence[str] = (),
    snow: Any = None,
) -> tuple[Path, Any]:
    """Solve the explorer's grid (:func:`skisnow.explore.explorer_dataset`) and write its page
    to ``path`` atomically (a killed run leaves no half page). Returns ``(path, dataset)``.

    ``dataset``: an explorer dataset already solved (e.g. :func:`explorer_from_sweeps` of a
    sweep run for something else); then nothing is solved and ``skis``/``grid``/the solver
    options are ignored."""
    from skisnow import __version__
    from skisnow._atomic import atomic_write
    from skisnow.explore._data import explorer_dataset

    if dataset is None:
        dataset = explorer_dataset(skis, grid, profile_source=profile_source,
                                   ski_models=ski_models, store=store, workers=workers,
                                   scheduler=scheduler, progress=progress, bases=bases,
                                   snow=snow)  # fmt: skip
    ds = dataset.copy()
    ds.attrs["skisnow_version"] = __version__
    names = ", ".join(display_name(s) for s in ds["ski"].values)
    page = render_explorer(
        ds, title="skisnow explorer", subtitle=f"{names} · skisnow {__version__}"
    )
    return atomic_write(path, page), ds
