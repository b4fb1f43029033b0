"""Half-space influence coefficients vs quadrature; the FFT convolution vs a direct sum."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate, signal, special

from skisnow import InputError
from skisnow.contact import (
    Convolution,
    line_convolution,
    line_kernel,
    strip_convolution,
    strip_kernel,
    surface_convolution,
    surface_kernel,
)

E = 2.0e9  # equivalent modulus E' [Pa]
PREF = 2.0 / (np.pi * E)


@pytest.mark.parametrize(("i", "j"), [(1, 1), (1, 0), (2, 1), (0, 3)])
def test_surface_kernel_matches_quadrature(i: int, j: int) -> None:
    # Love's closed form vs adaptive quadrature of the Boussinesq integral; the quadrature is
    # accurate to ~1e-10 (rel) away from the singular self cell (tested exactly below).
    dx, dy = 1.0e-3, 2.0e-3
    k = surface_kernel((3, 4), dx, dy, modulus=E)
    x, y = i * dx, j * dy
    val = integrate.dblquad(
        lambda eta, xi: 1.0 / np.hypot(x - xi, y - eta),
        -dx / 2,
        dx / 2,
        -dy / 2,
        dy / 2,
        epsabs=0,
        epsrel=1e-11,
    )[0]
    assert k[2 + i, 3 + j] == pytest.approx(PREF * val, rel=1e-8)


def test_surface_kernel_self_and_far_field() -> None:
    # Square cell of side s: ∬ dA / r at its centre = 4 s ln(1 + √2) (exact).
    s = 1.0e-3
    k = surface_kernel((40, 40), s, s, modulus=E)
    assert k[39, 39] == pytest.approx(PREF * 4 * s * np.log1p(np.sqrt(2)), rel=1e-14)
    # Far field: a cell acts like a point load s²/r; the correction is O((s/r)²) ≈ 1e-4 at 39 cells.
    r = 39 * s
    assert k[78, 39] == pytest.approx(PREF * s * s / r, rel=2e-4)
    assert np.allclose(k, k[::-1, ::-1], rtol=1e-13)


@pytest.mark.parametrize("offset", [0, 1, 7])
def test_strip_kernel_is_width_average_of_surface(offset: int) -> None:
    # The strip coefficient = width average of the displacement of a full-width cell; check it
    # by Gauss–Legendre over y of Love's closed form evaluated at (x, y) (smooth except at the
    # cell edges, which a 400-point rule resolves to ~1e-7 relative).
    dx, w = 2.0e-3, 0.044
    ks = strip_kernel(10, dx, w, modulus=E)
    y, wts = special.roots_legendre(400)
    y = y * w / 2
    x = offset * dx
    from skisnow.contact._kernels import _love_primitive as F

    a, b = dx / 2, w / 2
    u = F(x + a, y + b) - F(x - a, y + b) - F(x + a, y - b) + F(x - a, y - b)
    mean = np.sum(u * wts) / 2
    assert ks[9 + offset] == pytest.approx(PREF * mean, rel=2e-6)


def test_line_kernel_matches_quadrature() -> None:
    dx, ref = 1.0e-3, 0.5
    k = line_kernel(5, dx, modulus=E, reference_length=ref)
    for off in (0, 1, 4):
        x = off * dx
        val = integrate.quad(
            lambda xi, x=x: np.log(abs(x - xi) / ref),
            -dx / 2,
            dx / 2,
            points=[x] if off == 0 else None,
        )[0]
        assert k[4 + off] == pytest.approx(-4 / (np.pi * E) * val, rel=1e-10)


@pytest.mark.parametrize("shape", [(17,), (64,), (13, 9), (32, 20)])
def test_convolution_equals_direct_aperiodic_sum(shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(1)
    if len(shape) == 1:
        kern = strip_kernel(shape[0], 1e-3, 0.044, modulus=E)
        conv = strip_convolution(shape[0], 1e-3, 0.044, modulus=E, workers=2)
    else:
        kern = surface_kernel(shape, 1e-3, 2e-3, modulus=E)
        conv = surface_convolution(shape, 1e-3, 2e-3, modulus=E, workers=2)
    p = rng.random(shape)
    full = signal.convolve(p, kern, mode="full", method="direct")
    direct = full[tuple(slice(n - 1, 2 * n - 1) for n in shape)]
    # FFT round-off: ~1e-15 of the largest displacement
    assert np.max(np.abs(conv(p) - direct)) <= 1e-13 * np.max(np.abs(direct))
    # batches along a leading axis
    batch = conv(np.stack([p, 2 * p]))
    assert np.allclose(batch[1], 2 * batch[0], rtol=1e-13, atol=0)
    assert conv.self_influence == pytest.approx(kern[tuple(n - 1 for n in shape)], rel=1e-12)


def test_line_convolution_and_errors() -> None:
    conv = line_convolution(8, 1e-3, modulus=E)
    assert conv(np.ones(8)).shape == (8,)
    with pytest.raises(InputError, match="shape"):
        conv(np.ones(9))
    with pytest.raises(InputError, match="modulus"):
        surface_kernel((4, 4), 1e-3, 1e-3, modulus=-1.0)
    with pytest.raises(InputError, match="kernel has shape"):
        Convolution.from_kernel(np.ones(5), (4,))


@pytest.mark.parametrize("shape", [(40,), (12, 7)])
def test_direct_columns_equal_the_fft(shape: tuple[int, ...]) -> None:
    if len(shape) == 1:
        conv = strip_convolution(shape[0], 1e-3, 0.044, modulus=E)
    else:
        conv = surface_convolution(shape, 1e-3, 2e-3, modulus=E)
    rng = np.random.default_rng(3)
    cells = rng.choice(int(np.prod(shape)), size=5, replace=False)
    values = rng.random(5)
    p = np.zeros(int(np.prod(shape)))
    p[cells] = values
    out = np.zeros(shape)
    conv.add_columns(out, cells, values)
    assert np.allclose(out, conv(p.reshape(shape)), rtol=0, atol=1e-14 * np.abs(out).max())


def test_one_default_worker_count_for_ffts_and_sweeps() -> None:
    # one definition of "the cores this process may use": the FFT threads of the contact
    # operators and the processes of a sweep's local cluster
    import os

    from skisnow._parallel import default_workers
    from skisnow.sweep import default_workers as sweep_workers

    assert sweep_workers is default_workers
    conv = strip_convolution(16, 1e-3, 0.044, modulus=1e8)
    assert conv.workers == default_workers() >= 1
    if hasattr(os, "sched_getaffinity"):
        assert default_workers() == len(os.sched_getaffinity(0))
