"""Breitschädel's 50 µm contact criterion, one definition for skisnow (Breitschädel 2012).

A practitioner reads contact off a camber bench where the gap between the loaded ski and the flat
stone it rests on is below 50 µm (Breitschädel, Procedia Eng. 34 (2012) 391–396; used as the
"Breitschädel estimate" beside the elastic contact by Kalliorinne et al. 2023, Figures 8–9). The
gap is measured from **the plane the ski rests on**: the line through the lowest points of the two
glide zones — the lower common tangent of the rear and the front glide zone, i.e. the edge of the
profile's lower convex hull that bridges the camber pocket. The glide zones are the parts of the
running surface behind and ahead of the kick zone (classic skis) or of the balance point x = 0
(skate skis, and profiles without a kick zone).

Measured from that line, the criterion is invariant to a rigid tilt of the profile (adding
a + b·x to h moves the line with it), as a bench reading is to how the profile was levelled;
measured from the global minimum of h, as skisnow did before, a slightly tilted profile loses the
contact of its higher glide zone.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError

__all__ = [
    "BREITSCHAEDEL_THRESHOLD",
    "breitschaedel_contact",
    "height_above_support",
    "support_line",
]

#: Breitschädel (2012): the ski touches the snow where its gap to the stone is below 50 µm [m].
BREITSCHAEDEL_THRESHOLD: float = 50e-6


def _glide_sides(x: NDArray[np.float64], kick_zone: tuple[float, float] | None) -> tuple[int, int]:
    """Stations ``[:rear_end]`` behind and ``[front_start:]`` ahead of the kick zone (or of the
    balance point) on increasing ``x``; the whole profile on both sides if one is empty."""
    if kick_zone is None:
        k0 = k1 = 0.0
    else:
        k0, k1 = float(kick_zone[0]), float(kick_zone[1])
        if not (np.isfinite(k0) and np.isfinite(k1) and k0 < k1):
            raise InputError(f"kick_zone must be (start, end) with start < end, got {kick_zone}")
    rear_end = int(np.searchsorted(x, k0, side="left"))
    front_start = int(np.searchsorted(x, k1, side="right"))
    if rear_end == 0 or front_start == x.size:
        # the profile lies on one side only: it rests on the lowest point of its own hull
        return x.size, 0
    return rear_end, front_start


def support_line(
    x: ArrayLike, height: ArrayLike, *, kick_zone: tuple[float, float] | None = None
) -> tuple[float, float]:
    """The plane the ski rests on, as the line h = a + b·x [m, –] (Breitschädel 2012).

    The lower common tangent of the rear and the front glide zone (module docstring): the line
    through one point of each with no point of either below it, found by walking the two
    contact points down the profile (each step replaces the point lying furthest below the
    current line; a few steps, each O(n)).

    Parameters
    ----------
    x
        Stations [m] from the balance point, increasing.
    height
        Loaded camber height h [m] at the stations.
    kick_zone
        ``(start, end)`` [m] of a classic ski's kick zone; the glide zones lie behind and ahead
        of it. ``None``: behind and ahead of the balance point x = 0.
    """
    xa = np.asarray(x, dtype=float)
    ha = np.asarray(height, dtype=float)
    if xa.ndim != 1 or ha.shape != xa.shape or xa.size < 2:
        raise InputError(f"x and height must be 1-D of the same length >= 2, got {xa.shape}, "
                         f"{ha.shape}")  # fmt: skip
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ha))):
        raise InputError("x and height must be finite")
    if np.any(np.diff(xa) <= 0):
        raise InputError("x must be strictly increasing")
    rear_end, front_start = _glide_sides(xa, kick_zone)
    rear, front = slice(0, rear_end), slice(front_start, None)  # views: no copies per step
    i = int(np.argmin(ha[rear]))
    j = front_start + int(np.argmin(ha[front]))
    if i == j or xa[i] == xa[j]:
        return float(ha[i]), 0.0
    tol = 1e-12 * max(float(ha.max() - ha.min()), 1e-9)
    for _ in range(xa.size):
        slope = (ha[j] - ha[i]) / (xa[j] - xa[i])
        r = ha - slope * xa  # the residual to the line, up to the constant ha[i] - slope·xa[i]
        c = ha[i] - slope * xa[i]
        i2 = int(np.argmin(r[rear]))
        j2 = front_start + int(np.argmin(r[front]))
        if min(r[i2], r[j2]) - c >= -tol:
            break
        if r[i2] <= r[j2]:
            i = i2
        else:
            j = j2
        if xa[i] >= xa[j]:  # a single glide side: the tangent at its lowest point
            k = int(np.argmin(ha))
            return float(ha[k]), 0.0
    slope = float((ha[j] - ha[i]) / (xa[j] - xa[i]))
    return float(ha[i] - slope * xa[i]), slope


def height_above_support(
    x: ArrayLike, height: ArrayLike, *, kick_zone: tuple[float, float] | None = None
) -> NDArray[np.float64]:
    """Gap h − (a + b·x) [m] between the profile and the plane it rests on
    (:func:`support_line`): ≥ 0 on the glide zones, 0 at the two support points; negative only
    where a classic ski's kick zone reaches below the glide zones' plane."""
    xa = np.asarray(x, dtype=float)
    a, b = support_line(xa, height, kick_zone=kick_zone)
    return np.asarray(height, dtype=float) - (a + b * xa)


def breitschaedel_contact(
    x: ArrayLike,
    height: ArrayLike,
    *,
    kick_zone: tuple[float, float] | None = None,
    threshold: float = BREITSCHAEDEL_THRESHOLD,
) -> NDArray[np.bool_]:
    """Breitschädel's (2012) contact mask: the gap to the plane the ski rests on is below
    ``threshold`` [m] (default 50 µm) — the one definition the zones
    (:func:`skisnow.contact.contact_zones`), the bench metrics (:func:`contact_lengths`) and the
    CLI use."""
    if not (np.isfinite(threshold) and threshold > 0):
        raise InputError(f"threshold must be positive, got {threshold!r}")
    return height_above_support(x, height, kick_zone=kick_zone) < threshold
