"""Property tests of the micro contact: roughness invariances and bearing-model invariants."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from skisnow.micro import (
    areal_parameters,
    bearing_area,
    make_topography,
    remove_form,
)

H = 15.9e6


@st.composite
def surfaces(draw, n: int = 48):
    """A random smooth surface: a few cosine modes of random amplitude, direction and phase."""
    k = draw(st.integers(1, 4))
    x = np.arange(n)[:, None] * 1e-6
    y = np.arange(n)[None, :] * 1e-6
    h = np.zeros((n, n))
    for _ in range(k):
        a = draw(st.floats(0.1e-6, 3e-6))
        lam = draw(st.floats(10e-6, 60e-6))
        ang = draw(st.floats(0, np.pi))
        ph = draw(st.floats(0, 2 * np.pi))
        h = h + a * np.cos(2 * np.pi * (x * np.cos(ang) + y * np.sin(ang)) / lam + ph)
    return h


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(h=surfaces(), c=st.floats(0.1, 10.0), tilt=st.floats(-0.3, 0.3))
def test_roughness_scaling_and_form_invariance(h: np.ndarray, c: float, tilt: float) -> None:
    t = make_topography(h, dx=1e-6)
    p = areal_parameters(remove_form(t, method="plane"))
    # adding a plane changes nothing after plane removal (to round-off of the lstsq fit)
    x = np.arange(h.shape[0])[:, None] * 1e-6
    tilted = remove_form(make_topography(h + tilt * x + 1e-3, dx=1e-6), method="plane")
    q = areal_parameters(tilted)
    for key in ("Sa", "Sq", "Sdq"):
        assert np.isclose(q[key], p[key], rtol=1e-6, atol=1e-15)
    # heights scaled by c: Sa, Sq, Sdq scale by c, Ssk and Sku do not change
    s = areal_parameters(remove_form(make_topography(c * h, dx=1e-6), method="plane"))
    for key in ("Sa", "Sq", "Sdq"):
        assert np.isclose(s[key], c * p[key], rtol=1e-9)
    for key in ("Ssk", "Sku"):
        assert np.isclose(s[key], p[key], rtol=1e-6, atol=1e-9)
    # mirror h → −h flips the skewness
    m = areal_parameters(remove_form(make_topography(-h, dx=1e-6), method="plane"))
    assert np.isclose(m["Ssk"], -p["Ssk"], rtol=1e-9, atol=1e-12)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(h=surfaces(), offset=st.floats(-1e-4, 1e-4), p=st.floats(5e3, 100e3))
def test_bearing_invariants(h: np.ndarray, offset: float, p: float) -> None:
    t = make_topography(h, dx=1e-6)
    m = bearing_area(t, diameter=30e-6, pressure=p, hardness=H)
    # A_fr >= p/H (slope factor >= 1); the real/projected ratio is bounded by the steepest pixel
    gx, gy = np.gradient(h, 1e-6)
    wmax = np.sqrt(1 + gx**2 + gy**2).max()
    assert np.all(m.fractional_area >= p / H * (1 - 1e-12))
    assert np.all(m.fractional_area <= p / H * wmax * (1 + 1e-12))
    assert np.all(m.penetration >= 0)
    # a constant offset of the base shifts the first contact and changes nothing else
    m2 = bearing_area(make_topography(h + offset, dx=1e-6), diameter=30e-6, pressure=p, hardness=H)
    np.testing.assert_allclose(m2.fractional_area, m.fractional_area, rtol=1e-12)
    np.testing.assert_allclose(m2.first_contact - offset, m.first_contact, atol=1e-15)
    # mirror symmetry: reversing axis 1 mirrors the raster of results
    m3 = bearing_area(make_topography(h[:, ::-1], dx=1e-6), diameter=30e-6, pressure=p, hardness=H)
    a = m.fractional_area.reshape(np.unique(m.positions[:, 0]).size, -1)
    b = m3.fractional_area.reshape(a.shape)
    np.testing.assert_allclose(b[:, ::-1], a, rtol=1e-9)
