"""The calibration's parametrisation: knots, starting skis, parameter vectors, the ski, the box.

A ski is a spline (:func:`skisnow.ski.spline_ski`): log EI at the EI knots and the free camber z0
at the camber knots (both PCHIP), two camber knots pinned at 0 (a line added to z0 is undone by
the resting on the plane). A parameter vector is log EI [ln N m²] at the EI knots and z0 [mm] at
the free camber knots, on the knots of the run, :data:`KNOTS` (the shipped skis'
:data:`~skisnow.ski.SPLINE_KNOTS`, or :data:`DENSE_KNOTS` with ``--knots dense``).
"""

from __future__ import annotations

import json
import math

import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.optimize import least_squares

from skisnow.ski import (
    SPLINE_ENDS,
    SPLINE_KNOTS,
    Ski,
    get_ski,
    solve_beam,
    spline_ski,
    wax_pocket,
)

__all__ = [
    "BODY",
    "DENSE_KNOTS",
    "KNOTS",
    "POS",
    "START",
    "bounds",
    "kick_zone_of",
    "make_ski",
    "record_vector",
    "resampled_vector",
    "shipped_vector",
    "start_vector",
    "unpack",
]

BODY, POS = 65.0, -0.080  # the practitioners' skier [kg] and load position [m]

#: Denser knots (``--knots dense``): the knots of SPLINE_KNOTS and one more between most
#: neighbours (19 log-EI and 26 camber knots instead of 10 and 13), still densest in the glide
#: zones (every 40-60 mm there, 130-140 mm in the middle). A superset of the default knots, with
#: the same two camber knots pinned (-0.64 and +0.54 m on the classic, -0.62 and +0.54 m on the
#: skate), so a record resampled onto them starts close to itself. Used to ask whether a misfit
#: is a limit of the parametrisation or of the model.
# fmt: off
DENSE_KNOTS: dict[str, tuple[tuple[float, ...], tuple[float, ...], tuple[int, int]]] = {
    "classic": (
        (-0.98, -0.92, -0.86, -0.80, -0.74, -0.68, -0.62, -0.54, -0.45, -0.22, 0.0, 0.20,
         0.40, 0.46, 0.52, 0.59, 0.66, 0.78, 1.02),
        (-0.98, -0.90, -0.82, -0.77, -0.72, -0.68, -0.64, -0.60, -0.56, -0.49, -0.42, -0.28,
         -0.14, 0.0, 0.13, 0.26, 0.38, 0.42, 0.46, 0.50, 0.54, 0.58, 0.62, 0.68, 0.74, 1.02),
        (6, 20),
    ),
    "skate": (
        (-0.92, -0.86, -0.80, -0.74, -0.68, -0.62, -0.56, -0.48, -0.40, -0.20, 0.0, 0.20,
         0.40, 0.46, 0.52, 0.59, 0.66, 0.78, 0.94),
        (-0.92, -0.86, -0.80, -0.75, -0.70, -0.66, -0.62, -0.58, -0.54, -0.47, -0.40, -0.27,
         -0.13, 0.0, 0.12, 0.24, 0.36, 0.41, 0.46, 0.50, 0.54, 0.58, 0.62, 0.67, 0.72, 0.94),
        (6, 20),
    ),
}
# fmt: on
#: The knots of this run: SPLINE_KNOTS (the shipped skis' knots, the default), or DENSE_KNOTS
#: with ``--knots dense`` (set by :func:`~skisnow.calibrate.run_calibration` for its run).
KNOTS = dict(SPLINE_KNOTS)


#: Starting skis (EI [N m²] at the EI knots, z0 [mm] at the camber knots, before the shovel and
#: tail rises): the classic is the previous shipped classic sampled at the knots; the skate a
#: hand-made ski with soft glide zones (the previous skate's glide zones were too stiff and too
#: curved to give long contacts).
START = {
    "classic": (
        [189, 479, 731, 945, 1184, 1450, 1240, 1095, 878, 137],
        [1.75, 0.59, 0.17, 0.0, -0.02, 0.49, 2.94, 0.30, 0.02, 0.0, 0.18, 0.86, 4.3],
    ),
    "skate": (
        [150, 200, 300, 400, 2000, 6000, 2000, 400, 250, 150],
        [1.0, 0.15, 0.04, 0.0, 0.0, 0.4, 6.0, 0.6, 0.05, 0.0, 0.0, 0.06, 1.0],
    ),
}


