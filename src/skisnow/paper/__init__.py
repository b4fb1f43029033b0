"""The paper's own numbers and findings, and skisnow's against them (Kalliorinne et al. 2023).

* :data:`CAPTIONS`, :func:`caption_table` — the contact lengths, mean pressures, load shares and
  patch counts of the captions of Figures 4–7, paper against skisnow (what the shipped skis are
  fitted to);
* :func:`solve_caption_case` — one caption case through the paper's pipeline;
* :func:`zone_maps`, :func:`figure89_findings` — the rear/front maps over load × snow and the
  findings the paper reads off its Figures 8–9, as checks (the validation of the fitted skis).

May import: ski, contact, pipeline
"""

from skisnow.paper._captions import (
    CAPTIONS,
    TOLERANCES,
    CaptionCase,
    CaptionRow,
    CaptionZone,
    Tolerances,
    caption_table,
    compare_case,
    solve_caption_case,
)
from skisnow.paper._findings import Finding, ZoneMaps, figure89_findings, zone_maps

# The names the modules export, listed again on purpose: __all__ is what ``import *`` and the
# docs of the package door see (one literal list: static, what readers and tools read).
__all__ = [
    "CAPTIONS",
    "TOLERANCES",
    "CaptionCase",
    "CaptionRow",
    "CaptionZone",
    "Finding",
    "Tolerances",
    "ZoneMaps",
    "caption_table",
    "compare_case",
    "figure89_findings",
    "solve_caption_case",
    "zone_maps",
]
