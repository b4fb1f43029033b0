"""The physics of one sweep chunk: loaded profile + contact solve + zone metrics, per mass.

For one ski, one load position x_m and one snow modulus E_counter, along the masses m (ascending):

1. the rigid loaded camber profile h(x) = f(x, m, x_m) (Kalliorinne et al. 2023, eq. 1) from
   ``skisnow.ski.camber_profile`` (the shipped network, or the beam);
2. the apparent contact of that profile on an elastic half-space of equivalent modulus E'
   (eq. 2, E_base and ν of the spec) with force and moment balance about x_m (eq. 3), from
   ``skisnow.contact.solve_contact``, warm-started from the pressure of the previous (lighter)
   mass: along the load path the contact patches move little, so the previous pressure is a
   good start;
3. the zone metrics (rear / middle / front / total, Breitschädel 50 µm) from
   ``skisnow.contact.contact_zones``; the classic ski's kick zone defines its middle zone.

A point whose load the profile cannot carry (the solver raises :class:`UnsupportedLoadError`, e.g.
contact reaching a ski end) is recorded as NaN with ``converged = False`` rather than failing the
chunk: a map over loads legitimately has such corners. Any other error fails the chunk (and Dask
retries it).

Loaded profiles do not depend on the snow: :func:`loaded_profiles` computes those of all masses
of one (ski, x_m) once, in the sweep's client (the camber network's JAX never runs on the Dask
workers), and they are cached per process when computed point by point.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from skisnow._errors import UnsupportedLoadError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.sweep._grid import SweepSpec

#: Units of the stored variables: SI value × factor.
_TO_FIELD = {"length": 1e3, "area": 1e4, "mean_pressure": 1e-3, "max_pressure": 1e-3}


@lru_cache(maxsize=4096)
def _profile(
    ski_name: str, source: str, mass: float, load_position: float, n_points: int
) -> tuple[np.ndarray, np.ndarray]:
    """Loaded profile (x, h) [m] on ``n_points`` uniform stations from tail to tip (cached)."""
    from skisnow.ski import camber_profile, get_ski

    ski = get_ski(ski_name)
    x = np.linspace(ski.x_tail, ski.x_tip, n_points)
    xs, h = camber_profile(ski_name, mass=mass, load_position=load_position, x=x, source=source)  # type: ignore[arg-type]
    xs, h = np.asarray(xs, dtype=float), np.asarray(h, dtype=float)
    xs.setflags(write=False)
    h.setflags(write=False)
    return xs, h


def loaded_profiles(spec: SweepSpec, ski_name: str, load_position: float) -> dict[str, np.ndarray]:
    """The loaded profiles of every mass of ``spec`` at one (ski, x_m): ``{"x": (n_points,),
    "height": (n_mass, n_points)}`` [m]. Shared by all snow moduli of the (ski, x_m); the sweep
    computes it once in the client and scatters it to the workers.

    Network profiles come from one batched call over all masses (measured 0.17 s for 126 masses
    × 4096 stations, against 9 s one mass at a time); beam profiles mass by mass, a load the beam
    cannot carry giving a row of NaN (recorded as a non-converged point).
    """
    from skisnow.ski import camber_profile, get_ski

    ski = get_ski(ski_name)  # an unknown ski is an InputError here, in the client
    x = np.linspace(ski.x_tail, ski.x_tip, spec.n_points)
    masses = np.asarray(spec.masses, dtype=float)
    if spec.profile_source == "network":
        x, heights = camber_profile(
            ski_name, mass=masses, load_position=float(load_position), x=x, source="network"
        )
        return {"x": np.asarray(x), "height": np.asarray(heights).reshape(masses.size, x.size)}
    rows = []
    for mass in masses:
        try:
            x, h = _profile(
                ski_name, spec.profile_source, float(mass), float(load_position), spec.n_points
            )
        except UnsupportedLoadError:
            h = np.full(spec.n_points, np.nan)
        rows.append(h)
    return {"x": np.asarray(x), "height": np.vstack(rows)}


def solve_point(
    spec: SweepSpec,
    ski_name: str,
    mass: float,
    load_position: float,
    snow_modulus: float,
    *,
    initial_pressure: np.ndarray | None = None,
    profile: tuple[np.ndarray, np.ndarray] | None = None,
):
    """One point of a sweep: ``(ContactSolution, ZoneMetrics)`` (SI units).

    ``profile`` (x, h) [m] skips computing the loaded profile. Raises
    :class:`UnsupportedLoadError` where the profile cannot carry the load.
    """
    from skisnow.contact import contact_zones, effective_modulus, solve_contact
    from skisnow.ski import get_ski

    ski = get_ski(ski_name)
    if profile is None:
        x, h = _profile(
            ski_name, spec.profile_source, float(mass), float(load_position), spec.n_points
        )
    else:
        x, h = profile
        if not np.all(np.isfinite(h)):
            raise UnsupportedLoadError(f"no loaded profile of {ski_name} at m = {mass} kg")
    modulus = effective_modulus(snow_modulus, spec.base_modulus, poisson=spec.poisson)
    solution = solve_contact(
        x,
        h,
        load=float(mass) * STANDARD_GRAVITY,
        load_position=float(load_position),
        modulus=modulus,
        model=spec.model,
        width=ski.width,
        initial_pressure=initial_pressure,
        tol=spec.tol,
        workers=1,  # one FFT thread: parallelism comes from the Dask workers
    )
    zones = contact_zones(solution, kick_zone=ski.kick_zone)
    return solution, zones


def contact_chunk(
    spec: SweepSpec,
    ski_name: str,
    load_position: float,
    snow_modulus: float,
    profiles: dict[str, np.ndarray] | None = None,
) -> dict[str, np.ndarray]:
    """The chunk function of real sweeps: every mass of ``spec`` at one (ski, x_m, E_counter).

    ``profiles`` is :func:`loaded_profiles` of this (ski, x_m), if already computed. Returns the
    variables of :data:`skisnow.sweep.VARIABLES` in their stored (field) units.
    """
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
    previous: np.ndarray | None = None
    for a, mass in enumerate(spec.masses):
        try:
            profile = None if profiles is None else (profiles["x"], profiles["height"][a])
            solution, zones = solve_point(
                spec,
                ski_name,
                mass,
                load_position,
                snow_modulus,
                initial_pressure=previous,
                profile=profile,
            )
        except UnsupportedLoadError:
            previous = None
            continue
        for q, name in enumerate(spec.zones):
            zone = zones[name]
            out["length_mm"][a, q] = zone.length * _TO_FIELD["length"]
            out["area_cm2"][a, q] = zone.area * _TO_FIELD["area"]
            out["mean_pressure_kpa"][a, q] = zone.mean_pressure * _TO_FIELD["mean_pressure"]
            out["max_pressure_kpa"][a, q] = zone.max_pressure * _TO_FIELD["max_pressure"]
            out["load_share"][a, q] = zone.load_share
            out["patches"][a, q] = zone.patches
            b = zones.breitschaedel[name]
            out["breitschaedel_length_mm"][a, q] = b.length * _TO_FIELD["length"]
            out["breitschaedel_area_cm2"][a, q] = b.area * _TO_FIELD["area"]
        out["iterations"][a] = solution.iterations
        out["residual"][a] = solution.residual
        out["converged"][a] = solution.converged
        previous = solution.pressure if (solution.converged and spec.warm_start) else None
    return out
