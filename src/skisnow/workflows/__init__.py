"""Technician workflows: a fleet side by side, pairs, and the contact over a load cycle.

Built on the one-case chain of Kalliorinne et al. (2023): the loaded profile (eq. 1) pressed into
the elastic half-space with force and moment balance (eq. 2–3), grouped into zones.

* skis: :func:`resolve_ski`, :func:`resolve_fleet` → :class:`FleetSki` (a shipped name, a ski
  file, a bench file);
* a fleet: :func:`compare_fleet` → :class:`FleetComparison` (metrics and contact at ½ and 1
  body weight, :data:`CRITERIA` for rankings), :func:`rank_across_snow` → :class:`SnowRanking`;
* pairs: :func:`match_pairs` → :class:`Pairing` (minimum-weight matching of
  :func:`pair_distance`; a pair is a tie within uncertainty by the simultaneous "same ski?"
  test, :func:`same_ski_test`; on two skis' shapes alone, :func:`same_ski`);
* load cycles: :class:`LoadHistory`, :func:`read_load_history`, :data:`TEMPLATES`,
  :func:`template_history`, :func:`run_cycle` (an xarray Dataset over time),
  :func:`kick_contact_summary` (for an identified ski with 95 % intervals over posterior
  samples, :func:`cycle_intervals`); with a base texture, the friction proxies over the stride,
  :func:`real_cycle_summary`;
* skis × bases on one snow: :func:`real_table`, :func:`rank_real` by a proxy of
  :data:`PROXIES` (ties within the glide-test precision, :data:`GLIDE_TEST_PRECISION`,
  Lemmettylä et al. 2021);
* an identified ski's answers with 95 % intervals (``compare_fleet(samples=...)``,
  :func:`interval_records`); rankings mark *a tie within uncertainty* where intervals overlap.

May import: ski, bench, network, identify, pipeline, multiscale, snow
"""

from skisnow.workflows._bases import (
    GLIDE_TEST_PRECISION,
    GLIDE_TEST_PRECISION_RANGE,
    PROXIES,
    Proxy,
    rank_real,
    real_table,
)
from skisnow.workflows._cycle import (
    UNLOADED_MASS,
    ZONES,
    kick_contact_summary,
    real_cycle_summary,
    run_cycle,
)
from skisnow.workflows._cycle_intervals import CYCLE_QUANTITIES, cycle_intervals, cycle_quantities
from skisnow.workflows._fleet import (
    CRITERIA,
    DEFAULT_LOAD_POSITION,
    Criterion,
    FleetComparison,
    FleetEntry,
    compare_fleet,
)
from skisnow.workflows._fleet_intervals import interval_records
from skisnow.workflows._fleet_snow import SnowRanking, rank_across_snow
from skisnow.workflows._history import (
    MAX_GAP_FACTOR,
    LoadHistory,
    check_positions,
    read_load_history,
)
from skisnow.workflows._pairs import (
    CAMBER_TOLERANCE,
    CONTACT_TOLERANCE,
    POOR_MATCH_DISTANCE,
    STIFFNESS_TOLERANCE,
    PairDistance,
    Pairing,
    match_pairs,
    pair_distance,
    same_ski,
)
from skisnow.workflows._same_ski import SameSkiTest, same_ski_test
from skisnow.workflows._skis import FleetSki, resolve_fleet, resolve_ski
from skisnow.workflows._templates import TEMPLATES, CycleTemplate, template_history
from skisnow.workflows._ties import competition_ranks, tied_with

__all__ = [
    "CAMBER_TOLERANCE",
    "CONTACT_TOLERANCE",
    "CRITERIA",
    "CYCLE_QUANTITIES",
    "DEFAULT_LOAD_POSITION",
    "GLIDE_TEST_PRECISION",
    "GLIDE_TEST_PRECISION_RANGE",
    "MAX_GAP_FACTOR",
    "POOR_MATCH_DISTANCE",
    "PROXIES",
    "STIFFNESS_TOLERANCE",
    "TEMPLATES",
    "UNLOADED_MASS",
    "ZONES",
    "Criterion",
    "CycleTemplate",
    "FleetComparison",
    "FleetEntry",
    "FleetSki",
    "LoadHistory",
    "PairDistance",
    "Pairing",
    "Proxy",
    "SameSkiTest",
    "SnowRanking",
    "check_positions",
    "compare_fleet",
    "competition_ranks",
    "cycle_intervals",
    "cycle_quantities",
    "interval_records",
    "kick_contact_summary",
    "match_pairs",
    "pair_distance",
    "rank_across_snow",
    "rank_real",
    "read_load_history",
    "real_cycle_summary",
    "real_table",
    "resolve_fleet",
    "resolve_ski",
    "run_cycle",
    "same_ski",
    "same_ski_test",
    "template_history",
    "tied_with",
]
