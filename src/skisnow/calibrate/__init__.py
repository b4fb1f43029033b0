"""The calibration of the shipped skis on the captions of Kalliorinne et al. (2023), Figs. 4–7.

A fitting program, the provenance of the shipped ski files: a ski is a spline (log EI and the
free camber z0 at knots, PCHIP, as :func:`skisnow.ski.spline_ski` makes them; the parametrisation
in :mod:`skisnow.calibrate._params`); for a parameter vector the paper's pipeline runs on the ski
(:func:`skisnow.paper.solve_caption_case`: the beam on the rigid plane → rigid loaded profile →
strip half-space with force and moment balance, E_base = 900 MPa, ν = 0.3); the residuals, in
units of the tolerances of :data:`skisnow.paper.TOLERANCES`, plus hinge terms on the
practitioners' numbers, the paper's load topology and the shape of EI(x)
(:func:`residuals`, :class:`FitOptions`), are minimised by a seeded differential evolution, then
a bounded least-squares polish (:func:`fit`); :func:`report` makes the calibration record,
:func:`write_shipped` the ski file of a record, :func:`run_calibration` one run of the program
(:class:`CalibrationRun`). ``--knots dense`` fits on :data:`DENSE_KNOTS` (19 log-EI and 26
camber knots instead of 10 and 13, every start resampled onto them: :func:`resampled_vector`),
to ask whether a misfit is a limit of the knots or of the model; ``--caption-only`` drops the
plausibility terms (what the captions alone want). Records go to
``OUT/calibration_<ski>[_caption_only]<tag>.json``.

Run::

    uv run skisnow calibrate [--ski skate|classic] [--seed 0] [--generations 30] [--popsize 6]
        [--caption-only] [--knots default|dense] [--out DIR] [--start RECORD|shipped] ...
    uv run skisnow calibrate --write-shipped RECORD.json      # the shipped ski file of a record

(``uv run python benchmarks/calibrate_skis.py ...``, which the shipped skis' provenance cites,
runs the same command.)

May import: ski, paper
"""

from __future__ import annotations

from skisnow.calibrate._command import CalibrationRun, run_calibration
from skisnow.calibrate._fit import fit, report
from skisnow.calibrate._params import (
    BODY,
    DENSE_KNOTS,
    KNOTS,
    POS,
    START,
    bounds,
    kick_zone_of,
    make_ski,
    record_vector,
    resampled_vector,
    shipped_vector,
    start_vector,
    unpack,
)
from skisnow.calibrate._residuals import (
    BAD,
    EI_SHAPE_SCALE,
    EI_STEP_MAX,
    PATCH_PENALTY,
    SHARE_CHANGE_MAX,
    FitOptions,
    caption_residuals,
    default_knot_indices,
    ei_shape_residuals,
    hinge_limits,
    plausibility,
    plausibility_residuals,
    residuals,
    topology,
    topology_residuals,
)
from skisnow.calibrate._shipped import write_shipped

__all__ = [
    "BAD",
    "BODY",
    "DENSE_KNOTS",
    "EI_SHAPE_SCALE",
    "EI_STEP_MAX",
    "KNOTS",
    "PATCH_PENALTY",
    "POS",
    "SHARE_CHANGE_MAX",
    "START",
    "CalibrationRun",
    "FitOptions",
    "bounds",
    "caption_residuals",
    "default_knot_indices",
    "ei_shape_residuals",
    "fit",
    "hinge_limits",
    "kick_zone_of",
    "make_ski",
    "plausibility",
    "plausibility_residuals",
    "record_vector",
    "report",
    "resampled_vector",
    "residuals",
    "run_calibration",
    "shipped_vector",
    "start_vector",
    "topology",
    "topology_residuals",
    "unpack",
    "write_shipped",
]
