"""Report section of the real contact: the standard loads with a base texture on a snow.

It renders cases solved with a textured base and a snow (:attr:`skisnow.pipeline.Case.real`):
the real contact of the whole ski and per region, the friction proxies with their assumptions,
and the figure of p(x), the real-area fraction and the separation along the ski. It computes
nothing.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from skisnow.report._html import Figure, Section, Table

__all__ = ["real_contact_section"]


def real_contact_section(cases: Sequence[Any]) -> Section:
    """The real contact of ``cases`` (each with ``case.real``), one row per case and region."""
    from skisnow.plot import figure_svg, plot_real_contact

    rows = []
    for case in cases:
        summary = case.real_summary()
        est = case.real.friction_estimate()
        for name, s in summary.items():
            if name.startswith("patch"):
                continue
            rows.append((
                f"{case.mass:g} kg", case.snow_modulus / 1e6, name, s.apparent_area * 1e4,
                s.real_area_grains * 1e6, s.real_area * 1e6, s.mean_separation * 1e6,
                s.reciprocal_separation, s.viscous_force,
                f"{est['mu_lubricated']:.3g}–{est['mu']:.3g}" if name == "total" else "",
            ))  # fmt: skip
    table = Table(
        ["load", "snow E [MPa]", "region", "apparent [cm²]", "real, grains [mm²]",
         "real, flat ice [mm²]", "mean separation [µm]", "∫1/u dA [m]", "η·v·∫1/u dA [N]",
         "µ lubricated–dry"],
        rows,
        floatfmt=".3g",
    )  # fmt: skip
    first = cases[0]
    r = first.real
    notes = (
        f"Base {r.base} × snow {r.snow} ({first.snow.describe()}). The micro curves of this base "
        "× snow (the bearing model of ice grains, Scherge et al. 2021, eq. 5–13, and the "
        "elastic–plastic contact of the texture with flat ice) are read at the apparent pressure "
        "of every station (Kalliorinne et al. 2023, Lubricants 11(10) 427).",
        "The plastic real area is W·s/H whatever the camber (s: the texture's slope factor, H: "
        "the ice hardness): the camber acts through the separation, its reciprocal ∫1/u dA — the "
        "viscous term, which counts the thin gaps beside the patches — and the elastic rims.",
        "µ is a range, never a measurement: " + first.real.friction_estimate()["assumptions"],
    )
    figures = [
        Figure(
            figure_svg(plot_real_contact(case)),
            f"{case.label}, {case.mass:g} kg on {case.snow_modulus / 1e6:g} MPa snow: apparent "
            "pressure, real-area fraction (flat ice and grains) and mean separation along the ski.",
        )
        for case in cases[-1:]
    ]
    return Section("Real contact: the grind on the snow", notes, (table, *figures))
