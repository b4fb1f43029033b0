"""Patch topology in rankings (issue 25, item 4): a patch-based criterion (the rear zone's load
share) never ranks apart two skis whose rear glide patch and kick contact are joined in one and
split in the other, nor a ski whose posterior samples straddle the two; it says so and offers
the regions."""

from __future__ import annotations

import dataclasses

import numpy as np

from skisnow.pipeline import Intervals, solve_case, topology_text, zone_topology
from skisnow.ski import get_ski
from skisnow.workflows import competition_ranks, tied_with
from skisnow.workflows._topology import (
    SkiTopology,
    comparable,
    patch_zone,
    ski_topology,
    topology_warnings,
)

JOINED = "rear 1 patch, middle 0 patches"
SPLIT = "rear 1 patch, middle 1 patch"


def test_the_shipped_classics_topology_and_the_zones_a_criterion_looks_at() -> None:
    case = solve_case(get_ski("classic"), mass=70, load_position=-0.12, snow_modulus=300e6,
                      profile_source="beam", n_points=1024)  # fmt: skip
    top = zone_topology(case.zones)
    # the rear glide zone and the kick contact form one patch (issue 25's 222 mm patch)
    assert dict(top) == {"rear": 1, "middle": 0, "front": 1, "merged": 0}
    assert topology_text(top, ("rear", "middle")) == JOINED
    assert ski_topology(case.zones, (), "rear").text == JOINED
    assert ski_topology(case.zones, (), "front").text == "middle 0 patches, front 1 patch"
    assert patch_zone("full_rear_load_share") == "rear"
    # the total, the kick contact and the regions never jump: not patch-based
    for column in ("full_total_length_mm", "full_kick_load_share", "full_rear_glide_load_share"):
        assert patch_zone(column) is None


def test_skis_in_different_topologies_tie_and_the_warning_names_zones_and_regions() -> None:
    # rear share: a joined ski 0.77, a split one 0.36, a third joined one 0.60
    values = [0.77, 0.36, 0.60]
    tops = [SkiTopology(text=JOINED), SkiTopology(text=SPLIT), SkiTopology(text=JOINED)]
    ok = comparable(tops)
    assert ok.tolist() == [[True, False, True], [False, True, False], [True, False, True]]
    assert competition_ranks(values, better="higher").tolist() == [1, 3, 2]
    ranks = competition_ranks(values, better="higher", comparable=ok)
    # the split ski is never ranked apart from the joined ones; the joined ones still are
    assert ranks.tolist() == [1, 1, 2]
    assert tied_with(values, better="higher", comparable=ok) == [[1], [0, 2], [1]]
    warnings = topology_warnings(["a", "b", "c"], tops, "rear-share", "rear")
    assert len(warnings) == 2 and warnings[0].startswith("a / b") and "b / c" in warnings[1]
    w0 = warnings[0]
    assert "rear/middle" in w0 and "rear_glide" in w0 and "not comparable" in w0
    assert f"a: {JOINED}; b: {SPLIT}" in w0


def test_a_ski_whose_samples_straddle_two_topologies_is_comparable_with_no_one() -> None:
    # 5 % of the samples split: more than one tail of a 95 % interval (2.5 %)
    straddling = SkiTopology(text=JOINED, shares={JOINED: 0.95, SPLIT: 0.05})
    steady = SkiTopology(text=JOINED, shares={JOINED: 0.99, SPLIT: 0.01})
    assert straddling.mixed and not steady.mixed
    assert "5.0 % of samples" in straddling.describe()
    ok = comparable([straddling, SkiTopology(text=JOINED), steady])
    assert not ok[0, 1] and not ok[0, 2] and ok[1, 2]
    # not a patch-based criterion: always comparable
    assert comparable([None, None]).all()


def test_intervals_say_when_their_samples_straddle_two_topologies() -> None:
    joined = (("rear", 1), ("middle", 0), ("front", 1), ("merged", 0))
    split = (("rear", 1), ("middle", 1), ("front", 1), ("merged", 0))
    iv = Intervals(estimate={}, low={}, high={}, samples=200, seed=0, level=0.95,
                   topology=split, sample_topologies=(joined,) * 10 + (split,) * 190)  # fmt: skip
    shares = iv.topology_shares()
    assert list(shares) == [topology_text(split), topology_text(joined)]  # the estimate's first
    assert np.isclose(shares[topology_text(joined)], 0.05)
    note = iv.topology_note()
    assert note is not None and "5.0 %" in note and "rear_glide.load_share" in note
    assert dataclasses.replace(iv, sample_topologies=(split,) * 200).topology_note() is None
    # no samples recorded (answers that are not a case's zones): nothing said
    assert dataclasses.replace(iv, sample_topologies=()).topology_note() is None
