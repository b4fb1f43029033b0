"""Profile CSV in, fields CSV out (field units at the edge)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from skisnow import FileFormatError
from skisnow.contact import fields_table, read_profile, solve_contact, write_fields


def test_read_profile_converts_units_and_resamples(tmp_path: Path) -> None:
    x_mm = 100 * np.array([0, 1, 2, 3, 5, 6, 7, 8, 9, 10.0])  # one irregular step
    csv = tmp_path / "p.csv"
    pd.DataFrame({"x_mm": x_mm, "height_mm": 0.02 * x_mm}).to_csv(csv, index=False)
    x, h = read_profile(csv)
    assert np.allclose(np.diff(x), np.diff(x).mean(), rtol=1e-12)  # uniform now
    assert x[0] == 0 and x[-1] == pytest.approx(1.0)
    assert np.allclose(h, 0.02 * x, rtol=1e-12)  # a linear profile is resampled exactly
    with pytest.raises(FileFormatError, match="uniformly"):
        read_profile(csv, resample=False)


def test_read_profile_errors(tmp_path: Path) -> None:
    csv = tmp_path / "p.csv"
    rows = "\n".join(f"{100 * (10 - i)},{0.5 * i}" for i in range(10))
    csv.write_text("x_mm,height_mm\n" + rows + "\n")
    with pytest.raises(FileFormatError, match="line 3, column x_mm: x_mm must increase"):
        read_profile(csv)
    with pytest.raises(FileFormatError, match="no such"):
        read_profile(tmp_path / "missing.csv")


def test_fields_round_trip_keeps_the_balance(tmp_path: Path) -> None:
    x = np.linspace(-0.5, 0.5, 200)
    h = 1e-3 * x**2 + 1e-4 * np.cos(8 * x) ** 2
    for model in ("strip", "surface"):
        sol = solve_contact(
            x, h, load=200.0, load_position=0.05, modulus=2e8, model=model, n_across=4, tol=1e-10
        )
        path = write_fields(sol, tmp_path / f"{model}.csv")
        table = pd.read_csv(path)
        assert table.equals(table[list(fields_table(sol).columns)])
        force = table["pressure_kpa"].sum() * 1e3 * (x[1] - x[0]) * 0.044
        assert force == pytest.approx(200.0, rel=1e-8)
