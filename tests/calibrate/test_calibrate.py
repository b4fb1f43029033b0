"""The calibration of the shipped skis (``skisnow.calibrate``, ``skisnow calibrate``).

Its parametrisation rebuilds the shipped skis; its residuals are the paper's pipeline (the
numbers ``skisnow captions`` prints); its records are reproduced by their own knots; its hinges
vanish exactly inside the practitioners' limits; a seeded fit never ends worse than its start;
the command and the ``benchmarks/calibrate_skis.py`` shim that the shipped skis' provenance
cites write the shipped ski files from their records.
"""

from __future__ import annotations

import json
import math
import runpy
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import OptimizeResult

from skisnow import calibrate as cs
from skisnow.calibrate import _fit
from skisnow.cli import main
from skisnow.paper import TOLERANCES, caption_table
from skisnow.paper._captions import N_POINTS
from skisnow.ski import get_ski, read_ski

ROOT = Path(__file__).resolve().parents[2]
#: The calibration records the shipped ski files were written from (their provenance's seed,
#: evaluations and caption misfit).
RECORDS = {
    "classic": ROOT / "benchmarks" / "calibration" / "calibration_classic_v3.json",
    "skate": ROOT / "benchmarks" / "calibration" / "calibration_skate_v5.json",
}


def _misfit_of_rows(rows: list[dict], tol=TOLERANCES) -> float:  # type: ignore[no-untyped-def]
    """The caption misfit from a caption table, by the definitions of the calibration's
    residuals (in tolerance units): log length and pressure ratios over log(1 + tolerance),
    share differences over the share tolerance, 3 per wrong patch count (at most two counted)
    and for every zone the paper does not have."""
    total = 0.0
    for r in rows:
        pl, pp, ps, pn = (
            r["paper_length_mm"], r["paper_mean_pressure_kpa"], r["paper_load_share_pct"],
            r["paper_patches"],
        )  # fmt: skip
        if pl is None:  # a zone the paper does not have
            total += (cs.PATCH_PENALTY if r["patches"] else 0.0) ** 2
            continue
        pressure = r["mean_pressure_kpa"] if math.isfinite(r["mean_pressure_kpa"]) else 1e6
        total += (math.log(max(r["length_mm"], 1.0) / pl) / math.log(1 + tol.length)) ** 2
        total += (math.log(pressure / pp) / math.log(1 + tol.pressure)) ** 2
        # a share the caption implies (Figs. 4, 7) counts only where the tolerances hold it
        if ps is not None and (not r.get("paper_share_implied") or tol.implied_shares):
            total += ((r["load_share_pct"] - ps) / (100 * tol.share)) ** 2
        if pn is not None or r["patches"] == 0:
            total += (cs.PATCH_PENALTY * min(abs(r["patches"] - (pn or 1)), 2)) ** 2
    return total


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_the_shipped_vector_rebuilds_the_shipped_ski(kind: str) -> None:
    """make_ski(kind, shipped_vector(kind)) is the shipped ski: EI and z0 at its stations (the
    spline through the same knot values), the classic's kick zone to the 0.1 mm it is stored
    to."""
    shipped = get_ski(kind)
    ski = cs.make_ski(kind, cs.shipped_vector(kind))
    x_ei, x_z = np.array(shipped.stiffness_x), np.array(shipped.camber_x)
    np.testing.assert_allclose(ski.stiffness(x_ei), shipped.stiffness(x_ei), rtol=1e-12)
    np.testing.assert_allclose(ski.free_camber(x_z), shipped.free_camber(x_z), rtol=0, atol=1e-15)
    if kind == "classic":  # the 0.2 / 0.1 mm marks at half body weight: stored to 0.1 mm, of
        # the fit before its knot values were rounded (-254.26 mm here, -254.2 mm stored)
        np.testing.assert_allclose(ski.kick_zone, shipped.kick_zone, rtol=0, atol=1e-4)
    else:
        assert ski.kick_zone is None and shipped.kick_zone is None


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_the_caption_residuals_are_the_papers_pipeline(kind: str) -> None:
    """The calibration's caption table of the shipped vector is the one ``skisnow captions``
    prints for the shipped ski (the same pipeline on the same ski, to the last bit), and its
    residuals sum to the misfit of that table's rows (the definitions, computed apart)."""
    layout: list = []
    res, rows = cs.caption_residuals(cs.make_ski(kind, cs.shipped_vector(kind)), layout=layout)
    expected = [r.as_dict() for r in caption_table({kind: get_ski(kind)})]
    assert [r.as_dict() for r in rows] == expected
    # the zones the paper does not have (a skate's middle, say) stay empty: no penalty; the
    # others' residuals are their table rows'
    stated = {(r["case"], r["zone"]) for r in expected}
    extra = [res[s] for case, zone, s in layout if (case, zone) not in stated]
    assert extra and all(r == [0.0] for r in extra)
    assert float(np.sum(np.square(res))) == pytest.approx(_misfit_of_rows(expected), rel=1e-12)


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_the_reproduction_residuals_hold_the_implied_shares(kind: str) -> None:
    """In the reproduction units (10 %, 10 %, 3 points) the residuals of the reproduction ski
    are its caption table's misfit with the implied shares of Figs. 4 and 7 counted."""
    from skisnow.paper import REPRODUCTION_TOLERANCES as R

    ski = get_ski(f"{kind}-k22")
    res, rows = cs.caption_residuals(ski, tolerances=R)
    dicts = [r.as_dict() for r in rows]
    assert float(np.sum(np.square(res))) == pytest.approx(_misfit_of_rows(dicts, R), rel=1e-12)
    implied = [d for d in dicts if d["paper_share_implied"]]
    assert implied and all(d["figure"] in ("Fig. 4", "Fig. 7") for d in implied)
    # the same rows in the plausible units leave the implied shares out: a smaller misfit
    loose, _ = cs.caption_residuals(ski)
    assert len(loose) == len(res) - len(implied)


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_the_shipped_records_reproduce(kind: str) -> None:
    """The record of a shipped ski: its misfit is its caption table's, and its knots give back
    that table up to what their rounding (EI to 0.01 N m², z0 to 0.1 µm) moves: a contact edge
    by a cell of the pipeline's grid (the classic's rear zone at 60 kg / -210 mm by one cell,
    misfit 43.72 against the fit's 43.35), the load shares by hundredths of a point. Its hinge
    residuals are those of the practitioners' numbers of its ski."""
    doc = json.loads(RECORDS[kind].read_text())
    assert doc["caption_misfit"] == pytest.approx(_misfit_of_rows(doc["captions"]), rel=1e-12)
    ski = cs.make_ski(kind, cs.record_vector(kind, doc))
    _, rows = cs.caption_residuals(ski)
    cell = (ski.x_tip - ski.x_tail) / (N_POINTS - 1) * 1e3
    for got, stored in zip((r.as_dict() for r in rows), doc["captions"], strict=True):
        assert (got["case"], got["zone"], got["patches"]) == (
            stored["case"], stored["zone"], stored["patches"],
        )  # fmt: skip
        assert abs(got["length_mm"] - stored["length_mm"]) <= 1.01 * cell
        assert abs(got["load_share_pct"] - stored["load_share_pct"]) < 0.05
    opts = cs.FitOptions(k_range_n_per_mm=tuple(doc.get("k_range_n_per_mm") or (225.0, 251.0)))
    prac = cs.plausibility(ski)
    assert cs.plausibility_residuals(kind, prac, opts) == doc["hinge_residuals"]
    for key, value in doc["plausibility"].items():
        assert prac[key] == pytest.approx(value, rel=1e-3), key


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_hinges_vanish_inside_the_limits_and_grow_outside(kind: str) -> None:
    """Zero inside every practitioners' limit (its edges included); outside, the distance to
    the limit in units of its scale, one limit at a time."""
    opts = cs.FitOptions(kick_gap_max_mm=0.05)
    limits = cs.hinge_limits(kind, opts)
    assert ("kick_gap_2x_mm" in [k for k, *_ in limits]) == (kind == "classic")

    def inside(lo: float | None, hi: float | None, scale: float) -> float:
        if lo is not None and hi is not None:
            return 0.5 * (lo + hi)
        return lo + scale if lo is not None else hi - scale  # type: ignore[operator]

    ok = {key: inside(lo, hi, scale) for key, lo, hi, scale in limits}
    assert cs.plausibility_residuals(kind, ok, opts) == [0.0] * len(limits)
    for i, (key, lo, hi, scale) in enumerate(limits):
        for edge in (lo, hi):
            if edge is not None:
                assert cs.plausibility_residuals(kind, {**ok, key: edge}, opts)[i] == 0.0
        for value, want in ((lo, 2.0), (hi, 3.0)):
            if value is None:
                continue
            off = value - 2.0 * scale if value is lo else value + 3.0 * scale
            got = cs.plausibility_residuals(kind, {**ok, key: off}, opts)
            assert got[i] == pytest.approx(want, rel=1e-12), key
            assert all(g == 0.0 for j, g in enumerate(got) if j != i)


