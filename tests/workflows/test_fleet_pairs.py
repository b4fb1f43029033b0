"""Fleet comparison and pair matching: balance of the load shares, the physics of the ranking
across snow, a broken file in a fleet, and the matching against a brute-force search."""

from __future__ import annotations

import dataclasses
import itertools
from pathlib import Path

import numpy as np
import pytest

from skisnow.ski import get_ski
from skisnow.workflows import (
    CRITERIA,
    FleetSki,
    compare_fleet,
    match_pairs,
    pair_distance,
    rank_across_snow,
)

N = 512


@pytest.fixture(scope="module")
def fleet(tmp_path_factory: pytest.TempPathFactory):
    broken = tmp_path_factory.mktemp("fleet") / "broken.json"
    broken.write_text("{ not json", encoding="utf-8")
    return compare_fleet(
        ["classic", "skate", str(broken)], body_mass=70, snow_modulus=100e6, n_points=N
    ), broken


def test_a_broken_file_is_named_and_the_others_compared(fleet) -> None:
    cmp, broken = fleet
    assert [e.ski.label for e in cmp.entries] == ["classic", "skate"]
    assert len(cmp.failures) == 1 and cmp.failures[0][0] == str(broken)
    assert "broken.json" in cmp.failures[0][1]


def test_records_balance_the_load_and_scale_with_body_weight(fleet) -> None:
    cmp, _ = fleet
    for entry, rec in zip(cmp.entries, cmp.records(), strict=True):
        for load, factor in (("half", 0.5), ("full", 1.0)):
            shares = sum(rec[f"{load}_{z}_load_share"] for z in ("rear", "middle", "front"))
            assert shares == pytest.approx(1.0, abs=1e-9)
            sol = entry.cases[load].solution
            assert sol.total_force == pytest.approx(factor * 70 * 9.80665, rel=1e-6)
        # more load, more contact
        assert rec["full_total_length_mm"] > rec["half_total_length_mm"]
    classic, skate = cmp.records()[:2]
    assert classic["full_kick_contact"] == (classic["full_kick_length_mm"] > 0)
    # a skate ski has no kick zone: no value in any kick-zone column (NaN; JSON null)
    for load in ("half", "full"):
        assert skate[f"{load}_kick_contact"] is None
        for q in ("length_mm", "area_cm2", "mean_pressure_kpa", "peak_pressure_kpa",
                  "load_share"):  # fmt: skip
            assert np.isnan(skate[f"{load}_kick_{q}"]), q


@pytest.mark.parametrize("name", list(CRITERIA))
def test_ranking_follows_the_stated_direction(fleet, name: str) -> None:
    cmp, _ = fleet
    crit = CRITERIA[name]
    ranked = [r[crit.column] for r in cmp.ranking(name)]
    expected = sorted(ranked, reverse=crit.better == "higher")
    assert ranked == expected


def test_ranking_across_snow_follows_the_half_space() -> None:
    """On stiffer snow the ski sinks less: shorter contact, higher mean pressure."""
    cmp = compare_fleet(["classic", "skate"], body_mass=70, snow_modulus=100e6, n_points=N)
    moduli = [20e6, 60e6, 200e6, 400e6]
    mp = rank_across_snow(cmp, "mean-pressure", moduli, n_points=N)
    cl = rank_across_snow(cmp, "contact-length", moduli, n_points=N)
    assert np.all(np.diff(mp.values, axis=1) > 0)
    assert np.all(np.diff(cl.values, axis=1) < 0)
    for r in (mp, cl):
        assert sorted(r.ranks[:, 0].tolist()) == [1, 2]
        for j, winner in enumerate(r.winners()):
            assert r.ranks[r.skis.index(winner), j] == 1
        # a change is reported exactly where neighbouring orders differ
        orders = [tuple(np.argsort(r.ranks[:, j])) for j in range(len(moduli))]
        n_changes = sum(a != b for a, b in itertools.pairwise(orders))
        assert len(r.changes) == n_changes
    # the value at the comparison's own snow is the comparison's
    j = moduli.index(200e6)
    at200 = compare_fleet(["classic", "skate"], body_mass=70, snow_modulus=200e6, n_points=N)
    for i, rec in enumerate(at200.records()):
        assert mp.values[i, j] == pytest.approx(rec["full_total_mean_pressure_kpa"], rel=1e-5)


def variant(name: str, stiffness: float = 1.0, camber: float = 1.0) -> FleetSki:
    base = get_ski("classic")
    ski = dataclasses.replace(
        base,
        name=name,
        stiffness_values=tuple(v * stiffness for v in base.stiffness_values),
        camber_values=tuple(v * camber for v in base.camber_values),
    )
    return FleetSki(label=name, ski=ski, origin="test")


def test_distance_is_symmetric_zero_for_twins_and_grows_with_the_difference() -> None:
    a, b, c = variant("a"), variant("b", stiffness=1.1), variant("c", stiffness=1.3)
    kw = {"body_mass": 70, "snow_modulus": 100e6, "n_points": N}
    assert pair_distance(a, variant("a2"), **kw).total == 0.0
    dab, dba = pair_distance(a, b, **kw), pair_distance(b, a, **kw)
    assert dab.total == pytest.approx(dba.total, rel=1e-12)
    assert dab.stiffness == pytest.approx(np.log(1.1) / 0.05, rel=1e-9)
    assert dab.camber == 0.0
    assert pair_distance(a, c, **kw).total > dab.total


