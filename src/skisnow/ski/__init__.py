"""The ski at the macro scale: beam model, shipped virtual skis, virtual bench, metrics, network.

* :class:`Ski`, :func:`get_ski`, :data:`SHIPPED_SKIS` — virtual skis (EI(x), z0(x), kick zone).
* :func:`solve_beam` → :class:`BeamSolution`, :func:`loaded_profile` — the free-floating
  Euler–Bernoulli beam on the rigid bench stone (seed paper 000, §3.1, eq. 1 h = f(x, m, x_m)).
* :func:`run_bench` — the virtual camber bench (the paper's load sequence) → ``BenchData``.
* :func:`ski_metrics` and friends — practitioners' metrics (camber, wax pocket, closing load,
  Breitschädel's stiffness and 50 µm contact lengths).
* :func:`camber_profile` — THE function downstream code calls for a loaded profile (beam or
  network).
* The camber network (issue 4) is re-exported lazily (``CamberNetwork``, ``train_network``,
  ``load_network``, ``save_network``, ``shipped_network``) so that ``import skisnow.ski`` does
  not import JAX.
"""

from __future__ import annotations

from skisnow._lazy import lazy_getattr
from skisnow.ski._beam import (
    BeamSolution,
    beam_stiffness_matrix,
    cantilever_tip_deflection,
    hermite_interpolate,
    loaded_profile,
    solve_beam,
    three_point_bending_deflection,
)
from skisnow.ski._profiles import camber_profile
from skisnow.ski._skis import SHIPPED_SKIS, Ski, get_ski

# The bench and the metrics read and write tables (pandas), the network needs JAX: imported on
# first use, so that the contact sweep's workers and the CLI start without them (pandas alone
# measured 1.4 s of a 2.9 s cold import).
_LAZY = {
    **dict.fromkeys(
        ("DEFAULT_LOAD_POSITIONS", "DEFAULT_MASSES", "bench_grid", "run_bench"),
        "skisnow.ski._bench",
    ),
    **dict.fromkeys(
        (
            "BREITSCHAEDEL_THRESHOLD",
            "CLOSED_THRESHOLD",
            "SkiMetrics",
            "camber_height",
            "closing_load",
            "closing_load_from_bench",
            "contact_lengths",
            "contact_patches",
            "ski_metrics",
            "ski_stiffness",
            "wax_pocket",
            "wax_pocket_length",
        ),
        "skisnow.ski._metrics",
    ),
    **dict.fromkeys(
        ("Architecture", "BlockNetwork", "CamberNetwork", "Domain", "ReferenceProfile", "Scaling"),
        "skisnow.ski._network",
    ),
    # the model's file format lives in skisnow.io; re-exported here for convenience
    **dict.fromkeys(("load_network", "save_network", "shipped_network"), "skisnow.io"),
    **dict.fromkeys(("TrainingProgress", "train_network"), "skisnow.ski._training"),
}


__getattr__ = lazy_getattr(__name__, _LAZY)


__all__ = [
    "BREITSCHAEDEL_THRESHOLD",
    "CLOSED_THRESHOLD",
    "DEFAULT_LOAD_POSITIONS",
    "DEFAULT_MASSES",
    "SHIPPED_SKIS",
    "Architecture",
    "BeamSolution",
    "BlockNetwork",
    "CamberNetwork",
    "Domain",
    "ReferenceProfile",
    "Scaling",
    "Ski",
    "SkiMetrics",
    "TrainingProgress",
    "beam_stiffness_matrix",
    "bench_grid",
    "camber_height",
    "camber_profile",
    "cantilever_tip_deflection",
    "closing_load",
    "closing_load_from_bench",
    "contact_lengths",
    "contact_patches",
    "get_ski",
    "hermite_interpolate",
    "load_network",
    "loaded_profile",
    "run_bench",
    "save_network",
    "shipped_network",
    "ski_metrics",
    "ski_stiffness",
    "solve_beam",
    "three_point_bending_deflection",
    "train_network",
    "wax_pocket",
    "wax_pocket_length",
]
