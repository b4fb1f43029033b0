"""One case, one pipeline: ski → loaded profile → apparent contact → zones.

:func:`solve_case` is the single door to one case of Kalliorinne et al. (2023), §3: the loaded
camber profile h = f(x, m, x_m) (eq. 1), the rigid ski pressed into elastic snow with force and
moment balance (eq. 2–3), the contact zones and the Breitschädel (2012) 50 µm estimate. The
sweep, ``skisnow contact``, the report, the demo and the examples call it, so the same inputs
give the same numbers whichever door a user comes in by. For a ski that carries its posterior
(an identified ski), :func:`case_intervals` gives the case's answers 95 % intervals by solving
the case on posterior samples (:class:`Intervals`; :func:`sample_intervals` for any answer).

Grid convention: ``n_points`` (default 4096) stations evenly spaced from the tail to the tip of
the running surface, both ends included (:func:`stations`), each the centre of one contact cell.

>>> case = solve_case("skate", mass=60.0, load_position=-0.12,
...                   snow_modulus=100e6)                           # doctest: +SKIP
>>> case.zones["rear"].length, case.breitschaedel["total"].length   # doctest: +SKIP

May import: ski, bench, network, contact, micro, snow, multiscale

Kept for compatibility; the home of what the report of a ski shows (MAP_MASSES, MAP_MODULI,
STANDARD_SNOWS, SkiStudy, standard_cases, study_ski: metrics, the cases at the standard loads,
the maps' sweep) is :mod:`skisnow.report`, above the sweep it runs: these names are imported
from there on first use.
"""

from skisnow._lazy import lazy_getattr
from skisnow.pipeline._case import DEFAULT_TOL, MODELS, SKI_MODELS, Case, solve_case
from skisnow.pipeline._intervals import (
    DEFAULT_LEVEL,
    DEFAULT_SAMPLES,
    INTERVAL_ZONES,
    MIXED_SHARE,
    PATCH_ZONES,
    ZONE_QUANTITIES,
    Intervals,
    Topology,
    case_intervals,
    case_quantities,
    sample_intervals,
    topology_shares,
    topology_text,
    zone_topology,
)
from skisnow.pipeline._profiles import (
    DEFAULT_N_POINTS,
    DEFAULT_PROFILE_SOURCE,
    PROFILE_SOURCES,
    loaded_profiles,
    resolve_ski,
    shipped_twin,
    stations,
)
from skisnow.pipeline._real import station_masks, zone_station_masks
from skisnow.pipeline._record import (
    note_implausible,
    note_solved,
    note_unconverged,
    recording_implausible,
    recording_solved,
    recording_unconverged,
)

_LAZY = dict.fromkeys(
    ("MAP_MASSES", "MAP_MODULI", "STANDARD_SNOWS", "SkiStudy", "standard_cases", "study_ski"),
    "skisnow.report",
)

__getattr__ = lazy_getattr(__name__, _LAZY)

__all__ = [
    "DEFAULT_LEVEL",
    "DEFAULT_N_POINTS",
    "DEFAULT_PROFILE_SOURCE",
    "DEFAULT_SAMPLES",
    "DEFAULT_TOL",
    "INTERVAL_ZONES",
    "MAP_MASSES",
    "MAP_MODULI",
    "MIXED_SHARE",
    "MODELS",
    "PATCH_ZONES",
    "PROFILE_SOURCES",
    "SKI_MODELS",
    "STANDARD_SNOWS",
    "ZONE_QUANTITIES",
    "Case",
    "Intervals",
    "SkiStudy",
    "Topology",
    "case_intervals",
    "case_quantities",
    "loaded_profiles",
    "note_implausible",
    "note_solved",
    "note_unconverged",
    "recording_implausible",
    "recording_solved",
    "recording_unconverged",
    "resolve_ski",
    "sample_intervals",
    "shipped_twin",
    "solve_case",
    "standard_cases",
    "station_masks",
    "stations",
    "study_ski",
    "topology_shares",
    "topology_text",
    "zone_station_masks",
    "zone_topology",
]
