"""Bearing model (eq. 5–9): analytic cases, balance at every position, pruned vs naive search."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow._errors import InputError
from skisnow.micro import (
    bearing_area,
    bearing_area_reference,
    bearing_sweep,
    grind_preset,
    lowpass,
    make_topography,
)

H = 15.9e6
P = 20e3


def test_flat_base_gives_p_over_h_exactly() -> None:
    t = make_topography(np.full((120, 100), 3e-6), dx=2e-6, dy=2.5e-6)
    for d in (100e-6, 150e-6):
        m = bearing_area(t, diameter=d, pressure=P, hardness=H)
        # the discretisation keeps A0 = N*·dx·dy exactly and every slope factor is 1
        np.testing.assert_allclose(m.fractional_area, P / H, rtol=1e-13)
        assert m.positions.shape[0] > 0


def test_tilted_plane_gives_its_slope_factor() -> None:
    s = 0.2
    x = np.arange(120) * 1e-6
    t = make_topography(s * x[:, None] * np.ones((1, 90)), dx=1e-6)
    m = bearing_area(t, diameter=60e-6, pressure=P, hardness=H)
    # np.gradient is exact on a plane: every pixel has the slope factor √(1 + s²)
    np.testing.assert_allclose(m.fractional_area, P / H * np.sqrt(1 + s * s), rtol=1e-12)


def test_sinusoidal_groove_slope_factor_of_the_contact_patch() -> None:
    """A grain on the crest of a sinusoidal groove h = A cos kx: A_fr/(p/H) is the mean slope
    factor over the patch {h − s ≥ A − δ}, computed here independently by quadrature on a
    10× finer grid with δ found by bisection."""
    a, lam, radius, dx, n = 5e-6, 60e-6, 100e-6, 1e-6, 260
    k = 2 * np.pi / lam
    x = np.arange(n) * dx
    t = make_topography(a * np.cos(k * (x - x[n // 2]))[:, None] * np.ones((1, n)), dx=dx)
    p = 0.02 * H  # a patch of ~800 pixels, large enough to resolve its slope factor
    m = bearing_area(t, diameter=2 * radius, pressure=p, hardness=H)
    crest = m.positions[:, 0] == n // 2
    ratio = m.fractional_area[crest] / (p / H)

    d = 0.1e-6
    xs = np.arange(-40e-6, 40e-6, d) + d / 2
    xx, yy = np.meshgrid(xs, xs, indexing="ij")
    f = a * np.cos(k * xx) - (radius - np.sqrt(radius**2 - xx**2 - yy**2))
    w = np.sqrt(1 + (a * k * np.sin(k * xx)) ** 2)
    target = p * (2 * radius) ** 2 / H
    lo, hi = 0.0, a
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if (f >= a - mid).sum() * d * d < target else (lo, mid)
    patch = f >= a - hi
    expected = w[patch].mean()
    assert expected - 1 > 0.03  # the effect tested is a 3 % excess of the real area
    # 1 µm pixels vs the 0.1 µm quadrature: measured 3e-4; allow 1e-3 (3 % of the effect)
    np.testing.assert_allclose(ratio, expected, rtol=1e-3)
    np.testing.assert_allclose(m.penetration[crest], hi, rtol=1e-2)


@pytest.mark.parametrize("shape", ["sphere", "paraboloid"])
@pytest.mark.parametrize("stride", [1, 3])
def test_pruned_search_equals_naive_search(shape: str, stride: int) -> None:
    t = lowpass(grind_preset("S4", size=240e-6, dx=2e-6, seed=2), cutoff=33e-6)
    kw = {"diameter": 150e-6, "pressure": P, "hardness": H, "shape": shape, "stride": stride}
    fast = bearing_area(t, **kw, block=(3, 5))
    ref = bearing_area_reference(t, **kw)
    np.testing.assert_array_equal(fast.positions, ref.positions)
    # the same pixels are selected: identical sums up to summation order
    np.testing.assert_allclose(fast.fractional_area, ref.fractional_area, rtol=1e-12)
    np.testing.assert_allclose(fast.penetration, ref.penetration, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(fast.first_contact, ref.first_contact, rtol=0, atol=1e-18)


def test_balance_at_every_position() -> None:
    """A0(δ)·H = p(2R)² at every raster position, A0 counted from the gap field itself."""
    t = lowpass(grind_preset("S5", size=200e-6, dx=2e-6, seed=5), cutoff=33e-6)
    d = 120e-6
    m = bearing_area(t, diameter=d, pressure=P, hardness=H)
    np.testing.assert_allclose(m.projected_area * H, P * d * d, rtol=1e-13)
    h = np.asarray(t.heights)
    r = d / 2
    ii, jj = np.meshgrid(np.arange(h.shape[0]), np.arange(h.shape[1]), indexing="ij")
    nstar = m.target_pixels
    for k in range(0, len(m.positions), 97):
        i, j = m.positions[k]
        r2 = ((ii - i) * t.dx) ** 2 + ((jj - j) * t.dy) ** 2
        inside = r2 <= r * r
        f = h[inside] - (r - np.sqrt(r * r - r2[inside]))
        z0 = f.max()
        assert z0 == pytest.approx(m.first_contact[k], abs=1e-18)  # first contact: max of F
        level = z0 - m.penetration[k]
        # strictly-in-contact pixels < N* <= pixels in contact at the boundary level
        assert (f > level + 1e-18).sum() <= nstar <= (f >= level - 1e-18).sum() + 1


def test_sweep_and_positions_inside_the_map() -> None:
    t = make_topography(np.zeros((100, 80)), dx=2e-6)
    s = bearing_sweep(t, diameters=[60e-6, 100e-6], pressure=P, hardness=H, workers=2)
    # centres whose disc of radius R fits: (100 − 2·ceil(R/dx)) × (80 − 2·ceil(R/dx))
    assert s.n_positions.tolist() == [(100 - 30) * (80 - 30), (100 - 50) * (80 - 50)]
    np.testing.assert_allclose(s.fractional_area, P / H, rtol=1e-13)
    with pytest.raises(InputError, match="too small"):
        bearing_area(t, diameter=200e-6, pressure=P, hardness=H)
    with pytest.raises(InputError, match="hardness"):
        bearing_area(t, diameter=50e-6, pressure=P, hardness=P / 2)


@pytest.mark.parametrize("shape", ["sphere", "paraboloid"])
def test_exact_ties_are_broken_like_the_reference(shape: str) -> None:
    """A terraced base (heights on 4 levels) makes F = h − s(r) tie exactly between pixels at
    the same distance on the same terrace, while their slope factors differ near the steps:
    the contact sum then depends on which tied pixels are taken. The fast search must take
    them in raster order, as the reference's stable sort does."""
    rng = np.random.default_rng(7)
    levels = rng.integers(0, 4, size=(12, 12)).astype(float) * 0.5e-6
    h = np.kron(levels, np.ones((7, 7)))  # 84 × 84 px terraces of 7 × 7 px
    t = make_topography(h, dx=2e-6)
    kw = {"diameter": 100e-6, "pressure": P, "hardness": H, "shape": shape}
    fast = bearing_area(t, **kw)
    ref = bearing_area_reference(t, **kw)
    np.testing.assert_array_equal(fast.positions, ref.positions)
    # same pixels, summed in another order: 1e-12
    np.testing.assert_allclose(fast.fractional_area, ref.fractional_area, rtol=1e-12)
    np.testing.assert_allclose(fast.penetration, ref.penetration, rtol=1e-9, atol=1e-15)
    np.testing.assert_array_equal(fast.first_contact, ref.first_contact)


