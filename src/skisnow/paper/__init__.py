"""The paper's own numbers and findings, and skisnow's against them (Kalliorinne et al. 2023).

* :data:`CAPTIONS`, :func:`caption_table` — the contact lengths, mean pressures, load shares and
  patch counts of the captions of Figures 4–7, paper against skisnow (what the shipped skis are
  fitted to);
* :func:`solve_caption_case` — one caption case through the paper's pipeline;
* :func:`zone_maps`, :func:`figure89_findings` — the rear/front maps over load × snow (either
  profile route) and the twelve statements the paper reads off its Figures 8–9, each with its
  numerical criterion (:data:`STATEMENTS`): predictions, never fitted.

May import: ski, contact, pipeline
"""

from skisnow.paper._captions import (
    CAPTIONS,
    REPRODUCTION_TOLERANCES,
    ROUTES,
    TOLERANCES,
    CaptionCase,
    CaptionRow,
    CaptionZone,
    Tolerances,
    caption_table,
    compare_case,
    solve_caption_case,
    tolerances_of,
)
from skisnow.paper._findings import STATEMENTS, Finding, figure89_findings
from skisnow.paper._maps import (
    FIGURE89_MASS_RANGE_KG,
    FIGURE89_MODULI_MPA,
    ZoneMaps,
    figure89_masses,
    zone_maps,
)

# The names the modules export, listed again on purpose: __all__ is what ``import *`` and the
# docs of the package door see (one literal list: static, what readers and tools read).
__all__ = [
    "CAPTIONS",
    "FIGURE89_MASS_RANGE_KG",
    "FIGURE89_MODULI_MPA",
    "REPRODUCTION_TOLERANCES",
    "ROUTES",
    "STATEMENTS",
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
    "figure89_masses",
    "solve_caption_case",
    "tolerances_of",
    "zone_maps",
]
