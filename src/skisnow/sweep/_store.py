"""The Zarr store of a sweep: its layout, chunk-by-chunk writes, completion markers, resuming.

Layout (Zarr format 2 — its string coordinates are part of the specification, unlike format 3's
in zarr-python 3.x, which warns):

* coordinates ``ski``, ``mass_kg``, ``load_position_mm``, ``snow_modulus_mpa``, ``zone`` (field
  units, as the dimension names say);
* per zone and point: ``length_mm``, ``area_cm2``, ``mean_pressure_kpa``, ``max_pressure_kpa``,
  ``load_share``, ``patches``;
* per zone, independent of the snow (a property of the profile alone): ``breitschaedel_length_mm``,
  ``breitschaedel_area_cm2`` (the 50 µm criterion of Kalliorinne et al. 2023, §4);
* per point: ``iterations``, ``residual``, ``converged``;
* per chunk: ``chunk_done`` (int8, 1 = the chunk's data are completely written). It is the
  completion marker: written *after* the chunk's data, as its own uncompressed one-byte Zarr chunk,
  so a process killed at any instant leaves either a complete chunk with its marker, or a chunk
  without its marker (recomputed on resume). Never a marker without its data. (zarr-python 3's
  LocalStore also replaces each chunk file atomically, write-then-rename; the marker reader
  still treats an unreadable marker as "not done", for stores without that guarantee.)

The store is created from a template with ``Dataset.to_zarr(compute=False)`` (metadata and
coordinates only); each chunk is then written into its Zarr chunks
(:class:`skisnow.sweep._writer.ChunkWriter`). The
Zarr chunking equals the task chunking (one ski × one position × one modulus × all masses), so no
two tasks ever touch the same Zarr chunk.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from skisnow._errors import FileFormatError, InputError, SkisnowError
from skisnow.sweep._grid import SweepSpec

if TYPE_CHECKING:  # xarray is imported lazily: the store functions pay for it, not the package
    import xarray as xr

DIMS = ("ski", "mass_kg", "load_position_mm", "snow_modulus_mpa", "zone")
POINT_DIMS = DIMS[:4]
PROFILE_DIMS = ("ski", "mass_kg", "load_position_mm", "zone")
CHUNK_DIMS = ("ski", "load_position_mm", "snow_modulus_mpa")

#: The attribute that holds the sweep's inputs (canonical JSON of :class:`SweepSpec`).
SPEC_ATTR = "skisnow_sweep_spec"


@dataclass(frozen=True)
class _Var:
    dims: tuple[str, ...]
    dtype: str
    units: str
    long_name: str


#: Every variable a chunk function must return, with its dims (a chunk's arrays have the shape of
#: the dims minus ski/load_position_mm/snow_modulus_mpa: (n_mass, n_zone) or (n_mass,)).
VARIABLES: dict[str, _Var] = {
    "length_mm": _Var(DIMS, "float64", "mm", "apparent contact length of the zone"),
    "area_cm2": _Var(DIMS, "float64", "cm2", "apparent contact area of the zone"),
    "mean_pressure_kpa": _Var(DIMS, "float64", "kPa", "mean apparent pressure over the zone"),
    "max_pressure_kpa": _Var(DIMS, "float64", "kPa", "maximum apparent pressure in the zone"),
    "load_share": _Var(DIMS, "float64", "1", "fraction of the load m·g carried by the zone"),
    "patches": _Var(DIMS, "int32", "1", "number of separate contact patches in the zone"),
    "breitschaedel_length_mm": _Var(
        PROFILE_DIMS, "float64", "mm", "length where the loaded camber height is below 50 µm"
    ),
    "breitschaedel_area_cm2": _Var(
        PROFILE_DIMS, "float64", "cm2", "area where the loaded camber height is below 50 µm"
    ),
    "iterations": _Var(POINT_DIMS, "int32", "1", "iterations of the contact solver"),
    "residual": _Var(POINT_DIMS, "float64", "1", "final residual of the contact solver"),
    "converged": _Var(POINT_DIMS, "bool", "1", "the contact solver reached its tolerance"),
}


FIELD_DIMS = (*POINT_DIMS, "station")

#: The fields along the ski a sweep stores when ``spec.field_stations > 0`` (block means on the
#: display stations; float32: a display needs no more).
FIELD_VARIABLES: dict[str, _Var] = {
    "pressure_kpa": _Var(FIELD_DIMS, "float32", "kPa", "contact pressure (station block mean)"),
    "base_um": _Var(
        FIELD_DIMS, "float32", "um", "ski base above the undeformed snow, h − δ − θ(x − x_m)"
    ),
    "snow_um": _Var(FIELD_DIMS, "float32", "um", "snow surface, −u (station block mean)"),
    "zone_code": _Var(
        FIELD_DIMS,
        "int8",
        "1",
        "zone of the contact at the station: 0 none, 1 rear, 2 middle, 3 front",
    ),
    "x_mm": _Var(("ski", "station"), "float64", "mm", "display stations along the ski"),
}


#: The real contact a sweep stores when ``spec.base`` names a texture (per zone: the zone's
#: contact stations; ``total``: the whole ski, the gaps beside the patches included).
REAL_VARIABLES: dict[str, _Var] = {
    "real_area_mm2": _Var(DIMS, "float64", "mm2", "real contact area (flat-ice model)"),
    "real_area_grains_mm2": _Var(
        DIMS, "float64", "mm2", "real contact area (bearing model of ice grains)"
    ),
    "real_fraction": _Var(DIMS, "float64", "1", "real over apparent contact area"),
    "mean_separation_um": _Var(
        DIMS, "float64", "um", "mean base-snow separation over the apparent contact"
    ),
    "reciprocal_separation_m": _Var(
        DIMS, "float64", "m", "total reciprocal separation, integral of 1/u dA"
    ),
    "dry_force_n": _Var(DIMS, "float64", "N", "dry/adhesive friction proxy tau * A_r"),
    "viscous_force_n": _Var(DIMS, "float64", "N", "viscous friction proxy eta * v * int 1/u dA"),
    "mu": _Var(POINT_DIMS, "float64", "1", "(tau A_r + eta v int 1/u dA) / W, dry real contact"),
    "mu_lubricated": _Var(
        POINT_DIMS, "float64", "1", "(eta v A_r / u_c + eta v int 1/u dA) / W, lubricated spots"
    ),
}


#: Real-contact fields along the ski (with ``field_stations`` and a base): the explorer's curves.
REAL_FIELD_VARIABLES: dict[str, _Var] = {
    "real_fraction_percent": _Var(
        FIELD_DIMS, "float32", "percent", "real over apparent area where the ski bears"
    ),
    "separation_um": _Var(FIELD_DIMS, "float32", "um", "mean base-snow separation"),
}


def variables(spec: SweepSpec) -> dict[str, _Var]:
    """The variables of a sweep's store: :data:`VARIABLES`, :data:`FIELD_VARIABLES` when the
    spec asks for fields, :data:`REAL_VARIABLES` when it names a base texture."""
    out = VARIABLES | FIELD_VARIABLES if spec.field_stations else VARIABLES
    if spec.base:
        out = out | REAL_VARIABLES
        if spec.field_stations:
            out = out | REAL_FIELD_VARIABLES
    return out


def chunk_shapes(spec: SweepSpec) -> dict[str, tuple[int, ...]]:
    """Shape of each variable in one chunk's result (its dims less ski, position, modulus)."""
    sizes = {"mass_kg": len(spec.masses), "zone": len(spec.zones), "station": spec.field_stations}
    return {
        name: tuple(sizes[d] for d in var.dims if d in sizes)
        for name, var in variables(spec).items()
    }


