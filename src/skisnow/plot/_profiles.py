"""Camber profiles of skis under several loads (the bench view of Kalliorinne et al. 2023,
Fig. 4–6)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from skisnow.network import camber_profile
from skisnow.plot._style import COLORS, new_figure
from skisnow.ski import get_ski

__all__ = ["plot_camber_profiles"]


def plot_camber_profiles(
    skis: Sequence[str] = ("classic", "skate"),
    *,
    masses: Sequence[float] = (10.0, 32.5, 65.0, 100.0),
    load_position: float = -0.080,
    source: str = "beam",
) -> Figure:
    """One panel per ski: loaded camber height h [mm] along x [mm] for each mass [kg].

    ``load_position`` [m] from the balance point (default 80 mm behind). The load position is
    marked by a red arrow, the kick zone (classic skis) shaded.
    """
    fig, axes = new_figure(len(skis), 1, width=4.2 * len(skis), height=3.2)
    for ax, name in zip(axes[0], skis, strict=True):
        ski = get_ski(name)
        shades = np.linspace(0.35, 1.0, len(masses))
        for shade, m in zip(shades, masses, strict=True):
            x, h = camber_profile(name, mass=m, load_position=load_position, source=source)  # type: ignore[arg-type]
            ax.plot(
                x * 1e3, h * 1e3, color=COLORS["profile"], alpha=float(shade), label=f"{m:g} kg"
            )
        if ski.kick_zone is not None:
            ax.axvspan(
                ski.kick_zone[0] * 1e3,
                ski.kick_zone[1] * 1e3,
                color="0.9",
                zorder=0,
                label="kick zone",
            )
        ax.annotate(
            "",
            xy=(load_position * 1e3, 0.0),
            xytext=(load_position * 1e3, 3.0),
            arrowprops={"arrowstyle": "->", "color": COLORS["load"]},
        )
        ax.set_ylim(-0.2, 8.0)
        ax.set_xlabel("x from balance point [mm] (tip →)")
        ax.set_ylabel("camber height h [mm]")
        ax.set_title(f"{name}: load {abs(load_position) * 1e3:.0f} mm behind balance point")
        ax.legend(loc="upper left")
    return fig
