"""Micro curves, once per base × snow: the real contact as a function of the nominal pressure.

For a log-spaced grid of nominal pressures p (default 1 kPa to 4.6 MPa, three per decade —
what the apparent contact of a ski produces, from the lightly loaded ends of a patch to the
peaks on stiff snow), two micro models of Scherge et al. (2021) see the prepared texture:

(a) the bearing model of plastic ice grains (eq. 5–9), averaged over the snow's grains (eq. 13,
    on the grain nodes of :meth:`skisnow.snow.Snow.grain_nodes`): the real-area fraction
    A_fr(p), exactly (p/H)·⟨slope factor over the contact⟩ (projected area p/H by construction);
(b) the elastic–perfectly-plastic contact of the texture with a flat ice half-space capped at H
    (:func:`skisnow.micro.elastoplastic_curve`, the contact package's Polonsky–Keer core with the
    mirror-continued half-space): real-area fraction, mean separation ū(p) and the gap
    distribution that gives the reciprocal separation ⟨1/u⟩(p) for any film cut-off.

The pressure distribution along a ski matters only through what is nonlinear in p: in the
purely plastic bearing model A_r = Σ p·dA·s/H = W·s/H whatever the camber. (b) is nonlinear
(elastic rims of the contact spots at light load, the separation and its reciprocal), and so
is the film cut-off; the along-ski coupling (:mod:`skisnow.multiscale._along`) is built on them.

Numerics: the prepared texture is sampled every ``pixel`` (default 2 µm; alias-free because
the preparation removed every wavelength below 33 µm, and refused when the cut-off would not
allow it). The bearing model runs on the same samples, on a raster of at most
``bearing_positions``² grain positions over the map, the map continued by its mirror images as
far as the largest grain needs (the same continuation as the half-space of (b)).

Curves are cached on disk (:mod:`skisnow.multiscale._cache`), keyed by the prepared texture,
the snow's micro properties (temperature, hardness model, grain nodes), the settings, the
skisnow version and :data:`CURVES_FORMAT`.
"""

from __future__ import annotations

import functools
import hashlib
import json
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from skisnow._errors import DomainWarning, InputError
from skisnow.materials import ICE
from skisnow.micro import (
    GAP_EDGES,
    reciprocal_from_bins,
)
from skisnow.multiscale._base import Base, make_base
from skisnow.multiscale._cache import load_arrays, save_arrays
from skisnow.multiscale._compute import compute_curves

__all__ = [
    "CURVES_FORMAT",
    "DEFAULT_PIXEL",
    "DEFAULT_PRESSURES",
    "MicroCurves",
    "micro_curves",
]

#: Bumped whenever the computation of the curves changes (part of the cache key).
CURVES_FORMAT: int = 1
#: Nominal pressures of the curves [Pa]: 1 kPa to 4.64 MPa, three per decade.
DEFAULT_PRESSURES: np.ndarray = 10.0 ** (3.0 + np.arange(12) / 3.0)
#: Sampling of the prepared texture for both micro models [m].
DEFAULT_PIXEL: float = 2e-6
#: Grain positions per side of the bearing model's raster.
DEFAULT_BEARING_POSITIONS: int = 40
#: Grain-size nodes of the bearing model's average (eq. 13).
DEFAULT_GRAIN_NODES: int = 3


