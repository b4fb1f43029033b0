"""`skisnow contact`: JSON document, fields file (balance laws), profile CSV, figure, errors."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from skisnow.cli import main

BASE = ["contact", "--mass-kg", "60", "--load-position-mm", "-70", "--snow-modulus-mpa", "100"]


def run_json(capsys: pytest.CaptureFixture[str], args: list[str]) -> dict:
    code = main([*args, "--json"])
    out = capsys.readouterr().out
    assert code == 0, out
    return json.loads(out)


def test_json_document_and_fields_balance(capsys, tmp_path: Path) -> None:
    fields = tmp_path / "fields.csv"
    doc = run_json(
        capsys, [*BASE, "--ski", "classic", "--points", "1024", "--fields-out", str(fields)]
    )
    keys = {
        "length_mm",
        "area_cm2",
        "mean_pressure_kpa",
        "max_pressure_kpa",
        "load_share",
        "patches",
    }
    for zone in ("rear", "middle", "front", "total"):
        assert keys <= set(doc[zone])
        assert set(doc["breitschaedel"][zone]) >= {"length_mm", "area_cm2", "patches"}
    assert doc["converged"] is True and doc["iterations"] > 0
    assert {"translation_um", "rotation_rad"} <= set(doc)
    # a classic ski loaded 70 mm behind the balance point collapses into its kick zone
    assert doc["kick"]["load_share"] > 0.05 and doc["rear"]["patches"] >= 1
    shares = sum(doc[z]["load_share"] for z in ("rear", "middle", "front"))
    assert shares == pytest.approx(1.0, rel=1e-12)
    # anyone can check the balance laws from the fields file (written with 10 digits)
    table = pd.read_csv(fields)
    assert list(table.columns) == ["x_mm", "pressure_kpa", "gap_um", "snow_displacement_um",
                                   "region", "patch"]  # fmt: skip
    x = table["x_mm"].to_numpy() * 1e-3
    p = table["pressure_kpa"].to_numpy() * 1e3
    dx = x[1] - x[0]
    force = np.sum(p) * dx * 0.044
    assert force == pytest.approx(60 * 9.80665, rel=1e-8)
    assert abs(np.sum((x + 0.070) * p) * dx * 0.044) < 1e-8 * force * 2.0
    assert np.all(table["gap_um"][p > 0].abs() < 1e-3)  # closed where loaded (≤ 1 nm)


def test_profile_csv_gives_the_same_answer_as_the_ski(capsys, tmp_path: Path) -> None:
    from skisnow.network import camber_profile
    from skisnow.pipeline import stations

    # the stations of the grid convention (skisnow.pipeline), written with 17 digits
    x, h = camber_profile(
        "skate", mass=30.0, load_position=-0.12, x=stations("skate", 512), source="beam"
    )
    csv = tmp_path / "profile.csv"
    pd.DataFrame({"x_mm": x * 1e3, "height_mm": h * 1e3}).to_csv(
        csv, index=False, float_format="%.17g"
    )
    args = ["contact", "--mass-kg", "30", "--load-position-mm", "-120", "--snow-modulus-mpa", "100"]
    a = run_json(capsys, [*args, "--ski", "skate", "--points", "512", "--profile-source", "beam"])
    b = run_json(capsys, [*args, "--profile", str(csv)])
    for zone in ("rear", "front", "total"):
        assert b[zone]["length_mm"] == pytest.approx(a[zone]["length_mm"], rel=1e-9)
        assert b[zone]["mean_pressure_kpa"] == pytest.approx(a[zone]["mean_pressure_kpa"], rel=1e-6)


def test_surface_model_and_figure(capsys, tmp_path: Path) -> None:
    fig = tmp_path / "contact.png"
    doc = run_json(
        capsys,
        [
            *BASE,
            "--ski",
            "skate",
            "--model",
            "surface",
            "--points",
            "512",
            "--n-across",
            "8",
            "--figure",
            str(fig),
        ],
    )
    assert doc["model"] == "surface" and doc["converged"]
    assert fig.stat().st_size > 10_000


def test_table_output(capsys) -> None:
    assert main([*BASE, "--ski", "skate", "--points", "256"]) == 0
    out = capsys.readouterr().out
    assert "rear" in out and "front" in out and "converged" in out


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ([], "exactly one of --ski"),
        (["--ski", "classic", "--profile", "x.csv"], "exactly one of --ski"),
        (["--ski", "nope"], "nope"),
        (["--ski", "classic", "--model", "periodic"], "--model"),
    ],
)
def test_errors_are_one_line(capsys, extra: list[str], message: str) -> None:
    assert main([*BASE, *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err and err.count("\n") == 1


def test_bad_profile_files(capsys, tmp_path: Path) -> None:
    bad = tmp_path / "bad.csv"
    bad.write_text("x_mm,height\n1,2\n")
    assert main([*BASE, "--profile", str(bad)]) == 2
    assert "missing column height_mm" in capsys.readouterr().err
    rows = "\n".join(f"{i},{0.1 if i != 5 else 'abc'}" for i in range(10))
    bad.write_text("x_mm,height_mm\n" + rows + "\n")
    assert main([*BASE, "--profile", str(bad)]) == 2
    assert "line 7, column height_mm" in capsys.readouterr().err


def test_subprocess_smoke(tmp_path: Path) -> None:
    # a synthetic two-zone profile (no beam solve): the smoke test checks the real process only
    x = np.linspace(-1000.0, 1000.0, 256)
    h = (
        0.3 * np.clip(1 - (x / 450) ** 2, 0, None) ** 2
        + 4 * np.clip(abs(x) - 450, 0, None) ** 3 / 550**3
    )
    csv = tmp_path / "p.csv"
    pd.DataFrame({"x_mm": x, "height_mm": h}).to_csv(csv, index=False)
    code = "from skisnow.cli import main; raise SystemExit(main())"
    args = [*BASE, "--profile", str(csv), "--json"]
    proc = subprocess.run(
        [sys.executable, "-c", code, *args], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    assert doc["converged"] is True and doc["rear"]["patches"] == 1
