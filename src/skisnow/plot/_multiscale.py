"""The real contact along the ski and the micro curves behind it (Kalliorinne et al. 2023,
Lubricants 11(10) 427; Scherge et al. 2021).

* :func:`plot_real_contact` — three panels sharing x along the ski: the apparent pressure p(x)
  (the rigid profile pressed into the snow); the real-area fraction A_r/A of the flat-ice
  (elastic–plastic) and grain (bearing) models where the ski bears; the mean separation between
  base and snow (log scale: µm under the contact patches, the camber's gap elsewhere);
* :func:`plot_micro_curves` — the micro curves of one or more base × snow over the nominal
  pressure: real-area fraction over p/H (1 is the purely plastic limit), mean separation and
  reciprocal separation.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from skisnow.plot._style import COLORS, ZONE_COLORS, ZONE_LABELS, new_figure, style

__all__ = ["plot_micro_curves", "plot_real_contact"]


def plot_real_contact(case: Any, *, title: str | None = None) -> Figure:
    """p(x), real-area fraction and separation along the ski of a case with a real contact."""
    r = case.real
    if r is None:
        from skisnow._errors import InputError

        raise InputError("the case has no real contact (solve it with a textured base and snow)")
    x = r.x * 1e3
    fig, axes = new_figure(1, 3, width=7.5, height=6.6, sharex=True)
    a0, a1, a2 = axes[:, 0]
    with style():
        masks = case.station_masks()
        colors = {"rear_glide": "rear", "kick_zone": "middle", "front_glide": "front"}
        for name, zone in colors.items():
            if name not in masks or not masks[name].any():
                continue
            sel = masks[name]
            lo, hi = x[sel].min(), x[sel].max()
            color = ZONE_COLORS.get(zone, "grey")
            for ax in (a0, a1, a2):
                ax.axvspan(lo, hi, color=color, alpha=0.06, lw=0,
                           label=ZONE_LABELS[name] if ax is a0 else None)  # fmt: skip
        a0.plot(x, r.pressure * 1e-3, color=COLORS["pressure"], label="apparent pressure")
        a0.legend(loc="upper left", fontsize=7, ncols=2)
        a0.set_ylabel("apparent p [kPa]")
        bearing = r.apparent_area > 0
        frac = np.where(bearing, r.real_fraction, np.nan) * 100
        with np.errstate(invalid="ignore", divide="ignore"):
            grains = np.where(bearing, r.real_area_grains / r.apparent_area, np.nan) * 100
        a1.plot(x, frac, color="#16a085", label="flat ice (elastic–plastic)")
        a1.plot(x, grains, color="#7f8c8d", ls="--", label="ice grains (bearing model)")
        a1.set_ylabel("real area [% of apparent]")
        a1.legend(loc="upper right")
        a2.semilogy(x, r.mean_separation * 1e6, color=COLORS["profile"])
        a2.set_ylabel("mean separation [µm]")
        a2.set_xlabel("x from the balance point [mm] (tip →)")
        t = r.total
        est = r.friction_estimate()
        a0.set_title(
            title
            or f"{case.label}: {case.mass:g} kg at {case.load_position * 1e3:g} mm, base "
            f"{r.base} × snow {r.snow}"
        )
        a2.set_title(
            f"A_r {t.real_area * 1e6:.3g} mm² of {t.apparent_area * 1e4:.3g} cm² apparent; "
            f"∫1/u dA {t.reciprocal_separation:.3g} m; µ {est['mu_lubricated']:.3g}–"
            f"{est['mu']:.3g} (lubricated–dry, see the assumptions)",
            fontsize=8,
        )
    return fig


def plot_micro_curves(curves: Sequence[Any], *, film_cutoff: float = 1e-7) -> Figure:
    """Real fraction over p/H, mean separation and ⟨1/u⟩ against nominal pressure."""
    fig, axes = new_figure(3, 1, width=9.0, height=3.0)
    a0, a1, a2 = axes[0]
    with style():
        for c in curves:
            p = c.pressures
            label = f"{c.base} × {c.snow}"
            (line,) = a0.semilogx(p * 1e-3, c.real_fractional_area / (p / c.hardness), label=label)
            a0.semilogx(
                c.bearing_pressures * 1e-3,
                c.bearing_fraction / (c.bearing_pressures / c.hardness),
                ls="--",
                color=line.get_color(),
            )
            a1.semilogx(p * 1e-3, c.mean_separation_grid * 1e6, color=line.get_color())
            a2.loglog(p * 1e-3, c.reciprocal_separation(p, film_cutoff) * 1e-6,
                      color=line.get_color())  # fmt: skip
        a0.axhline(1.0, color="black", lw=0.6)
        a0.set_ylabel("A_r / (A·p/H)  (— flat ice, -- grains)")
        a1.set_ylabel("mean separation ū [µm]")
        a2.set_ylabel(f"⟨1/u⟩ [1/µm], cut-off {film_cutoff * 1e9:g} nm")
        for ax in (a0, a1, a2):
            ax.set_xlabel("nominal pressure [kPa]")
        a0.legend(fontsize=7)
    return fig
