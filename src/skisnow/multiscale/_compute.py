"""The computation of the micro curves of one base × snow (see :mod:`skisnow.multiscale._curves`
for the models, the pressure grid and the cache): the prepared texture sampled every ``pixel``,
the flat-ice curve (:func:`skisnow.micro.elastoplastic_curve`) and the grain-averaged bearing
model on the map continued by its mirror images; a smooth base in closed form.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from skisnow._errors import InputError
from skisnow.micro import (
    GAP_EDGES,
    Topography,
    bearing_area,
    elastoplastic_curve,
    make_topography,
)
from skisnow.multiscale._base import Base

__all__ = ["compute_curves"]


def _sample(t: Topography, pixel: float, cutoff: float | None) -> Topography:
    """The prepared map every ``pixel`` [m] (per axis, never finer than the map's own)."""
    k = [max(1, round(pixel / d)) for d in (t.dx, t.dy)]
    for ki, d in zip(k, (t.dx, t.dy), strict=True):
        if ki > 1 and (cutoff is None or ki * d > cutoff / 4.0):
            raise InputError(
                f"sampling the texture at {ki * d * 1e6:.3g} µm would alias it: the preparation "
                f"keeps wavelengths down to {cutoff if cutoff is None else cutoff * 1e6:.3g} µm "
                "(need a pixel of at most a quarter of the cut-off)"
            )
    h = np.ascontiguousarray(np.asarray(t.heights)[:: k[0], :: k[1]])
    return make_topography(h, dx=t.dx * k[0], dy=t.dy * k[1], source=t.source)


def _bearing(
    t: Topography, snow: Any, pressures: np.ndarray, hardness: float, positions: int, nodes: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Grain-averaged real fraction of the bearing model at each pressure (eq. 5–9, 13)."""
    diam, wts = snow.grain_nodes(nodes)
    out = np.zeros(pressures.size)
    h = np.asarray(t.heights)
    for d, w in zip(diam, wts, strict=True):
        pi, pj = (math.ceil(d / 2 / s) + 1 for s in (t.dx, t.dy))
        ext = np.pad(h, ((pi, pi), (pj, pj)), mode="symmetric")
        if ext.shape[0] < 2 * pi + 1 or min(h.shape) < 2:
            raise InputError(f"{t.source}: map too small for the bearing model")
        big = make_topography(ext, dx=t.dx, dy=t.dy, source=t.source)
        stride = max(1, math.ceil(max(h.shape) / positions))
        for i, p in enumerate(pressures):
            m = bearing_area(
                big, diameter=float(d), pressure=float(p), hardness=hardness, stride=stride
            )
            out[i] += w * m.mean_fractional_area
    return out, diam, wts


def compute_curves(
    b: Base,
    s: Any,
    p: np.ndarray,
    hardness: float,
    modulus: float,
    pixel: float,
    positions: int,
    nodes: int,
) -> tuple[dict, dict]:
    bp = np.unique(np.concatenate([p[::3], p[-1:]]))
    meta: dict[str, Any] = {
        "base": b.name,
        "snow": s.name,
        "hardness": hardness,
        "modulus": modulus,
    }
    if b.prepared is None:  # smooth: full contact with flat ice, p/H on grains (exact)
        n = p.size
        d, w = s.grain_nodes(nodes)
        arrays = {
            "pressures": p,
            "fractional_area": np.ones(n),
            "real_fractional_area": np.ones(n),
            "plastic_fraction": np.zeros(n),
            "mean_separation_grid": np.zeros(n),
            "gap_area": np.zeros((n, GAP_EDGES.size - 1)),
            "gap_reciprocal": np.zeros((n, GAP_EDGES.size - 1)),
            "gap_below": np.zeros(n),
            "rest_gaps": np.zeros(3),
            "rest_mean": np.array(0.0),
            "converged": np.ones(n, dtype=bool),
            "bearing_pressures": bp,
            "bearing_fraction": bp / hardness,
            "grain_nodes": d,
            "grain_weights": w,
        }
        return arrays, meta | {"pixel": [0.0, 0.0], "map_size": [0.0, 0.0], "smooth": True}
    t = _sample(b.prepared, pixel, b.cutoff)
    curve = elastoplastic_curve(t, pressures=p, hardness=hardness, modulus=modulus)
    frac, d, w = _bearing(t, s, bp, hardness, positions, nodes)
    h = np.asarray(t.heights)
    arrays = {
        "pressures": curve.pressures,
        "fractional_area": curve.fractional_area,
        "real_fractional_area": curve.real_fractional_area,
        "plastic_fraction": curve.plastic_fraction,
        "mean_separation_grid": curve.mean_separation,
        "gap_area": curve.gap_area,
        "gap_reciprocal": curve.gap_reciprocal,
        "gap_below": curve.gap_below,
        "rest_gaps": curve.rest_gaps,
        "rest_mean": np.array(float(h.max() - h.mean())),
        "converged": curve.converged,
        "bearing_pressures": bp,
        "bearing_fraction": frac,
        "grain_nodes": d,
        "grain_weights": w,
    }
    return arrays, meta | {"pixel": [t.dx, t.dy], "map_size": list(t.size), "smooth": False}
