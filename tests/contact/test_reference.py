"""The analytic references checked on their own: equilibrium by quadrature, textbook values."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate

from skisnow import InputError
from skisnow.contact import reference

E = 2.0e9  # E' [Pa]


def test_hertz_sphere_equilibrium_and_textbook_numbers() -> None:
    ref = reference.hertz_sphere(10.0, 0.05, modulus=E)
    # ∫ p 2πr dr = W (quadrature to 1e-10)
    force = integrate.quad(lambda r: ref.pressure(r) * 2 * np.pi * r, 0, ref.contact_radius)[0]
    assert force == pytest.approx(10.0, rel=1e-9)
    # Johnson eq. 4.22 with E* = E'/2 = 1 GPa: a³ = 3WR/(4E*) = 3.75e-10 m³
    assert ref.contact_radius**3 == pytest.approx(3 * 10.0 * 0.05 / (4 * 1.0e9), rel=1e-14)
    assert ref.approach == pytest.approx(ref.contact_radius**2 / 0.05, rel=1e-14)


def test_hertz_line_equilibrium_and_surface_shape() -> None:
    ref = reference.hertz_line(1000.0, 0.05, modulus=E)
    a = ref.half_width
    assert integrate.quad(ref.pressure, -a, a)[0] == pytest.approx(1000.0, rel=1e-9)

    # inside the contact the plane-strain displacement of this pressure is parabolic:
    # u(x) − u(0) = −x²/(2R) · (−1) ... i.e. u(0) − u(x) = x²/(2R) (rigid cylinder pressed flat)
    def u(x: float) -> float:
        f = lambda s: ref.pressure(s) * np.log(abs(x - s))  # noqa: E731
        return -4 / (np.pi * E) * integrate.quad(f, -a, a, points=[x], limit=200)[0]

    for x in (0.3 * a, 0.7 * a):
        assert u(0.0) - u(x) == pytest.approx(x * x / (2 * 0.05), rel=1e-6)


@pytest.mark.parametrize("e_frac", [0.0, 0.2, -0.45])
def test_flat_punch_equilibrium(e_frac: float) -> None:
    a, w = 0.01, 500.0
    ref = reference.flat_punch(w, a, modulus=E, eccentricity=e_frac * a)
    # substitute x = a·sin φ to remove the edge singularities, then Gauss–Kronrod to 1e-12
    phi_lo, phi_hi = -np.pi / 2 * (1 - 1e-12), np.pi / 2 * (1 - 1e-12)
    jac = lambda ph: a * np.cos(ph)  # noqa: E731
    f = integrate.quad(lambda ph: ref.pressure(a * np.sin(ph)) * jac(ph), phi_lo, phi_hi)[0]
    m = integrate.quad(
        lambda ph: a * np.sin(ph) * ref.pressure(a * np.sin(ph)) * jac(ph), phi_lo, phi_hi
    )[0]
    assert f == pytest.approx(w, rel=1e-7)
    assert m == pytest.approx(w * e_frac * a, rel=1e-6, abs=1e-9)
    # the exact cell averages integrate to the same force
    edges = np.linspace(-a, a, 65)
    assert np.sum(ref.cell_average(edges) * np.diff(edges)) == pytest.approx(w, rel=1e-13)
    assert np.all(ref.pressure(np.linspace(-0.999 * a, 0.999 * a, 101)) > 0)


def test_flat_punch_rejects_loss_of_contact() -> None:
    with pytest.raises(InputError, match="a/2"):
        reference.flat_punch(1.0, 0.01, modulus=E, eccentricity=0.006)
