"""Continuing a network on another ski's bench (benchmarks/network_widen.py --rebench, issue 30
eighth pass): the network moved into the new bench's frame predicts exactly what it predicted
before, shifted by the change of the reference profile (an identity, not a fit)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def _script(monkeypatch):  # type: ignore[no-untyped-def]
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))  # it imports bench_network
    path = ROOT / "benchmarks" / "network_widen.py"
    spec = importlib.util.spec_from_file_location("network_widen", path)
    mod = importlib.util.module_from_spec(spec)  # type: ignore[arg-type]
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    return mod


def test_reframed_network_keeps_its_prediction_up_to_the_reference(  # type: ignore[no-untyped-def]
    monkeypatch, small_network
):
    from conftest import SMALL_MASSES, SMALL_POSITIONS
    from skisnow.bench import run_bench

    mod = _script(monkeypatch)
    other = run_bench(
        "classic-k22", masses=SMALL_MASSES, load_positions=SMALL_POSITIONS, dx=10e-3
    )  # another ski of the same length: the same input scaling, another output frame
    net1 = mod.reframed(small_network, other, dict(small_network.metadata))
    net0 = small_network
    assert net1.scaling != net0.scaling
    assert not np.array_equal(net1.reference.height, net0.reference.height)
    x = np.linspace(-0.9, 0.9, 181)
    shift = net1.reference(x) - net0.reference(x)
    assert np.max(np.abs(shift)) > 1e-5  # the skis differ by more than the test's tolerance
    for m, p in ((25.0, -0.07), (85.0, -0.2)):
        h0 = net0.predict(x, m, p, on_domain_error="ignore", clip=False)
        h1 = net1.predict(x, m, p, on_domain_error="ignore", clip=False)
        np.testing.assert_allclose(h1 - h0, shift, atol=1e-12)


def test_rebench_refuses_another_input_scaling(monkeypatch, small_network) -> None:  # type: ignore[no-untyped-def]
    from conftest import SMALL_MASSES
    from skisnow.bench import run_bench

    mod = _script(monkeypatch)
    other = run_bench("classic", masses=SMALL_MASSES, load_positions=(-0.04, -0.12), dx=10e-3)
    with pytest.raises(SystemExit, match="not scaled as"):
        mod.reframed(small_network, other, dict(small_network.metadata))
