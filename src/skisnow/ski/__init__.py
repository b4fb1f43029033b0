"""The ski itself: an Euler–Bernoulli beam with stiffness EI(x) and free camber z0(x), as files.

After Kalliorinne et al., "Characterisation of the Contact between Cross-Country Skis and Snow:
A Macro-Scale Investigation of the Apparent Contact", Lubricants 11 (2023), §2–3.1, and
Breitschädel (2012, Procedia Eng. 34, 391–396) for the practitioners' metrics of a profile. The
ski (not in the paper: the ground truth that generates bench data) free-floating on the rigid
stone — force and moment balance as in eq. 3 with the unilateral contact solved as an LCP
(Nocedal & Wright 2006, Alg. 16.3; Júdice & Pires 1994), with contact points between the nodes
(an exchange method for the non-penetration along the whole ski: :func:`solve_point_contact`,
:class:`PointContact`, :class:`SubGrid`): :func:`solve_beam` → :class:`BeamSolution`,
:func:`loaded_profile`; the skis :class:`Ski`, :class:`Provenance`, the
shipped ones :data:`SHIPPED_SKIS` and :func:`get_ski` (a shipped name or a ski file), spline skis
(:func:`spline_ski`); ski files (JSON ``skisnow-ski`` v1 and v2, validated, exact round trip;
v2 adds an identified ski's determined stations and posterior modes):
:func:`read_ski`, :func:`write_ski`, :func:`ski_to_json`; samples of an identified ski from
its posterior, :func:`sample_skis`, and what a ski's answers are worth in words,
:func:`uncertainty_note` (the shipped skis: calibrated, not identified; no stated interval);
the beam's finite elements, which the
identification reuses (:func:`beam_stiffness_matrix`, :func:`hermite_interpolate`,
:func:`boot_load_vector`, :class:`BeamLcp`, …) and beam references for the tests
(:func:`cantilever_tip_deflection`, :func:`three_point_bending_deflection`); metrics of a loaded
profile (Breitschädel 2012): :func:`camber_height`, :func:`wax_pocket`,
:func:`wax_pocket_length`, :func:`ski_stiffness`, :func:`contact_lengths`,
:func:`contact_patches`, and the 50 µm contact criterion measured from the plane the ski rests
on (:func:`support_line`, :func:`height_above_support`, :func:`breitschaedel_contact`, the one
definition skisnow uses).

May import: core only

Kept for compatibility; their homes are :mod:`skisnow.bench` (the camber bench: DEFAULT_MASSES,
DEFAULT_LOAD_POSITIONS, bench_grid, run_bench, SkiMetrics, ski_metrics, closing_load,
closing_load_from_bench, SkiPassport, ski_passport), :mod:`skisnow.network` (the camber
network: Architecture, BlockNetwork, CamberNetwork, Domain, ReferenceProfile, Scaling,
TrainingProgress, train_network, load_network, save_network, shipped_network, camber_profile)
and :mod:`skisnow.identify` (IdentificationResult, identify_ski, BenchPlanPrediction,
predict_identification_uncertainty): these names are imported from there on first use.
"""

from __future__ import annotations

from skisnow._lazy import lazy_getattr
from skisnow.ski._beam import (
    DEFAULT_BOOT_LENGTH,
    DEFAULT_N_ELEMENTS,
    BeamSolution,
    beam_stiffness_matrix,
    cantilever_tip_deflection,
    hermite_interpolate,
    loaded_profile,
    solve_beam,
    three_point_bending_deflection,
)
from skisnow.ski._breitschaedel import (
    BREITSCHAEDEL_THRESHOLD,
    breitschaedel_contact,
    height_above_support,
    support_line,
)
from skisnow.ski._contact_points import (
    DEFAULT_TOL_PENETRATION,
    PointContact,
    SubGrid,
    hermite_rows,
    solve_point_contact,
)
from skisnow.ski._fem import GAUSS4_W, GAUSS4_X, banded_upper, boot_load_vector, shape_functions
from skisnow.ski._lcp import BeamLcp, LcpResult, lower_hull_bracket
from skisnow.ski._metrics import (
    CLOSED_THRESHOLD,
    DEFAULT_METRIC_POSITION,
    camber_height,
    contact_lengths,
    contact_patches,
    ski_stiffness,
    wax_pocket,
    wax_pocket_length,
)
from skisnow.ski._posterior import sample_skis, uncertainty_note
from skisnow.ski._registry import (
    PLAUSIBLE_SKIS,
    REPRODUCTION_SKIS,
    SHIPPED_SKIS,
    get_ski,
    shipped_ski_path,
)
from skisnow.ski._shipped import SHIPPED_SOURCES, rest_on_plane
from skisnow.ski._skifile import (
    SKI_FILE_FORMAT,
    SKI_FILE_VERSION,
    read_ski,
    ski_from_document,
    ski_from_json,
    ski_to_document,
    ski_to_json,
    write_ski,
)
from skisnow.ski._skis import Provenance, Ski
from skisnow.ski._spline import SPLINE_ENDS, SPLINE_KNOTS, spline_ski

