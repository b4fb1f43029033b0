"""The physics of one sweep chunk: every mass of one (ski, x_m, E_counter), each point one case
of :func:`skisnow.pipeline.solve_case` (loaded profile, contact with force and moment balance,
zones; Kalliorinne et al. 2023, eq. 1–3), warm-started from the pressure of the previous
(lighter) mass: along the load path the contact patches move little, so the previous pressure is
a good start.

A point whose load the profile cannot carry (the solver raises :class:`UnsupportedLoadError`, e.g.
contact reaching a ski end) is recorded as NaN with ``converged = False`` rather than failing the
chunk: a map over loads legitimately has such corners. Any other error fails the chunk (and Dask
retries it).

Loaded profiles do not depend on the snow: :func:`loaded_profiles` computes those of all masses
of one (ski, x_m) once, shared by its chunks: beam profiles on the Dask workers in one part per
worker, network profiles in the sweep's client (the camber network's JAX never runs on the
workers); beam profiles are cached per process by :mod:`skisnow.pipeline`.
"""

from __future__ import annotations

import operator
from typing import Any

import numpy as np

from skisnow._errors import UnsupportedLoadError
from skisnow.sweep._grid import SweepSpec

#: Units of the stored variables: SI value × factor.
_TO_FIELD = {"length": 1e3, "area": 1e4, "mean_pressure": 1e-3, "max_pressure": 1e-3}


def loaded_profiles(
    spec: SweepSpec, ski_name: str, load_position: float, *, part: tuple[int, int] = (0, 1)
) -> dict[str, np.ndarray]:
    """The loaded profiles of the masses of ``spec`` at one (ski, x_m): ``{"x": (n_points,),
    "height": (n_mass, n_points)}`` [m], from :func:`skisnow.pipeline.loaded_profiles` (one
    batched network call; a load the beam cannot carry gives a row of NaN, recorded as a
    non-converged point). Shared by all snow moduli of the (ski, x_m).

    ``part=(k, n)``: only the k-th of n consecutive slices of the masses (``np.array_split``);
    :func:`merge_profiles` joins the parts. The sweep computes beam profiles in parts on its
    workers (:func:`split_profiles`), network profiles whole in its client.
    """
    from skisnow import pipeline

    if spec.ski_model == "flexible":  # the flexible ski needs no loaded profile
        return {}
    k, n = part
    x, heights = pipeline.loaded_profiles(
        spec.ski(ski_name),  # the definition the spec carries (a ski file's, or a shipped ski)
        np.array_split(np.asarray(spec.masses, dtype=float), n)[k],
        float(load_position),
        profile_source=spec.profile_source,
        n_points=spec.n_points,
    )
    return {"x": x, "height": heights}


def split_profiles(spec: SweepSpec) -> bool:
    """Whether a sweep on Dask computes the loaded profiles on its workers, in as many parts as
    workers (beam profiles: the 126 beam solves of a Figure 8/9 map cost ~0.2 s, serial in the
    client otherwise), or whole in the client (network profiles: one batched call, and JAX
    never runs on the workers)."""
    return spec.ski_model != "flexible" and spec.profile_source == "beam"


#: The last parts merged in this process and their merge (a worker gets the same part objects
#: for every chunk of a (ski, x_m): they are joined once, not once a chunk).
_MERGED: list[tuple[list[dict[str, np.ndarray]], dict[str, np.ndarray]]] = []


def merge_profiles(
    parts: dict[str, np.ndarray] | list[dict[str, np.ndarray]] | None,
) -> dict[str, np.ndarray] | None:
    """The profiles of all masses from :func:`loaded_profiles`'s parts (in order), or the
    whole as given. The same part objects as in the previous call give the previous merge (a
    4 MB copy a Figure 8/9 chunk otherwise, ~1 ms and the core's cache)."""
    if parts is None or isinstance(parts, dict):
        return parts
    if len(parts) == 1 or not parts[0]:
        return parts[0]
    last = _MERGED[0] if _MERGED else None
    if last and len(last[0]) == len(parts) and all(map(operator.is_, last[0], parts)):
        return last[1]
    merged = {"x": parts[0]["x"], "height": np.vstack([p["height"] for p in parts])}
    _MERGED[:] = [(list(parts), merged)]
    return merged


