"""The calibrated band widths (issue 25, eighth pass): the split-conformal factor against the
guarantee it claims (conformal risk control on exchangeable skis, Angelopoulos et al. 2024), and
the scaled bands an identification writes against the Laplace ones (k times them where the
bench determines the ski, the prior's elsewhere, the posterior's modes alike, the method named
in the ski file)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from skisnow import InputError
from skisnow.bench import run_bench
from skisnow.identify import identify_ski
from skisnow.identify._bands import (
    CONFORMAL_SCALE_EI,
    CONFORMAL_SCALE_Z0,
    band_scale,
    calibrated_scale,
)
from skisnow.ski import read_ski, write_ski
from skisnow.ski._shipped import build_shipped


def _units(rng, n: int, m: int = 40):
    """``n`` exchangeable "skis" of ``m`` correlated stations each: normalised errors |b + e|
    with a ski-wide offset b (zero on most skis, a few sd on one in five: a fit landed in
    another basin) and a smooth station error e (an AR(1) of correlation 0.9), so that stations
    within a ski are far from independent."""
    from scipy.signal import lfilter

    b = np.where(rng.random(n) < 0.2, rng.normal(0.0, 4.0, n), 0.0)
    e = lfilter([np.sqrt(1 - 0.81)], [1.0, -0.9], rng.normal(size=(n, m + 60)), axis=1)[:, 60:]
    return list(np.abs(b[:, None] + e))


def test_the_conformal_factor_reaches_its_nominal_coverage_on_fresh_skis() -> None:
    # Conformal risk control (Angelopoulos et al. 2024, Theorems 1 and 2) with one unit per ski:
    # over calibration draws and fresh skis the expected share of stations outside the widened
    # band is at most alpha and (continuous loss) at least alpha - 2/(n + 1). The population is
    # a mixture (most skis covered by the 2-sd band, one in five far off), as the fits are.
    rng = np.random.default_rng(7)
    alpha, n = 0.10, 29
    losses = []
    for _ in range(300):
        k = calibrated_scale(_units(rng, n), alpha=alpha)
        losses.append(float(np.mean(np.stack(_units(rng, 100)) > 2 * k)))  # equal-size skis
    mean, se = float(np.mean(losses)), float(np.std(losses) / np.sqrt(len(losses)))
    assert alpha - 2 / (n + 1) - 3 * se <= mean <= alpha + 3 * se, (mean, se)
    # the plain 2-sd band under-covers this population (the factor is needed: > 1)
    assert np.mean(np.stack(_units(rng, 2000)) > 2.0) > 1.3 * alpha


def test_the_conformal_factor_is_the_smallest_that_holds_and_needs_enough_skis() -> None:
    rng = np.random.default_rng(3)
    units = _units(rng, 14)
    k = calibrated_scale(units, alpha=0.10)

    def bound(f: float) -> float:
        return (sum(np.mean(u > 2 * f) for u in units) + 1) / 15

    assert bound(k) <= 0.10 < bound(k * (1 - 1e-9))
    # the +1 of the finite-sample rule: 1/(n + 1) > alpha cannot be met by any factor
    assert calibrated_scale(units[:8], alpha=0.10) == np.inf
    assert calibrated_scale(units, alpha=0.05) == np.inf  # 14 skis: 1/15 > 5 %
    # the band's own scale: a factor on the errors is the same factor on k
    assert calibrated_scale([3 * u for u in units], alpha=0.10) == pytest.approx(3 * k)


@pytest.fixture(scope="module")
def pair():
    """One bench (the first release's classic: four masses at -120 mm, 10 µm, tip and tail not
    measured), identified with the Laplace and with the conformal bands (a short fit from the
    truth: the bands, not the fit, are under test)."""
    true = build_shipped("classic")
    data = run_bench(true, masses=(20, 40, 60, 80), load_positions=(-0.12,), noise=1e-5,
                     seed=3, contact="continuous")  # fmt: skip
    t = data.table
    bench = dataclasses.replace(data, table=t[(t["x_mm"] > -900) & (t["x_mm"] < 850)])
    kw = dict(initial=true, lambdas=(10.0,), max_nfev=2, continuation=())
    return bench, identify_ski(bench, **kw), identify_ski(bench, bands="conformal", **kw)


def _mode_sd(modes) -> np.ndarray:
    return np.sqrt(np.sum(np.asarray(modes) ** 2, axis=0))


def test_the_conformal_bands_are_k_times_the_laplace_bands(pair, tmp_path: Path) -> None:
    _, lap, con = pair
    a, b = lap.ski, con.ski
    assert a.stiffness_values == b.stiffness_values and a.camber_values == b.camber_values
    for what, k in (("stiffness", CONFORMAL_SCALE_EI), ("camber", CONFORMAL_SCALE_Z0)):
        det = np.asarray(getattr(a, f"{what}_determined"), dtype=bool)
        assert det.any() and (~det).any()  # the tail and tip are not measured
        assert getattr(b, f"{what}_determined") == getattr(a, f"{what}_determined")
        sd_a = np.asarray(getattr(a, "stiffness_log_sd" if what == "stiffness" else "camber_sd"))
        sd_b = np.asarray(getattr(b, "stiffness_log_sd" if what == "stiffness" else "camber_sd"))
        assert sd_b[det] == pytest.approx(k * sd_a[det], rel=1e-9)
        assert sd_b[~det] == pytest.approx(sd_a[~det], rel=1e-12)  # the prior's width
        # the samples (sample_skis, pairs' same-ski test) spread as the scaled bands say
        ma, mb = _mode_sd(getattr(a, f"{what}_modes")), _mode_sd(getattr(b, f"{what}_modes"))
        assert mb[det] == pytest.approx(k * ma[det], rel=1e-6)
        assert mb[~det] == pytest.approx(ma[~det], rel=1e-6)
    # the ski file records the method and its calibration
    detail = read_ski(write_ski(b, tmp_path / "c.json")).provenance.detail("bands")
    assert (
        f"×{CONFORMAL_SCALE_EI:g} (log EI)" in detail and f"×{CONFORMAL_SCALE_Z0:g} (z0)" in detail
    )
    assert "conformal" in detail and "seeded skis 1-14" in detail
    lap = a.provenance.detail("bands")
    assert lap.startswith("Laplace posterior, 95 % = 2 sd") and "widths scaled" not in lap


def test_the_conformal_bands_are_refused_where_they_are_not_calibrated(pair, tmp_path) -> None:
    from skisnow.bench import write_bench
    from skisnow.cli import main

    bench = pair[0]
    with pytest.raises(InputError, match="bands must be one of"):
        identify_ski(bench, bands="wide")
    with pytest.raises(InputError, match="calibrated on those only"):
        identify_ski(bench, bands="conformal", discrepancy_bands=True)
    with pytest.raises(InputError, match="no population prior"):  # what identify_ski asks
        band_scale("conformal", calibrated_on=False)  # with prior=..., or without the bias
    assert band_scale("laplace", calibrated_on=False) == (1.0, 1.0)
    src = write_bench(bench, tmp_path / "b.csv")
    args = ["identify", str(src), "--out", str(tmp_path / "s.json"), "--bands", "conformal"]
    assert main([*args, "--bootstrap", "2", "--json"]) == 2
    assert main([*args[:-1], "wide"]) == 2
