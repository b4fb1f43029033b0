"""Spline skis: log EI(x) and free camber z0(x) through knots (the shipped skis since v2).

The shipped skis of version 2 are fitted to the captions of Kalliorinne et al. (2023),
Figs. 4–7, by ``benchmarks/calibrate_skis.py``: EI at 10 knots (PCHIP in log EI, as
:class:`~skisnow.ski.Ski` interpolates it) and the running-surface shape at 13 knots (PCHIP,
sampled every 5 mm), the knots denser in the glide zones than in the middle — the contact
lengths on snow come from how the glide zones flatten under load. The shovel (30 mm over the
last 200 mm) and tail (4 mm over the last 50 mm) rises are added and the ski is rested on the
plane (the lower convex hull under the balance point), as for the skis of version 1.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy.interpolate import PchipInterpolator

from skisnow.ski._shipped import rest_on_plane
from skisnow.ski._skis import Provenance, Ski

__all__ = ["SPLINE_ENDS", "SPLINE_KNOTS", "spline_ski"]

#: Knots of the spline skis: (log-EI knots [m], camber knots [m], indices of the two camber
#: knots pinned at 0 in the fit — a line added to z0 is undone by the resting on the plane).
SPLINE_KNOTS: dict[str, tuple[tuple[float, ...], tuple[float, ...], tuple[int, int]]] = {
    "classic": (
        (-0.98, -0.86, -0.74, -0.62, -0.45, 0.0, 0.40, 0.52, 0.66, 1.02),
        (-0.98, -0.82, -0.72, -0.64, -0.56, -0.42, 0.0, 0.38, 0.46, 0.54, 0.62, 0.74, 1.02),
        (3, 9),
    ),
    "skate": (
        (-0.92, -0.80, -0.68, -0.56, -0.40, 0.0, 0.40, 0.52, 0.66, 0.94),
        (-0.92, -0.80, -0.70, -0.62, -0.54, -0.40, 0.0, 0.36, 0.46, 0.54, 0.62, 0.72, 0.94),
        (3, 9),
    ),
}
#: Running-surface ends (tail, tip) [m] from the balance point (as the skis of version 1).
SPLINE_ENDS: dict[str, tuple[float, float]] = {"classic": (-0.98, 1.02), "skate": (-0.92, 0.94)}


def spline_ski(
    kind: Literal["classic", "skate"],
    stiffness: ArrayLike,
    camber: ArrayLike,
    *,
    kick_zone: tuple[float, float] | None,
    description: str = "",
    provenance: Provenance | None = None,
    name: str | None = None,
    knots: tuple[Sequence[float], Sequence[float]] | None = None,
) -> Ski:
    """A ski from EI [N m²] and z0 [m] at the knots of :data:`SPLINE_KNOTS` (both PCHIP).

    Parameters
    ----------
    kind
        ``'classic'`` or ``'skate'`` (selects knots and ends).
    stiffness
        EI [N m²] at the stiffness knots (10 of :data:`SPLINE_KNOTS`).
    camber
        Running-surface height [m] at the camber knots (13 of :data:`SPLINE_KNOTS`), before
        the shovel and tail rises.
    kick_zone
        (start, end) [m] of the kick zone (classic) or ``None``.
    description, provenance, name
        Stored with the ski (``name`` defaults to ``kind``).
    knots
        (stiffness knots, camber knots) [m] from the balance point instead of those of
        :data:`SPLINE_KNOTS` (the denser knots of ``benchmarks/calibrate_skis.py --knots
        dense``); within the running surface of ``kind``, its ends as first and last knots.
    """
    ek, zk = SPLINE_KNOTS[kind][:2] if knots is None else knots
    x_tail, x_tip = SPLINE_ENDS[kind]
    x = np.round(np.linspace(x_tail, x_tip, round((x_tip - x_tail) / 0.005) + 1), 6)
    z = PchipInterpolator(np.array(zk), np.asarray(camber, dtype=float))(x)
    shovel, tail = 0.20, 0.05  # lengths [m] of the tip (shovel) and tail rises
    z = z + 30e-3 * np.clip((x - (x_tip - shovel)) / shovel, 0.0, 1.0) ** 2.5
    z = z + 4e-3 * np.clip(((x_tail + tail) - x) / tail, 0.0, 1.0) ** 2
    return Ski(
        name=name or kind,
        kind=kind,
        x_tail=x_tail,
        x_tip=x_tip,
        width=0.044,
        boot_plate=(-0.30, 0.0),
        stiffness_x=np.array(ek),
        stiffness_values=np.asarray(stiffness, dtype=float),
        camber_x=x,
        camber_values=rest_on_plane(x, z),
        kick_zone=kick_zone,
        description=description,
        provenance=provenance if provenance is not None else Provenance(),
    )