def solve_point(
    spec: SweepSpec,
    ski_name: str,
    mass: float,
    load_position: float,
    snow_modulus: float,
    *,
    initial_pressure: np.ndarray | None = None,
    profile: tuple[np.ndarray, np.ndarray] | None = None,
    ski: Any = None,
    media: dict[str, Any] | None = None,
):
    """One point of a sweep as a :class:`skisnow.pipeline.Case` (SI units), solved by
    :func:`skisnow.pipeline.solve_case` with the settings of ``spec``.

    ``profile`` (x, h) [m] skips computing the loaded profile; ``initial_pressure`` warm-starts
    the contact iteration; ``ski``, the :class:`~skisnow.ski.Ski` of ``ski_name`` if already
    resolved (a chunk resolves it once, not per mass); ``media``, the base, snow, micro curves
    and friction of the real contact if already resolved (:func:`real_media`). Raises
    :class:`UnsupportedLoadError` where the profile cannot carry the load.
    """
    from skisnow.pipeline import solve_case

    if media is None:
        media = real_media(spec, snow_modulus)
    return solve_case(
        spec.ski(ski_name) if ski is None else ski,
        mass=float(mass),
        load_position=float(load_position),
        model=spec.model,
        profile_source=spec.profile_source,
        n_points=spec.n_points,
        **media,
        poisson=spec.poisson,
        start=initial_pressure,
        profile=None if spec.ski_model == "flexible" else profile,
        ski_model=spec.ski_model,
        tol=spec.tol,
        workers=1,  # one FFT thread: parallelism comes from the Dask workers
    )


def real_media(spec: SweepSpec, snow_modulus: float) -> dict[str, Any]:
    """What :func:`skisnow.pipeline.solve_case` needs of the snow and the base at one modulus:
    with ``spec.base`` the textured base, the snow at this modulus, the micro curves and the
    friction parameters (the real contact); else the base modulus and the snow modulus."""
    if not spec.base:
        return {"base": spec.base_modulus, "snow_modulus": float(snow_modulus)}
    return {
        "base": spec.texture(),
        "snow": spec.snow_definition().replace(modulus=float(snow_modulus)),
        "curves": spec.micro_curves(),
        "friction": spec.friction_parameters(),
    }


