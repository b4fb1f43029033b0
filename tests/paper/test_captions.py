"""The captions of Kalliorinne et al. (2023), Figs. 4-7, and the shipped skis against them.

The shipped skis are FITTED to these numbers (benchmarks/calibrate_skis.py): the test holds the
tolerances of the fit (lengths ±20 %, mean pressures ±25 %, load shares ±5 points, patch counts
exact), so that a change to a ski, the beam, the solver or the zones that moves them is seen.
"""

from __future__ import annotations

import numpy as np
import pytest

from _extras import needs_network
from skisnow import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.paper import (
    CAPTIONS,
    REPRODUCTION_TOLERANCES,
    ROUTES,
    TOLERANCES,
    caption_table,
    solve_caption_case,
    tolerances_of,
)
from skisnow.ski import PLAUSIBLE_SKIS, REPRODUCTION_SKIS, SHIPPED_SKIS, get_ski


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


def test_implied_shares_of_figures_4_and_7() -> None:
    # length × mean pressure over the sum: the classic 70/30 on the stone, 50 and 200 MPa, the
    # skate 67/33 on the stone; stated shares are taken as stated
    for case in CAPTIONS:
        shares = case.shares()
        assert sum(s for s, _ in shares.values()) == pytest.approx(1.0)
        if case.figure in ("Fig. 4", "Fig. 7"):
            assert all(implied for _, implied in shares.values())
            rear = shares["rear"][0]
            assert rear == pytest.approx(0.70 if case.ski == "classic" else 0.667, abs=0.01)
        else:
            assert shares == {z.zone: (z.load_share, False) for z in case.zones}


def test_each_ski_has_its_tolerances() -> None:
    for name in PLAUSIBLE_SKIS:
        assert tolerances_of(get_ski(name)) == TOLERANCES
    for name in REPRODUCTION_SKIS:
        tol = tolerances_of(get_ski(name))
        assert tol == REPRODUCTION_TOLERANCES and tol.implied_shares
        assert (tol.length, tol.pressure, tol.share) == (0.10, 0.10, 0.03)


#: The network route needs the 'network' extra (tests/_extras.py); the beam route never does.
ROUTE_PARAMS = [pytest.param(r, marks=needs_network) if r == "network" else r for r in ROUTES]


@pytest.fixture(scope="module", params=ROUTE_PARAMS)
def rows(request):  # type: ignore[no-untyped-def]
    return request.param, caption_table(route=request.param)


@pytest.mark.parametrize("route", ROUTE_PARAMS)
def test_caption_cases_balance_force_and_moment(route: str) -> None:
    case = next(c for c in CAPTIONS if c.ski == "classic" and c.load_position == -0.070)
    zones = solve_caption_case(case, get_ski("classic-k22"), route=route)
    force = sum(zones[n].force for n in ("rear", "middle", "front"))
    assert force == pytest.approx(case.mass * STANDARD_GRAVITY, rel=1e-8)
    assert sum(zones[n].load_share for n in ("rear", "middle", "front")) == pytest.approx(1.0)


#: Caption numbers the shipped skis do NOT reach, per (ski, route), each as (case label, zone,
#: quantity). The plausible skis are held to TOLERANCES (±20 %, ±25 %, stated shares ±5 points):
#: where the captions and the practitioners' limits pull against each other the plausible ski
#: ships (docs/validation/paper-reproduction.md). The reproduction skis are held to
#: REPRODUCTION_TOLERANCES (±10 %, ±10 %, ±3 points, implied shares too). Measured with the
#: shipped skis and networks; strict both ways: a listed miss that starts to pass, or an
#: unlisted one that fails, is a failure.
KNOWN_MISSES: dict[tuple[str, str], set[tuple[str, str, str]]] = {
    ("classic", "network"): {
        ("Fig. 4 classic 30 kg -120 mm stone", "front", "length"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "front", "share"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "length"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "pressure"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "share"),
        ("Fig. 6 classic 60 kg -70 mm 100 MPa", "front", "share"),
        ("Fig. 6 classic 60 kg -70 mm 100 MPa", "middle", "length"),
        ("Fig. 6 classic 60 kg -70 mm 100 MPa", "middle", "pressure"),
        ("Fig. 6 classic 60 kg -70 mm 100 MPa", "middle", "share"),
        ("Fig. 7 classic 30 kg -120 mm 200 MPa", "rear", "length"),
        ("Fig. 7 classic 30 kg -120 mm 200 MPa", "rear", "pressure"),
        ("Fig. 7 classic 30 kg -120 mm 50 MPa", "front", "pressure"),
        ("Fig. 7 classic 30 kg -120 mm 50 MPa", "rear", "length"),
    },
    ("skate", "network"): {
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
    },
    ("classic-k22", "network"): {
        ("Fig. 4 classic 30 kg -120 mm stone", "front", "length"),
        ("Fig. 4 classic 30 kg -120 mm stone", "front", "pressure"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "front", "length"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "front", "share"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "length"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "pressure"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "share"),
        ("Fig. 6 classic 60 kg -70 mm 100 MPa", "front", "length"),
        ("Fig. 7 classic 30 kg -120 mm 200 MPa", "front", "length"),
        ("Fig. 7 classic 30 kg -120 mm 200 MPa", "front", "pressure"),
    },
    ("skate-k22", "network"): {
        ("Fig. 5 skate 60 kg -120 mm 100 MPa", "front", "patches"),
    },
    ("classic", "beam"): {
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
    },
    ("skate", "beam"): {
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
    },
    ("classic-k22", "beam"): {
        ("Fig. 4 classic 30 kg -120 mm stone", "front", "length"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "front", "length"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "front", "share"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "length"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "pressure"),
        ("Fig. 6 classic 60 kg -210 mm 100 MPa", "rear", "share"),
        ("Fig. 7 classic 30 kg -120 mm 200 MPa", "front", "length"),
        ("Fig. 7 classic 30 kg -120 mm 200 MPa", "front", "pressure"),
    },
    ("skate-k22", "beam"): {
        ("Fig. 5 skate 60 kg -120 mm 100 MPa", "front", "patches"),
    },
}