def _interp_log(p: np.ndarray, grid: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Piecewise linear in log p (clamped beyond the grid's last point)."""
    return np.interp(np.log(p), np.log(grid), values)


@dataclass(frozen=True, kw_only=True, eq=False)
class MicroCurves:
    """The micro contact of one base × snow over nominal pressure (SI units).

    Interpolate with :meth:`real_fraction`, :meth:`mean_separation`,
    :meth:`reciprocal_separation` (for p > 0) and :meth:`rest_separation`,
    :meth:`rest_reciprocal` (outside the apparent contact, at a macroscopic gap G).
    Below the grid's first pressure the fractions are linear in p (both the plastic and the
    elastic light-load limits are), the separations linear between their zero-load value and
    the first point; beyond the last pressure the values are held (:meth:`beyond` flags it).
    """

    base: str
    snow: str
    key: str
    pressures: np.ndarray
    hardness: float
    modulus: float
    pixel: tuple[float, float]
    map_size: tuple[float, float]
    smooth: bool
    fractional_area: np.ndarray
    real_fractional_area: np.ndarray
    plastic_fraction: np.ndarray
    mean_separation_grid: np.ndarray
    gap_area: np.ndarray = field(repr=False)
    gap_reciprocal: np.ndarray = field(repr=False)
    gap_below: np.ndarray = field(repr=False)
    rest_gaps: np.ndarray = field(repr=False)
    rest_mean: float
    converged: np.ndarray
    bearing_pressures: np.ndarray
    bearing_fraction: np.ndarray
    grain_nodes: np.ndarray
    grain_weights: np.ndarray
    seconds: float = float("nan")
    cpu_seconds: float = float("nan")
    from_cache: bool = False
    version: str = ""

    # -- inside the apparent contact (p > 0) -----------------------------------------------
    def real_fraction(self, pressure: np.ndarray, *, model: str = "flat-ice") -> np.ndarray:
        """Real-area fraction A_r/A at nominal pressure p [Pa]: ``'flat-ice'`` (b, with the
        slope factor) or ``'grains'`` (a, the bearing model averaged over the grains)."""
        p = np.asarray(pressure, dtype=np.float64)
        if model == "flat-ice":
            grid, vals = self.pressures, self.real_fractional_area
        elif model == "grains":
            grid, vals = self.bearing_pressures, self.bearing_fraction
        else:
            raise InputError(f"real-area model {model!r} unknown; valid: 'flat-ice', 'grains'")
        if self.smooth and model == "flat-ice":  # flat on flat: full contact at any load
            return np.where(p > 0, 1.0, 0.0)
        safe = np.maximum(p, 1e-300)
        inside = np.exp(_interp_log(np.clip(safe, grid[0], grid[-1]), grid, np.log(vals)))
        low = vals[0] * safe / grid[0]
        return np.where(p <= 0, 0.0, np.minimum(np.where(p < grid[0], low, inside), 1.0))

    def mean_separation(self, pressure: np.ndarray) -> np.ndarray:
        """ū(p) [m] over the nominal area (flat-ice model b)."""
        return self._with_rest(pressure, self.mean_separation_grid, self.rest_mean)

    def reciprocal_separation(self, pressure: np.ndarray, film_cutoff: float) -> np.ndarray:
        """⟨1/u⟩(p) [1/m] over the non-contact area, gaps below ``film_cutoff`` [m] counted as
        the cut-off (flat-ice model b)."""
        grid = self._reciprocal_grid(float(film_cutoff))
        return self._with_rest(pressure, grid, float(self.rest_reciprocal(0.0, film_cutoff)))

    def _with_rest(self, pressure: np.ndarray, grid_values: np.ndarray, rest: float) -> np.ndarray:
        p = np.asarray(pressure, dtype=np.float64)
        g = self.pressures
        inside = _interp_log(np.clip(np.maximum(p, g[0]), g[0], g[-1]), g, grid_values)
        low = rest + (grid_values[0] - rest) * np.clip(p, 0.0, None) / g[0]
        if self.smooth:  # flat on flat: any load closes the whole interface
            low = np.where(p > 0, grid_values[0], rest)
        return np.where(p < g[0], low, inside)

    def reciprocal_grid(self, film_cutoff: float) -> np.ndarray:
        """⟨1/u⟩ [1/m] at the grid's pressures for a film cut-off [m] (the curve's points)."""
        return self._reciprocal_grid(float(film_cutoff))

    @functools.lru_cache(maxsize=8)  # noqa: B019 - a frozen object, a few cut-offs per run
    def _reciprocal_grid(self, film_cutoff: float) -> np.ndarray:
        return reciprocal_from_bins(
            GAP_EDGES, self.gap_area, self.gap_reciprocal, self.gap_below, film_cutoff
        )

    def contact_values(
        self, pressure: np.ndarray, film_cutoff: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """All four at once for p > 0, as :meth:`real_fraction` (flat ice, then grains),
        :meth:`mean_separation` and :meth:`reciprocal_separation` give them (one search in the
        grid for the four: the along-ski evaluation of every station of every case)."""
        p = np.asarray(pressure, dtype=np.float64)
        table, r0 = self._contact_table(float(film_cutoff))
        lg = self._log_pressures
        x = np.log(np.clip(p, self.pressures[0], self.pressures[-1]))
        i = np.searchsorted(lg, x, side="right") - 1
        np.clip(i, 0, lg.size - 2, out=i)
        w = ((x - lg[i]) / (lg[i + 1] - lg[i]))[:, None]
        v = table[i]
        v += (table[i + 1] - v) * w
        fr = np.exp(v[:, 0])
        frg = np.exp(v[:, 1])
        sep, rec = v[:, 2], v[:, 3]
        low = p < self.pressures[0]
        if low.any():
            t = p[low] / self.pressures[0]
            fr[low] = np.exp(table[0, 0]) * t
            frg[low] = np.exp(table[0, 1]) * t
            if self.smooth:
                sep[low], rec[low] = table[0, 2], table[0, 3]
            else:
                sep[low] = self.rest_mean + (table[0, 2] - self.rest_mean) * t
                rec[low] = r0 + (table[0, 3] - r0) * t
        np.minimum(fr, 1.0, out=fr)
        np.minimum(frg, 1.0, out=frg)
        if self.smooth:
            fr[:] = 1.0
        return fr, frg, sep, rec

    @functools.cached_property
    def _log_pressures(self) -> np.ndarray:
        return np.log(self.pressures)

    @functools.lru_cache(maxsize=8)  # noqa: B019
    def _contact_table(self, film_cutoff: float) -> tuple[np.ndarray, float]:
        """Columns on the pressure grid: log A_r/A (flat ice), log A_r/A (grains, interpolated
        log-log from its sub-grid), ū, ⟨1/u⟩ at ``film_cutoff``; and ⟨1/u⟩ at zero load."""
        grains = np.exp(
            _interp_log(self.pressures, self.bearing_pressures, np.log(self.bearing_fraction))
        )
        flat = np.maximum(self.real_fractional_area, 1e-300)
        table = np.column_stack([
            np.log(flat), np.log(grains), self.mean_separation_grid,
            self._reciprocal_grid(film_cutoff),
        ])  # fmt: skip
        return table, float(self.rest_reciprocal(0.0, film_cutoff))

    def beyond(self, pressure: np.ndarray) -> np.ndarray:
        """Where p lies above the grid's last pressure (values held there)."""
        return np.asarray(pressure) > self.pressures[-1] * (1 + 1e-12)

    # -- outside the apparent contact (p = 0, macroscopic gap G ≥ 0) --------------------------
    def rest_separation(self, gap: np.ndarray) -> np.ndarray:
        """Mean separation [m] where the ski does not touch: G + ⟨h_max − h⟩."""
        return np.asarray(gap, dtype=np.float64) + self.rest_mean

    def rest_reciprocal(self, gap: np.ndarray | float, film_cutoff: float) -> np.ndarray:
        """⟨1/max(G + h_max − h, u_c)⟩ [1/m] at macroscopic gaps G [m] (tabulated, log-log)."""
        g_grid, r_grid = self._rest_table(float(film_cutoff))
        g = np.maximum(np.asarray(gap, dtype=np.float64), 0.0)
        lg = np.log(np.maximum(g, g_grid[1]))
        out = np.exp(np.interp(lg, self._rest_log_grid, np.log(r_grid[1:])))
        small = g <= g_grid[1]  # below 0.1 nm: linear from G = 0 (rare: the patch edges)
        if np.any(small):
            out = np.where(small, np.interp(g, g_grid[:2], r_grid[:2]), out)
        return out

    @functools.cached_property
    def _rest_log_grid(self) -> np.ndarray:
        return np.log(np.geomspace(1e-10, 1.0, 401))

    @functools.lru_cache(maxsize=8)  # noqa: B019
    def _rest_table(self, film_cutoff: float) -> tuple[np.ndarray, np.ndarray]:
        g = np.concatenate([[0.0], np.geomspace(1e-10, 1.0, 401)])
        s = self.rest_gaps[None, :]
        r = np.mean(1.0 / np.maximum(g[:, None] + s, film_cutoff), axis=1)
        return g, r

    def as_dict(self) -> dict[str, Any]:
        """The curves in field units (kPa, µm, 1/µm at the default film cut-off) for tables."""
        from skisnow.multiscale._friction import DEFAULT_FILM_CUTOFF

        return {
            "base": self.base,
            "snow": self.snow,
            "pressure_kpa": (self.pressures / 1e3).tolist(),
            "real_fraction": self.real_fractional_area.tolist(),
            "plastic_fraction": self.plastic_fraction.tolist(),
            "mean_separation_um": (self.mean_separation_grid * 1e6).tolist(),
            "reciprocal_separation_per_um": (
                self._reciprocal_grid(DEFAULT_FILM_CUTOFF) * 1e-6
            ).tolist(),
            "bearing_pressure_kpa": (self.bearing_pressures / 1e3).tolist(),
            "bearing_real_fraction": self.bearing_fraction.tolist(),
            "hardness_mpa": self.hardness / 1e6,
            "converged": bool(np.all(self.converged)),
        }


def _key(base: Base, snow: Any, settings: dict[str, Any]) -> str:
    from skisnow import __version__

    doc = {
        "format": CURVES_FORMAT,
        "version": __version__,
        "base": base.key,
        "snow": snow.micro_key(),
        "ice": [ICE.modulus, ICE.poisson],
        "settings": settings,
    }
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()


def micro_curves(
    base: Base | str,
    snow: Any,
    *,
    pressures: np.ndarray | None = None,
    pixel: float = DEFAULT_PIXEL,
    bearing_positions: int = DEFAULT_BEARING_POSITIONS,
    grain_nodes: int = DEFAULT_GRAIN_NODES,
    cache: bool = True,
    cache_dir: str | Path | None = None,
) -> MicroCurves:
    """The micro curves of ``base`` × ``snow`` (see the module docstring), from the cache if
    they are there.

    Parameters
    ----------
    base
        A :class:`~skisnow.multiscale.Base` or what :func:`make_base` accepts (``'S3'``, a file).
    snow
        A :class:`~skisnow.snow.Snow` or what :func:`skisnow.snow.get_snow` accepts.
    pressures
        Nominal pressures [Pa] (default :data:`DEFAULT_PRESSURES`, capped below H/2).
    pixel
        Sampling of the prepared texture [m] for both models.
    bearing_positions, grain_nodes
        Grain positions per side of the bearing raster; grain-size nodes of the average.
    cache, cache_dir
        Read and write the disk cache; its directory (default: see
        :func:`skisnow.multiscale.cache_dir`).
    """
    from skisnow import __version__
    from skisnow.snow import get_snow

    b = make_base(base)
    s = get_snow(snow)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DomainWarning)  # said once, by the caller's Snow
        hardness = s.hardness
    p = DEFAULT_PRESSURES if pressures is None else np.sort(np.asarray(pressures, dtype=float))
    p = p[p < 0.5 * hardness]
    if p.size < 2:
        raise InputError(
            f"the ice hardness {hardness / 1e6:.3g} MPa leaves fewer than two pressures of the "
            "grid below H/2"
        )
    from skisnow.contact import effective_modulus

    modulus = effective_modulus(ICE, b.micro_material)
    settings = {
        "pressures": [float(v) for v in p],
        "pixel": float(pixel),
        "bearing_positions": int(bearing_positions),
        "grain_nodes": int(grain_nodes),
        "boundary": "mirror",
    }
    key = _key(b, s, settings)
    if cache and key in _MEMORY:
        return _MEMORY[key]
    if cache:
        hit = load_arrays(key, cache_dir)
        if hit is not None:
            return _remember(key, _from_arrays(*hit, from_cache=True))
    t0, c0 = time.perf_counter(), time.process_time()
    arrays, meta = compute_curves(b, s, p, hardness, modulus, pixel, bearing_positions, grain_nodes)
    meta |= {
        "seconds": time.perf_counter() - t0,
        "cpu_seconds": time.process_time() - c0,
        "key": key,
        "version": __version__,
    }
    if cache:
        save_arrays(key, arrays, meta, cache_dir)
    return _remember(key, _from_arrays(arrays, meta, from_cache=False))


#: Curves already computed or read in this process (by cache key; a few dozen at most).
_MEMORY: dict[str, MicroCurves] = {}


def _remember(key: str, curves: MicroCurves) -> MicroCurves:
    if len(_MEMORY) >= 64:
        _MEMORY.pop(next(iter(_MEMORY)))
    _MEMORY[key] = curves
    return curves


def _from_arrays(arrays: dict, meta: dict, *, from_cache: bool) -> MicroCurves:
    a = {k: np.asarray(v) for k, v in arrays.items()}
    return MicroCurves(
        base=str(meta["base"]),
        snow=str(meta["snow"]),
        key=str(meta.get("key", "")),
        pressures=a["pressures"].astype(float),
        hardness=float(meta["hardness"]),
        modulus=float(meta["modulus"]),
        pixel=tuple(float(v) for v in meta["pixel"]),  # type: ignore[arg-type]
        map_size=tuple(float(v) for v in meta["map_size"]),  # type: ignore[arg-type]
        smooth=bool(meta["smooth"]),
        fractional_area=a["fractional_area"],
        real_fractional_area=a["real_fractional_area"],
        plastic_fraction=a["plastic_fraction"],
        mean_separation_grid=a["mean_separation_grid"],
        gap_area=a["gap_area"],
        gap_reciprocal=a["gap_reciprocal"],
        gap_below=a["gap_below"],
        rest_gaps=a["rest_gaps"],
        rest_mean=float(a["rest_mean"]),
        converged=a["converged"].astype(bool),
        bearing_pressures=a["bearing_pressures"],
        bearing_fraction=a["bearing_fraction"],
        grain_nodes=a["grain_nodes"],
        grain_weights=a["grain_weights"],
        seconds=float(meta.get("seconds", float("nan"))),
        cpu_seconds=float(meta.get("cpu_seconds", float("nan"))),
        from_cache=from_cache,
        version=str(meta.get("version", "")),
    )
