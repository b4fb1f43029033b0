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
