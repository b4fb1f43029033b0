"""Widening a trained network (zero-output growth, Net2Net) and continuing its training.

Invariance: the widened network predicts exactly what the trained one predicts. Continuation:
the Levenberg–Marquardt phase keeps its best held-out parameters, starting ones included, so a
continued network never ends worse on its held-out conditions than it started.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import InputError


def test_widening_preserves_every_prediction(small_network, small_bench_x):
    from skisnow.network import widen_network

    wide = widen_network(small_network, "6,12,10,9,8,7", seed=1)
    assert wide.architecture.widths == (6, 12, 10, 9, 8, 7)
    assert wide.metadata["widened_from"] == [4, 8, 8, 8, 6, 6]
    masses = np.array([10.0, 55.0, 130.0])
    np.testing.assert_allclose(
        wide.predict(small_bench_x, masses, -0.1, clip=False),
        small_network.predict(small_bench_x, masses, -0.1, clip=False),
        rtol=0,
        atol=1e-15,
    )
    # the new neurons are live: their incoming weights are not zero
    w = np.asarray(wide.members[0].collapse[1].weight)
    assert np.abs(w[8:, :]).max() > 0
    with pytest.raises(InputError, match="widths"):
        widen_network(small_network, "3,8,8,8,6,6")


def test_continued_training_starts_from_the_initial_network(small_network, small_bench):
    from skisnow.network import train_network, widen_network

    kw = {"lm_points": 800, "report_every": 50, "seed": 3}
    wide = widen_network(small_network, "5,10,10,10,7,7", seed=2)
    cont = train_network(small_bench, initial=wide, adam_steps=0, lm_steps=5, **kw)
    assert cont.architecture == wide.architecture
    assert cont.metadata["options"]["initial"] is True
    before = small_network.metadata["validation_errors"]["mean_um"]
    after = cont.metadata["validation_errors"]["mean_um"]
    assert after <= before * (1 + 1e-9)
    # another seed splits the bench differently: refused, not silently retrained
    with pytest.raises(InputError, match="initial network"):
        train_network(small_bench, initial=wide, adam_steps=0, lm_steps=1, seed=4)
