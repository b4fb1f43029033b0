"""The inverse problem: a ski's stiffness EI(x) and free camber z0(x) from its camber bench.

Nonlinear least squares of the beam of :mod:`skisnow.ski` in unilateral contact with the bench
stone (Kalliorinne et al. 2023, §3.1, eq. 1) against every profile of a bench sequence
(:class:`~skisnow.bench.BenchData`), with the exact Jacobian, a homotopy on a smoothed contact,
Levenberg–Marquardt, λ by generalised cross-validation and Gauss–Newton bands:
:func:`identify_ski` → :class:`IdentificationResult`, widened by a parametric bootstrap with
:func:`bootstrap_bands` (the method: the docstring of
:mod:`skisnow.identify._identify`); and the uncertainty of an identification predicted for a
bench plan before measuring (Fisher information, Cramér–Rao):
:func:`predict_identification_uncertainty` → :class:`BenchPlanPrediction`; an opt-in population
prior of the fit (:func:`population_prior` → :class:`PopulationPrior`, ``identify_ski(prior=...)``).

May import: ski, bench
"""

from __future__ import annotations

from skisnow.identify._bench_plan import BenchPlanPrediction, predict_identification_uncertainty
from skisnow.identify._bootstrap import (
    Replicates,
    bootstrap_bands,
    replicate_scale,
    run_replicates,
    widen_bands,
)
from skisnow.identify._identify import IdentificationResult, identify_ski
from skisnow.identify._prior import PopulationPrior, population_prior

__all__ = [
    "BenchPlanPrediction",
    "IdentificationResult",
    "PopulationPrior",
    "Replicates",
    "bootstrap_bands",
    "identify_ski",
    "population_prior",
    "predict_identification_uncertainty",
    "replicate_scale",
    "run_replicates",
    "widen_bands",
]