def _coords(spec: SweepSpec) -> dict[str, Any]:
    if spec.field_stations:
        return _base_coords(spec) | {"station": np.arange(spec.field_stations)}
    return _base_coords(spec)


def _base_coords(spec: SweepSpec) -> dict[str, Any]:
    return {
        "ski": np.array(spec.skis, dtype=str),
        "mass_kg": np.array(spec.masses, dtype=float),
        "load_position_mm": np.round(np.array(spec.load_positions, dtype=float) * 1e3, 9),
        "snow_modulus_mpa": np.round(np.array(spec.snow_moduli, dtype=float) / 1e6, 9),
        "zone": np.array(spec.zones, dtype=str),
    }


def _fill(dtype: str) -> Any:
    return {"float64": np.nan, "float32": np.nan, "int32": 0, "bool": False, "int8": 0}[dtype]


def template(spec: SweepSpec, *, attrs: Mapping[str, Any]) -> xr.Dataset:
    """The lazy (Dask-backed) full dataset of a sweep, chunked as the tasks are."""
    import dask.array as da
    import xarray as xr

    coords = _coords(spec)
    sizes = {d: len(v) for d, v in coords.items()}
    task_chunk = {
        "ski": 1,
        "mass_kg": sizes["mass_kg"],
        "load_position_mm": 1,
        "snow_modulus_mpa": 1,
        "zone": sizes["zone"],
        "station": sizes.get("station", 0),
    }
    data_vars = {}
    for name, var in variables(spec).items():
        shape = tuple(sizes[d] for d in var.dims)
        chunks = tuple(task_chunk[d] for d in var.dims)
        arr = da.full(shape, _fill(var.dtype), dtype=var.dtype, chunks=chunks)
        data_vars[name] = (var.dims, arr, {"units": var.units, "long_name": var.long_name})
    shape = tuple(sizes[d] for d in CHUNK_DIMS)
    data_vars["chunk_done"] = (
        CHUNK_DIMS,
        da.zeros(shape, dtype="int8", chunks=(1,) * len(CHUNK_DIMS)),
        {"long_name": "1 when the chunk's data are completely written (completion marker)"},
    )
    ds = xr.Dataset(data_vars, coords=coords, attrs=dict(attrs))
    ds["mass_kg"].attrs.update(units="kg", long_name="loaded mass m (load m·g)")
    ds["load_position_mm"].attrs.update(
        units="mm", long_name="load position x_m from the balance point, + toward the tip"
    )
    ds["snow_modulus_mpa"].attrs.update(units="MPa", long_name="elastic modulus of the snow")
    return ds


