"""Figures (Matplotlib, imported only here). Numerics never import this package.

One house style (``_style``): no pyplot, fixed layout, PNG and SVG.
"""

from skisnow.plot._contact import plot_contact
from skisnow.plot._maps import plot_load_share, plot_sweep, plot_zone_map
from skisnow.plot._profiles import plot_camber_profiles

__all__ = [
    "plot_camber_profiles",
    "plot_contact",
    "plot_load_share",
    "plot_sweep",
    "plot_zone_map",
]