def test_a_seeded_fit_never_ends_worse_than_its_start(monkeypatch: pytest.MonkeyPatch) -> None:
    """One generation of the differential evolution (21 members around the shipped classic, the
    start one of them) and a polish that finds nothing better: the misfit returned is the best
    member's, at most the start's (fewer evaluations than a real run: the polish is stubbed)."""
    opts = cs.FitOptions()
    v0 = cs.shipped_vector("classic")
    start_misfit = float(np.sum(cs.residuals("classic", v0, opts) ** 2))

    def no_progress(fun, u, **_):  # the least-squares polish, finding nothing better
        return OptimizeResult(x=u, cost=math.inf, nfev=0)

    monkeypatch.setattr(_fit, "least_squares", no_progress)
    out = cs.fit("classic", seed=4, generations=1, popsize=1, opts=opts, start=v0, sigma=0.005)
    assert out["generations_run"] == 1
    assert out["evaluations"] == 2 * v0.size  # the population (popsize x parameters), twice
    misfit = float(np.sum(cs.residuals("classic", np.array(out["vector"]), opts) ** 2))
    assert misfit <= start_misfit


def _same_numbers(written, shipped) -> None:
    """The written ski's values are the shipped file's to 1e-12 relative (1e-9 µm on a camber of
    a mm): the same numbers, not bitwise — NumPy/SciPy take different SIMD/FMA paths on different
    CPUs (seen: the shipped classic regenerated on another machine differs in the last bit at
    one station of 401), which floating point does not promise to make identical."""
    np.testing.assert_allclose(np.asarray(written), np.asarray(shipped), rtol=1e-12, atol=0.0)