def start_vector(kind: str) -> np.ndarray:
    """The starting ski as a parameter vector: log EI [ln N m²] and the free z0 knots [mm]."""
    ek, zk, _ = SPLINE_KNOTS[kind]  # START is tabulated at the default knots
    ei, z = START[kind]
    return resampled_vector(kind, list(ek), ei, list(zk), z)


def _pchip_fit(
    x_new: np.ndarray, x: np.ndarray, y: np.ndarray, fixed: dict[int, float]
) -> np.ndarray:
    """Values at ``x_new`` whose PCHIP is closest (least squares at ``x``) to ``y``.

    Starts from ``y`` interpolated at the new knots; ``fixed`` holds values kept as they are.
    """
    v = np.interp(x_new, x, y)
    for k, val in fixed.items():
        v[k] = val
    free = [k for k in range(x_new.size) if k not in fixed]

    def curve(p: np.ndarray) -> np.ndarray:
        w = v.copy()
        w[free] = p
        return PchipInterpolator(x_new, w)(x) - y

    v[free] = least_squares(curve, v[free]).x
    return v


def resampled_vector(
    kind: str, ei_knots: list[float], ei: list[float], z_knots: list[float], z_mm: list[float]
) -> np.ndarray:
    """A ski at other knots (a record, the shipped ski) as a parameter vector at :data:`KNOTS`.

    On the same knots the values are taken as they are. Otherwise the source curves, log EI and
    z0 (PCHIP through the source knots, as :func:`spline_ski` interpolates them, z0 less the line
    through the new pinned knots, which the resting on the plane undoes), are sampled every
    5 mm, and the values at the new knots are those whose PCHIP is closest to them (least
    squares, from the source curves at the new knots): PCHIP through values read off a PCHIP is
    not the same curve, and a 0.06 mm change of the pocket at half weight moves the kick zone's
    0.2 mm mark, which groups the patches into zones, by 125 mm.
    """
    ek, zk, pins = KNOTS[kind]
    free = [k for k in range(len(zk)) if k not in pins]
    if tuple(ei_knots) == tuple(ek) and tuple(z_knots) == tuple(zk):
        return np.concatenate([np.log(ei), np.array(z_mm)[free]])
    x_tail, x_tip = SPLINE_ENDS[kind]
    xs = np.linspace(x_tail, x_tip, round((x_tip - x_tail) / 0.005) + 1)
    log_ei = PchipInterpolator(np.array(ei_knots), np.log(ei))(xs)
    z = PchipInterpolator(np.array(z_knots), np.array(z_mm, dtype=float))(xs)
    za, zb = np.interp([zk[pins[0]], zk[pins[1]]], xs, z)
    z = z - (za + (zb - za) * (xs - zk[pins[0]]) / (zk[pins[1]] - zk[pins[0]]))
    log_ei_k = _pchip_fit(np.array(ek), xs, log_ei, {})
    z_k = _pchip_fit(np.array(zk), xs, z, {pins[0]: 0.0, pins[1]: 0.0})
    return np.concatenate([log_ei_k, z_k[free]])


def record_vector(kind: str, doc: dict) -> np.ndarray:
    """A calibration record (JSON) as a parameter vector at :data:`KNOTS` (resampled)."""
    return resampled_vector(
        kind, doc["ei_knots_m"], doc["ei_n_m2"], doc["camber_knots_m"], doc["camber_mm"]
    )