# Compatibility re-exports (see the docstring): imported on first use, which also keeps
# ``import skisnow.ski`` light (the bench and its metrics need pandas, the network JAX). The
# names repeat those of their homes on purpose: a compatibility map names each old name and its
# home, statically (read by tools/import_graph.py and tests/test_compat.py).
_LAZY = {
    **dict.fromkeys(
        ("DEFAULT_LOAD_POSITIONS", "DEFAULT_MASSES", "bench_grid", "run_bench"), "skisnow.bench"
    ),
    **dict.fromkeys(
        ("SkiMetrics", "closing_load", "closing_load_from_bench", "ski_metrics"), "skisnow.bench"
    ),
    **dict.fromkeys(("SkiPassport", "ski_passport"), "skisnow.bench"),
    **dict.fromkeys(
        ("Architecture", "BlockNetwork", "CamberNetwork", "Domain", "ReferenceProfile", "Scaling"),
        "skisnow.network",
    ),
    **dict.fromkeys(("load_network", "save_network", "shipped_network"), "skisnow.network"),
    **dict.fromkeys(("TrainingProgress", "train_network", "camber_profile"), "skisnow.network"),
    **dict.fromkeys(("IdentificationResult", "identify_ski"), "skisnow.identify"),
    **dict.fromkeys(
        ("BenchPlanPrediction", "predict_identification_uncertainty"), "skisnow.identify"
    ),
}


__getattr__ = lazy_getattr(__name__, _LAZY)


__all__ = [
    "BREITSCHAEDEL_THRESHOLD",
    "CLOSED_THRESHOLD",
    "DEFAULT_BOOT_LENGTH",
    "DEFAULT_LOAD_POSITIONS",
    "DEFAULT_MASSES",
    "DEFAULT_METRIC_POSITION",
    "DEFAULT_N_ELEMENTS",
    "DEFAULT_TOL_PENETRATION",
    "GAUSS4_W",
    "GAUSS4_X",
    "PLAUSIBLE_SKIS",
    "REPRODUCTION_SKIS",
    "SHIPPED_SKIS",
    "SHIPPED_SOURCES",
    "SKI_FILE_FORMAT",
    "SKI_FILE_VERSION",
    "SPLINE_ENDS",
    "SPLINE_KNOTS",
    "Architecture",
    "BeamLcp",
    "BeamSolution",
    "BenchPlanPrediction",
    "BlockNetwork",
    "CamberNetwork",
    "Domain",
    "IdentificationResult",
    "LcpResult",
    "PointContact",
    "Provenance",
    "ReferenceProfile",
    "Scaling",
    "Ski",
    "SkiMetrics",
    "SkiPassport",
    "SubGrid",
    "TrainingProgress",
    "banded_upper",
    "beam_stiffness_matrix",
    "bench_grid",
    "boot_load_vector",
    "breitschaedel_contact",
    "camber_height",
    "camber_profile",
    "cantilever_tip_deflection",
    "closing_load",
    "closing_load_from_bench",
    "contact_lengths",
    "contact_patches",
    "get_ski",
    "height_above_support",
    "hermite_interpolate",
    "hermite_rows",
    "identify_ski",
    "load_network",
    "loaded_profile",
    "lower_hull_bracket",
    "predict_identification_uncertainty",
    "read_ski",
    "rest_on_plane",
    "run_bench",
    "sample_skis",
    "save_network",
    "shape_functions",
    "shipped_network",
    "shipped_ski_path",
    "ski_from_document",
    "ski_from_json",
    "ski_metrics",
    "ski_passport",
    "ski_stiffness",
    "ski_to_document",
    "ski_to_json",
    "solve_beam",
    "solve_point_contact",
    "spline_ski",
    "support_line",
    "three_point_bending_deflection",
    "train_network",
    "uncertainty_note",
    "wax_pocket",
    "wax_pocket_length",
    "write_ski",
]
