"""Fixtures of the network tests: a small virtual bench and a small network trained on it once.

The bench is the real beam model of the shipped classic ski (so the tests train on the physics
the network is for), thinned to keep JIT compile and training within the test budget: 5 masses
× 4 positions, a profile point every 10 mm, and a network of widths 4,8,8,8,6,6 (~420 weights).
"""

from __future__ import annotations

import numpy as np
import pytest

from _extras import HAS_NETWORK, NETWORK_REASON


@pytest.fixture(autouse=True, scope="session")
def _needs_network_extra() -> None:
    """Every test here needs the optional ``network`` extra (session scope: before the
    session-scoped network fixtures); without it they are skipped, saying why."""
    if not HAS_NETWORK:
        pytest.skip(NETWORK_REASON)


SMALL_MASSES = (10.0, 40.0, 70.0, 100.0, 130.0)
SMALL_POSITIONS = (-0.04, -0.10, -0.16, -0.24)
SMALL_WIDTHS = "4,8,8,8,6,6"
SMALL_TRAINING = {"adam_steps": 300, "lm_steps": 40, "lm_points": 800, "report_every": 50}


@pytest.fixture(scope="session")
def small_bench():
    from skisnow.bench import run_bench

    return run_bench("classic", masses=SMALL_MASSES, load_positions=SMALL_POSITIONS, dx=10e-3)


@pytest.fixture(scope="session")
def small_network(small_bench):
    from skisnow.network import train_network

    return train_network(small_bench, seed=3, architecture=SMALL_WIDTHS, **SMALL_TRAINING)


@pytest.fixture(scope="session")
def small_bench_x(small_bench) -> np.ndarray:
    return np.unique(small_bench.table["x_mm"].to_numpy()) * 1e-3


@pytest.fixture(scope="session")
def small_training_kwargs() -> dict:
    """Keyword arguments of the small test training (widths and steps)."""
    return {"architecture": SMALL_WIDTHS, **SMALL_TRAINING}


@pytest.fixture(scope="session")
def toy_network():
    """An untrained network (random weights) with a made-up scaling and the paper's domain."""
    return make_toy_network(1)


def make_toy_network(n_members: int = 1):
    import jax

    from skisnow.network import (
        Architecture,
        BlockNetwork,
        CamberNetwork,
        Domain,
        ReferenceProfile,
        Scaling,
    )
    from skisnow.network._network import x64

    arch = Architecture.from_widths("3,5,4,6,4,3")
    scaling = Scaling(
        x_center=0.02,
        x_scale=1.0,
        mass_center=67.5,
        mass_scale=62.5,
        position_center=-0.14,
        position_scale=0.1,
        height_center=0.015,
        height_scale=0.015,
    )
    domain = Domain(
        mass_min=5.0,
        mass_max=130.0,
        position_min=-0.24,
        position_max=-0.04,
        x_min=-0.98,
        x_max=1.02,
    )
    with x64():
        members = tuple(BlockNetwork(arch, key=jax.random.PRNGKey(k)) for k in range(n_members))
    reference = ReferenceProfile(x_min=-0.98, x_max=1.02, height=np.linspace(0.01, 0.02, 11))
    return CamberNetwork(
        architecture=arch,
        scaling=scaling,
        domain=domain,
        members=members,
        reference=reference,
        metadata={"ski": "toy"},
    )
