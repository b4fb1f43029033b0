"""Maps of a sweep: zone metrics versus load, one line per snow modulus (Kalliorinne et al. 2023,
Figures 8–9), and load-share plots.

All functions take the :class:`xarray.Dataset` of :func:`skisnow.sweep.open_sweep` (dims ``ski,
mass_kg, load_position_mm, snow_modulus_mpa, zone``) and return a Matplotlib ``Figure``;
:func:`sweep_figures` draws the standard set for a whole sweep.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from skisnow._errors import InputError
from skisnow.plot._style import (
    COLORS,
    ZONE_COLORS,
    ZONE_LABELS,
    modulus_colorbar,
    modulus_colors,
    new_figure,
)

#: Axis labels of the mapped variables (the paper's units: cm² and kPa).
LABELS: dict[str, str] = {
    "area_cm2": "apparent contact area [cm²]",
    "length_mm": "apparent contact length [mm]",
    "mean_pressure_kpa": "mean apparent pressure [kPa]",
    "max_pressure_kpa": "max apparent pressure [kPa]",
    "load_share": "load share [%]",
    "patches": "contact patches",
}
#: The Breitschädel (50 µm) counterpart of a variable, drawn as a thick black line.
BREITSCHAEDEL: dict[str, str] = {
    "area_cm2": "breitschaedel_area_cm2",
    "length_mm": "breitschaedel_length_mm",
}


def _select(ds: Any, ski: str | None, load_position_mm: float | None) -> tuple[Any, str, float]:
    skis = [str(s) for s in ds["ski"].values]
    if ski is None:
        ski = skis[0]
    if ski not in skis:
        raise InputError(f"ski {ski!r} is not in the sweep (it has {skis})")
    positions = ds["load_position_mm"].values
    if load_position_mm is None:
        load_position_mm = float(positions[np.argmin(np.abs(positions + 120.0))])
    if not np.any(np.isclose(positions, load_position_mm)):
        raise InputError(
            f"load position {load_position_mm} mm is not in the sweep (it has {positions.tolist()})"
        )
    sub = ds.sel(ski=ski).sel(load_position_mm=load_position_mm, method="nearest")
    return sub, ski, float(load_position_mm)


def plot_zone_map(
    ds: Any,
    *,
    variable: str = "area_cm2",
    ski: str | None = None,
    load_position_mm: float | None = None,
    zones: Sequence[str] = ("rear", "front"),
    breitschaedel: bool = True,
    title: str | None = None,
) -> Figure:
    """``variable`` of each zone versus the loaded mass, one line per snow modulus, zones side by
    side (rear left, front right: the layout of Kalliorinne et al. 2023, Figures 8–9).

    With ``breitschaedel`` (and a variable that has one: area, length) the estimate of the 50 µm
    criterion is drawn as a thick black line; it does not depend on the snow.
    """
    if variable not in ds:
        raise InputError(f"variable {variable!r} is not in the sweep (it has {list(ds.data_vars)})")
    sub, ski, x_m = _select(ds, ski, load_position_mm)
    moduli = [float(e) for e in sub["snow_modulus_mpa"].values]
    colors = modulus_colors(moduli)
    mass = sub["mass_kg"].values
    scale = 100.0 if variable == "load_share" else 1.0
    fig, axes = new_figure(len(zones), 1, width=3.4 * len(zones) + 0.8, height=3.0, sharey=True)
    for ax, zone in zip(axes[0], zones, strict=True):
        for e, c in zip(moduli, colors, strict=True):
            y = sub[variable].sel(zone=zone, snow_modulus_mpa=e).values * scale
            ax.plot(mass, y, color=c, lw=1.0)
        bvar = BREITSCHAEDEL.get(variable)
        if breitschaedel and bvar is not None and bvar in sub:
            ax.plot(
                mass,
                sub[bvar].sel(zone=zone).values,
                color=COLORS["breitschaedel"],
                lw=2.6,
                label="Breitschädel (h < 50 µm)",
            )
            ax.legend(loc="best", frameon=False)
        ax.set_title(ZONE_LABELS.get(zone, zone))
        ax.set_xlabel("load on the ski [kg]")
    axes[0][0].set_ylabel(LABELS.get(variable, variable))
    modulus_colorbar(fig, axes[0], moduli, label="snow modulus [MPa]")
    fig.suptitle(title or f"{ski} ski, load at {x_m:g} mm from the balance point")
    return fig


def plot_load_share(
    ds: Any,
    *,
    ski: str | None = None,
    load_position_mm: float | None = None,
    snow_modulus_mpa: float | None = None,
    zones: Sequence[str] | None = None,
) -> Figure:
    """How the load m·g is shared between the regions of the ski versus the loaded mass.

    Left: stacked shares at one snow modulus (default: the median of the sweep). Right: the rear
    glide's share for every modulus (one line each), showing how much the snow moves the load
    around. ``zones`` default: the regions fixed by the ski (rear glide, kick zone, front glide),
    whose shares never jump when two contact patches join; a sweep stored before the regions
    existed falls back to the paper's zones.
    """
    sub, ski, x_m = _select(ds, ski, load_position_mm)
    stored = [str(z) for z in ds["zone"].values]
    if zones is None:
        regions = [z for z in ("rear_glide", "kick_zone", "front_glide") if z in stored]
        zones = regions if regions else ["rear", "middle", "front"]
    rear = zones[0]
    moduli = [float(e) for e in sub["snow_modulus_mpa"].values]
    if snow_modulus_mpa is None:
        snow_modulus_mpa = moduli[len(moduli) // 2]
    one = sub.sel(snow_modulus_mpa=snow_modulus_mpa, method="nearest")
    mass = sub["mass_kg"].values
    fig, axes = new_figure(2, 1, width=7.6, height=3.0)
    ax = axes[0][0]
    shares = [np.nan_to_num(one["load_share"].sel(zone=z).values) * 100 for z in zones]
    ax.stackplot(mass, shares, labels=[ZONE_LABELS.get(z, z) for z in zones],
                 colors=[ZONE_COLORS[z] for z in zones], alpha=0.75)  # fmt: skip
    ax.set_ylim(0, 100)
    ax.set_xlabel("load on the ski [kg]")
    ax.set_ylabel(LABELS["load_share"])
    ax.set_title(f"snow modulus {float(one['snow_modulus_mpa']):g} MPa")
    ax.legend(loc="lower right", frameon=True)
    ax = axes[0][1]
    for e, c in zip(moduli, modulus_colors(moduli), strict=True):
        ax.plot(mass, sub["load_share"].sel(zone=rear, snow_modulus_mpa=e).values * 100, color=c)
    ax.set_xlabel("load on the ski [kg]")
    ax.set_ylabel(f"{ZONE_LABELS.get(rear, rear)} load share [%]")
    ax.set_title(f"{ZONE_LABELS.get(rear, rear)}, every snow")
    modulus_colorbar(fig, axes[0][1], moduli, label="snow modulus [MPa]")
    fig.suptitle(f"{ski} ski, load at {x_m:g} mm from the balance point: load partitioning")
    return fig


#: The standard maps of a sweep: name -> variable (``load_share``: :func:`plot_load_share`).
MAP_KINDS: dict[str, str] = {
    "area": "area_cm2",  # Figure 8
    "mean_pressure": "mean_pressure_kpa",  # Figure 9
    "length": "length_mm",
    "load_share": "load_share",
}


def sweep_figures(
    ds: Any,
    *,
    skis: Sequence[str] | None = None,
    load_positions_mm: Sequence[float] | None = None,
    kinds: Sequence[str] = tuple(MAP_KINDS),
) -> dict[str, Figure]:
    """The standard maps of a sweep, ``{stem: Figure}`` with stems ``{ski}_x{pos}mm_{kind}``.

    For every ski and load position of ``ds`` (or those given) and every kind of
    :data:`MAP_KINDS` (or those given): ``area`` (Kalliorinne et al. 2023, Figure 8),
    ``mean_pressure`` (Figure 9), ``length`` and ``load_share``. The one loop over a sweep's
    maps: save them with :func:`skisnow.plot.save_figure` or embed them in a page.
    """
    bad = [k for k in kinds if k not in MAP_KINDS]
    if bad:
        raise InputError(f"kinds: {bad} not among {list(MAP_KINDS)}")
    skis = [str(s) for s in ds["ski"].values] if skis is None else list(skis)
    positions = (
        [float(p) for p in ds["load_position_mm"].values]
        if load_positions_mm is None
        else [float(p) for p in load_positions_mm]
    )
    figures: dict[str, Figure] = {}
    for ski in skis:
        for pos in positions:
            for kind in kinds:
                if kind == "load_share":
                    fig = plot_load_share(ds, ski=ski, load_position_mm=pos)
                else:
                    fig = plot_zone_map(ds, variable=MAP_KINDS[kind], ski=ski, load_position_mm=pos)
                figures[f"{ski}_x{pos:g}mm_{kind}"] = fig
    return figures
