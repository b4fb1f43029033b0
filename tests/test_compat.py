"""Every name users imported before the package split still imports where it did, and is the
same object as at its new home (issue 24: ``skisnow.ski`` split into ``ski``, ``bench``,
``network`` and ``identify``; ``skisnow.io`` a compatibility facade; the study of a ski moved
from ``skisnow.pipeline`` to ``skisnow.report``)."""

from __future__ import annotations

import importlib

import pytest

from _extras import HAS_NETWORK, NETWORK_REASON
from skisnow._optional import MissingDependencyError

# the __all__ lists of skisnow.ski, skisnow.io and skisnow.pipeline before the split
OLD_ALL = {
    "skisnow.ski": [
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
    ],
    "skisnow.io": [
        "BENCH_COLUMNS",
        "MIN_PROFILE_POINTS",
        "MODEL_FORMAT",
        "MODEL_FORMAT_VERSION",
        "BenchData",
        "load_network",
        "metadata_checksum",
        "model_paths",
        "network_arrays",
        "network_from_files",
        "parse_model_bytes",
        "read_bench",
        "read_model_files",
        "save_network",
        "shipped_network",
        "validate_bench_table",
        "write_bench",
        "write_model_files",
    ],
    "skisnow.pipeline": [
        "DEFAULT_N_POINTS",
        "DEFAULT_TOL",
        "MAP_MASSES",
        "MAP_MODULI",
        "MODELS",
        "PROFILE_SOURCES",
        "SKI_MODELS",
        "STANDARD_SNOWS",
        "Case",
        "SkiStudy",
        "loaded_profiles",
        "resolve_ski",
        "solve_case",
        "standard_cases",
        "stations",
        "study_ski",
    ],
}

# where each name lives now (names not listed stayed where they were)
HOMES = {
    **dict.fromkeys(
        [
            "DEFAULT_LOAD_POSITIONS",
            "DEFAULT_MASSES",
            "SkiMetrics",
            "SkiPassport",
            "bench_grid",
            "closing_load",
            "closing_load_from_bench",
            "run_bench",
            "ski_metrics",
            "ski_passport",
            "BENCH_COLUMNS",
            "MIN_PROFILE_POINTS",
            "BenchData",
            "read_bench",
            "validate_bench_table",
            "write_bench",
        ],
        "skisnow.bench",
    ),
    **dict.fromkeys(
        [
            "Architecture",
            "BlockNetwork",
            "CamberNetwork",
            "Domain",
            "ReferenceProfile",
            "Scaling",
            "TrainingProgress",
            "camber_profile",
            "load_network",
            "save_network",
            "shipped_network",
            "train_network",
            "MODEL_FORMAT",
            "MODEL_FORMAT_VERSION",
            "metadata_checksum",
            "model_paths",
            "network_arrays",
            "network_from_files",
            "parse_model_bytes",
            "read_model_files",
            "write_model_files",
        ],
        "skisnow.network",
    ),
    **dict.fromkeys(
        [
            "BenchPlanPrediction",
            "IdentificationResult",
            "identify_ski",
            "predict_identification_uncertainty",
        ],
        "skisnow.identify",
    ),
    **dict.fromkeys(
        ["MAP_MASSES", "MAP_MODULI", "STANDARD_SNOWS", "SkiStudy", "standard_cases", "study_ski"],
        "skisnow.report",
    ),
}

CASES = [(old, name) for old, names in OLD_ALL.items() for name in names]


def _get(module, name: str):
    """``module.name``; without the optional ``network`` extra a name of the camber network
    must fail by naming the extra to install (never an AttributeError): then skip, saying so."""
    try:
        return getattr(module, name)
    except MissingDependencyError as exc:
        assert not HAS_NETWORK and "--extra network" in str(exc), exc
        pytest.skip(f"{module.__name__}.{name}: {NETWORK_REASON}")


@pytest.mark.parametrize(("old", "name"), CASES, ids=[f"{o}.{n}" for o, n in CASES])
def test_old_name_resolves_to_its_new_home(old: str, name: str) -> None:
    module = importlib.import_module(old)
    assert name in module.__all__  # `from old import *` still brings it
    home = importlib.import_module(HOMES.get(name, old))
    assert name in home.__all__
    assert _get(module, name) is _get(home, name)
    # and the object says where it lives (classes and functions)
    where = getattr(_get(home, name), "__module__", None)
    if where is not None and callable(_get(home, name)):
        assert where.startswith(HOMES.get(name, old) + "."), where


def test_star_imports_of_the_old_homes() -> None:
    for old, names in OLD_ALL.items():
        scope: dict = {}
        try:
            exec(f"from {old} import *", scope)
        except MissingDependencyError as exc:  # the star brings the camber network's names
            assert not HAS_NETWORK and "--extra network" in str(exc), exc
            continue
        assert set(names) <= set(scope), old


def test_an_unknown_name_is_still_an_attribute_error() -> None:
    import skisnow.io
    import skisnow.pipeline
    import skisnow.ski

    for module in (skisnow.ski, skisnow.io, skisnow.pipeline):
        with pytest.raises(AttributeError, match="no_such_name"):
            _ = module.no_such_name  # type: ignore[attr-defined]


def test_nothing_inside_skisnow_imports_skisnow_io() -> None:
    """``skisnow.io`` holds no code: importing the library never needs it."""
    import subprocess
    import sys

    code = (
        "import sys, skisnow.ski, skisnow.bench, skisnow.network, skisnow.identify, "
        "skisnow.pipeline, skisnow.report, skisnow.cli; print('skisnow.io' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize(
    "package",
    ["ski", "bench", "network", "identify", "io", "pipeline", "report", "calibrate", "contact"],
)
def test_every_name_of_a_package_door_resolves(package: str) -> None:
    module = importlib.import_module(f"skisnow.{package}")
    assert len(set(module.__all__)) == len(module.__all__)
    for name in module.__all__:
        try:
            obj = getattr(module, name)
        except MissingDependencyError as exc:  # a camber network name without its extra
            assert not HAS_NETWORK and "--extra network" in str(exc), exc
            continue
        assert obj is not None, name
