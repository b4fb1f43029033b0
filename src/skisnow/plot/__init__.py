"""Figures (Matplotlib, imported only here). Numerics never import this package.

Every function returns a Matplotlib ``Figure`` (no pyplot, one house style, fixed layout); one
helper writes them, :func:`save_figure` (PNG and SVG by default, no creation dates), and
:func:`figure_svg` gives the inline SVG of a page.

* :func:`plot_contact` — profile, pressure and deformed snow of one case (Kalliorinne et al.
  2023, Figures 4–7);
* :func:`plot_zone_map`, :func:`plot_load_share`, :func:`sweep_figures` — maps of a sweep
  (Figures 8–9);
* :func:`plot_camber_profiles` — free camber of skis;
* :func:`topography_figure`, :func:`bearing_figure` — the micro scale;
* :func:`plot_real_contact`, :func:`plot_micro_curves` — the real contact along the ski and the
  micro curves of a base × snow;
* :func:`plot_fleet`, :func:`plot_snow_ranking`, :func:`plot_cycle`, :func:`animate_cycle` —
  the technician workflows (a fleet, a ranking across snow, a load cycle and its animation).

May import: ski, bench, network, contact
"""

from skisnow.plot._contact import plot_contact
from skisnow.plot._maps import MAP_KINDS, plot_load_share, plot_zone_map, sweep_figures
from skisnow.plot._micro import bearing_figure, topography_figure
from skisnow.plot._multiscale import plot_micro_curves, plot_real_contact
from skisnow.plot._profiles import plot_camber_profiles
from skisnow.plot._ski import plot_passport
from skisnow.plot._style import (
    FORMATS,
    MAP_CMAP,
    ZONE_COLORS,
    ZONE_LABELS,
    cmap_stops,
    figure_svg,
    save_figure,
    smallest_text_pt,
)
from skisnow.plot._workflows import (
    animate_cycle,
    plot_cycle,
    plot_fleet,
    plot_pairs,
    plot_snow_ranking,
)

__all__ = [
    "FORMATS",
    "MAP_CMAP",
    "MAP_KINDS",
    "ZONE_COLORS",
    "ZONE_LABELS",
    "animate_cycle",
    "bearing_figure",
    "cmap_stops",
    "figure_svg",
    "plot_camber_profiles",
    "plot_contact",
    "plot_cycle",
    "plot_fleet",
    "plot_load_share",
    "plot_micro_curves",
    "plot_pairs",
    "plot_passport",
    "plot_real_contact",
    "plot_snow_ranking",
    "plot_zone_map",
    "save_figure",
    "smallest_text_pt",
    "sweep_figures",
    "topography_figure",
]
