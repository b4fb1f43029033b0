"""Intervals carried to the answers at the CLI (issue 25, item 4): an identified ski's answers
come with 95 % intervals that hold them, a ski without bands says it carries none, and
``--samples`` is checked like every option."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from _posterior import with_posterior
from skisnow.cli import main
from skisnow.ski import get_ski, write_ski

CONTACT = ["contact", "--mass-kg", "70", "--load-position-mm", "-120", "--snow-modulus-mpa", "100",
           "--points", "2048"]  # fmt: skip


@pytest.fixture(scope="module")
def identified(tmp_path_factory) -> Path:
    ski = dataclasses.replace(with_posterior(get_ski("classic")), name="identified classic")
    return write_ski(ski, tmp_path_factory.mktemp("ski") / "identified.json")


def _json(capsys, args) -> dict:
    code = main([*args, "--json"])
    out = capsys.readouterr().out
    assert code == 0, out
    return json.loads(out)


def test_contact_of_an_identified_ski_carries_intervals(capsys, identified: Path) -> None:
    doc = _json(capsys, [*CONTACT, "--ski", str(identified), "--samples", "40"])
    unc = doc["uncertainty"]
    assert unc["recorded"] and unc["samples"] == 40 and unc["level"] == 0.95
    assert unc["failed_samples"] == 0
    for zone in ("rear", "front", "total"):
        for key in ("length_mm", "area_cm2", "mean_pressure_kpa", "max_pressure_kpa",
                    "load_share"):  # fmt: skip
            lo, hi = unc["intervals"][zone][key]
            assert lo <= doc[zone][key] <= hi, (zone, key)
        assert unc["intervals"][zone]["length_mm"][1] > unc["intervals"][zone]["length_mm"][0]
    assert "Monte Carlo" in unc["why_enough"]


def test_a_ski_without_bands_says_it_carries_no_uncertainty(capsys) -> None:
    doc = _json(capsys, [*CONTACT, "--ski", "classic"])
    assert doc["uncertainty"]["recorded"] is False
    assert "no uncertainty recorded" in doc["uncertainty"]["note"]
    assert main([*CONTACT, "--ski", "classic"]) == 0
    assert "no uncertainty recorded" in capsys.readouterr().out.replace("\n", " ")


@pytest.mark.parametrize(("value", "words"), [("1", "at least 2"), ("-3", "--samples")])
def test_samples_option_is_checked(capsys, value: str, words: str) -> None:
    assert main([*CONTACT, "--ski", "classic", "--samples", value]) == 2
    assert words in capsys.readouterr().err


def test_compare_marks_a_ski_and_its_own_sample_a_tie_within_uncertainty(
    capsys, tmp_path: Path, identified: Path
) -> None:
    # a ski and a draw from its own posterior (which carries the same bands): their intervals
    # overlap, so the ranking may not put one ahead; the skate ski is a different ski (its mean
    # pressure lies outside the classic's interval) and is ranked apart
    from skisnow.ski import read_ski, sample_skis

    ski = read_ski(identified)
    (draw,) = sample_skis(ski, 1, seed=7)
    draw = dataclasses.replace(with_posterior(draw), name="its own sample")
    other = write_ski(draw, tmp_path / "sample.json")
    doc = _json(capsys, ["compare", str(identified), str(other), "skate", "--body-mass-kg", "70",
                         "--snow-modulus-mpa", "100", "--samples", "30", "--points", "1024",
                         "--snow-range-mpa", "50,100", "--criterion", "mean-pressure"])  # fmt: skip
    rank = {r["ski"]: r for r in doc["ranking"]}
    a, b = rank["identified.json"], rank["sample.json"]
    assert a["full_total_mean_pressure_kpa"] != b["full_total_mean_pressure_kpa"]
    assert a["tied"] and b["tied"] and a["within_uncertainty"] and a["rank"] == b["rank"]
    assert "sample.json" in a["tied_with"] and "skate" not in a["tied_with"]
    assert rank["skate"]["interval"] is None
    lo, hi = a["interval"]
    assert lo <= a["full_total_mean_pressure_kpa"] <= hi
    col = "full_total_mean_pressure_kpa"
    for rec in doc["snow_ranking"]:  # across snow: the same intervals and ties on every modulus
        lo, hi = rec[f"identified.json_{col}_low"], rec[f"identified.json_{col}_high"]
        assert lo <= rec[f"identified.json_{col}"] <= hi
        assert rec[f"skate_{col}_low"] == rec[f"skate_{col}_high"] == rec[f"skate_{col}"]
        if rec["snow_modulus_mpa"] == 100:
            assert rec["identified.json_rank"] == rec["sample.json_rank"]
            assert rec[f"identified.json_{col}_low"] == pytest.approx(a["interval"][0])
    recs = {r["ski"]: r for r in doc["intervals"]}
    assert recs["identified.json"]["samples"] == 30
    assert "no uncertainty recorded" in recs["skate"]["uncertainty"]
    assert recs["identified.json"]["full_total_length_mm_low"] <= doc["skis"][0][
        "full_total_length_mm"] <= recs["identified.json"]["full_total_length_mm_high"]  # fmt: skip


def test_cycle_summary_carries_intervals_for_an_identified_ski(capsys, identified: Path) -> None:
    args = ["cycle", "--template", "diagonal", "--body-mass-kg", "70", "--snow-modulus-mpa",
            "100", "--frames", "20", "--points", "1024", "--samples", "8"]  # fmt: skip
    doc = _json(capsys, [*args[:1], str(identified), *args[1:]])
    unc = doc["uncertainty"]["diagonal"]
    assert unc["recorded"] and unc["samples"] == 8
    for key, (lo, hi) in unc["intervals"].items():
        assert lo <= unc["estimates"][key] <= hi, key
    summary = doc["summaries"][0]
    lo, hi = unc["intervals"]["kick_contact_time_s"]
    assert lo <= summary["kick_contact_time_s"] <= hi
    shipped = _json(capsys, [*args[:1], "classic", *args[1:]])
    assert shipped["uncertainty"]["diagonal"]["recorded"] is False
    assert "no uncertainty recorded" in shipped["uncertainty"]["diagonal"]["note"]


def test_report_shows_intervals_or_says_there_are_none(capsys, tmp_path: Path, identified):
    from types import SimpleNamespace

    from skisnow.report._report import _uncertainty

    code = main(["report", str(identified), "--out", str(tmp_path), "--mass-kg", "40:80:40",
                 "--snow-modulus-mpa", "100,200", "--stride", "none", "--samples", "6",
                 "--points", "1024", "--json"])  # fmt: skip
    assert code == 0, capsys.readouterr().err
    html = Path(json.loads(capsys.readouterr().out)["report"]).read_text()
    assert "95 % intervals of the answers above from 6 samples" in html
    text, items = _uncertainty(SimpleNamespace(ski=get_ski("classic"), intervals=()))
    assert "no uncertainty recorded" in text and items == ()


def test_the_passport_states_what_the_ski_is_worth(capsys, identified: Path) -> None:
    shipped = _json(capsys, ["skis", "--show", "skate"])
    assert "shipped plausible ski" in shipped["uncertainty"]
    assert "not identified" in shipped["uncertainty"]
    assert "posterior" in _json(capsys, ["skis", "--show", str(identified)])["uncertainty"]
