"""`skisnow topo | grind | bearing | rank`: JSON documents, files, figures, clean errors."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from skisnow.cli import main


def run_json(capsys: pytest.CaptureFixture[str], args: list[str]) -> dict:
    code = main([*args, "--json"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    return json.loads(captured.out)


@pytest.mark.shared
def test_topo_real_file(capsys, topography_dir: Path, tmp_path: Path) -> None:
    doc = run_json(
        capsys,
        [
            "topo",
            str(topography_dir / "x3p-2.x3p"),
            "--cutoff-um",
            "0",
            "--figure",
            str(tmp_path / "map.png"),
        ],
    )
    assert doc["grid"] == [650, 650] and doc["missing_pixels"] == 0
    # plane removed, no filter: the README's SurfaceTopography value 77.19 nm
    assert doc["parameters"]["Sq_um"] == pytest.approx(0.07719, rel=1e-3)
    assert Path(doc["figures"][0]).stat().st_size > 1000


def test_grind_then_topo_and_bearing(capsys, tmp_path: Path) -> None:
    out = tmp_path / "s2.x3p"
    doc = run_json(
        capsys, ["grind", "S2", "--out", str(out), "--size-um", "200", "--pixel-um", "2"]
    )
    assert out.is_file() and doc["grid"] == [100, 100]
    topo = run_json(capsys, ["topo", str(out)])
    assert topo["pixel_um"] == pytest.approx([2.0, 2.0])
    fig = tmp_path / "afr.svg"
    bear = run_json(
        capsys,
        [
            "bearing",
            str(out),
            "--temperature-c",
            "-2",
            "--pressure-kpa",
            "20",
            "--grain-um",
            "100:150:50",
            "--workers",
            "1",
            "--figure",
            str(fig),
        ],
    )
    assert bear["regime"]["yielding"] == "ice"
    assert bear["regime"]["ice_hardness_mpa"] == pytest.approx(15.9)
    assert [g["diameter_um"] for g in bear["grains"]] == [100.0, 150.0]
    for g in bear["grains"]:  # a rough base: A_fr above p/H, by a slope factor of a few %
        assert bear["flat_base_fractional_area"] <= g["fractional_area"] < 1.1 * (20e3 / 15.9e6)
    assert bear["grain_averaged_fractional_area"] is not None
    assert fig.is_file()


def test_human_output_and_rank(capsys, tmp_path: Path) -> None:
    table = tmp_path / "glide.csv"
    table.write_text(
        "structure,glide_time_s,A_fr,Sa_um\n"
        "S1,7.64,0.00131,1.86\nS2,7.37,0.00127,1.63\nS3,7.33,0.00126,2.84\n"
        "S4,7.35,0.00127,2.45\nS5,7.45,0.00129,1.81\n"
    )
    doc = run_json(capsys, ["rank", str(table)])
    assert [s["rank"] for s in doc["structures"]] == [5, 3, 1, 2, 4]
    corr = {c["descriptor"]: c for c in doc["correlations"]}
    assert corr["A_fr"]["significant"] and not corr["Sa_um"]["significant"]
    assert doc["critical_r"] == pytest.approx(0.878, abs=1e-3)
    assert main(["rank", "--paper-tables"]) == 0
    out = capsys.readouterr().out
    assert "Table 4" in out and "Sdq" in out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["topo", "missing.opd"], "missing.opd: no such file"),
        (["bearing", "S1", "--grain-um", "700:500:10"], "--grain-um"),
        (["grind", "S9", "--out", "x.x3p"], "S9"),
        (["rank"], "TABLE.csv"),
    ],
)
def test_errors_are_one_line(capsys, args: list[str], message: str) -> None:
    assert main(args) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_corrupt_file_error(capsys, tmp_path: Path) -> None:
    bad = tmp_path / "bad.sur"
    bad.write_bytes(b"DIGITAL SURF" + b"\x00" * 50)
    assert main(["topo", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "bad.sur" in err and "FileFormatError" in err and "Traceback" not in err


def test_subprocess_smoke(tmp_path: Path) -> None:
    out = tmp_path / "s5.npy"
    cmd = [sys.executable, "-c", "from skisnow.cli import main; raise SystemExit(main())"]
    r = subprocess.run(
        [*cmd, "grind", "S5", "--out", str(out), "--size-um", "100", "--pixel-um", "2"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    r = subprocess.run(
        [*cmd, "topo", str(out), "--pixel-um", "2", "--json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["grid"] == [50, 50]


@pytest.mark.parametrize("temperature_c", [-2.0, -30.0])
def test_bearing_pressure_at_the_ice_hardness_is_refused_naming_the_option(
    capsys, temperature_c: float
) -> None:
    """p/H >= 1 has no bearing model (the flat base would rest on the ice everywhere): refused
    as bad input naming --pressure-kpa and the hardness H(T) in the option's unit, before the
    map is read (was: 'ice hardness must exceed the pressure [Pa], got 15899999.999999998')."""
    import re

    from skisnow.micro import deformation_regime

    hardness_kpa = deformation_regime(temperature_c).ice_hardness * 1e-3
    args = [
        "--allow-implausible",  # above 20 MPa (at -30 °C) the pressure is implausible too
        "bearing",
        "S3",
        "--grain-um",
        "500",
        "--temperature-c",
        str(temperature_c),
    ]
    code = main([*args, "--pressure-kpa", f"{1.0001 * hardness_kpa:.6g}"])
    err = capsys.readouterr().err
    assert code == 2 and "--pressure-kpa" in err, err
    shown = float(re.search(r"ice hardness at \S+ °C \(([\d.]+) kPa", err).group(1))
    assert shown == pytest.approx(hardness_kpa, rel=1e-3)
