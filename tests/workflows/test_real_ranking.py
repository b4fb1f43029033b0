"""Skis × bases ranked by a real-contact proxy: the fleet's tie rule, NaN last, the proxies."""

from __future__ import annotations

import math

import pytest

from skisnow import InputError
from skisnow.workflows import PROXIES, rank_real


def _rec(ski: str, base: str, visc: float) -> dict:
    return {"ski": ski, "base": base, "viscous_force_n": visc}


def test_equal_values_tie_and_share_a_rank() -> None:
    recs = [_rec("a", "S1", 3.0), _rec("b", "S1", 2.0), _rec("a", "S3", 2.0),
            _rec("b", "S3", math.nan)]  # fmt: skip
    out = rank_real(recs, "viscous")
    assert [r["rank"] for r in out] == [1, 1, 3, 4]  # 1 = 1 3, NaN last
    assert out[0]["ties_with"] == ["a × S3"] and out[1]["ties_with"] == ["b × S1"]
    assert out[2]["ski"] == "a" and out[2]["base"] == "S1" and out[2]["ties_with"] == []
    assert math.isnan(out[3]["viscous_force_n"])


def test_every_proxy_names_a_column_and_a_direction() -> None:
    for p in PROXIES.values():
        assert p.better in ("lower", "higher") and p.column and p.description
    with pytest.raises(InputError, match="proxy"):
        rank_real([_rec("a", "S1", 1.0)], "speed")


def test_glide_proxies_tie_within_the_glide_test_precision() -> None:
    # Lemmettylä et al. (2021): a skitester resolves glide to 0.6-1.1 % relative variation;
    # values 1.5 % apart overlap at ±1.1 % and tie, 3 % apart do not; precision 0 restores
    # the exact rule
    from skisnow.workflows import GLIDE_TEST_PRECISION

    assert pytest.approx(0.011) == GLIDE_TEST_PRECISION
    recs = [_rec("a", "S1", 1.0), _rec("b", "S1", 1.015), _rec("c", "S1", 1.03)]
    out = {r["ski"]: r for r in rank_real(recs, "viscous")}
    assert out["a"]["ties_with"] == ["b × S1"] and out["a"]["within_glide_test_precision"]
    assert sorted(out["b"]["ties_with"]) == ["a × S1", "c × S1"]
    assert [out[k]["rank"] for k in "abc"] == [1, 1, 2]
    exact = {r["ski"]: r for r in rank_real(recs, "viscous", precision=0.0)}
    assert [exact[k]["rank"] for k in "abc"] == [1, 2, 3]
    assert not any(r["within_glide_test_precision"] for r in exact.values())