def _encoding(spec: SweepSpec) -> dict[str, dict[str, Any]]:
    enc: dict[str, dict[str, Any]] = {}
    for name, var in variables(spec).items():
        if not var.dtype.startswith("float"):
            # No _FillValue: integers and booleans stay integers and booleans when read back.
            enc[name] = {"_FillValue": None}
    # The marker is one uncompressed byte per Zarr chunk: written whole or not at all.
    enc["chunk_done"] = {"_FillValue": None, "compressors": None}
    return enc


#: Tag of the temporary sibling a store is created in (``.STEM.creating-PID-RAND.zarr``, made by
#: :func:`skisnow._atomic.temporary_sibling`).
CREATING_TAG = "creating"


def lock_path(path: Path) -> Path:
    """The lock file of a store: a hidden sibling ``.NAME.lock`` (it must exist before the
    store does, so it cannot live inside it)."""
    return path.with_name(f".{path.name}.lock")


class StoreLock:
    """An exclusive, advisory lock on a sweep store (``fcntl.flock`` on :func:`lock_path`).

    A second sweep on the same store is refused at once with a message naming the process that
    holds it, instead of racing on the chunk files. The kernel releases the lock when its
    process ends, however it ends (a SIGKILLed sweep never leaves a stale lock). Standard
    library rather than the ``filelock`` package: POSIX ``flock`` is all skisnow needs (on
    platforms without ``fcntl`` the lock is skipped).
    """

    def __init__(self, path: str | Path, *, token: str | None = None) -> None:
        self.path = Path(path)
        self.token = token  # the run's token, on the file's second line (workers check it)
        self._fd: int | None = None

    def __enter__(self) -> StoreLock:
        import os

        try:
            import fcntl
        except ImportError:  # pragma: no cover - Windows: no advisory lock
            return self
        lock = lock_path(self.path)
        lock.parent.mkdir(parents=True, exist_ok=True)
        fd = os.open(str(lock), os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = (os.pread(fd, 64, 0).decode("ascii", "replace").split() or ["?"])[0]
            os.close(fd)
            raise SkisnowError(
                f"{self.path} is being written by another skisnow sweep (process {holder}); "
                "wait for it to finish (then run the same command to complete or reuse the "
                "store), or choose another --out"
            ) from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n{self.token or ''}\n".encode("ascii"), 0)
        self._fd = fd
        return self

    def __exit__(self, *exc: object) -> None:
        import os

        if self._fd is not None:
            os.close(self._fd)  # releases the flock
            self._fd = None


def create_store(path: Path, spec: SweepSpec, *, attrs: Mapping[str, Any]) -> None:
    """Create the store atomically: metadata and coordinates (``to_zarr(compute=False)``) are
    written into a temporary sibling directory, which is renamed onto ``path`` only when the
    skeleton is complete. So ``path`` exists only as a complete, resumable store; a process
    killed during creation leaves a ``.STEM.creating-*`` sibling
    (:func:`skisnow._atomic.temporary_sibling`) that the next run (holding the lock) removes.
    Call it with the store's :class:`StoreLock` held."""
    import os

    from skisnow._atomic import fsync_dir, remove_stale_siblings, temporary_sibling

    # left by a killed creation: stale whoever made it, as we hold the store's lock
    remove_stale_siblings(path, tags=(CREATING_TAG,), any_process=True)
    tmp = temporary_sibling(path, tag=CREATING_TAG)
    ds = template(spec, attrs=attrs)
    ds.to_zarr(
        tmp, mode="w-", compute=False, encoding=_encoding(spec), consolidated=False, zarr_format=2
    )
    os.rename(tmp, path)  # atomic; fails if something appeared at path meanwhile
    fsync_dir(path.parent)


def check_skeleton(path: Path, spec: SweepSpec) -> None:
    """Raise :class:`FileFormatError` unless every array of the sweep is in the store with the
    shape of ``spec`` (a store half-created by an older skisnow, or damaged by hand)."""
    import zarr

    sizes = {
        "ski": len(spec.skis),
        "mass_kg": len(spec.masses),
        "load_position_mm": len(spec.load_positions),
        "snow_modulus_mpa": len(spec.snow_moduli),
        "zone": len(spec.zones),
        "station": spec.field_stations,
    }
    group = zarr.open_group(str(path), mode="r")
    want = {name: var.dims for name, var in variables(spec).items()} | {"chunk_done": CHUNK_DIMS}
    want |= {d: (d,) for d in DIMS}
    if spec.field_stations:
        want["station"] = ("station",)
    for name, dims in want.items():
        shape = tuple(sizes[d] for d in dims)
        try:
            got = group[name].shape
        except Exception:
            got = None
        if got != shape:
            raise FileFormatError(
                f"{path}: incomplete or damaged sweep store (array {name!r} is "
                f"{'missing' if got is None else f'of shape {got}'}, expected {shape}); delete "
                "it and run the sweep again, or choose another --out"
            )


def read_spec(path: Path) -> SweepSpec:
    """The :class:`SweepSpec` stored in a sweep's Zarr store."""
    import zarr

    from skisnow._json import read_json_file

    for meta in sorted(Path(path).glob("**/.z*")) + sorted(Path(path).glob("**/zarr.json")):
        if meta.is_file():  # zarr parses them with json.loads: a nested bomb is refused here
            read_json_file(meta, what="sweep store metadata", max_bytes=64 << 20)
    try:
        group = zarr.open_group(str(path), mode="r")
        text = group.attrs[SPEC_ATTR]
    except (FileNotFoundError, KeyError, ValueError) as exc:
        raise FileFormatError(
            f"{path}: not a skisnow sweep store (no readable '{SPEC_ATTR}' attribute: {exc})"
        ) from None
    return SweepSpec.from_json(str(text), where=f"{path}: {SPEC_ATTR}")


def check_same_sweep(path: Path, spec: SweepSpec, stored_attrs: Mapping[str, Any]) -> None:
    """Raise :class:`InputError` if the store at ``path`` holds a different sweep than ``spec``."""
    stored = read_spec(path)
    if stored.to_json() == spec.to_json():
        return
    a, b = stored.__dict__, spec.__dict__
    diffs = [k for k in a if a[k] != b[k]]
    raise InputError(
        f"{path} already holds a different sweep (differs in: {', '.join(diffs)}); "
        "resuming needs exactly the same grid and options. Use another --out, or delete the "
        "store to start afresh."
    )


def done_chunks(path: Path, spec: SweepSpec) -> set[tuple[int, int, int]]:
    """Chunk keys whose completion marker is set.

    Read marker by marker: a marker file torn by a kill (empty or unreadable) counts as not done.
    """
    import zarr

    arr = zarr.open_array(str(path), path="chunk_done", mode="r")
    try:
        flags = np.asarray(arr[...])
    except Exception:  # a torn one-byte marker: read them one by one
        flags = np.zeros(arr.shape, dtype="int8")
        for key in spec.chunks():
            try:
                flags[key] = arr[key]
            except Exception:
                flags[key] = 0
    return {key for key in spec.chunks() if flags[key] == 1}


def open_sweep(path: str | Path, *, require_complete: bool = True) -> xr.Dataset:
    """Open a sweep's Zarr store as an in-memory :class:`xarray.Dataset`.

    With ``require_complete`` (default) a store with missing chunks raises :class:`InputError`
    saying how many are missing and that re-running the same ``skisnow sweep`` completes it.
    """
    import xarray as xr

    path = Path(path)
    spec = read_spec(path)
    ds = xr.open_zarr(path, consolidated=False, chunks=None).load()  # no Dask graph: 3-5x faster
    if require_complete:
        missing = int((ds["chunk_done"].values != 1).sum())
        if missing:
            raise InputError(
                f"{path}: {missing} of {ds['chunk_done'].size} chunks are not computed yet; run "
                "the same sweep again to complete it (finished chunks are kept)"
            )
    ds.attrs[SPEC_ATTR] = spec.to_json()
    return ds


def save_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Export a (complete) sweep dataset to NetCDF with the first engine available.

    The primary format is Zarr; NetCDF is an export. Engines tried: netCDF4, h5netcdf, scipy
    (NetCDF-3; booleans become int8 with a ``dtype`` attribute, as xarray encodes them).
    """
    import importlib.util

    from skisnow._atomic import atomic_path

    path = Path(path)
    for engine, module in (("netcdf4", "netCDF4"), ("h5netcdf", "h5netcdf"), ("scipy", "scipy")):
        if importlib.util.find_spec(module) is not None:
            # written whole or not at all: a killed export never leaves a .nc full of garbage
            with atomic_path(path) as tmp:
                ds.to_netcdf(tmp, engine=engine)
            return path
    raise InputError("no NetCDF engine is installed (netCDF4, h5netcdf or scipy); use Zarr")
