"""The simultaneous "same ski?" test of pairs (issue 25, item 4): calibrated under its hypothesis
(a ski and its own identification tie at the test's level whatever the number of stations), the
pointwise rule it replaced measured miscalibrated on the same draws, symmetric, and able to see a
10 % stiffness difference and a 50 µm camber bump."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from skisnow.workflows._same_ski import same_ski_test

X = np.linspace(-0.5, 0.5, 600)


def _posterior(seed: int, k: int = 16, undercount: float = 1.6):
    """Smooth random modes (Gaussian bumps) of z0 [m] and log EI, and bands wider than the
    modes' sd by ``undercount`` (the file's modes keep part of the variance; the bands all)."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-0.5, 0.5, (2, k))
    widths = rng.uniform(0.05, 0.2, (2, k))
    bumps = np.exp(-0.5 * ((X[None, :] - centres[:, :, None]) / widths[:, :, None]) ** 2)
    mz = 3e-6 * rng.standard_normal((k, 1)) * bumps[0]
    mk = 0.02 * rng.standard_normal((k, 1)) * bumps[1]
    sd = [undercount * np.sqrt(np.sum(m**2, axis=0)) for m in (mz, mk)]
    return mz, mk, sd[0], sd[1]


def _null_difference(rng, mz, mk, sz, sk):
    """A difference drawn under "same ski" with bands that are calibrated: the modes' draw
    rescaled per station to the band's sd."""
    xi = rng.standard_normal(mz.shape[0])
    dz = (xi @ mz) * sz / np.sqrt(np.sum(mz**2, axis=0))
    dk = (xi @ mk) * sk / np.sqrt(np.sum(mk**2, axis=0))
    return dz, dk


def test_a_ski_and_its_identification_tie_at_the_level_and_the_pointwise_rule_did_not() -> None:
    mz, mk, sz, sk = _posterior(3)
    rng = np.random.default_rng(11)  # the differences: independent of the critical value's draws
    n, new, old = 200, 0, 0
    for _ in range(n):
        dz, dk = _null_difference(rng, mz, mk, sz, sk)
        t = same_ski_test(x=X, dz=dz, dk=dk, sd_z=sz, sd_k=sk, modes_z=mz, modes_k=mk,
                          draws=1000)  # fmt: skip
        new += t.tie
        old += np.mean(np.abs(dz) <= 2 * sz) >= 0.95 and np.mean(np.abs(dk) <= 2 * sk) >= 0.95
    # 95 % level; 3 binomial sd at n = 200 is ±4.6 points (and ±2 points from the critical
    # value's 1000 draws)
    assert 0.90 <= new / n <= 0.995
    # the rule before: within the pointwise 95 % band at >= 95 % of the stations, i.e. at its
    # expected share, so it fails a same ski far more often than 5 %
    assert old / n < 0.85


def test_the_verdict_does_not_depend_on_which_ski_comes_first() -> None:
    mz, mk, sz, sk = _posterior(5)
    dz, dk = _null_difference(np.random.default_rng(2), mz, mk, sz, sk)
    a = same_ski_test(x=X, dz=dz, dk=dk, sd_z=sz, sd_k=sk, modes_z=mz, modes_k=mk)
    b = same_ski_test(x=X, dz=-dz, dk=-dk, sd_z=sz, sd_k=sk, modes_z=-mz, modes_k=mk)
    assert a.statistic == b.statistic and np.isclose(a.critical, b.critical, rtol=0.03)


def test_a_ten_percent_stiffer_ski_is_not_a_tie_and_the_verdict_is_reproducible() -> None:
    mz, mk, sz, sk = _posterior(7)
    dz, dk = _null_difference(np.random.default_rng(4), mz, mk, sz, sk)
    stiffer = same_ski_test(x=X, dz=dz, dk=dk + np.log(1.10), sd_z=sz, sd_k=sk, modes_z=mz,
                            modes_k=mk)  # fmt: skip
    assert not stiffer.tie and stiffer.worst[0] == "stiffness"
    # a 50 µm camber bump (Gaussian, 40 mm wide) is seen too: not a line
    bump = 50e-6 * np.exp(-0.5 * (X / 0.04) ** 2)
    bumped = same_ski_test(x=X, dz=dz + bump, dk=dk, sd_z=sz, sd_k=sk, modes_z=mz, modes_k=mk)
    assert not bumped.tie and bumped.worst[0] == "camber" and abs(bumped.worst[1]) < 0.05
    again = same_ski_test(x=X, dz=dz, dk=dk + np.log(1.10), sd_z=sz, sd_k=sk, modes_z=mz,
                          modes_k=mk)  # fmt: skip
    assert again == stiffer  # a fixed seed: the same verdict every time


def test_without_modes_the_bonferroni_bound_is_used_and_is_conservative() -> None:
    mz, mk, sz, sk = _posterior(9)
    rng = np.random.default_rng(6)
    ties = 0
    for _ in range(100):
        dz, dk = _null_difference(rng, mz, mk, sz, sk)
        t = same_ski_test(x=X, dz=dz, dk=dk, sd_z=sz, sd_k=sk, modes_z=None, modes_k=None)
        ties += t.tie
    assert t.method == "bonferroni" and t.draws == 0
    # z_{1 - 0.025/1200} = 4.1: at least the level's ties (here all)
    assert np.isclose(t.critical, 4.09, atol=0.02) and ties >= 95


@pytest.mark.slow
def test_an_identified_ski_is_closer_to_its_truth_than_to_a_ten_percent_stiffer_one() -> None:
    # a held-out ski (seed 1001, fixed after the identification's development), its bench by
    # the independent reference implementation (finite differences at 2 mm, not the fit's
    # forward model), shop plan, 5 µm noise: the identified ski against the truth and against
    # the truth with EI x 1.10. Whether the truth itself ties is the coverage the benchmark
    # measures (benchmarks/bench_pair_ties.py: 6/24 with the Laplace bands, missed); here the
    # test must at least see the stiffer ski, and rank the truth closer.
    from skisnow.bench import random_ski, reference_bench
    from skisnow.identify import identify_ski
    from skisnow.workflows import same_ski

    true = random_ski(1001)
    bench = reference_bench(true, masses=(30, 60, 90, 120), load_positions=(-0.04, -0.12),
                            station_step=0.010, noise=5e-6, seed=1, dx=2e-3)  # fmt: skip
    ident = identify_ski(bench).ski
    stiffer = dataclasses.replace(
        true, stiffness_values=tuple(1.10 * np.asarray(true.stiffness_values))
    )
    same, other = same_ski(true, ident), same_ski(stiffer, ident)
    assert same is not None and other is not None and other.method == "sup-t"
    assert not other.tie and other.statistic > same.statistic
    assert 2.5 < other.critical < 4.5  # sup-t over ~2 x 900 correlated stations (Bonferroni 4.1)
