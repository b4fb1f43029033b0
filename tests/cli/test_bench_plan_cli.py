"""``skisnow bench-plan``: plans parsed in field units, one JSON document, clear errors."""

from __future__ import annotations

import json

import pytest

from skisnow.cli import main


def test_bench_plan_json_two_plans(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["bench-plan", "classic", "--noise-um", "10", "--stations-mm=-900,850",
            "--plan", "40,80@-120", "--plan", "60@-120", "--json"]  # fmt: skip
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    two, one = doc["plans"]
    assert (two["plan"], two["load_cases"], one["load_cases"]) == ("40,80@-120", 2, 1)
    # one profile cannot separate EI from z0: said, with no finite bound
    assert one["ei_identifiable"] is False and one["ei_sd_crb_percent"] is None
    assert one["null_dimension"] > 0 and not one["ei_target_reachable"]
    assert two["ei_identifiable"] and two["ei_sd_crb_percent"] > 0
    assert doc["stations_mm"] == [-900.0, 850.0] and doc["targets"]["z0_um"] == 10.0


@pytest.mark.parametrize(
    ("plan", "message"),
    [("20,40", "MASSES_KG@POSITIONS_MM"), ("-20@-120", "mass"), ("20@x", "cannot read")],
)
def test_bench_plan_bad_plans_exit_2(capsys, plan: str, message: str) -> None:
    assert main(["bench-plan", "classic", "--plan", plan]) == 2
    assert message in capsys.readouterr().err
