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
