"""The ski at the macro scale: beam model, shipped virtual skis, virtual bench, metrics, network.

After Kalliorinne et al., "Characterisation of the Contact between Cross-Country Skis and Snow:
A Macro-Scale Investigation of the Apparent Contact", Lubricants 11 (2023), §2–3.1, and
Breitschädel (2012, Procedia Eng. 34, 391–396) for the practitioners' metrics.

Equation map (Kalliorinne et al. 2023 unless named):

* eq. 1, h = f(x, m, x_m), the loaded camber profile on the bench:
  :func:`camber_profile` (the one function downstream code calls), computed by the beam
  (:func:`solve_beam` → :class:`BeamSolution`, :func:`loaded_profile`) or predicted by the
  camber network (:class:`CamberNetwork`, :meth:`CamberNetwork.predict`).
* Figure 3, the network's block architecture (load condition, ski collapse, ski camber,
  prediction): :class:`BlockNetwork`, :class:`Architecture`; MATLAB's ``mapminmax``:
  :class:`Scaling`; the trained range: :class:`Domain`; training with held-out load
  conditions and Levenberg–Marquardt (Marquardt 1963): :func:`train_network`.
* §2.1, the SkiSelector bench and its load sequence (m 5–130 kg, x_m 40–240 mm behind the
  balance point): :func:`run_bench`, :func:`bench_grid` → :class:`~skisnow.io.BenchData`.
* The ski itself (not in the paper: the ground truth that generates bench data): an
  Euler–Bernoulli beam with stiffness EI(x) and free camber z0(x), free-floating on the rigid
  stone — force and moment balance as in eq. 3 with the unilateral contact solved as an LCP
  (Nocedal & Wright 2006, Alg. 16.3; Júdice & Pires 1994): :func:`solve_beam`; the shipped
  skis :data:`SHIPPED_SKIS`, :class:`Ski`, :func:`get_ski` (a shipped name or a ski file),
  :class:`Provenance`; ski files (JSON ``skisnow-ski`` v1, validated, exact round trip):
  :func:`read_ski`, :func:`write_ski`, :func:`ski_to_json`; the passport (EI(x), z0(x), bands,
  metrics): :func:`ski_passport` → :class:`SkiPassport`; EI(x) and z0(x) identified from a
  bench sequence: :func:`identify_ski` → :class:`IdentificationResult`, its uncertainty predicted
  for a bench plan before measuring (Fisher information, Cramér–Rao):
  :func:`predict_identification_uncertainty` → :class:`BenchPlanPrediction`; beam references for the
  tests: :func:`cantilever_tip_deflection`, :func:`three_point_bending_deflection`,
  :func:`beam_stiffness_matrix`, :func:`hermite_interpolate`.
* Practitioners' metrics (Breitschädel 2012): camber height :func:`camber_height`, wax pocket
  :func:`wax_pocket`, :func:`wax_pocket_length`, closing load :func:`closing_load`,
  :func:`closing_load_from_bench`, stiffness :func:`ski_stiffness`, contact lengths with the
  50 µm criterion measured from the plane the ski rests on (:func:`support_line`,
  :func:`height_above_support`, :func:`breitschaedel_contact`, the one definition skisnow
  uses) :func:`contact_lengths`, :func:`contact_patches`; all of them for one ski:
  :func:`ski_metrics` → :class:`SkiMetrics`.

Eq. 2 (the equivalent modulus) and eq. 3 (the contact with force and moment balance) are
:mod:`skisnow.contact`'s. The network's file format (``save_network``, ``load_network``,
``shipped_network``) lives in :mod:`skisnow.io` and is re-exported here. The bench, the metrics
(pandas) and the network (JAX) are imported on first use, so ``import skisnow.ski`` stays light.
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
from skisnow.ski._breitschaedel import (
    BREITSCHAEDEL_THRESHOLD,
    breitschaedel_contact,
    height_above_support,
    support_line,
)
from skisnow.ski._metrics import (
    CLOSED_THRESHOLD,
    camber_height,
    contact_lengths,
    contact_patches,
    ski_stiffness,
    wax_pocket,
    wax_pocket_length,
)
from skisnow.ski._passport import SkiPassport, ski_passport
from skisnow.ski._profiles import camber_profile
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
from skisnow.ski._skis import SHIPPED_SKIS, Provenance, Ski, get_ski, shipped_ski_path

# The bench and the metrics of one ski read and write tables (pandas), the network needs JAX:
# imported on first use, so that the contact sweep's workers and the CLI start without them
# (pandas alone measured 1.4 s of a 2.9 s cold import).
_LAZY = {
    **dict.fromkeys(
        ("DEFAULT_LOAD_POSITIONS", "DEFAULT_MASSES", "bench_grid", "run_bench"),
        "skisnow.ski._bench",
    ),
    **dict.fromkeys(
        ("SkiMetrics", "closing_load", "closing_load_from_bench", "ski_metrics"),
        "skisnow.ski._ski_metrics",
    ),
    **dict.fromkeys(
        ("Architecture", "BlockNetwork", "CamberNetwork", "Domain", "ReferenceProfile", "Scaling"),
        "skisnow.ski._network",
    ),
    # the model's file format lives in skisnow.io; re-exported here for convenience
    **dict.fromkeys(("load_network", "save_network", "shipped_network"), "skisnow.io"),
    **dict.fromkeys(("TrainingProgress", "train_network"), "skisnow.ski._training"),
    **dict.fromkeys(("IdentificationResult", "identify_ski"), "skisnow.ski._identify"),
    **dict.fromkeys(
        ("BenchPlanPrediction", "predict_identification_uncertainty"), "skisnow.ski._bench_plan"
    ),
}


__getattr__ = lazy_getattr(__name__, _LAZY)


__all__ = [
    "BREITSCHAEDEL_THRESHOLD",
    "CLOSED_THRESHOLD",
    "DEFAULT_LOAD_POSITIONS",
    "DEFAULT_MASSES",
    "SHIPPED_SKIS",
    "SKI_FILE_FORMAT",
    "SKI_FILE_VERSION",
    "Architecture",
    "BeamSolution",
    "BenchPlanPrediction",
    "BlockNetwork",
    "CamberNetwork",
    "Domain",
    "IdentificationResult",
    "Provenance",
    "ReferenceProfile",
    "Scaling",
    "Ski",
    "SkiMetrics",
    "SkiPassport",
    "TrainingProgress",
    "beam_stiffness_matrix",
    "bench_grid",
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
    "identify_ski",
    "load_network",
    "loaded_profile",
    "predict_identification_uncertainty",
    "read_ski",
    "run_bench",
    "save_network",
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
    "support_line",
    "three_point_bending_deflection",
    "train_network",
    "wax_pocket",
    "wax_pocket_length",
    "write_ski",
]
