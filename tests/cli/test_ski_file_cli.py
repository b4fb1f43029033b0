"""Every command that takes a ski takes a ski file too, with the same numbers as by name."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from skisnow.bench import read_bench
from skisnow.cli import main
from skisnow.ski import get_ski, write_ski
from skisnow.sweep import open_sweep


@pytest.fixture(scope="module")
def ski_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_ski(get_ski("classic"), tmp_path_factory.mktemp("skis") / "my_classic.json")


def _run(capsys: pytest.CaptureFixture[str], argv: list[str]) -> dict:
    assert main(argv) == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def test_contact_by_file_equals_by_name(ski_file: Path, capsys: pytest.CaptureFixture[str]) -> None:
    args = ["contact", "--mass-kg", "60", "--load-position-mm", "-70", "--snow-modulus-mpa",
            "100", "--points", "1024", "--json"]  # fmt: skip
    by_name = _run(capsys, [*args, "--ski", "classic", "--profile-source", "beam"])
    by_file = _run(capsys, [*args, "--ski", str(ski_file)])  # auto: the beam for a ski file
    assert by_file["profile_source"] == "beam"
    for zone in ("rear", "middle", "front", "total"):  # the kick zone comes from the file too
        assert by_file[zone] == by_name[zone]


def test_bench_and_metrics_of_a_ski_file(
    ski_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "b.csv"
    doc = _run(capsys, ["bench", str(ski_file), "--out", str(out), "--mass-kg", "20,40",
                        "--load-position-mm", "-80", "--json"])  # fmt: skip
    assert doc["profiles"] == 2
    data = read_bench(out)
    assert list(data.skis) == ["classic"]  # the ski's name inside the file labels the bench
    by_file = _run(capsys, ["metrics", str(ski_file), "--json"])["metrics"][0]
    by_name = _run(capsys, ["metrics", "classic", "--json"])["metrics"][0]
    assert by_file == by_name


def test_sweep_and_report_take_a_ski_file(
    ski_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "s.zarr"
    grid = ["--mass-kg", "30,60", "--load-position-mm", "-120", "--snow-modulus-mpa", "100",
            "--points", "512", "--workers", "0", "--json"]  # fmt: skip
    # --profile-source auto: the beam for a ski file (the network exists only for shipped skis)
    _run(capsys, ["sweep", "--ski", str(ski_file), "--out", str(store), *grid])
    ds = open_sweep(store)
    _run(capsys, ["sweep", "--ski", "classic", "--profile-source", "beam", "--out",
                  str(tmp_path / "n.zarr"), *grid])  # fmt: skip
    ref = open_sweep(tmp_path / "n.zarr")
    np.testing.assert_array_equal(ds.length_mm.values, ref.length_mm.values)
    assert bool(ds.converged.all())
    report = ["report", str(ski_file), "--out", str(tmp_path / "r"), "--mass-kg", "20,60",
              "--snow-modulus-mpa", "100", "--points", "512", "--json"]  # fmt: skip
    doc = _run(capsys, report)
    assert Path(doc["report"]).name == "classic_report.html"  # the name inside the file
    assert (tmp_path / "r" / "my_classic_maps_beam.zarr").is_dir()


def test_skis_show_writes_file_and_figure(
    ski_file: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out, fig = tmp_path / "copy.json", tmp_path / "passport.png"
    doc = _run(capsys, ["skis", "--show", str(ski_file), "--out", str(out), "--figure", str(fig),
                        "--json"])  # fmt: skip
    assert out.read_bytes() == ski_file.read_bytes() and fig.stat().st_size > 10_000
    assert doc["ski"]["length_mm"] == pytest.approx(2000.0)
    assert doc["stations"]["x_mm"][0] == pytest.approx(-980.0)
    assert 50.0 < doc["metrics"]["closing_load_kg"] < 65.0
    assert main(["skis", "--show", str(ski_file)]) == 0
    assert "Provenance" in capsys.readouterr().out


def test_bad_ski_file_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "skisnow-ski", "format_version": 1, "kind": "alpine"}')
    argv = ["contact", "--ski", str(bad), "--mass-kg", "30", "--load-position-mm", "-120",
            "--snow-modulus-mpa", "100"]  # fmt: skip
    assert main(argv) == 2  # an input error
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "FileFormatError" in err
    assert main(["skis", "--show", "nothing"]) == 2
    assert "neither a shipped ski" in capsys.readouterr().err
