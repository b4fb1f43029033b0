"""Practitioners' camber metrics as pure functions on a profile (x, h) in SI units.

What ski technicians read off a camber bench (SkiSelector) and what Breitschädel (2012,
Procedia Eng. 34, 391-396) tabulated for national-team skis:

* camber height at the balance point h(0) under a load;
* wax-pocket ("kick zone") length: the connected stretch around the balance point where the
  base stands higher than 0.1 mm (the industry's "closed" limit) or 0.2 mm;
* the closing load: the mass at which h(0) drops below 0.1 mm for a given load position;
* the stiffness k = (F_full - F_half) / (h_half - h_full) between half and full body weight
  (Breitschädel's measure, in N/mm in the field; SI N/m here);
* the glide-zone contact lengths with Breitschädel's criterion: contact wherever h < 50 µm
  (Kalliorinne et al. 2023, §1 and §3.2), split into rear / middle (kick zone) / front.

All functions take arrays in SI (m, kg) and return SI. The closing load and the metrics of one
ski from its beam or a bench file (:func:`~skisnow.bench.ski_metrics`) are in
:mod:`skisnow.bench._metrics`; the practitioners' default load case is half or full body
weight 80 mm behind the balance point (:data:`DEFAULT_METRIC_POSITION`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.ski._breitschaedel import BREITSCHAEDEL_THRESHOLD, breitschaedel_contact

__all__ = [
    "BREITSCHAEDEL_THRESHOLD",
    "CLOSED_THRESHOLD",
    "DEFAULT_METRIC_POSITION",
    "camber_height",
    "contact_lengths",
    "contact_patches",
    "ski_stiffness",
    "wax_pocket",
    "wax_pocket_length",
]

#: The industry's "closed" kick zone [m]: camber height below 0.1 mm.
CLOSED_THRESHOLD: float = 0.1e-3
#: Default practitioners' load position [m]: 80 mm behind the balance point.
DEFAULT_METRIC_POSITION: float = -0.080


def _profile(x: ArrayLike, height: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    xa = np.asarray(x, dtype=float)
    ha = np.asarray(height, dtype=float)
    if xa.ndim != 1 or xa.shape != ha.shape or xa.size < 2:
        raise InputError("x and height must be 1-D arrays of the same length >= 2")
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ha))):
        raise InputError("x and height must be finite")
    if np.any(np.diff(xa) <= 0):
        raise InputError("x must be strictly increasing")
    return xa, ha


def camber_height(x: ArrayLike, height: ArrayLike, *, at: float = 0.0) -> float:
    """Camber height [m] at position ``at`` [m] (default: the balance point), linear in samples."""
    xa, ha = _profile(x, height)
    if not (xa[0] <= at <= xa[-1]):
        raise InputError(f"position {at} m is outside the profile [{xa[0]}, {xa[-1]}] m")
    return float(np.interp(at, xa, ha))


def _cell_widths(xa: NDArray[np.float64]) -> NDArray[np.float64]:
    edges = np.concatenate([[xa[0]], 0.5 * (xa[1:] + xa[:-1]), [xa[-1]]])
    return np.diff(edges)


def wax_pocket(
    x: ArrayLike, height: ArrayLike, *, threshold: float = CLOSED_THRESHOLD, at: float = 0.0
) -> tuple[float, float] | None:
    """The wax pocket: (start, end) [m] of the connected stretch around ``at`` with h > threshold.

    The ends are located by linear interpolation between samples. ``None`` when h(at) <=
    threshold (the pocket is closed at the balance point).
    """
    xa, ha = _profile(x, height)
    if camber_height(xa, ha, at=at) <= threshold:
        return None
    above = ha > threshold
    i = int(np.clip(np.searchsorted(xa, at), 0, xa.size - 1))
    if not above[i]:
        i = i - 1 if i > 0 and above[i - 1] else i
    lo = i
    while lo > 0 and above[lo - 1]:
        lo -= 1
    hi = i
    while hi < xa.size - 1 and above[hi + 1]:
        hi += 1

    def cross(j0: int, j1: int) -> float:
        h0, h1 = ha[j0] - threshold, ha[j1] - threshold
        return float(xa[j0] + (xa[j1] - xa[j0]) * h0 / (h0 - h1))

    start = cross(lo, lo - 1) if lo > 0 else float(xa[0])
    end = cross(hi, hi + 1) if hi < xa.size - 1 else float(xa[-1])
    return start, end


def wax_pocket_length(
    x: ArrayLike, height: ArrayLike, *, threshold: float = CLOSED_THRESHOLD, at: float = 0.0
) -> float:
    """Length [m] of :func:`wax_pocket` (0 when closed)."""
    pocket = wax_pocket(x, height, threshold=threshold, at=at)
    return 0.0 if pocket is None else pocket[1] - pocket[0]


def contact_patches(
    x: ArrayLike,
    height: ArrayLike,
    *,
    threshold: float = BREITSCHAEDEL_THRESHOLD,
    kick_zone: tuple[float, float] | None = None,
) -> tuple[tuple[float, float], ...]:
    """Runs of samples in Breitschädel contact (:func:`breitschaedel_contact`: gap to the plane
    the ski rests on below ``threshold``) as ((start, end), ...) [m] (first and last sample)."""
    xa, ha = _profile(x, height)
    idx = np.flatnonzero(breitschaedel_contact(xa, ha, kick_zone=kick_zone, threshold=threshold))
    if idx.size == 0:
        return ()
    cut = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[cut + 1]])
    ends = np.concatenate([idx[cut], [idx[-1]]])
    return tuple((float(xa[s]), float(xa[e])) for s, e in zip(starts, ends, strict=True))


def contact_lengths(
    x: ArrayLike,
    height: ArrayLike,
    *,
    threshold: float = BREITSCHAEDEL_THRESHOLD,
    kick_zone: tuple[float, float] | None = None,
) -> dict[str, float]:
    """Contact lengths [m] with Breitschädel's criterion (:func:`breitschaedel_contact`), per zone.

    Zones: ``rear`` (x < kick start), ``middle`` (inside the kick zone), ``front`` (x > kick
    end), ``total``. Without a kick zone (skate skis) ``middle`` is 0 and rear/front are split,
    as in :func:`skisnow.contact.contact_zones`, at the top of the camber arch: the sample of
    greatest height between the centres of the rearmost and the frontmost contact patch (at the
    balance point if there are fewer than two patches). Each sample stands for its cell
    (half-way to its neighbours).
    """
    xa, ha = _profile(x, height)
    touching = breitschaedel_contact(xa, ha, kick_zone=kick_zone, threshold=threshold)
    if kick_zone is None:
        patches = contact_patches(xa, ha, threshold=threshold)
        split = 0.0
        if len(patches) >= 2:
            lo = 0.5 * sum(patches[0])
            hi = 0.5 * sum(patches[-1])
            inside = (xa >= lo) & (xa <= hi)
            split = float(xa[inside][np.argmax(ha[inside])])
        a = b = split
    else:
        a, b = kick_zone
    w = _cell_widths(xa) * touching
    return {
        "rear": float(np.sum(w[xa < a])),
        "middle": float(np.sum(w[(xa >= a) & (xa <= b)])) if kick_zone is not None else 0.0,
        "front": float(np.sum(w[xa > b])),
        "total": float(np.sum(w)),
    }


def ski_stiffness(height_half: float, height_full: float, body_mass: float) -> float:
    """Breitschädel's stiffness k [N/m]: ½·m·g over the camber drop from half to full weight."""
    drop = height_half - height_full
    if drop <= 0:
        return float("inf")
    return 0.5 * body_mass * STANDARD_GRAVITY / drop
