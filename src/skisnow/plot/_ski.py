"""The ski passport figure: EI(x) and z0(x) with 95 % bands (Kalliorinne et al. 2023, §3.1)."""

from __future__ import annotations

from collections.abc import Sequence

from matplotlib.figure import Figure

from skisnow.bench import SkiPassport, ski_passport
from skisnow.plot._style import COLORS, new_figure
from skisnow.ski import Ski

__all__ = ["plot_passport"]


def plot_passport(
    passport: SkiPassport | Ski,
    *,
    reference: Ski | None = None,
    labels: Sequence[str] = ("ski", "reference"),
) -> Figure:
    """Two panels: bending stiffness EI(x) [N m²] (log axis) and free camber z0(x) [mm] along
    x [mm], with the 95 % bands of an identified ski, the kick zone shaded and the boot plate
    marked; ``reference`` (e.g. the true ski of a round-trip test) is drawn dashed.
    """
    pp = (
        passport
        if isinstance(passport, SkiPassport)
        else ski_passport(passport, step=0.005, metrics=False)
    )
    ski = pp.ski
    fig, axes = new_figure(1, 2, width=6.4, height=5.6)
    ax_ei, ax_z = axes[0][0], axes[1][0]
    x_mm = pp.x * 1e3
    color = COLORS["profile"]
    ax_ei.plot(x_mm, pp.stiffness, color=color, label=labels[0])
    ax_z.plot(x_mm, pp.camber * 1e3, color=color, label=labels[0])
    if pp.has_bands:
        ax_ei.fill_between(x_mm, pp.stiffness_low, pp.stiffness_high, color=color, alpha=0.25,
                           linewidth=0, label="95 % band")  # fmt: skip
        ax_z.fill_between(x_mm, pp.camber_low * 1e3, pp.camber_high * 1e3, color=color,
                          alpha=0.25, linewidth=0, label="95 % band")  # fmt: skip
    if reference is not None:
        ref = ski_passport(reference, step=0.005, metrics=False)
        ax_ei.plot(ref.x * 1e3, ref.stiffness, "--", color="0.2", label=labels[1])
        ax_z.plot(ref.x * 1e3, ref.camber * 1e3, "--", color="0.2", label=labels[1])
    for ax in (ax_ei, ax_z):
        if ski.kick_zone is not None:
            ax.axvspan(ski.kick_zone[0] * 1e3, ski.kick_zone[1] * 1e3, color="0.92", zorder=0,
                       label="kick zone")  # fmt: skip
        if ski.boot_plate is not None:
            for edge in ski.boot_plate:
                ax.axvline(edge * 1e3, color=COLORS["load"], linewidth=0.8, linestyle=":")
        ax.axvline(0.0, color="0.5", linewidth=0.6)
    ax_ei.set_yscale("log")
    from matplotlib.ticker import FuncFormatter

    # plain numbers (100, 1000), not 10² whose exponent would print at 70 % of the text size
    ax_ei.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    ax_ei.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
    ax_ei.set_ylabel("bending stiffness EI [N m²]")
    ax_ei.set_title(f"{ski.name} ({ski.kind} ski): passport")
    ax_ei.legend(loc="lower center", fontsize="small")
    ax_z.set_ylim(-0.5, min(10.0, float(pp.camber_high.max()) * 1e3 + 0.5))
    ax_z.set_ylabel("free camber z0 [mm]")
    ax_z.set_xlabel("x from balance point [mm] (tip →)")
    return fig
