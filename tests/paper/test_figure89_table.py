"""The Figure 8-9 table of the documentation holds what it claims (issue 30).

``benchmarks/figure89_table.py`` stores the maps of every shipped ski on both routes in
``docs/validation/data/`` and prints the verdict table of ``docs/validation/figures-8-9.md``.
Here: sample points of the stored maps are solved afresh through the one door (the maps are
the model's, not stale), and the verdicts are re-read from the stored maps by
``figure89_findings`` and compared with the JSON and with the table in the documentation.
"""

from __future__ import annotations

import importlib.util
import json
import re
from pathlib import Path

import numpy as np
import pytest

from _extras import needs_network

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "docs" / "validation" / "data"
DOC = ROOT / "docs" / "validation" / "figures-8-9.md"


def _script():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location(
        "figure89_table", ROOT / "benchmarks" / "figure89_table.py"
    )
    mod = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    return mod


@pytest.fixture(scope="module")
def stored() -> dict:
    return json.loads((DATA / "fig89_findings.json").read_text())


def test_every_shipped_ski_is_in_the_table(stored) -> None:  # type: ignore[no-untyped-def]
    from skisnow.paper import STATEMENTS
    from skisnow.ski import SHIPPED_SKIS

    skis = {c.split("/")[0] for c in stored["columns"]}
    assert skis == set(SHIPPED_SKIS)
    assert list(stored["rows"]) == list(STATEMENTS)


def test_verdicts_follow_from_the_stored_maps(stored) -> None:  # type: ignore[no-untyped-def]
    mod = _script()
    skis = list(dict.fromkeys(c.split("/")[0] for c in stored["columns"]))
    routes = list(dict.fromkeys(c.split("/")[1] for c in stored["columns"]))
    again = mod.findings_table(skis, routes, DATA)
    assert again == stored


def test_the_documentation_shows_the_stored_verdicts(stored) -> None:  # type: ignore[no-untyped-def]
    mod = _script()
    table = mod.markdown(stored)
    text = DOC.read_text()
    assert table in text, "docs/validation/figures-8-9.md: re-run benchmarks/figure89_table.py"


@pytest.mark.parametrize(
    ("ski", "route", "mass", "modulus"),
    [("skate", "beam", 37.0, 300.0),
     pytest.param("skate-k22", "network", 61.0, 100.0, marks=needs_network),
     ("classic-k22", "beam", 30.0, 400.0),
     pytest.param("classic", "network", 90.0, 20.0, marks=needs_network)],
)  # fmt: skip
def test_stored_maps_are_the_models(ski: str, route: str, mass: float, modulus: float) -> None:
    from skisnow.paper import zone_maps

    mod = _script()
    maps = mod.load_maps(ski, route, DATA)
    i = int(np.flatnonzero(maps.masses_kg == mass)[0])
    j = int(np.flatnonzero(maps.moduli_mpa == modulus)[0])
    # three masses around the sample (zone_maps needs three), one snow
    fresh = zone_maps(ski, maps.masses_kg[i - 1 : i + 2], [modulus], route=route,
                      n_points=maps.n_points)  # fmt: skip
    station = 1.86 / maps.n_points * 0.044 * 1e4  # one station of contact [cm²], about
    for zone in ("rear", "front"):
        assert fresh.area_cm2[zone][1, 0] == pytest.approx(maps.area_cm2[zone][i, j], abs=station)
        assert fresh.patches[zone][1, 0] == maps.patches[zone][i, j]
        a, b = fresh.pressure_kpa[zone][1, 0], maps.pressure_kpa[zone][i, j]
        assert (np.isnan(a) and np.isnan(b)) or a == pytest.approx(b, rel=0.02)
        assert fresh.breitschaedel_cm2[zone][1] == pytest.approx(maps.breitschaedel_cm2[zone][i])


def test_doc_table_has_a_row_per_statement() -> None:
    text = DOC.read_text()
    rows = [ln for ln in text.splitlines() if re.match(r"\| \d+ \| [a-z0-9-]+ \(", ln)]
    assert len(rows) == 12
