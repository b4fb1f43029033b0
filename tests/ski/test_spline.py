"""Spline skis (skisnow.ski._spline): the knots argument of ``spline_ski``.

The shipped skis of version 2 are spline skis on SPLINE_KNOTS; ``benchmarks/calibrate_skis.py
--knots dense`` fits on other (denser) knots through the same builder.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.ski import SPLINE_ENDS, SPLINE_KNOTS, spline_ski


def _values(kind: str, ek, zk) -> tuple[np.ndarray, np.ndarray]:
    """A smooth, ski-like EI [N m²] (stiff middle, soft ends) and z0 [m] (a cambered arch)."""
    x_tail, x_tip = SPLINE_ENDS[kind]
    half = 0.5 * (x_tip - x_tail)
    ei = 200.0 + 1500.0 * np.exp(-((np.asarray(ek) / (0.6 * half)) ** 2))
    z = 4e-3 * np.cos(0.5 * np.pi * np.asarray(zk) / half) ** 2
    return ei, z


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_default_knots_given_explicitly_build_the_same_ski(kind: str) -> None:
    ek, zk, _ = SPLINE_KNOTS[kind]
    ei, z = _values(kind, ek, zk)
    a = spline_ski(kind, ei, z, kick_zone=None)
    b = spline_ski(kind, ei, z, kick_zone=None, knots=(ek, zk))
    np.testing.assert_array_equal(a.stiffness_x, b.stiffness_x)
    np.testing.assert_array_equal(a.stiffness_values, b.stiffness_values)
    np.testing.assert_array_equal(a.camber_x, b.camber_x)
    np.testing.assert_array_equal(a.camber_values, b.camber_values)


@pytest.mark.parametrize("kind", ["classic", "skate"])
def test_other_knots_carry_their_values(kind: str) -> None:
    """On other knots the ski passes through the given EI and, up to the shovel and tail
    rises and the resting line, the given z0 at every knot (PCHIP interpolates)."""
    ek0, zk0, _ = SPLINE_KNOTS[kind]
    ek = np.sort(np.concatenate([ek0, 0.5 * (np.array(ek0[1:]) + ek0[:-1])]))
    zk = np.round(np.sort(np.concatenate([zk0, 0.5 * (np.array(zk0[1:]) + zk0[:-1])])), 3)
    zk = np.unique(np.round(zk / 0.005) * 0.005)  # on the 5 mm stations of the surface
    ei, z = _values(kind, ek, zk)
    ski = spline_ski(kind, ei, z, kick_zone=None, knots=(tuple(ek), tuple(zk)))
    np.testing.assert_allclose(ski.stiffness(ek), ei, rtol=1e-9)
    x_tail, x_tip = SPLINE_ENDS[kind]
    rise = 30e-3 * np.clip((zk - (x_tip - 0.20)) / 0.20, 0.0, 1.0) ** 2.5
    rise += 4e-3 * np.clip(((x_tail + 0.05) - zk) / 0.05, 0.0, 1.0) ** 2
    cx, cz = np.asarray(ski.camber_x), np.asarray(ski.camber_values)
    idx = np.searchsorted(cx, zk - 1e-9)
    np.testing.assert_allclose(cx[idx], zk, atol=1e-9)
    line = cz[idx] - rise - z  # the resting on the plane: a line
    slope = (line[-1] - line[0]) / (zk[-1] - zk[0])
    np.testing.assert_allclose(line, line[0] + slope * (zk - zk[0]), atol=1e-12)
