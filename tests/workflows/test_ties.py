"""Ties (issue 26): identical skis tie in a ranking, a perfect pair is never the worst, and a
ski's name never changes its numbers."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from _extras import needs_network
from skisnow.workflows import compare_fleet, competition_ranks, rank_across_snow, tied_with

N = 512


def test_competition_ranks_share_a_rank_and_take_intervals() -> None:
    assert competition_ranks([3.0, 1.0, 3.0, 2.0], better="lower").tolist() == [3, 1, 3, 2]
    assert competition_ranks([3.0, 1.0, 3.0, 2.0], better="higher").tolist() == [1, 4, 1, 3]
    assert tied_with([3.0, 1.0, 3.0], better="lower") == [[2], [], [0]]
    # NaN (no answer) is last and ties with NaN; inf is a real answer at its end of the order
    assert competition_ranks([np.nan, np.inf, 1.0, np.nan], better="higher").tolist() == [
        3,
        1,
        2,
        3,
    ]
    # intervals (issue 25): overlapping intervals tie, whatever their centres; the rule is
    # 1 + the number strictly better, so a non-transitive tie chain is still well defined
    iv = [(1.0, 2.0), (1.5, 3.0), (2.5, 4.0), (5.0, 6.0)]
    assert competition_ranks([1.5, 2.2, 3.2, 5.5], better="lower", intervals=iv).tolist() == [
        1, 1, 2, 4]  # fmt: skip


def test_identical_skis_tie_in_compare(tmp_path: Path) -> None:
    from skisnow.ski import get_ski, write_ski

    copy = write_ski(get_ski("classic"), tmp_path / "renamed_classic.json")
    cmp = compare_fleet(["classic", str(copy), "skate"], body_mass=70, snow_modulus=100e6,
                        n_points=N)  # fmt: skip
    ranking = cmp.ranking("mean-pressure")
    by_ski = {r["ski"]: r for r in ranking}
    a, b = by_ski["classic"], by_ski["renamed_classic.json"]
    assert a["rank"] == b["rank"] and a["tied"] and b["tied"]
    assert a["tied_with"] == ["renamed_classic.json"] and not by_ski["skate"]["tied"]
    snow = rank_across_snow(cmp, "mean-pressure", np.array([50e6, 200e6]), n_points=N)
    assert (snow.ranks[0] == snow.ranks[1]).all()
    assert all(" = " in w for w in snow.winners()) or all(
        "classic = renamed_classic.json" in snow.order_text(j) for j in range(2))  # fmt: skip


def _contact_docs(tmp_path: Path, capsys, *extra: str) -> tuple[dict, dict]:
    """``contact --json`` of the shipped classic and of a renamed copy of its file."""
    from dataclasses import replace

    from skisnow.cli import main
    from skisnow.ski import get_ski, write_ski

    copy = write_ski(replace(get_ski("classic"), name="my-old-pair"), tmp_path / "mine.json")
    docs = []
    for ski in ("classic", str(copy)):
        args = ["contact", "--ski", ski, "--mass-kg", "70", "--load-position-mm", "-120",
                "--snow-modulus-mpa", "300", "--points", "1024", "--json", *extra]  # fmt: skip
        assert main(args) == 0
        docs.append(json.loads(capsys.readouterr().out))
    return docs[0], docs[1]


def test_a_renamed_shipped_ski_gives_bit_identical_numbers(tmp_path: Path, capsys) -> None:
    a, b = _contact_docs(tmp_path, capsys)
    assert a["profile_route"] == b["profile_route"] == "beam"
    for key in ("total", "rear", "front", "regions", "patches", "translation_um"):
        assert a[key] == b[key]


@needs_network
def test_a_renamed_shipped_ski_finds_its_network_by_content(tmp_path: Path, capsys) -> None:
    # asked for, the network route is found by content too: the copy uses the shipped network
    beam, _ = _contact_docs(tmp_path, capsys)
    a, b = _contact_docs(tmp_path, capsys, "--profile-source", "network")
    assert a["total"] == b["total"] and a["profile_route"] == b["profile_route"] == "network"
    assert a["total"]["length_mm"] != pytest.approx(beam["total"]["length_mm"], rel=1e-6)
