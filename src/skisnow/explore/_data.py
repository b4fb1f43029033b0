"""The explorer's data: zone metrics AND fields along the ski over a grid of load and snow.

Each grid point is one contact case of the chain in Kalliorinne et al. (2023): loaded camber
profile h(x) = f(x, m, x_m) (§3.1), the rigid profile pressed into the elastic half-space with
force and moment balance (eq. 2–3), zones (§4). Beside the zone metrics the page needs the fields:
pressure p(x), the ski base b(x) = h(x) − δ − θ(x − x_m) and the snow surface −u(x), on a display
grid of ``n_display`` stations: block means of the ``n_points`` solver cells (a block mean of the
pressure keeps the force balance; peak pressures are in the metrics).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from skisnow._errors import InputError

#: Zones of :class:`skisnow.contact.ZoneMetrics` on the page; ``kick`` is the contact between the
#: kick-zone marks, whatever patch it belongs to (where the grip wax touches the snow).
ZONES = ("rear", "middle", "front", "total", "kick")
METRICS = ("length_mm", "area_cm2", "mean_pressure_kpa", "max_pressure_kpa", "load_share")
#: Field units: SI value × factor.
_TO_FIELD = {
    "length_mm": 1e3,
    "area_cm2": 1e4,
    "mean_pressure_kpa": 1e-3,
    "max_pressure_kpa": 1e-3,
    "load_share": 1.0,
}
_ZONE_ATTR = {
    "length_mm": "length",
    "area_cm2": "area",
    "mean_pressure_kpa": "mean_pressure",
    "max_pressure_kpa": "max_pressure",
    "load_share": "load_share",
}


@dataclass(frozen=True, kw_only=True)
class ExplorerGrid:
    """The grid an explorer page covers (SI units; masses in kg).

    The default is the page's reference size: 26 masses (5–130 kg) × 6 load positions (240–40 mm
    behind the balance point, the paper's bench positions) × 10 snow moduli (40–400 MPa).
    """

    masses: tuple[float, ...] = tuple(float(m) for m in range(5, 131, 5))
    load_positions: tuple[float, ...] = tuple(-0.001 * p for p in range(240, 39, -40))
    snow_moduli: tuple[float, ...] = tuple(1e6 * e for e in range(40, 401, 40))
    n_points: int = 4096
    n_display: int = 512

    def __post_init__(self) -> None:
        for name in ("masses", "load_positions", "snow_moduli"):
            v = np.asarray(getattr(self, name), dtype=float)
            if v.ndim != 1 or v.size == 0 or not np.all(np.isfinite(v)):
                raise InputError(f"{name}: need a non-empty list of finite numbers")
            if np.any(np.diff(v) <= 0):
                raise InputError(f"{name}: must be strictly increasing, got {v.tolist()}")
            object.__setattr__(self, name, tuple(float(a) for a in v))
        if self.n_display < 16 or self.n_points % self.n_display:
            raise InputError(
                f"n_display must be ≥ 16 and divide n_points = {self.n_points}, "
                f"got {self.n_display}"
            )


def block_mean(values: np.ndarray, n_blocks: int) -> np.ndarray:
    """Means of ``n_blocks`` equal consecutive blocks along the last axis."""
    v = np.asarray(values, dtype=float)
    return v.reshape(*v.shape[:-1], n_blocks, v.shape[-1] // n_blocks).mean(axis=-1)


def zone_codes(x: np.ndarray, zones, n_blocks: int) -> np.ndarray:
    """Zone of each display station: 0 none, 1 rear, 2 middle, 3 front (the zone of the contact
    cells in the block; the most forward zone where a block holds two)."""
    code = np.zeros(x.size, dtype=np.uint8)
    for k, name in enumerate(ZONES[:3], start=1):
        for a, b in zones[name].intervals:
            code[(x >= a) & (x <= b)] = k
    return code.reshape(n_blocks, -1).max(axis=-1)


def explorer_dataset(
    skis: Sequence[str],
    grid: ExplorerGrid | None = None,
    *,
    profile_source: str = "network",
    ski_models: Sequence[str] = ("rigid",),
    progress: Callable[[int, int], None] | None = None,
):
    """Solve every point of ``grid`` for each ski: an :class:`xarray.Dataset` with dims
    ``ski, model, mass_kg, load_position_mm, snow_modulus_mpa, zone, station``.

    Variables: ``x_mm`` (ski, station); ``pressure_kpa``, ``bottom_um``, ``snow_um`` and
    ``zone_code`` per point and station; the zone metrics of :data:`METRICS` and ``patches`` per
    point and zone; ``converged`` per point. A point whose load the profile cannot carry is NaN
    (fields) with ``converged = False``. ``progress(done, total)`` is called after each chunk of
    masses. Along the masses each solve starts from the previous pressure (warm start).

    ``ski_models``: ``'rigid'`` (the paper's method: the loaded profile from ``profile_source``
    pressed into the snow as a rigid body) and/or ``'flexible'`` (the beam and the half-space
    solved together, :func:`skisnow.contact.solve_flexible`); the ski base shown is the rigid
    profile, or the bent ski, lowered by δ + θ(x − x_m).
    """
    import xarray as xr

    from skisnow._errors import UnsupportedLoadError
    from skisnow.pipeline import loaded_profiles, resolve_ski, solve_case

    grid = grid or ExplorerGrid()
    names = tuple(skis)
    if not names or len(set(names)) != len(names):
        raise InputError(f"skis: need distinct skis, got {list(names)}")
    resolved = [resolve_ski(s) for s in names]  # an unknown ski fails here, before any solve
    models = tuple(ski_models)
    if not models or len(set(models)) != len(models) or set(models) - {"rigid", "flexible"}:
        raise InputError(f"ski models: need distinct 'rigid' and/or 'flexible', got {models}")
    n_s, n_m, n_p, n_e = (
        len(names),
        len(grid.masses),
        len(grid.load_positions),
        len(grid.snow_moduli),
    )
    nd = grid.n_display
    shape = (n_s, len(models), n_m, n_p, n_e)
    fields = {k: np.full((*shape, nd), np.nan) for k in ("pressure_kpa", "bottom_um", "snow_um")}
    codes = np.zeros((*shape, nd), dtype=np.uint8)
    metrics = {k: np.full((*shape, len(ZONES)), np.nan) for k in METRICS}
    patches = np.zeros((*shape, len(ZONES)), dtype=np.int32)
    converged = np.zeros(shape, dtype=bool)
    x_mm = np.zeros((n_s, nd))
    total, done = n_s * len(models) * n_p * n_e, 0
    for s, ski in enumerate(resolved):
        for p, xm in enumerate(grid.load_positions):
            x, heights = loaded_profiles(
                ski, grid.masses, xm, profile_source=profile_source, n_points=grid.n_points
            )
            x_mm[s] = block_mean(x, nd) * 1e3
            for (j, ski_model), (e, modulus) in itertools.product(
                enumerate(models), enumerate(grid.snow_moduli)
            ):
                previous = None
                for a, mass in enumerate(grid.masses):
                    try:
                        case = solve_case(
                            ski,
                            mass=mass,
                            load_position=xm,
                            snow_modulus=modulus,
                            profile=(x, heights[a]) if ski_model == "rigid" else None,
                            ski_model=ski_model,
                            start=previous,
                            n_points=grid.n_points,
                            workers=1,
                        )
                    except UnsupportedLoadError:
                        previous = None
                        continue
                    i = (s, j, a, p, e)
                    sol, zones = case.solution, case.zones
                    base = sol.height - sol.translation - sol.rotation * (sol.x - xm)
                    fields["pressure_kpa"][i] = block_mean(sol.pressure, nd) * 1e-3
                    fields["bottom_um"][i] = block_mean(base, nd) * 1e6
                    fields["snow_um"][i] = -block_mean(sol.displacement, nd) * 1e6
                    codes[i] = zone_codes(sol.x, zones, nd)
                    for q, z in enumerate(ZONES):
                        zone = zones[z]
                        for k in METRICS:
                            metrics[k][(*i, q)] = getattr(zone, _ZONE_ATTR[k]) * _TO_FIELD[k]
                        patches[(*i, q)] = zone.patches
                    converged[i] = sol.converged
                    previous = sol.pressure if sol.converged else None
                done += 1
                if progress is not None:
                    progress(done, total)
    point = ("ski", "model", "mass_kg", "load_position_mm", "snow_modulus_mpa")
    data = {k: ((*point, "station"), v) for k, v in fields.items()}
    data["zone_code"] = ((*point, "station"), codes)
    data.update({k: ((*point, "zone"), v) for k, v in metrics.items()})
    data["patches"] = ((*point, "zone"), patches)
    data["converged"] = (point, converged)
    data["x_mm"] = (("ski", "station"), x_mm)
    coords = {
        "ski": [getattr(k, "name", str(k)) for k in resolved],
        "model": list(models),
        "mass_kg": list(grid.masses),
        "load_position_mm": [round(v * 1e3, 6) for v in grid.load_positions],
        "snow_modulus_mpa": [round(v * 1e-6, 6) for v in grid.snow_moduli],
        "zone": list(ZONES),
    }
    return xr.Dataset(data, coords=coords, attrs={"profile_source": profile_source})