def test_the_command_and_the_shim_write_the_shipped_skis(tmp_path: Path) -> None:
    """``skisnow calibrate --write-shipped RECORD --ski-out FILE`` and the shim the shipped
    files' provenance cites write the shipped ski (same EI, z0, kick zone, provenance method)."""
    record = RECORDS["classic"]
    out = tmp_path / "classic.json"
    assert main(["calibrate", "--write-shipped", str(record), "--ski-out", str(out)]) == 0
    written, shipped = read_ski(out), get_ski("classic")
    _same_numbers(written.stiffness_values, shipped.stiffness_values)
    _same_numbers(written.camber_values, shipped.camber_values)
    assert written.kick_zone == shipped.kick_zone
    assert written.provenance.method == shipped.provenance.method
    assert "benchmarks/calibrate_skis.py" in written.provenance.method
    shim_out = tmp_path / "shim.json"
    argv = sys.argv
    sys.argv = ["calibrate_skis.py", "--write-shipped", str(record), "--ski-out", str(shim_out)]
    try:
        with pytest.raises(SystemExit) as stop:
            runpy.run_path(str(ROOT / "benchmarks" / "calibrate_skis.py"), run_name="__main__")
    finally:
        sys.argv = argv
    assert stop.value.code == 0
    _same_numbers(read_ski(shim_out).camber_values, shipped.camber_values)


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_the_reproduction_skis_are_written_from_their_records(kind: str, tmp_path: Path) -> None:
    """The shipped reproduction ski is its record written by ``--write-shipped`` (the record
    the provenance names by seed and misfit), named ``<kind>-k22``, with its departures from
    plausibility in numbers."""
    shipped = get_ski(f"{kind}-k22")
    seed = shipped.provenance.detail("seed")
    misfit = shipped.provenance.detail("caption_misfit")
    records = sorted((ROOT / "benchmarks" / "calibration").glob(f"calibration_{kind}_k22*.json"))
    docs = [(p, json.loads(p.read_text())) for p in records]
    (record,) = [
        p for p, d in docs if d["seed"] == seed and round(d["caption_misfit"], 3) == misfit
    ]
    out = tmp_path / f"{kind}-k22.json"
    assert main(["calibrate", "--write-shipped", str(record), "--ski-out", str(out)]) == 0
    written = read_ski(out)
    assert written.name == f"{kind}-k22" and written.kind == kind
    _same_numbers(written.stiffness_values, shipped.stiffness_values)
    _same_numbers(written.camber_values, shipped.camber_values)
    assert written.kick_zone == shipped.kick_zone
    assert "REPRODUCTION" in written.description and "k " in written.description
    departures = json.loads(written.provenance.detail("departures"))
    assert any("Breitschädel stiffness k" in d for d in departures)


