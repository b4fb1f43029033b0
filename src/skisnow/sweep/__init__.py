"""Sweeps of the contact over ski, load and snow, on Dask, resumable, as xarray datasets.

Each point of a sweep is a loaded camber profile (``skisnow.network.camber_profile``, network or
beam) and a contact solve on elastic snow (``skisnow.contact.solve_contact``, force and moment
balance, Kalliorinne et al. 2023, eq. 2–3), summarised per zone (``skisnow.contact.contact_zones``).
The result is an :class:`xarray.Dataset` with dims ``ski, mass_kg, load_position_mm,
snow_modulus_mpa, zone`` written chunk by chunk into a Zarr store (see :mod:`._store`).

>>> spec = SweepSpec(skis=("skate",), masses=range(5, 131), load_positions=(-0.12,),
...                  snow_moduli=np.arange(20e6, 401e6, 20e6))           # doctest: +SKIP
>>> run_sweep(spec, "fig8.zarr")                                          # doctest: +SKIP
>>> ds = open_sweep("fig8.zarr")                                          # doctest: +SKIP

May import: ski, pipeline, snow, multiscale
"""

from skisnow.sweep._fields import block_mean, station_fields, unconverged_points, zone_codes
from skisnow.sweep._grid import (
    MODELS,
    PAPER_BASE_MODULUS,
    PAPER_POISSON,
    PROFILE_SOURCES,
    ZONES,
    SweepSpec,
    parse_values,
)
from skisnow.sweep._run import (
    ChunkFunction,
    ProgressCallback,
    SweepRun,
    default_workers,
    prepare_store,
    run_sweep,
)
from skisnow.sweep._store import (
    FIELD_VARIABLES,
    REAL_FIELD_VARIABLES,
    REAL_VARIABLES,
    VARIABLES,
    open_sweep,
    read_spec,
    save_netcdf,
)


def __getattr__(name: str):  # the physics chunk function imports the solvers only when asked
    if name in ("contact_chunk", "solve_point"):
        from skisnow.sweep import _point

        return getattr(_point, name)
    raise AttributeError(name)


__all__ = [
    "FIELD_VARIABLES",
    "MODELS",
    "PAPER_BASE_MODULUS",
    "PAPER_POISSON",
    "PROFILE_SOURCES",
    "REAL_FIELD_VARIABLES",
    "REAL_VARIABLES",
    "VARIABLES",
    "ZONES",
    "ChunkFunction",
    "ProgressCallback",
    "SweepRun",
    "SweepSpec",
    "block_mean",
    "contact_chunk",
    "default_workers",
    "open_sweep",
    "parse_values",
    "prepare_store",
    "read_spec",
    "run_sweep",
    "save_netcdf",
    "solve_point",
    "station_fields",
    "unconverged_points",
    "zone_codes",
]
