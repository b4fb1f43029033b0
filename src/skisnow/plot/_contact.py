"""The apparent contact of one load case, drawn like Kalliorinne et al. (2023), Figures 4–7.

Positioned camber profile (blue), deformed snow surface (black), apparent pressure (red, right
axis), the load arrow at x_m (red) and the glide direction (black arrow toward the tip). Heights
are in µm against x in mm: the vertical exaggeration is stated on the figure.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from skisnow.contact import ContactSolution, ZoneMetrics
from skisnow.plot._style import COLORS, ZONE_COLORS, ZONE_LABELS, new_figure, style

__all__ = ["plot_contact"]


def plot_contact(
    solution: ContactSolution,
    zones: ZoneMetrics | None = None,
    *,
    title: str | None = None,
    height_range_um: float | None = None,
    reference: ContactSolution | None = None,
    label: str = "ski base (positioned)",
    reference_label: str = "rigid profile (positioned)",
) -> Figure:
    """Figure of one contact solution (x along the ski [mm], heights [µm], pressure [kPa]).

    ``zones`` (from :func:`~skisnow.contact.contact_zones`) shades the rear/middle/front
    contact intervals (named in the legend; a merged footprint says that its zones are the
    regions) and draws the kick-zone marks. ``height_range_um`` caps the height axis (default:
    4× the deepest snow displacement, at least 100 µm), so that the pocket and the deformed
    snow are both visible.
    ``reference``: a second solution of the same case drawn dashed (its positioned ski base and
    pressure), e.g. the rigid profile beside the flexible ski's bent base.
    """
    s = solution
    xi = s.x - s.load_position
    if s.pressure.ndim == 2:
        fp = s.footprint
        p = np.where(fp, s.pressure, 0.0).sum(axis=1) / fp.sum(axis=1)
        u = np.where(fp, s.displacement, 0.0).sum(axis=1) / fp.sum(axis=1)
        h = np.where(fp, s.height, np.inf).min(axis=1)
    else:
        p, u, h = s.pressure, s.displacement, s.height
    ski = h - s.translation - s.rotation * xi  # the positioned rigid profile
    snow = -u
    x_mm = s.x * 1e3
    depth = float(max(np.max(u), 0.0)) * 1e6
    top = height_range_um if height_range_um is not None else max(4 * depth, 100.0)
    bottom = -1.3 * max(depth, 1.0)

    fig, axes = new_figure(1, 1, width=7.5, height=3.9)
    ax = axes[0, 0]
    with style():
        shading = []
        if zones is not None:
            from matplotlib.patches import Patch

            region = {"rear": "rear_glide", "middle": "kick_zone", "front": "front_glide"}
            for name in ("rear", "middle", "front"):
                for a, b in zones[name].intervals:
                    ax.axvspan(a * 1e3, b * 1e3, color=ZONE_COLORS[name], alpha=0.12, lw=0)
                if zones[name].intervals:
                    text = (ZONE_LABELS[region[name]].replace("(region)", "(merged footprint)")
                            if zones.merged else ZONE_LABELS[name].split(" (")[0])  # fmt: skip
                    shading.append(Patch(color=ZONE_COLORS[name], alpha=0.25, label=text))
            if zones.kick_zone is not None:
                for k in zones.kick_zone:
                    ax.axvline(k * 1e3, color=ZONE_COLORS["kick_zone"], ls="--", lw=0.8)
                shading.append(
                    Patch(
                        facecolor="none",
                        edgecolor=ZONE_COLORS["kick_zone"],
                        ls="--",
                        label="kick-zone marks",
                    )
                )
        ax.plot(x_mm, ski * 1e6, color=COLORS["profile"], label=label)
        if reference is not None:
            r = reference
            rh = r.height if r.height.ndim == 1 else r.height.min(axis=1)
            rp = r.pressure if r.pressure.ndim == 1 else r.pressure.mean(axis=1)
            r_ski = rh - r.translation - r.rotation * (r.x - r.load_position)
            ax.plot(r.x * 1e3, r_ski * 1e6, ls="--", color=COLORS["profile"], lw=0.9,
                    alpha=0.8, label=reference_label)  # fmt: skip
        ax.plot(x_mm, snow * 1e6, color=COLORS["snow"], lw=0.9, label="deformed snow")
        ax.set_ylim(bottom, top)
        ax.set_xlim(x_mm[0], x_mm[-1])
        ax.set_xlabel("x from the balance point [mm] (tip →)")
        ax.set_ylabel("height [µm]")
        ax2 = ax.twinx()
        ax2.plot(x_mm, p * 1e-3, color=COLORS["pressure"], lw=1.0, label="apparent pressure")
        if reference is not None:
            ax2.plot(r.x * 1e3, rp * 1e-3, ls="--", color=COLORS["pressure"], lw=0.8,
                     alpha=0.8, label="pressure, " + reference_label.split(" (")[0])  # fmt: skip
        ax2.set_ylabel("apparent pressure [kPa]", color=COLORS["pressure"])
        p_top = max(float(p.max()), float(rp.max()) if reference is not None else 0.0)
        ax2.set_ylim(0, max(p_top * 1e-3 * 1.15, 1e-9))
        ax2.grid(False)
        ax2.spines["right"].set_visible(True)
        # load arrow at x_m and the glide direction (toward the tip, +x)
        xm = s.load_position * 1e3
        ax.annotate(
            "",
            xy=(xm, 0.0),
            xytext=(xm, 0.8 * top),
            arrowprops={"arrowstyle": "-|>", "color": COLORS["load"], "lw": 1.5},
        )
        ax.text(xm, 0.82 * top, f" {s.load:.0f} N", color=COLORS["load"], va="bottom")
        span = x_mm[-1] - x_mm[0]
        ax.annotate(
            "glide",
            xy=(x_mm[0] + 0.25 * span, 0.9 * top),
            xytext=(x_mm[0] + 0.05 * span, 0.9 * top),
            va="center",
            arrowprops={"arrowstyle": "-|>", "color": "black"},
        )
        # vertical exaggeration: (µm per data unit on the x axis) / (µm per data unit on y)
        fig.canvas.draw()  # settle the layout to measure the axes box
        bbox = ax.get_window_extent()
        um_per_px_x = span * 1e3 / bbox.width
        um_per_px_y = (top - bottom) / bbox.height
        exaggeration = um_per_px_x / um_per_px_y
        ax.set_title(
            (title + "\n" if title else "")
            + f"contact modulus of snow and base {s.modulus / 1e6:.0f} MPa, {s.model} model; "
            f"heights ×{exaggeration:,.0f} against lengths",
        )
        lines = [
            ln for ln in ax.get_lines() + ax2.get_lines() if not ln.get_label().startswith("_")
        ]
        handles = [*lines, *shading]
        # the legend under the axes: it never hides the contact or the load arrow
        ax.legend(
            handles,
            [h.get_label() for h in handles],
            loc="upper center",
            bbox_to_anchor=(0.5, -0.2),
            ncols=4,
            fontsize="small",
            frameon=False,
        )
        fig.subplots_adjust(bottom=1.25 / fig.get_figheight())
    return fig