def contact_chunk(
    spec: SweepSpec,
    ski_name: str,
    load_position: float,
    snow_modulus: float,
    profiles: dict[str, np.ndarray] | list[dict[str, np.ndarray]] | None = None,
) -> dict[str, np.ndarray]:
    """The chunk function of real sweeps: every mass of ``spec`` at one (ski, x_m, E_counter).

    ``profiles`` is :func:`loaded_profiles` of this (ski, x_m), or the list of its parts, if
    already computed. Returns the variables of :data:`skisnow.sweep.VARIABLES` in their stored
    (field) units.
    """
    profiles = merge_profiles(profiles)
    n_m, n_z = len(spec.masses), len(spec.zones)
    out: dict[str, np.ndarray] = {
        name: np.full((n_m, n_z), np.nan)
        for name in (
            "length_mm",
            "area_cm2",
            "mean_pressure_kpa",
            "max_pressure_kpa",
            "load_share",
            "breitschaedel_length_mm",
            "breitschaedel_area_cm2",
        )
    }
    out["patches"] = np.zeros((n_m, n_z), dtype=np.int32)
    out["iterations"] = np.zeros(n_m, dtype=np.int32)
    out["residual"] = np.full(n_m, np.nan)
    out["converged"] = np.zeros(n_m, dtype=bool)
    ski = spec.ski(ski_name)  # once per chunk: a shipped ski's file check or a ski file's parse
    n_f = spec.field_stations
    if n_f:
        from skisnow.pipeline import stations
        from skisnow.sweep._fields import block_mean, station_fields

        for name in ("pressure_kpa", "base_um", "snow_um"):
            out[name] = np.full((n_m, n_f), np.nan)
        out["zone_code"] = np.zeros((n_m, n_f), dtype=np.int8)
        out["x_mm"] = block_mean(stations(ski, spec.n_points), n_f) * 1e3
    if spec.base:
        from skisnow.sweep._store import REAL_FIELD_VARIABLES, REAL_VARIABLES

        for name, var in REAL_VARIABLES.items():
            out[name] = np.full((n_m, n_z) if "zone" in var.dims else n_m, np.nan)
        if n_f:
            for name in REAL_FIELD_VARIABLES:
                out[name] = np.full((n_m, n_f), np.nan)
    media = real_media(spec, snow_modulus)  # once per chunk: the modulus is the chunk's
    previous: np.ndarray | None = None
    for a, mass in enumerate(spec.masses):
        try:
            profile = None if not profiles else (profiles["x"], profiles["height"][a])
            case = solve_point(
                spec,
                ski_name,
                mass,
                load_position,
                snow_modulus,
                initial_pressure=previous,
                profile=profile,
                ski=ski,
                media=media,
            )
        except UnsupportedLoadError:
            previous = None
            continue
        solution, zones = case.solution, case.zones
        for q, name in enumerate(spec.zones):
            zone = zones[name]
            out["length_mm"][a, q] = zone.length * _TO_FIELD["length"]
            out["area_cm2"][a, q] = zone.area * _TO_FIELD["area"]
            out["mean_pressure_kpa"][a, q] = zone.mean_pressure * _TO_FIELD["mean_pressure"]
            out["max_pressure_kpa"][a, q] = zone.max_pressure * _TO_FIELD["max_pressure"]
            out["load_share"][a, q] = zone.load_share
            out["patches"][a, q] = zone.patches
            b = zones.breitschaedel.get(name)  # none for 'kick' (between the kick-zone marks)
            if b is not None:
                out["breitschaedel_length_mm"][a, q] = b.length * _TO_FIELD["length"]
                out["breitschaedel_area_cm2"][a, q] = b.area * _TO_FIELD["area"]
        out["iterations"][a] = solution.iterations
        out["residual"][a] = solution.residual
        out["converged"][a] = solution.converged
        if n_f:
            for name, value in station_fields(solution, zones, n_f).items():
                out[name][a] = value
        if case.real is not None:
            _real_point(out, a, case, spec.zones, n_f)
        previous = solution.pressure if (solution.converged and spec.warm_start) else None
    return out


def _real_point(out: dict[str, np.ndarray], a: int, case: Any, zones: tuple[str, ...],
                n_f: int) -> None:  # fmt: skip
    """The real contact of one point: per zone (a region: all its stations; a paper zone: its
    contact stations; ``total`` the whole ski) and, with fields, the real fraction and
    separation on the display stations."""
    from skisnow.pipeline import zone_station_masks

    real = case.real
    masks = zone_station_masks(case, zones)
    sums = real.sums(np.array([masks[z] for z in zones]))  # (zone, column)
    _, app, real_a, grains, sep, recip, dry, visc, lub = sums.T
    with np.errstate(invalid="ignore", divide="ignore"):
        out["real_fraction"][a] = np.where(app > 0, real_a / app, np.nan)
        out["mean_separation_um"][a] = np.where(app > 0, sep / app, np.nan) * 1e6
    out["real_area_mm2"][a] = real_a * 1e6
    out["real_area_grains_mm2"][a] = grains * 1e6
    out["reciprocal_separation_m"][a] = recip
    out["dry_force_n"][a] = dry
    out["viscous_force_n"][a] = visc
    t = zones.index("total") if "total" in zones else None
    if t is None:
        est = real.friction_estimate()
        out["mu"][a], out["mu_lubricated"][a] = est["mu"], est["mu_lubricated"]
    else:
        w = real.total_load
        out["mu"][a] = (dry[t] + visc[t]) / w
        out["mu_lubricated"][a] = (lub[t] + visc[t]) / w
    if n_f:
        from skisnow.sweep._fields import block_mean

        app_f = block_mean(real.apparent_area, n_f)
        with np.errstate(invalid="ignore", divide="ignore"):
            frac = np.where(app_f > 0, block_mean(real.real_area, n_f) / app_f, np.nan)
        out["real_fraction_percent"][a] = 100 * frac
        out["separation_um"][a] = block_mean(real.mean_separation, n_f) * 1e6
