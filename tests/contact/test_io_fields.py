"""Fields files round-trip: what ``write_fields`` writes, ``read_fields`` reads back, and the
balance laws still hold on what was read (Σ p·w·dx = m·g, Σ (x − x_m)·p·w·dx = 0)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from skisnow import FileFormatError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.contact import read_fields, write_fields
from skisnow.pipeline import solve_case


def test_fields_round_trip_and_balance(tmp_path: Path) -> None:
    case = solve_case("skate", mass=60.0, load_position=-0.12, snow_modulus=100e6,
                      profile_source="beam", n_points=1024)  # fmt: skip
    s = case.solution
    path = write_fields(s, tmp_path / "f.csv")
    back = read_fields(path)
    np.testing.assert_allclose(back["x"], s.x, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(back["pressure"], s.pressure, rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(back["gap"], s.gap, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(back["displacement"], s.displacement, rtol=1e-9, atol=1e-15)
    dx, w = back["x"][1] - back["x"][0], case.width
    force = back["pressure"].sum() * dx * w
    assert force == pytest.approx(60.0 * STANDARD_GRAVITY, rel=1e-7)
    moment = ((back["x"] - case.load_position) * back["pressure"]).sum() * dx * w
    assert abs(moment) < 1e-6 * force * (back["x"][-1] - back["x"][0])


@pytest.mark.parametrize(
    ("text", "where"),
    [
        ("x_mm,pressure_kpa,gap_um\n1,2,3\n", "snow_displacement_um"),
        (
            "x_mm,pressure_kpa,gap_um,snow_displacement_um\n1,2,3,4\n1,2,3,4\n",
            "line 3, column x_mm",
        ),
        ("x_mm,pressure_kpa,gap_um,snow_displacement_um\n# c\n1,-2,3,4\n2,2,3,4\n", "line 3"),
        ("x_mm,pressure_kpa,gap_um,snow_displacement_um\n1,abc,3,4\n2,2,3,4\n", "pressure_kpa"),
    ],
)
def test_bad_fields_files_name_their_place(tmp_path: Path, text: str, where: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(FileFormatError, match=where):
        read_fields(path)