def test_tiling_does_not_change_the_answer() -> None:
    """Tile and super-tile sizes are performance knobs only: every choice selects the same
    pixels (bit-identical first contact, sums equal to rounding)."""
    t = lowpass(grind_preset("S2", size=200e-6, dx=2e-6, seed=3), cutoff=33e-6)
    kw = {"diameter": 110e-6, "pressure": P, "hardness": H}
    base = bearing_area(t, **kw, block=1, superblock=1)
    for block, superblock in [((4, 4), (4, 4)), ((3, 5), (2, 3)), (7, 1)]:
        m = bearing_area(t, **kw, block=block, superblock=superblock)
        np.testing.assert_array_equal(m.first_contact, base.first_contact)
        np.testing.assert_allclose(m.fractional_area, base.fractional_area, rtol=1e-12)


def test_branch_free_selection_is_the_kth_largest_and_leaves_its_input() -> None:
    from skisnow.micro._bearing_select import _kth_largest

    rng = np.random.default_rng(7)
    for m in (1, 2, 3, 8, 61, 500):
        # continuous values, heavy ties (4 distinct values) and all equal
        for vals in (rng.normal(size=m), rng.integers(0, 4, size=m) * 0.5, np.full(m, 1.25)):
            ordered = np.sort(vals)[::-1]
            for k in sorted({1, 2, m // 2 + 1, m - 1, m} & set(range(1, m + 1))):
                buf = np.full(3 * m, np.nan)
                buf[:m] = vals
                assert _kth_largest(buf, m, k, m, 2 * m) == ordered[k - 1]
                np.testing.assert_array_equal(buf[:m], vals)
