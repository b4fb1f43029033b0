"""The captions of Kalliorinne et al. (2023), Figs. 4-7, and the shipped skis against them.

The shipped skis are FITTED to these numbers (benchmarks/calibrate_skis.py): the test holds the
tolerances of the fit (lengths ±20 %, mean pressures ±25 %, load shares ±5 points, patch counts
exact), so that a change to a ski, the beam, the solver or the zones that moves them is seen.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.paper import CAPTIONS, TOLERANCES, caption_table, solve_caption_case
from skisnow.ski import get_ski


def test_the_papers_captions_are_self_consistent() -> None:
    # length × 44 mm × mean pressure summed over the zones is the load m·g, and each zone's
    # part of it is the stated load share: the transcription is right, and the paper's numbers
    # are a strip 44 mm wide (3 significant digits: within 2 % and 0.01).
    for case in CAPTIONS:
        forces = [z.length * 0.044 * z.mean_pressure for z in case.zones]
        assert sum(forces) == pytest.approx(case.mass * STANDARD_GRAVITY, rel=0.02), case.label
        for z, f in zip(case.zones, forces, strict=True):
            if z.load_share is not None:
                assert f / sum(forces) == pytest.approx(z.load_share, abs=0.01), case.label


@pytest.fixture(scope="module")
def rows():
    return caption_table()


def test_caption_cases_balance_force_and_moment() -> None:
    case = next(c for c in CAPTIONS if c.ski == "classic" and c.load_position == -0.070)
    zones = solve_caption_case(case, get_ski("classic"))
    force = sum(zones[n].force for n in ("rear", "middle", "front"))
    assert force == pytest.approx(case.mass * STANDARD_GRAVITY, rel=1e-8)
    assert sum(zones[n].load_share for n in ("rear", "middle", "front")) == pytest.approx(1.0)


#: Caption numbers the shipped (plausible) skis do NOT reach: where the captions and the
#: practitioners' limits pull against each other the plausible ski ships (README, "The shipped
#: skis against the paper"). Each entry is (case label, zone, quantity); the test is strict both
#: ways: a listed miss that starts to pass, or an unlisted one that fails, is a failure.
#: Measured with the shipped skis: the classic of version 2 (spline fit of
#: benchmarks/calibrate_skis.py, benchmarks/calibration/calibration_classic_v3.json) and the
#: skate of version 2 (benchmarks/calibration/calibration_skate_v5.json: Breitschädel's k at its
#: upper limit, 420 N/mm, and the paper's Fig. 5/8 findings held; the captions pull k far
#: higher, so only the rear zone on the stone is within the tolerances; README).
KNOWN_MISSES: set[tuple[str, str, str]] = {
    ("Fig. 4 skate 30 kg -120 mm stone", "front", "length"),
    ("Fig. 4 skate 30 kg -120 mm stone", "front", "pressure"),
    ("Fig. 5 skate 30 kg -120 mm 100 MPa", "front", "length"),
    ("Fig. 5 skate 30 kg -120 mm 100 MPa", "front", "pressure"),
    ("Fig. 5 skate 30 kg -120 mm 100 MPa", "front", "share"),
    ("Fig. 5 skate 30 kg -120 mm 100 MPa", "rear", "length"),
    ("Fig. 5 skate 30 kg -120 mm 100 MPa", "rear", "pressure"),
    ("Fig. 5 skate 30 kg -120 mm 100 MPa", "rear", "share"),
    ("Fig. 5 skate 60 kg -120 mm 100 MPa", "front", "length"),
    ("Fig. 5 skate 60 kg -120 mm 100 MPa", "front", "pressure"),
    ("Fig. 5 skate 60 kg -120 mm 100 MPa", "front", "share"),
    ("Fig. 5 skate 60 kg -120 mm 100 MPa", "rear", "length"),
    ("Fig. 5 skate 60 kg -120 mm 100 MPa", "rear", "pressure"),
    ("Fig. 5 skate 60 kg -120 mm 100 MPa", "rear", "share"),
    ("Fig. 6 classic 60 kg -210 mm 100 MPa", "front", "share"),
    ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "length"),
    ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "pressure"),
    ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "share"),
    ("Fig. 6 classic 60 kg -70 mm 100 MPa", "middle", "length"),
    ("Fig. 6 classic 60 kg -70 mm 100 MPa", "middle", "pressure"),
    ("Fig. 7 classic 30 kg -120 mm 200 MPa", "rear", "length"),
    ("Fig. 7 classic 30 kg -120 mm 200 MPa", "rear", "pressure"),
    ("Fig. 7 classic 30 kg -120 mm 50 MPa", "front", "pressure"),
    ("Fig. 7 classic 30 kg -120 mm 50 MPa", "rear", "length"),
}


def _misses(r) -> set[tuple[str, str, str]]:  # type: ignore[no-untyped-def]
    label = r.case.label
    if r.paper is None:
        return {(label, r.zone, "extra zone")}
    out = set()
    if abs(r.length_error) > TOLERANCES.length:
        out.add((label, r.zone, "length"))
    if abs(r.pressure_error) > TOLERANCES.pressure:
        out.add((label, r.zone, "pressure"))
    if r.share_error is not None and abs(r.share_error) > TOLERANCES.share:
        out.add((label, r.zone, "share"))
    if r.paper.patches is not None and r.patches != r.paper.patches:
        out.add((label, r.zone, "patches"))
    return out


def test_shipped_skis_reproduce_the_captions_within_the_tolerances(rows) -> None:
    assert {r.case.label for r in rows} == {c.label for c in CAPTIONS}
    found: set[tuple[str, str, str]] = set()
    for r in rows:
        m = _misses(r)
        assert r.ok == (not m), (r.case.label, r.zone)
        found |= m
    details = {
        (r.case.label, r.zone): r.as_dict() for r in rows
    }  # for the message: the measured errors
    new = sorted(found - KNOWN_MISSES)
    fixed = sorted(KNOWN_MISSES - found)
    assert not new, "; ".join(
        f"{c} {z} {q}: length {details[(c, z)]['length_error_pct']}, pressure "
        f"{details[(c, z)]['pressure_error_pct']} %"
        for c, z, q in new
    )
    assert not fixed, f"now within tolerance (remove from KNOWN_MISSES): {fixed}"


def test_caption_table_input_errors() -> None:
    with pytest.raises(InputError, match="classic' or 'skate"):
        caption_table({"alpine": get_ski("skate")})
    with pytest.raises(InputError, match="must be a Ski"):
        caption_table({"skate": "skate"})  # type: ignore[dict-item]
    # a subset of skis runs only their cases
    only = caption_table({"skate": get_ski("skate")})
    assert {r.case.ski for r in only} == {"skate"} and np.all([r.zone != "middle" for r in only])


def test_captions_cli_json_and_bad_option(capsys) -> None:  # type: ignore[no-untyped-def]
    import json

    from skisnow.cli import main

    assert main(["captions", "--ski", "skate", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {r["ski"] for r in doc["rows"]} == {"skate"}
    assert doc["tolerances"]["length_pct"] == pytest.approx(20.0)
    row = doc["rows"][0]
    assert {"paper_length_mm", "length_mm", "mean_pressure_kpa", "load_share_pct", "ok"} <= set(row)
    assert main(["captions", "--ski", "alpine"]) == 2  # bad input: one line, exit code 2
    assert "--ski" in capsys.readouterr().err
