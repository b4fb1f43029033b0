"""One case, four doors, identical numbers: ``skisnow contact --json``, ``solve_case``, a
one-point sweep and the report all run the chain of :mod:`skisnow.pipeline` on the same grid,
the same width and the same solver settings, so they agree bit for bit (not to a tolerance)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from skisnow.cli import main
from skisnow.pipeline import solve_case
from skisnow.report import standard_cases

N = 512
SKI, MASS, XM, E = "classic", 45.0, -0.12, 100e6  # a classic ski: the kick zone is used too
ZONES = ("rear", "middle", "front", "total")


@pytest.fixture(scope="module")
def case():
    return solve_case(SKI, mass=MASS, load_position=XM, snow_modulus=E, n_points=N,
                      profile_source="beam")  # fmt: skip


@pytest.fixture(scope="module")
def sweep(tmp_path_factory):
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep

    spec = SweepSpec(skis=(SKI,), masses=(MASS,), load_positions=(XM,), snow_moduli=(E,),
                     n_points=N, profile_source="beam")  # fmt: skip
    store = tmp_path_factory.mktemp("doors") / "one.zarr"
    run_sweep(spec, store, workers=0)
    return open_sweep(store)


def test_cli_json_is_solve_case(case, capsys) -> None:
    args = ["contact", "--ski", SKI, "--mass-kg", "45", "--load-position-mm", "-120",
            "--snow-modulus-mpa", "100", "--points", str(N), "--profile-source", "beam",
            "--json"]  # fmt: skip
    assert main(args) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["points"] == N and doc["width_mm"] == case.width * 1e3
    for name in ZONES:
        z, got = case.zones[name], doc[name]
        assert got["length_mm"] == z.length * 1e3
        assert got["area_cm2"] == z.area * 1e4
        assert got["load_share"] == z.load_share
        assert got["patches"] == z.patches
        if z.patches:
            assert got["mean_pressure_kpa"] == z.mean_pressure * 1e-3
            assert got["max_pressure_kpa"] == z.max_pressure * 1e-3
        assert doc["breitschaedel"][name]["length_mm"] == case.breitschaedel[name].length * 1e3
    assert doc["iterations"] == case.solution.iterations
    assert doc["translation_um"] == case.solution.translation * 1e6


def test_one_point_sweep_is_solve_case(case, sweep) -> None:
    ds = sweep.isel(ski=0, mass_kg=0, load_position_mm=0, snow_modulus_mpa=0)
    for name in ZONES:
        z, row = case.zones[name], ds.sel(zone=name)
        assert float(row["length_mm"]) == z.length * 1e3
        assert float(row["area_cm2"]) == z.area * 1e4
        assert float(row["load_share"]) == z.load_share
        assert int(row["patches"]) == z.patches
        assert float(row["breitschaedel_length_mm"]) == case.breitschaedel[name].length * 1e3
        if z.patches:
            assert float(row["mean_pressure_kpa"]) == z.mean_pressure * 1e-3
            assert float(row["max_pressure_kpa"]) == z.max_pressure * 1e-3
    assert int(ds["iterations"]) == case.solution.iterations


def test_report_shows_solve_case(case, sweep) -> None:
    from skisnow.report import build_report, study_ski

    # the report's standard loads at body mass 2 x 45 kg: its half-weight case is this case
    half = standard_cases(SKI, body_mass=2 * MASS, load_position=XM, snows=(E,),
                          profile_source="beam", n_points=N)[0]  # fmt: skip
    np.testing.assert_array_equal(half.solution.pressure, case.solution.pressure)
    np.testing.assert_equal(half.zones.as_dict(), case.zones.as_dict())
    study = study_ski(SKI, body_mass=2 * MASS, load_position=XM, snows=(E,), dataset=sweep,
                      profile_source="beam", n_points=N)  # fmt: skip
    text = build_report(study)
    for name in ("rear", "front"):
        z = case.zones[name]
        if not z.patches:
            continue
        row = re.search(rf"<tr><td>half \(45 kg\)</td><td>100</td><td>{name}</td>"
                        r"<td>([^<]+)</td><td>([^<]+)</td><td>([^<]+)</td>", text)  # fmt: skip
        assert row is not None, name
        # the page prints 3 significant digits of the same numbers
        assert row.group(1) == format(z.length * 1e3, ".3g")
        assert row.group(3) == format(z.mean_pressure / 1e3, ".3g")