def brute_force(labels: list[str], d: np.ndarray) -> float:
    n = len(labels)
    best = np.inf
    for perm in itertools.permutations(range(n)):
        pairs = [(perm[2 * k], perm[2 * k + 1]) for k in range(n // 2)]
        best = min(best, sum(d[i, j] for i, j in pairs))
    return best


def test_matching_is_the_minimum_over_all_pairings_and_flags_the_worst() -> None:
    skis = [
        variant("A", 1.00),
        variant("B", 1.25, 1.1),
        variant("A'", 1.02),
        variant("C", 0.85, 0.8),
        variant("B'", 1.22, 1.1),
        variant("C'", 0.85, 0.75),
    ]
    res = match_pairs(skis, body_mass=70, snow_modulus=100e6, n_points=N)
    assert {frozenset(p[:2]) for p in res.pairs} == {
        frozenset(("A", "A'")),
        frozenset(("B", "B'")),
        frozenset(("C", "C'")),
    }
    assert res.total == pytest.approx(brute_force(list(res.skis), res.distances), rel=1e-12)
    assert res.worst == max(res.pairs, key=lambda p: p[2].total)
    assert res.spare is None


def test_odd_fleet_leaves_the_best_spare_and_a_broken_file_out(tmp_path: Path) -> None:
    bad = tmp_path / "ski.csv"
    bad.write_text("x\n1\n", encoding="utf-8")
    skis = [
        variant("A"),
        variant("A'", 1.03),
        variant("B", 1.4),
        variant("B'", 1.35, 1.05),
        variant("C", 1.0, 1.3),
    ]
    res = match_pairs(
        [*skis[:3], str(bad), *skis[3:]], body_mass=70, snow_modulus=100e6, n_points=N
    )
    assert res.failures and res.failures[0][0] == str(bad)
    d = res.distances
    best = min(
        brute_force(
            [s for k, s in enumerate(res.skis) if k != spare],
            np.delete(np.delete(d, spare, 0), spare, 1),
        )
        for spare in range(len(res.skis))
    )
    assert res.total == pytest.approx(best, rel=1e-12)
    assert res.spare is not None and len(res.pairs) == 2


def test_ski_files_enter_the_fleet(tmp_path: Path) -> None:
    from skisnow.ski import write_ski

    stiff = variant("stiff", stiffness=1.5).ski
    write_ski(stiff, tmp_path / "stiff.json")
    write_ski(get_ski("classic"), tmp_path / "classic_copy.json")
    cmp = compare_fleet(
        ["classic", str(tmp_path / "classic_copy.json"), str(tmp_path / "stiff.json")],
        body_mass=70,
        snow_modulus=100e6,
        n_points=N,
    )
    assert not cmp.failures
    plain, copy, stiffer = cmp.records()
    # one default route for every ski, whatever its name (issue 26)
    assert plain["profile_route"] == copy["profile_route"] == stiffer["profile_route"] == "beam"
    for key in ("full_total_length_mm", "full_total_mean_pressure_kpa", "camber_half_mm"):
        assert copy[key] == plain[key]  # bit-identical: the content decides, not the name
    # a stiffer ski closes its pocket later and stands on shorter glide zones
    assert stiffer["closing_load_kg"] > plain["closing_load_kg"]


@pytest.mark.slow
def test_a_bench_file_enters_through_identification(tmp_path: Path) -> None:
    """Round trip: the virtual bench of the shipped skate (4 masses, 5 µm noise) → identified
    ski → contact within 5 % of the true ski's (the identification's own target)."""
    from skisnow.bench import run_bench, write_bench

    bench = run_bench(
        "skate", masses=(20.0, 40.0, 60.0, 80.0), load_positions=(-0.12,), noise=5e-6, seed=1
    )
    path = write_bench(bench, tmp_path / "skate_bench.csv")
    cmp = compare_fleet(["skate", str(path)], body_mass=70, snow_modulus=100e6, n_points=1024)
    assert not cmp.failures
    true, ident = cmp.records()
    assert ident["origin"] == "bench file (identified)" and ident["profile_route"] == "beam"
    for key in ("full_total_length_mm", "full_total_mean_pressure_kpa", "half_total_length_mm"):
        assert ident[key] == pytest.approx(true[key], rel=0.05)


def test_an_infinite_value_is_ranked_not_dropped() -> None:
    # a closing load of inf (the pocket never closes on the bench) is the stiffest, the best of
    # "higher"; only NaN (no answer) goes last
    crit = CRITERIA["closing-load"]
    assert list(crit.order([101.3, np.inf, np.nan])) == [1, 0, 2]
    low = dataclasses.replace(crit, better="lower")
    assert list(low.order([np.inf, np.nan, 101.3])) == [2, 0, 1]
