"""Breitschädel's 50 µm criterion: one definition, measured from the plane the ski rests on.

What changed and why: skisnow measured the 50 µm from the profile's global minimum
(``contact_zones``: h − min h < 50 µm) or from h = 0 (the bench metrics: h ≤ 50 µm). A bench
reads the gap to the stone the ski rests on — the line through the lowest points of its two glide
zones — so a profile that is slightly tilted (a measured profile, a network prediction, a
profile levelled differently) lost the contact of its higher glide zone. Now one function
(:func:`skisnow.ski.breitschaedel_contact`) measures from that line, in the zones, the bench
metrics and the CLI, and is invariant to a rigid tilt of the profile.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.ski import (
    BREITSCHAEDEL_THRESHOLD,
    breitschaedel_contact,
    contact_lengths,
    height_above_support,
    support_line,
)

X = np.linspace(-0.9, 0.9, 3601)  # 0.5 mm stations
DX = X[1] - X[0]


def two_zone_profile(x: np.ndarray) -> np.ndarray:
    """A ski on the stone: flat glide zones (h = 0) on [-0.7, -0.45] and [0.25, 0.5], a parabolic
    camber arch of 0.6 mm between them and parabolic rises toward tail and tip."""
    h = np.zeros_like(x)
    arch = (x > -0.45) & (x < 0.25)
    h[arch] = 0.6e-3 * (1 - ((x[arch] + 0.1) / 0.35) ** 2)
    h[x < -0.7] = 0.05 * (x[x < -0.7] + 0.7) ** 2
    h[x > 0.5] = 0.05 * (x[x > 0.5] - 0.5) ** 2
    return h


def analytic_lengths() -> dict[str, float]:
    """Lengths where h < 50 µm of :func:`two_zone_profile`, from its formulas."""
    ends = np.sqrt(BREITSCHAEDEL_THRESHOLD / 0.05)  # rises: 0.05 s² = 50 µm
    # arch: 0.6 mm (1 − u²) = 50 µm at u = ±sqrt(1 − 1/12), u = (x + 0.1)/0.35
    arch = 0.35 * (1 - np.sqrt(1 - BREITSCHAEDEL_THRESHOLD / 0.6e-3))
    rear = ends + 0.25 + arch
    front = arch + 0.25 + ends
    return {"rear": rear, "front": front, "total": rear + front}


def test_untilted_profile_gives_the_analytic_lengths() -> None:
    want = analytic_lengths()
    got = contact_lengths(X, two_zone_profile(X))
    for zone in ("rear", "front", "total"):
        assert got[zone] == pytest.approx(want[zone], abs=2 * DX)  # one station per patch end


@pytest.mark.parametrize(("offset", "slope"), [(0.0, 2e-4), (3e-4, -1.5e-4), (-1e-3, 5e-5)])
def test_invariant_to_a_rigid_tilt_where_the_old_definition_is_not(offset, slope) -> None:
    h = two_zone_profile(X)
    tilted = h + offset + slope * X  # the same ski, levelled differently
    new = breitschaedel_contact(X, tilted)
    np.testing.assert_array_equal(new, breitschaedel_contact(X, h))
    np.testing.assert_allclose(height_above_support(X, tilted), h, atol=1e-15)
    a, b = support_line(X, tilted)
    assert a == pytest.approx(offset, abs=1e-15) and b == pytest.approx(slope, rel=1e-9)
    lengths = contact_lengths(X, tilted)
    for zone, want in analytic_lengths().items():
        assert lengths[zone] == pytest.approx(want, abs=2 * DX)
    # the old definition (h − min h < 50 µm) loses most of the higher glide zone: a tilt of
    # 0.05 mm/m across the ~0.75 m between the glide zones already exceeds 35 µm
    old = tilted - tilted.min() < BREITSCHAEDEL_THRESHOLD
    lost = (new & ~old).sum() * DX
    assert lost > 0.1, f"old and new differ by only {lost * 1e3:.1f} mm"


def test_a_kick_zone_below_the_glide_plane_touches() -> None:
    # a classic ski collapsed under load: the kick zone reaches 20 µm below the line through the
    # lowest points of the glide zones (behind and ahead of it): it is in contact, the gap there
    # is negative, and the glide zones still define the plane
    h = two_zone_profile(X)
    k0, k1 = -0.2, 0.0
    kick = (k0, k1)
    x = X
    inside = (x > k0) & (x < k1)
    h[inside] = -20e-6
    gap = height_above_support(X, h, kick_zone=kick)
    assert support_line(X, h, kick_zone=kick) == (0.0, 0.0)
    assert np.all(gap[inside] == -20e-6)
    lengths = contact_lengths(X, h, kick_zone=kick)
    assert lengths["middle"] == pytest.approx(0.2, abs=2 * DX)


def test_zones_use_the_same_definition() -> None:
    # contact_zones' Breitschädel estimate is this mask, also for a tilted profile fed to the
    # solver (the rigid rotation of eq. 3 absorbs the tilt of the contact; now the estimate too)
    from skisnow.contact import contact_zones, solve_contact

    x = np.linspace(-0.9, 0.9, 1024)
    h = two_zone_profile(x) + 1e-4 * x
    sol = solve_contact(x, h, load=300.0, load_position=-0.1, modulus=200e6, width=0.044)
    zones = contact_zones(sol)
    mask = breitschaedel_contact(x, h)
    assert zones.breitschaedel["total"].length == pytest.approx(mask.sum() * (x[1] - x[0]))
    assert zones.breitschaedel["rear"].patches == 1 and zones.breitschaedel["front"].patches == 1