def _misses(r) -> set[tuple[str, str, str]]:  # type: ignore[no-untyped-def]
    tol = tolerances_of(get_ski(r.ski))
    label = r.case.label
    if r.paper is None:
        return {(label, r.zone, "extra zone")}
    out = set()
    if abs(r.length_error) > tol.length:
        out.add((label, r.zone, "length"))
    if abs(r.pressure_error) > tol.pressure:
        out.add((label, r.zone, "pressure"))
    if (not r.share_implied or tol.implied_shares) and abs(r.share_error) > tol.share:
        out.add((label, r.zone, "share"))
    if r.paper.patches is not None and r.patches != r.paper.patches:
        out.add((label, r.zone, "patches"))
    return out


def test_shipped_skis_against_the_captions(rows) -> None:  # type: ignore[no-untyped-def]
    route, found_rows = rows
    assert {r.ski for r in found_rows} == set(SHIPPED_SKIS)
    for ski in SHIPPED_SKIS:
        mine = [r for r in found_rows if r.ski == ski]
        kind = get_ski(ski).kind
        assert {r.case.label for r in mine} == {c.label for c in CAPTIONS if c.ski == kind}
        found: set[tuple[str, str, str]] = set()
        for r in mine:
            m = _misses(r)
            assert r.ok == (not m), (ski, route, r.case.label, r.zone)
            found |= m
        known = KNOWN_MISSES[(ski, route)]
        assert found == known, (
            f"{ski} on the {route} route: new misses {sorted(found - known)}, now within "
            f"{sorted(known - found)}"
        )


def test_caption_table_input_errors() -> None:
    with pytest.raises(InputError, match="classic' or 'skate"):
        caption_table({"alpine": get_ski("skate")})
    with pytest.raises(InputError, match="must be a Ski"):
        caption_table({"skate": "skate"})  # type: ignore[dict-item]
    # a subset of skis runs only their cases
    only = caption_table({"skate": get_ski("skate")})
    assert {r.case.ski for r in only} == {"skate"} and np.all([r.zone != "middle" for r in only])


@needs_network
def test_captions_cli_json_and_bad_option(capsys) -> None:  # type: ignore[no-untyped-def]
    import json

    from skisnow.cli import main

    assert main(["captions", "--ski", "skate-k22", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert {r["ski"] for r in doc["rows"]} == {"skate-k22"}
    assert {r["route"] for r in doc["rows"]} == {"network", "beam"}  # both routes by default
    assert doc["tolerances"]["skate-k22"]["length_pct"] == pytest.approx(10.0)
    assert doc["tolerances"]["skate-k22"]["implied_shares"] is True
    row = doc["rows"][0]
    assert {"paper_length_mm", "length_mm", "mean_pressure_kpa", "load_share_pct", "ok",
            "paper_share_implied", "route"} <= set(row)  # fmt: skip
    assert doc["within"]["skate-k22"]["beam"][1] == 6
    assert main(["captions", "--ski", "skate", "--route", "beam"]) == 0  # the table
    out = capsys.readouterr().out
    assert "paper / beam" in out and "±20% length" in out
    assert main(["captions", "--ski", "alpine"]) == 2  # bad input: one line, exit code 2
    assert "--ski" in capsys.readouterr().err
    assert main(["captions", "--route", "stone"]) == 2
    assert "--route" in capsys.readouterr().err
