"""The reproduction skis' fit (benchmarks/fit_k22.py): its penalty and tally say what the
caption table says (issue 30)."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def _script():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location("fit_k22", ROOT / "benchmarks" / "fit_k22.py")
    mod = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    return mod


def test_the_tally_is_the_caption_tables() -> None:
    """Zones within, counted by the fit, are the zones ``skisnow captions`` marks within; an
    error of at most one tolerance is exactly a number within (the penalty's units)."""
    from skisnow.calibrate import record_vector
    from skisnow.paper import caption_table

    mod = _script()
    doc = json.loads((ROOT / "benchmarks/calibration/calibration_skate_k22_v4.json").read_text())

    rows = mod.rows_of("skate", record_vector("skate", doc))
    shipped = caption_table(["skate-k22"], route="beam")
    assert mod.tally(rows)[0] == sum(r.ok for r in shipped)
    e, _ = mod.errors(rows)
    for r in rows:  # each zone: within iff all its numbers are within one tolerance
        one, _ = mod.errors([r])
        assert r.ok == (all(x <= 1.0 + 1e-12 for x in one) and mod.errors([r])[1] == 0)
    assert len(e) == 3 * len(rows)  # length, pressure and (stated or implied) share per zone


def test_the_penalty_is_the_small_quadratic_inside_the_margin_and_saturates_with_a_cap() -> None:
    mod = _script()
    inside = mod.penalty([0.5, 0.8], 0)
    assert inside == pytest.approx(0.1 * (0.25 + 0.64))  # only the small quadratic
    far = mod.penalty([40.0], 0)
    capped = mod.penalty([40.0], 0, cap=2.0)
    assert capped == pytest.approx(0.1 * 4 + 10 * (2 - mod.MARGIN) ** 2) and far > 100 * capped
    assert mod.penalty([], 1) == pytest.approx(9.0)  # a wrong patch count
    assert np.isfinite(mod.penalty([1e3], 2, cap=2.0))
