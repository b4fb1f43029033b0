"""The explorer's data: zone metrics AND fields along the ski over a grid of load and snow.

They come from a sweep (:func:`skisnow.sweep.run_sweep`, Dask workers, a resumable Zarr store)
that also stores the fields on display stations (``SweepSpec.field_stations``). Each grid point
is one case of the chain of Kalliorinne et al. (2023) through :func:`skisnow.pipeline.solve_case`:
loaded camber profile h(x) = f(x, m, x_m) (§3.1), pressed into the elastic half-space with force
and moment balance (eq. 2–3), zones (§4) — or, for the flexible ski, the beam and the half-space
solved together. Fields: pressure p(x), the ski base b(x) = h(x) − δ − θ(x − x_m) and the snow
surface −u(x), as block means of the solver's cells (:func:`skisnow.sweep.station_fields`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from skisnow._atomic import scratch_directory
from skisnow._errors import InputError

#: Zones of :class:`skisnow.contact.ZoneMetrics` on the page: the paper's zones and the total,
#: then the regions fixed by the ski (``kick_zone`` is the contact between the kick-zone marks,
#: whatever patch it belongs to: where the grip wax touches the snow).
ZONES = ("rear", "middle", "front", "total", "rear_glide", "kick_zone", "front_glide")
#: What the page needs of a sweep, in the page's order of dims.
POINT = ("ski", "model", "base", "mass_kg", "load_position_mm", "snow_modulus_mpa")
FIELDS = ("pressure_kpa", "base_um", "snow_um", "zone_code")
METRICS = ("length_mm", "area_cm2", "mean_pressure_kpa", "max_pressure_kpa", "load_share")
#: The real contact the page shows with base textures: fields along the ski, totals per point.
REAL_FIELDS = ("real_fraction_percent", "separation_um")
REAL_METRICS = ("real_area_grains_mm2", "viscous_force_n")
REAL_POINT = ("mu", "mu_lubricated")


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


def explorer_dataset(
    skis: Sequence[str],
    grid: ExplorerGrid | None = None,
    *,
    profile_source: str = "beam",
    ski_models: Sequence[str] = ("rigid",),
    store: str | Path | None = None,
    workers: int | None = 0,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
    bases: Sequence[str] = (),
    snow: Any = None,
):
    """Sweep ``grid`` for each ski, ski model and base, fields included: an
    :class:`xarray.Dataset` with dims ``ski, model, base, mass_kg, load_position_mm,
    snow_modulus_mpa, zone, station``.

    Variables: ``x_mm`` (ski, station); ``pressure_kpa``, ``base_um``, ``snow_um`` and
    ``zone_code`` per point and station; the zone metrics of :data:`METRICS` and ``patches`` per
    point and zone (:data:`ZONES`); ``converged`` per point. A point whose load the ski cannot
    carry is NaN with ``converged = False``.

    ``ski_models``: ``'rigid'`` (the paper's method: the loaded profile from ``profile_source``
    pressed into the snow as a rigid body) and/or ``'flexible'`` (the beam and the half-space
    solved together). ``store``: a directory holding one resumable Zarr store per ski model
    (``explore_rigid.zarr``, ...; default: a temporary one); ``workers``/``scheduler`` as in
    :func:`skisnow.sweep.run_sweep` (``0``: in this process). ``progress(done, total)`` is
    called after each chunk (one ski, position and snow modulus, all masses, warm-started).

    ``bases`` (textures: ``'S1'``..``'S5'``, ``'smooth'``, files) with a ``snow``
    (:class:`~skisnow.snow.Snow`: its micro properties; the modulus is the grid's) add the real
    contact: ``real_fraction_percent`` and ``separation_um`` along the ski, the real area
    (grains) and viscous force per zone, ``mu`` and ``mu_lubricated`` per point. Without
    bases the ``base`` dimension has one empty entry.
    """
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep

    grid = grid or ExplorerGrid()
    models = tuple(ski_models)
    if not models or len(set(models)) != len(models) or set(models) - {"rigid", "flexible"}:
        raise InputError(f"ski models: need distinct 'rigid' and/or 'flexible', got {models}")
    textures = tuple(bases) or ("",)
    if bases and snow is None:
        raise InputError("bases: the real contact needs a snow (its temperature and grains)")
    if len(set(textures)) != len(textures):
        raise InputError(f"bases: need distinct textures, got {textures}")
    snow_text = ""
    if bases:
        import json

        from skisnow.snow import snow_record

        snow_text = json.dumps(snow_record(snow), sort_keys=True)
    specs = [
        SweepSpec(
            skis=tuple(skis),
            masses=grid.masses,
            load_positions=grid.load_positions,
            snow_moduli=grid.snow_moduli,
            profile_source=profile_source,
            n_points=grid.n_points,
            ski_model=model,
            **explorer_spec_options(grid.n_display),
            base=base,
            snow=snow_text if base else "",
        )
        for model in models
        for base in textures
    ]  # every input is checked here, before any store is created
    for spec in specs:
        if spec.base:  # the micro curves once, here (the workers read them from the cache)
            spec.micro_curves()
    total = sum(len(spec.chunks()) for spec in specs)
    done = 0

    def on_chunk(*_: object) -> None:
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total)

    # the temporary store on a RAM file system where the system has one (the client's time)
    with scratch_directory("explore", in_memory=True) as tmp:
        root = Path(tmp if store is None else store)
        parts: dict[str, Any] = {model: {} for model in models}
        for spec in specs:
            tag = spec.ski_model + (f"_{Path(spec.base).stem}" if spec.base else "")
            path = root / f"explore_{tag}.zarr"
            run_sweep(spec, path, workers=workers, scheduler=scheduler, on_progress=on_chunk)
            parts[spec.ski_model][Path(spec.base).name if spec.base else ""] = open_sweep(
                path
            ).load()
    if not bases:
        parts = {model: by_base[""] for model, by_base in parts.items()}
    return explorer_from_sweeps(parts, specs[0], snow=snow)


def explorer_spec_options(n_display: int) -> dict[str, object]:
    """What a :class:`skisnow.sweep.SweepSpec` needs beyond its grid to feed an explorer page:
    the explorer's zones and the fields on ``n_display`` stations (``SweepSpec(**grid,
    **explorer_spec_options(512))``)."""
    return {"zones": ZONES, "field_stations": int(n_display)}


def explorer_from_sweeps(sweeps: Mapping[str, Any], spec: Any, *, snow: Any = None):
    """The explorer's dataset from finished sweeps, one per ski model (``{'rigid': ds}``), each
    run with :func:`explorer_spec_options` (fields and the explorer's zones) on the skis and
    profile source of ``spec`` (a :class:`skisnow.sweep.SweepSpec`): a page can be built from a
    sweep that was run for something else (the demo's maps) without solving again.

    With base textures, each model maps to ``{base name: ds}`` instead (the sweeps run with
    ``SweepSpec.base`` and the ``snow`` of the real contact): the page gains the ``base``
    selector and the real contact along the ski."""
    import xarray as xr

    models = list(sweeps)
    if not models or set(models) - {"rigid", "flexible"}:
        raise InputError(f"ski models: need 'rigid' and/or 'flexible', got {models}")
    per_model = []
    names: list[str] | None = None
    for model in models:
        entry = sweeps[model]
        by_base = {"": entry} if isinstance(entry, xr.Dataset) else dict(entry)
        if names is not None and list(by_base) != names:
            raise InputError(f"the {model} sweeps hold other bases ({list(by_base)}) than {names}")
        names = list(by_base)
        parts = []
        for base, ds in by_base.items():
            keep = [*FIELDS, *METRICS, "patches", "converged", "x_mm"]
            keep += [*REAL_FIELDS, *REAL_METRICS, *REAL_POINT] if base else []
            missing = [v for v in keep if v not in ds]
            if missing or set(ZONES) - set(ds["zone"].values.tolist()):
                raise InputError(
                    f"the {model} sweep{f' of base {base}' if base else ''} lacks what the "
                    f"explorer shows ({', '.join(missing) or 'zones'}): run it with "
                    "skisnow.explore.explorer_spec_options"
                    + (" and the base and snow of the real contact" if base else "")
                )
            keep += ["iterations"] if "iterations" in ds else []  # "not carried" told apart
            parts.append(ds[keep].sel(zone=list(ZONES)))
        per_model.append(xr.concat(parts, dim=xr.DataArray(names, dims="base", name="base")))
    ds = xr.concat(per_model, dim=xr.DataArray(models, dims="model", name="model"))
    ds["x_mm"] = ds["x_mm"].isel(model=0, base=0, drop=True)
    ds = ds.transpose(*POINT, "zone", "station", missing_dims="ignore")
    # the kick-zone marks of each ski [mm] (NaN without a kick zone), drawn on the page
    marks = np.full((len(spec.skis), 2), np.nan)
    for k, label in enumerate(spec.skis):
        kz = spec.ski(label).kick_zone
        if kz is not None:
            marks[k] = (kz[0] * 1e3, kz[1] * 1e3)
    ds["kick_zone_mm"] = xr.DataArray(marks, dims=("ski", "mark"))
    ds.attrs = {"profile_source": spec.profile_source, "ski_models": models,
                "snow": "" if snow is None else snow.describe()}  # fmt: skip
    return ds