def test_a_reproduction_record_states_its_own_chain_of_fits(tmp_path: Path) -> None:
    """A record with a ``method`` (a ski made by more than one fit, e.g. profiles first, then
    Powell) has that method in its provenance; without it, the one fit the record names."""
    doc = json.loads(
        (ROOT / "benchmarks" / "calibration" / "calibration_skate_k22_v4.json").read_text()
    )
    plain = read_ski(cs.write_shipped(doc, tmp_path / "plain.json"))
    assert "benchmarks/fit_k22.py: differential evolution, then Powell" in (plain.provenance.method)
    chain = "least squares to designed profiles, then Powell"
    stated = read_ski(cs.write_shipped(doc | {"method": chain}, tmp_path / "stated.json"))
    assert f"alone ({chain})" in stated.provenance.method
    assert "differential evolution" not in stated.provenance.method
    assert stated.camber_values == plain.camber_values


def test_the_command_refuses_bad_options(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["calibrate", "--ski", "alpine"]) == 2
    assert "--ski must be classic or skate" in capsys.readouterr().err
    assert main(["calibrate", "--knots", "sparse"]) == 2


def test_a_ski_file_says_when_its_ei_step_limit_is_exceeded(tmp_path: Path) -> None:
    """The EI step limit is a hinge penalty of the fit, so a calibrated ski may exceed it: the
    description must not state the limit as met next to a larger step (the shipped classic,
    calibration_classic_v3: 8.50x between neighbouring knots against the limit 8x)."""
    from skisnow.calibrate import EI_STEP_MAX

    doc = json.loads(
        (ROOT / "benchmarks" / "calibration" / "calibration_classic_v3.json").read_text()
    )
    log_ei = np.log(np.array(doc["ei_n_m2"]))  # its knots are the default ones
    step = float(np.exp(np.max(np.abs(np.diff(log_ei)))))
    assert step > EI_STEP_MAX
    text = read_ski(cs.write_shipped(doc, tmp_path / "c.json")).description
    assert f"{EI_STEP_MAX:g}x exceeded by {(step / EI_STEP_MAX - 1) * 100:.1f} %" in text
    assert "exceeded by" in get_ski("classic").description  # the shipped file says so too
