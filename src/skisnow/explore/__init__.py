"""An interactive explorer page: move the load and the snow and watch the contact, offline.

:func:`explorer_dataset` solves the contact (Kalliorinne et al. 2023, eq. 2–3, zones of §4) over a
grid of mass × load position × snow modulus for one or more skis and keeps the fields along the
ski; :func:`render_explorer` packs them (:mod:`._pack`) into ONE self-contained HTML file with a
small inline script: sliders for mass, load position and snow modulus, a ski selector, the ski
base and the deformed snow, the pressure with the zones shaded, the zone table and the Figure
8/9-style maps with the current point marked. No server, no network, no CDN. The page's zone
palette and colour map come from :mod:`skisnow.plot`, embedded in its data (one palette).

May import: sweep, plot, snow
"""

from skisnow.explore._data import (
    ZONES,
    ExplorerGrid,
    explorer_dataset,
    explorer_from_sweeps,
    explorer_spec_options,
)
from skisnow.explore._pack import pack, quantise_curves, unpack
from skisnow.explore._page import render_explorer, write_explorer

__all__ = [
    "ZONES",
    "ExplorerGrid",
    "explorer_dataset",
    "explorer_from_sweeps",
    "explorer_spec_options",
    "pack",
    "quantise_curves",
    "render_explorer",
    "unpack",
    "write_explorer",
]
