"""The compiled Polonsky–Keer loop (``_pk_kernel.pk_dense``) is the algorithm of
:func:`skisnow.contact.polonsky_keer`: on the same dense operator and start it takes the same
steps (same iteration count, pressures to round-off) under every control."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.contact import polonsky_keer
from skisnow.contact._kernels import strip_kernel
from skisnow.contact._operators import _toeplitz_rows
from skisnow.contact._pk_kernel import DISPLACEMENT, LOAD, MOMENT, SUCCESSFUL, pk_dense
from skisnow.contact._polonsky_keer import restore
from skisnow.contact._starts import rigid_start


class Dense:
    """A dense matrix as a compliance operator (no ``add_columns``: full products only)."""

    def __init__(self, k: np.ndarray) -> None:
        self.k = k
        self.self_influence = float(k[0, 0])

    def __call__(self, v: np.ndarray) -> np.ndarray:
        return self.k @ v


@pytest.mark.parametrize("control", ["moment", "load", "displacement"])
def test_compiled_loop_takes_the_steps_of_polonsky_keer(control: str) -> None:
    n = 300
    x = (np.arange(n) + 0.5) / n - 0.5
    h = 2e-4 * np.cos(9 * x) ** 2 + 4e-4 * x**2  # two pockets: the contact set moves
    k = _toeplitz_rows(strip_kernel(n, 1.0 / n, 0.044, modulus=2e8), n, np.arange(n))
    xi = x - 0.03
    total = 3e5
    if control == "displacement":
        target = np.full(n, 1.5e-4) + 1e-4 * xi
        p0 = np.maximum(target - h, 0.0) / k[0, 0]
        hh = h - target
    else:
        target = None
        p0 = rigid_start(h, xi, total, control == "moment", k[0, 0], 1)
        p0, _ = restore(p0, xi, total, control == "moment")
        hh = h
    kw = dict(control=control, total=None if target is not None else total, arm=xi,
              target=target, tol=1e-12, max_iter=400)  # fmt: skip
    ref = polonsky_keer(Dense(k), h, p0=p0, **kw)
    code = {"moment": MOMENT, "load": LOAD, "displacement": DISPLACEMENT}[control]
    p, u, it, _, hist, status = pk_dense(
        k, np.zeros((0, 0), np.float32), False, hh, xi, p0, code, total, 1e-12, 400, k[0, 0]
    )
    assert ref.converged and status in (SUCCESSFUL, 6)
    assert it == ref.iterations
    np.testing.assert_allclose(p, ref.pressure, rtol=0, atol=1e-10 * ref.pressure.max())
    np.testing.assert_allclose(u, k @ p, rtol=1e-12, atol=0)
    assert hist.size == ref.history.size
