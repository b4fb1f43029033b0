"""Identification of EI(x) and z0(x) from bench data: exact Jacobian, consistency at the truth,
the identified ski as a file with bands and provenance, the CLI."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from skisnow import InputError
from skisnow.ski import _identify as ident
from skisnow.ski import _identify_fit as ident_fit
from skisnow.ski import read_ski, run_bench
from skisnow.ski._shipped import build_shipped

NOISE = 1e-5  # m: a bench's 10 µm
# the first release's classic (its parametric definition), independent of re-made shipped files
TRUE = build_shipped("classic")


@pytest.fixture(scope="module")
def bench():
    # what a user has: a few masses at one position, 10 µm noise, tip and tail not measured
    data = run_bench(TRUE, masses=(20, 40, 60, 80), load_positions=(-0.12,), noise=NOISE,
                     seed=3)  # fmt: skip
    t = data.table
    keep = (t["x_mm"] > -900) & (t["x_mm"] < 850)
    return dataclasses.replace(data, table=t[keep].reset_index(drop=True))


def _problem(bench, **kw):
    """The internal least-squares problem and start of identify_ski (captured, not solved)."""
    captured = {}

    class Stop(Exception):
        pass

    def capture(fun, p0, **_):
        captured["fun"], captured["p0"], captured["jac"] = fun, p0, _["jac"]
        raise Stop

    orig = ident_fit.least_squares
    ident_fit.least_squares = capture
    try:
        ident.identify_ski(bench, **kw)
    except Stop:
        pass
    finally:
        ident_fit.least_squares = orig
    return captured


def test_jacobian_is_the_derivative_of_the_residuals(bench) -> None:
    # The tangent through the beam at its active set against central differences (the active
    # set does not change for these small steps).
    c = _problem(bench, element_length=0.01, n_stiffness=8, n_camber=30, lambdas=(1e3,),
                 continuation=())  # fmt: skip
    rng = np.random.default_rng(0)
    p = c["p0"] + rng.normal(0, 1, c["p0"].size) * np.r_[np.full(8, 0.05), np.full(28, 2e-5)]
    j = c["jac"](p)
    checked = 0
    for k in range(p.size):
        step = 1e-5 if k < 8 else 1e-8
        e = np.zeros_like(p)
        e[k] = step
        fd = (c["fun"](p + e) - c["fun"](p - e)) / (2 * step)
        if np.linalg.norm(fd) < 1e-3 * np.linalg.norm(j):
            continue  # a spline coefficient the data barely see (noise of the LCP tolerance)
        assert np.linalg.norm(j[:, k] - fd) <= 2e-3 * np.linalg.norm(fd), k
        checked += 1
    assert checked >= 20


def test_the_fit_stays_at_the_truth_with_bands(bench) -> None:
    # Consistency: started at the true ski, the noisy bench does not pull the estimate away —
    # EI within 5 % rms between the glide zones, misfit at the noise, the noise estimated from
    # the data, z0 (modulo the rigid line the bench cannot see) within its bands.
    true = TRUE
    res = ident.identify_ski(bench, initial=true, lambdas=(1e3,), max_nfev=10, continuation=())
    ski = res.ski
    assert res.noise == pytest.approx(NOISE, rel=0.1)
    assert res.residual_rms < 1.3 * NOISE
    x = np.linspace(-0.45, 0.40, 86)  # between the glide zones
    err = ski.stiffness(x) / true.stiffness(x) - 1
    assert np.sqrt(np.mean(err**2)) < 0.05
    # z0 from four masses at one position: the zero-load extrapolation leaves a smooth bow
    # (measured 13 µm rms: the 10 µm target is missed in this sparse case); the Gauss–Newton
    # band of z0 is of the same order mid-ski (sd ≈ 10 µm)
    xz = np.linspace(-0.85, 0.80, 331)
    d = ski.free_camber(xz) - true.free_camber(xz)
    d -= np.polyval(np.polyfit(xz, d, 1), xz)
    assert ski.stiffness_log_sd is not None and ski.camber_sd is not None
    assert np.sqrt(np.mean(d**2)) < 20e-6
    sd_mid = float(np.interp(0.0, ski.camber_x, ski.camber_sd))
    assert 3e-6 < sd_mid < 30e-6
    assert min(ski.stiffness_log_sd) > 0
    assert ski.provenance.detail("criterion") == "given" or res.criterion == "gcv"


def test_identified_ski_is_a_valid_file(bench, tmp_path: Path) -> None:
    from skisnow.ski import write_ski

    res = ident.identify_ski(bench, initial=TRUE, lambdas=(1e3,), max_nfev=2,
                             name="my classic", continuation=())  # fmt: skip
    path = write_ski(res.ski, tmp_path / "id.json")
    back = read_ski(path)
    assert back == res.ski and back.name == "my classic"
    assert back.kick_zone == pytest.approx(TRUE.kick_zone, abs=1e-12)  # from the bench metadata
    assert back.provenance.detail("noise_mm") == pytest.approx(res.noise * 1e3)
    assert "identified" in back.provenance.method


def test_bad_input(bench) -> None:
    one = run_bench(TRUE, masses=(30,), load_positions=(-0.12,))
    with pytest.raises(InputError, match="at least 2 load cases"):
        ident.identify_ski(one)
    with pytest.raises(InputError, match="n_camber"):
        ident.identify_ski(bench, n_camber=3)
    with pytest.raises(InputError, match="must contain the balance point and the measured"):
        ident.identify_ski(bench, x_tip=0.5)


def test_cli_identify(bench, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from skisnow.cli import main
    from skisnow.io import write_bench

    src = write_bench(bench, tmp_path / "b.csv")
    out = tmp_path / "ski.json"
    code = main(["identify", str(src), "--out", str(out), "--regularisation", "1000",
                 "--n-camber", "40", "--max-nfev", "3", "--json"])  # fmt: skip
    assert code == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["load_cases"] == 4 and doc["criterion"] == "given"
    assert read_ski(out).name == "classic (identified)"
    assert main(["identify", str(src), "--out", str(tmp_path / "x.csv")]) != 0
    assert "ski file (.json)" in capsys.readouterr().err