def shipped_vector(kind: str) -> np.ndarray:
    """The shipped ski as a parameter vector.

    A spline ski's tabulated knot values are used as they are (resampled onto other knots, see
    :func:`resampled_vector`); a parametric ski (version 1) is
    sampled at the knots: EI at the EI knots, z0 at the camber knots less the shovel and tail
    rises that :func:`spline_ski` adds, less the line through the two pinned knots (undone by
    the resting on the plane). The sampled ski is close to, not the same as, the shipped one.
    """
    ski = get_ski(kind)
    ek, zk, pins = KNOTS[kind]
    free = [k for k in range(len(zk)) if k not in pins]
    try:
        ei = json.loads(ski.provenance.detail("ei_knots_n_m2"))
        z = json.loads(ski.provenance.detail("camber_knots_mm"))
        z_knots = SPLINE_KNOTS[kind][1]  # the shipped spline skis are on the default knots
        return resampled_vector(kind, list(ski.stiffness_x), ei, list(z_knots), z)
    except (KeyError, TypeError, ValueError):
        pass
    x = np.array(zk)
    x_tail, x_tip = SPLINE_ENDS[kind]
    rise = 30e-3 * np.clip((x - (x_tip - 0.20)) / 0.20, 0.0, 1.0) ** 2.5
    rise += 4e-3 * np.clip(((x_tail + 0.05) - x) / 0.05, 0.0, 1.0) ** 2
    z = np.asarray(ski.free_camber(x), dtype=float) - rise
    a, b = pins
    z = (z - (z[a] + (z[b] - z[a]) * (x - x[a]) / (x[b] - x[a]))) * 1e3
    ei = np.asarray(ski.stiffness(np.array(ek)), dtype=float)
    return np.concatenate([np.log(ei), z[free]])


def unpack(kind: str, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameter vector → (EI at the EI knots [N m²], z0 at the camber knots [m])."""
    ek, zk, pins = KNOTS[kind]
    n_e = len(ek)
    ei = np.exp(v[:n_e])
    z = np.zeros(len(zk))
    free = [k for k in range(len(zk)) if k not in pins]
    z[free] = v[n_e:] * 1e-3
    return ei, z


def kick_zone_of(ski: Ski) -> tuple[float, float] | None:
    """Kick zone: the 0.2 mm mark at the rear to the 0.1 mm mark in front (½ BODY, -80 mm)."""
    sol = solve_beam(ski, mass=0.5 * BODY, load_position=POS)
    x = np.linspace(ski.x_tail, ski.x_tip, 4001)
    h = sol.sample(x)
    p2, p1 = wax_pocket(x, h, threshold=0.2e-3), wax_pocket(x, h, threshold=0.1e-3)
    if p2 is None or p1 is None:
        return None
    return (p2[0], p1[1])


def make_ski(kind: str, v: np.ndarray) -> Ski:
    """The spline ski of parameter vector ``v``; a classic gets the kick zone of its wax pocket
    at half body weight (:func:`kick_zone_of`; ``ValueError`` when it has none)."""
    ei, z = unpack(kind, v)
    knots = KNOTS[kind][:2]
    ski = spline_ski(kind, ei, z, kick_zone=None, description="calibration candidate", knots=knots)
    if kind == "classic":
        kz = kick_zone_of(ski)
        if kz is None:
            raise ValueError("no wax pocket at half body weight")
        ski = spline_ski(
            kind, ei, z, kick_zone=kz, description="calibration candidate", knots=knots
        )
    return ski


def bounds(kind: str) -> tuple[np.ndarray, np.ndarray]:
    """The box: EI 40..30000 N m²; z0 knots [mm]: ends 0..8, glide zones -0.5..2, middle 0..20."""
    ek, zk, pins = KNOTS[kind]
    n_e = len(ek)
    free = [k for k in range(len(zk)) if k not in pins]
    lo = np.empty(n_e + len(free))
    hi = np.empty_like(lo)
    lo[:n_e], hi[:n_e] = math.log(40.0), math.log(30000.0)
    for m, k in enumerate(free):
        if k in (0, len(zk) - 1):
            lo[n_e + m], hi[n_e + m] = 0.0, 8.0
        elif abs(zk[k]) >= 0.42:
            lo[n_e + m], hi[n_e + m] = -0.5, 2.0
        else:
            lo[n_e + m], hi[n_e + m] = 0.0, 20.0
    return lo, hi
