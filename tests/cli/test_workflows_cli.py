"""`skisnow compare`, `pairs`, `cycle`: JSON documents, CSV tables, figures, errors in one line."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from skisnow.cli import main

SMALL = ["--points", "512"]


def run(capsys: pytest.CaptureFixture[str], args: list[str]) -> tuple[int, dict, str]:
    code = main([*args, "--json"])
    captured = capsys.readouterr()
    return code, json.loads(captured.out), captured.err


def test_compare_names_a_broken_file_and_compares_the_rest(capsys, tmp_path: Path) -> None:
    broken = tmp_path / "worn.json"
    broken.write_text("{", encoding="utf-8")
    code, doc, _ = run(
        capsys,
        ["compare", "classic", "skate", str(broken), "--body-mass-kg", "70",
         "--snow-modulus-mpa", "30", "--snow-range-mpa", "30,300", "--criterion",
         "peak-pressure", "--out", str(tmp_path / "out"), *SMALL],
    )  # fmt: skip
    assert code == 2  # bad input: something was left out
    assert [r["ski"] for r in doc["skis"]] == ["classic", "skate"]
    assert doc["failures"][0]["ski"] == str(broken)
    assert doc["criterion"]["better"] == "lower"
    assert [r["rank"] for r in doc["ranking"]] == [1, 2]
    assert len(doc["snow_ranking"]) == 2
    for name in ("comparison.csv", "ranking.csv", "snow_ranking.csv", "fleet.png"):
        assert (tmp_path / "out" / name).is_file()
    with (tmp_path / "out" / "comparison.csv").open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert [r["ski"] for r in rows] == ["classic", "skate"]
    assert float(rows[0]["full_total_length_mm"]) == pytest.approx(
        doc["skis"][0]["full_total_length_mm"]
    )


def test_pairs_flags_the_worst_pair(capsys, tmp_path: Path) -> None:
    import shutil

    from skisnow.ski import shipped_ski_path

    # twins: two skis of the same content (a name given twice is refused: issue 27)
    twins = [str(shutil.copy(shipped_ski_path(n), tmp_path / f"{n}_twin.json"))
             for n in ("classic", "skate")]  # fmt: skip
    code, doc, _ = run(
        capsys,
        ["pairs", "classic", "skate", *twins, "--body-mass-kg", "70",
         "--snow-modulus-mpa", "100", "--out", str(tmp_path), *SMALL],
    )  # fmt: skip
    assert code == 0
    assert len(doc["pairs"]) == 2
    assert doc["converged"] is True  # the contact terms' solves (was null: nothing reported)
    assert all(p["distance"] == 0.0 for p in doc["pairs"])  # twins pair up
    # two perfect pairs: neither is a poor match, so neither is flagged (issue 26: a pair of
    # distance 0 was flagged WORST)
    assert [p["worst"] for p in doc["pairs"]] == [False, False]
    assert [p["poor_match"] for p in doc["pairs"]] == [False, False]
    assert "d > 1" in doc["distance"]
    assert (tmp_path / "pairs.csv").is_file() and (tmp_path / "distances.csv").is_file()
    assert (tmp_path / "pairs.png").is_file()  # --out promises figures: it writes them


def test_cycle_from_a_file_and_a_template(capsys, tmp_path: Path) -> None:
    hist = tmp_path / "binding.csv"
    hist.write_text(
        "t_s,mass_kg,load_position_mm\n"
        + "".join(f"{0.02 * i:.2f},{40 + 10 * i},-120\n" for i in range(6)),
        encoding="utf-8",
    )
    code, doc, _ = run(
        capsys,
        ["cycle", "classic", "--load-history", str(hist), "--snow-modulus-mpa", "100",
         "--out", str(tmp_path / "c"), *SMALL],
    )  # fmt: skip
    assert code == 0
    frames = doc["frames"]["binding"]
    assert [f["force_n"] for f in frames] == pytest.approx(
        [9.80665 * (40 + 10 * i) for i in range(6)]
    )
    # one name scheme for one cycle or several: cycle_<history>.*
    assert (tmp_path / "c" / "cycle_binding.csv").is_file()
    assert (tmp_path / "c" / "cycle_binding.png").is_file()
    import xarray as xr

    with xr.open_dataset(tmp_path / "c" / "cycle_binding.nc") as ds:  # the whole Dataset, SI
        assert ds["load"].values == pytest.approx([f["force_n"] for f in frames])
    gif = tmp_path / "stride.gif"
    code, doc, _ = run(
        capsys,
        ["cycle", "skate", "--template", "diagonal", "--body-mass-kg", "90", "--frames", "21",
         "--snow-modulus-mpa", "100", "--animation", str(gif), "--out", str(tmp_path / "s"),
         *SMALL],
    )  # fmt: skip
    assert code == 0
    assert gif.is_file() and gif.read_bytes()[:6] in (b"GIF89a", b"GIF87a")
    assert doc["summaries"][0]["route"] == "beam"  # the default route of every ski


@pytest.mark.parametrize(
    ("line", "column"),
    [("0.04,,-120", "mass_kg"), ("0.01,60,-120", "t_s"), ("0.04,-3,-120", "mass_kg")],
)
def test_cycle_bad_history_is_one_line_naming_line_and_column(
    capsys, tmp_path: Path, line: str, column: str
) -> None:
    hist = tmp_path / "bad.csv"
    rows = ["t_s,mass_kg,load_position_mm", "0.00,50,-120", "0.02,60,-120", line, "0.06,60,-120"]
    hist.write_text("\n".join(rows) + "\n", encoding="utf-8")
    code = main(["cycle", "classic", "--load-history", str(hist), "--snow-modulus-mpa", "100"])
    err = capsys.readouterr().err.strip()
    assert code == 2  # bad input
    assert len(err.splitlines()) == 1
    assert "line 4" in err and repr(column) in err
