"""Trust audit finding 17: one notation for "no contact" in ``skisnow compare`` and its report
section — a zone without contact has length, area and load share 0 and NO pressure (mean and
peak: "—" in text, an empty CSV cell, JSON null); a ski without a kick zone has no value in
any kick-zone column, and the kick-zone rows are left out when no ski has a kick zone."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

from skisnow.cli import main

_ARGS = ["--body-mass-kg", "70", "--snow-modulus-mpa", "30", "--snow-range-mpa", "30,300",
         "--points", "512"]  # fmt: skip


def test_empty_zone_and_missing_kick_zone_have_no_value_everywhere(capsys, tmp_path: Path) -> None:
    out = tmp_path / "out"
    assert main(["compare", "classic", "skate", *_ARGS, "--out", str(out), "--json"]) == 0
    classic, skate = json.loads(capsys.readouterr().out)["skis"]
    # the middle zone of both skis holds no contact at these loads (the paper's Fig. 4 cases)
    for rec in (classic, skate):
        assert rec["half_middle_length_mm"] == 0.0 and rec["half_middle_load_share"] == 0.0
        assert rec["half_middle_mean_pressure_kpa"] is None
        assert rec["half_middle_peak_pressure_kpa"] is None
    # the skate ski has no kick zone: null in every kick-zone column, the classic has values
    kick = [k for k in skate if "_kick_" in k]
    assert kick and all(skate[k] is None for k in kick)
    assert classic["full_kick_contact"] is True and classic["full_kick_length_mm"] > 0
    with (out / "comparison.csv").open(encoding="utf-8") as fh:
        rows = {r["ski"]: r for r in csv.DictReader(fh)}
    assert rows["classic"]["half_middle_peak_pressure_kpa"] == ""
    assert rows["classic"]["half_middle_mean_pressure_kpa"] == ""
    assert all(rows["skate"][k] == "" for k in kick)
    # text: "—" for mean and peak alike; the skate column of the kick rows "—"
    assert main(["compare", "classic", "skate", *_ARGS]) == 0
    text = capsys.readouterr().out
    for line in text.splitlines():
        if "½ BW middle mean p" in line or "½ BW middle peak p" in line:
            assert line.count("—") == 2, line
        if "kick zone" in line or "grip wax" in line:
            assert line.rstrip(" │").split("│")[-1].strip() == "—", line


def test_no_kick_zone_rows_without_a_kick_zone(capsys, tmp_path: Path) -> None:
    ski = tmp_path / "skate2.json"
    assert main(["skis", "--show", "skate", "--out", str(ski)]) == 0
    assert main(["compare", "skate", str(ski), *_ARGS]) == 0
    text = capsys.readouterr().out
    assert "kick zone" not in text and "grip wax" not in text


def test_report_fleet_section_has_no_kick_rows_for_skate_skis(capsys, tmp_path: Path) -> None:
    from skisnow.report._workflows import fleet_section
    from skisnow.workflows import compare_fleet

    ski = tmp_path / "skate2.json"
    assert main(["skis", "--show", "skate", "--out", str(ski)]) == 0
    capsys.readouterr()
    cmp = compare_fleet(["skate", str(ski)], body_mass=70.0, snow_modulus=30e6, n_points=512)
    rows = fleet_section(cmp).items[0].rows
    labels = [r[0] for r in rows]
    assert not any("kick" in label for label in labels), labels
    assert not any(isinstance(v, float) and math.isnan(v) for r in rows for v in r[1:])
