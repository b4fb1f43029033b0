"""Sweeps that also store the fields along the ski (``SweepSpec.field_stations``): the stored
block-mean pressure carries the load of every point, the fields are the solver's, resuming a
complete store recomputes nothing, and bad station counts are refused before any store exists."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from skisnow import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.sweep import SweepSpec, open_sweep, run_sweep, station_fields

SPEC = dict(skis=("skate",), masses=(30.0, 60.0), load_positions=(-0.12,),
            snow_moduli=(50e6, 200e6), profile_source="beam", n_points=512)  # fmt: skip


def test_fields_are_stored_and_carry_the_load(tmp_path: Path) -> None:
    from skisnow.pipeline import solve_case
    from skisnow.ski import get_ski

    spec = SweepSpec(**SPEC, field_stations=64)
    run_sweep(spec, tmp_path / "f.zarr", workers=0)
    ds = open_sweep(tmp_path / "f.zarr")
    assert ds["pressure_kpa"].dims == ("ski", "mass_kg", "load_position_mm", "snow_modulus_mpa",
                                       "station")  # fmt: skip
    x = ds["x_mm"].values[0] * 1e-3
    force = ds["pressure_kpa"].values[0].sum(-1) * 1e3 * (x[1] - x[0]) * get_ski("skate").width
    expected = np.asarray(SPEC["masses"])[:, None, None] * STANDARD_GRAVITY
    np.testing.assert_allclose(force, np.broadcast_to(expected, force.shape), rtol=1e-5)
    case = solve_case("skate", mass=60.0, load_position=-0.12, snow_modulus=200e6,
                      profile_source="beam", n_points=512)  # fmt: skip
    want = station_fields(case.solution, case.zones, 64)
    point = ds.sel(ski="skate", mass_kg=60.0, load_position_mm=-120.0, snow_modulus_mpa=200.0)
    np.testing.assert_allclose(point["pressure_kpa"].values, want["pressure_kpa"], rtol=1e-5,
                               atol=1e-4)  # float32 storage  # fmt: skip
    np.testing.assert_array_equal(point["zone_code"].values, want["zone_code"])
    again = run_sweep(spec, tmp_path / "f.zarr", workers=0)
    assert len(again.computed) == 0


def test_a_store_without_fields_is_not_resumed_as_one_with_them(tmp_path: Path) -> None:
    run_sweep(SweepSpec(**SPEC), tmp_path / "s.zarr", workers=0)
    with pytest.raises(InputError):
        run_sweep(SweepSpec(**SPEC, field_stations=64), tmp_path / "s.zarr", workers=0)


@pytest.mark.parametrize("n", [-1, 8, 100, 2.5])
def test_bad_station_counts_are_refused(n: float) -> None:
    with pytest.raises(InputError, match="field_stations"):
        SweepSpec(**SPEC, field_stations=n)
