"""CLI of the ski area: in-process through skisnow.cli.main, plus one real subprocess."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from skisnow.bench import read_bench
from skisnow.cli import main
from skisnow.ski import get_ski


def _json(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict:
    assert main(argv) == 0
    out = capsys.readouterr().out
    return json.loads(out)  # exactly one JSON document on stdout


def test_skis_json(capsys: pytest.CaptureFixture[str]) -> None:
    doc = _json(capsys, ["skis", "--json"])
    names = [s["ski"] for s in doc["skis"]]
    assert names == ["classic", "skate", "classic-k22", "skate-k22"]
    # the reproduction skis (issue 30) are labelled as such in the list
    assert [s["reproduction_ski"] for s in doc["skis"]] == ["no", "no", "YES", "YES"]
    classic = doc["skis"][0]
    # the CLI converts the ski's kick zone to mm, whatever the shipped numbers are
    kick = get_ski("classic").kick_zone
    assert kick is not None
    assert classic["kick_zone_mm"] == pytest.approx([1e3 * kick[0], 1e3 * kick[1]])
    assert 50.0 < classic["closing_load_at_-80mm_kg"] < 65.0


def test_skis_table(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["skis"]) == 0
    out = capsys.readouterr().out
    assert "classic" in out and "skate" in out


def test_bench_then_metrics(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "b.csv"
    doc = _json(
        capsys,
        [
            "bench",
            "classic",
            "--out",
            str(out),
            "--mass-kg",
            "30,35,60,65",
            "--load-position-mm",
            "-80",
            "--noise-mm",
            "0.01",
            "--seed",
            "4",
            "--json",
        ],
    )
    assert doc["profiles"] == 4 and doc["file"] == str(out)
    data = read_bench(out)
    assert sorted(data.table["mass_kg"].unique()) == [30.0, 35.0, 60.0, 65.0]
    assert data.metadata["seed"] == 4
    metrics = _json(capsys, ["metrics", str(out), "--json"])["metrics"]
    assert metrics[0]["ski"] == "classic" and metrics[0]["source"] == "bench"
    assert metrics[0]["camber_half_mm"] > 0.5
    beam = _json(capsys, ["metrics", "classic", "--body-mass-kg", "65", "--json"])["metrics"][0]
    assert beam["camber_full_mm"] < 0.1
    assert main(["metrics", "skate"]) == 0
    assert "stiffness_n_per_mm" in capsys.readouterr().out


def test_range_syntax(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "r.csv"
    doc = _json(
        capsys,
        [
            "bench",
            "skate",
            "--out",
            str(out),
            "--mass-kg",
            "10:30:10",
            "--load-position-mm",
            "-240:-40:100",
            "--json",
        ],
    )
    assert doc["profiles"] == 3 * 3  # 10, 20, 30 kg at -240, -140, -40 mm


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["metrics", "nope"], "neither a shipped ski"),
        (["bench", "alpine", "--out", "x.csv"], "unknown ski 'alpine'"),
        (["bench", "classic", "--out", "x.txt"], ".csv or .parquet"),
        (["bench", "classic", "--out", "x.csv", "--mass-kg", "5:a"], "--mass-kg"),
    ],
)
def test_errors_are_one_line(
    argv: list[str], needle: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(argv) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0] and "Traceback" not in captured.err


def test_ski_part_of_the_demo_writes_files(tmp_path: Path) -> None:
    # The ski part of `skisnow demo` (issue 5 adds the contact part to the command itself).
    from skisnow.cli._demo import run_ski_demo

    doc = run_ski_demo(tmp_path / "out", progress=False)
    files = [Path(f) for f in doc["files"]]
    assert all(f.is_file() for f in files)
    names = {f.name for f in files}
    assert names >= {"bench_classic.csv", "bench_skate.csv", "camber_profiles.png"}
    assert [m["ski"] for m in doc["metrics"]] == ["classic", "skate"]
    assert read_bench(tmp_path / "out" / "bench_skate.csv").metadata["ski"] == "skate"


def test_subprocess_smoke() -> None:
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "from skisnow.cli import main; raise SystemExit(main())",
            "skis",
            "--json",
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert [s["ski"] for s in json.loads(proc.stdout)["skis"]] == [
        "classic",
        "skate",
        "classic-k22",
        "skate-k22",
    ]
