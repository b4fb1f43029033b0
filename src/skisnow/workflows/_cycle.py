"""A ski's contact over a load cycle: one load case per frame, warm-started along time.

Kalliorinne et al. (2023, §3.1) train the camber network so that a whole cycle of the diagonal
stride, double poling or a skating gear can be followed as a sequence of load cases. Each frame
of a :class:`~skisnow.workflows.LoadHistory` is one case: the loaded profile h = f(x, m, x_m)
(eq. 1) pressed into the elastic snow with force and moment balance (eq. 2–3). The contact
solve of a frame starts from the pressure of the previous loaded frame (the patches move little
between frames), and all network profiles come from one batched call.

Frames carrying less than :data:`UNLOADED_MASS` are the ski in the air or gliding unweighted
(the swing phase): they are not solved and carry zero contact.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from skisnow._errors import InputError, UnsupportedLoadError
from skisnow.workflows._history import LoadHistory, check_positions
from skisnow.workflows._skis import FleetSki, resolve_ski
from skisnow.workflows._solve import choose_route, loaded_profiles, solve_loaded, stations

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["UNLOADED_MASS", "ZONES", "kick_contact_summary", "real_cycle_summary", "run_cycle"]

#: Real-contact variables of a cycle with a base texture (per frame, the whole ski; SI).
_REAL_FIELDS = {
    "real_area": ("m2", "real contact area, bearing model of ice grains"),
    "real_area_flat": ("m2", "real contact area, flat-ice model"),
    "reciprocal_separation": ("m", "total reciprocal separation, integral of 1/u dA"),
    "dry_force": ("N", "dry/adhesive friction proxy tau * A_r"),
    "viscous_force": ("N", "viscous friction proxy eta * v * integral of 1/u dA"),
    "lubricated_force": ("N", "eta * v * A_r / u_c: contact spots sheared through the film"),
}

#: Below this load (as a mass, kg) a frame is the unloaded swing: not solved, no contact. It is
#: the lightest load the camber bench (and the shipped networks) cover.
UNLOADED_MASS: float = 5.0

#: The zones reported per frame: the paper's zones and the total, then the regions fixed by the
#: ski (``kick``: the kick-zone region, the contact between the kick-zone marks whatever patch it
#: belongs to — where the grip wax touches the snow; empty on a skate ski). The regions never
#: jump when two contact patches join (:func:`skisnow.contact.footprint`).
ZONES: tuple[str, ...] = ("rear", "middle", "front", "total", "rear_glide", "kick", "front_glide")

_ZONE_FIELDS = {
    "length": ("m", "contact length"),
    "area": ("m2", "contact area"),
    "force": ("N", "force carried"),
    "mean_pressure": ("Pa", "mean contact pressure (force / area)"),
    "max_pressure": ("Pa", "peak contact pressure"),
    "load_share": ("1", "share of the load carried"),
}


def run_cycle(
    ski: str | FleetSki,
    history: LoadHistory,
    *,
    snow_modulus: float,
    profile_source: Literal["auto", "network", "beam"] = "auto",
    n_points: int = 4096,
    keep_fields: bool = True,
    warm_start: bool = True,
    ski_model: Literal["rigid", "flexible"] = "rigid",
    progress: Callable[[int, int], None] | None = None,
    base: Any = None,
    snow: Any = None,
    friction: Any = None,
) -> xr.Dataset:
    """Contact of one ski over a load history → an :class:`xarray.Dataset` over time.

    Parameters
    ----------
    ski
        A shipped name, a ski file, or a resolved :class:`FleetSki`.
    history
        Force and centre of pressure over time (SI).
    snow_modulus
        Young's modulus of the snow [Pa] (E' of eq. 2 with the default ski base).
    profile_source
        ``'auto'``: the shipped network where it exists and every loaded frame lies in its
        trained domain, else the beam (the dataset's ``route_note`` says why); ``'network'`` or
        ``'beam'`` to insist.
    n_points
        Stations along the ski.
    keep_fields
        Keep h(x, t), p(x, t) and the snow displacement u(x, t) (for figures and animations).
    ski_model
        ``'rigid'``: the loaded profile pressed into the snow (the paper's method);
        ``'flexible'``: the ski's beam and the snow solved together (no network, no profile
        route; needs the ski's EI(x) and z0(x), which every ski file has).
    warm_start
        Start each frame's contact iteration from the previous loaded frame's pressure (it
        changes the iterations, not the answer; ``False`` only to measure what it saves).
    progress
        Called as ``progress(done, total)`` after each frame.
    base, snow, friction
        A base texture (:func:`skisnow.multiscale.make_base`), the :class:`~skisnow.snow.Snow`
        of its micro contact and :class:`~skisnow.multiscale.FrictionParameters`: each loaded
        frame then also carries the real contact of the whole ski and the friction proxies
        (``real_area``, ``real_area_flat``, ``reciprocal_separation``, ``dry_force``,
        ``viscous_force``, ``lubricated_force``; :func:`real_cycle_summary` over the stride).

    Returns
    -------
    xarray.Dataset
        Dimension ``time`` [s] (and ``zone``, ``x``): ``load`` (the force on the ski [N]),
        ``load_position``,
        ``loaded``; per zone of :data:`ZONES` ``length``, ``area``, ``force``,
        ``mean_pressure``, ``max_pressure``, ``load_share``, ``patches``; ``kick_contact``
        (the grip wax touches: contact between the kick-zone marks); ``translation``,
        ``rotation``, ``converged``; with ``keep_fields``
        ``height``, ``pressure``, ``snow_displacement`` over (time, x). SI units in ``attrs``.
        ``attrs`` also carry the route, its note, the history's source and the ski.

    Raises
    ------
    InputError
        A centre of pressure off the ski, a bad snow modulus.
    """
    import xarray as xr

    fs = resolve_ski(ski) if not isinstance(ski, FleetSki) else ski
    if not (np.isfinite(snow_modulus) and snow_modulus > 0):
        raise InputError(f"snow modulus must be a positive number of Pa, got {snow_modulus!r}")
    check_positions(history, x_tail=fs.ski.x_tail, x_tip=fs.ski.x_tip)
    x = stations(fs, n_points)
    n_t = history.time.size
    mass = history.mass
    loaded = mass >= UNLOADED_MASS
    idx = np.flatnonzero(loaded)
    if ski_model not in ("rigid", "flexible"):
        raise InputError(f"ski model must be rigid or flexible, got {ski_model!r}")
    heights = np.zeros((n_t, x.size))
    if ski_model == "flexible":
        route, note = "flexible", None
    else:
        route, note = choose_route(
            fs, mass[idx], history.load_position[idx], x, requested=profile_source
        )
        heights[idx] = loaded_profiles(fs, mass[idx], history.load_position[idx], x, route=route)
    if not loaded.all():
        # the unloaded ski: its free camber, shown in figures (not solved)
        heights[~loaded] = fs.ski.free_camber(x)
    nz = len(ZONES)
    zone_vals = {k: np.zeros((n_t, nz)) for k in _ZONE_FIELDS}
    for k in ("mean_pressure", "max_pressure"):
        zone_vals[k][:] = np.nan  # not defined without contact
    patches = np.zeros((n_t, nz), dtype=np.int64)
    merged = np.zeros(n_t, dtype=bool)
    translation = np.full(n_t, np.nan)
    rotation = np.full(n_t, np.nan)
    converged = np.ones(n_t, dtype=bool)
    iterations = np.zeros(n_t, dtype=np.int64)
    notes: list[str] = []
    fields = (
        {k: np.zeros((n_t, x.size)) for k in ("pressure", "snow_displacement")}
        if keep_fields
        else {}
    )
    micro = None
    real_vals = {}
    if base is not None:
        from skisnow.multiscale import FrictionParameters, make_base, micro_curves

        if snow is None:
            raise InputError("base: the real contact of a cycle needs the snow (snow=...)")
        curves = micro_curves(make_base(base), snow)
        resolved = (friction or FrictionParameters()).resolve(
            temperature_c=snow.temperature_c, hardness=curves.hardness
        )
        micro = (curves, resolved)
        real_vals = {k: np.zeros(n_t) for k in _REAL_FIELDS}
    start = None
    for done, i in enumerate(range(n_t), start=1):
        if loaded[i]:
            try:
                case = solve_loaded(
                    fs,
                    x,
                    heights[i],
                    mass=float(mass[i]),
                    load_position=float(history.load_position[i]),
                    snow_modulus=snow_modulus,
                    route=route,
                    start=start,
                )
            except UnsupportedLoadError as exc:
                raise InputError(
                    f"{history.name}: frame at t = {history.time[i]:g} s "
                    f"({mass[i]:.1f} kg at {history.load_position[i] * 1e3:.0f} mm): {exc}"
                ) from exc
            sol, zones = case.solution, case.zones
            heights[i] = case.height  # the bent ski on the flexible route
            start = sol.pressure if warm_start else None
            iterations[i] = sol.iterations
            notes += [f"t = {history.time[i]:g} s: {w}" for w in case.warnings]
            for j, name in enumerate(ZONES):
                z = zones[name]
                for k in _ZONE_FIELDS:
                    zone_vals[k][i, j] = getattr(z, k)
                patches[i, j] = z.patches
            merged[i] = zones.merged
            translation[i], rotation[i] = sol.translation, sol.rotation
            converged[i] = sol.converged
            if micro is not None:
                from skisnow.multiscale import real_contact

                r = real_contact(sol, *micro)
                t = r.total
                real_vals["real_area"][i] = t.real_area_grains
                real_vals["real_area_flat"][i] = t.real_area
                real_vals["reciprocal_separation"][i] = t.reciprocal_separation
                real_vals["dry_force"][i] = t.dry_force
                real_vals["viscous_force"][i] = t.viscous_force
                real_vals["lubricated_force"][i] = t.lubricated_force
            if keep_fields:
                fields["pressure"][i] = sol.pressure
                fields["snow_displacement"][i] = sol.displacement
        if progress is not None:
            progress(done, n_t)

    tz = ("time", "zone")
    data = {
        "load": ("time", history.force, {"units": "N", "long_name": "normal force on the ski"}),
        "load_position": (
            "time",
            history.load_position,
            {"units": "m", "long_name": "centre of pressure from the balance point"},
        ),
        "loaded": ("time", loaded, {"long_name": f"load >= {UNLOADED_MASS:g} kg (solved)"}),
        "patches": (tz, patches, {"long_name": "contact patches"}),
        "kick_contact": (
            "time",
            zone_vals["length"][:, ZONES.index("kick")] > 0,
            {"long_name": "grip wax touches the snow (contact between the kick-zone marks)"},
        ),
        "merged": (
            "time",
            merged,
            {"long_name": "the contact patches joined across the regions: zones = regions"},
        ),
        "translation": ("time", translation, {"units": "m"}),
        "rotation": ("time", rotation, {"units": "rad"}),
        "converged": ("time", converged, {}),
        "iterations": ("time", iterations, {"long_name": "contact solver iterations"}),
    }
    for k, (unit, long_name) in _ZONE_FIELDS.items():
        data[k] = (tz, zone_vals[k], {"units": unit, "long_name": long_name})
    for k, (unit, long_name) in _REAL_FIELDS.items():
        if k in real_vals:
            data[k] = ("time", real_vals[k], {"units": unit, "long_name": long_name})
    if keep_fields:
        data["height"] = (("time", "x"), heights, {"units": "m", "long_name": "loaded profile"})
        data["pressure"] = (("time", "x"), fields["pressure"], {"units": "Pa"})
        data["snow_displacement"] = (("time", "x"), fields["snow_displacement"], {"units": "m"})
    ds = xr.Dataset(
        data,
        coords={
            "time": ("time", history.time, {"units": "s"}),
            "zone": list(ZONES),
            "x": ("x", x, {"units": "m", "long_name": "position from the balance point"}),
        },
        attrs={
            "ski": fs.label,
            "ski_origin": fs.origin,
            "kick_zone": list(fs.ski.kick_zone) if fs.ski.kick_zone else [],
            "history": history.name,
            "history_source": history.source,
            "snow_modulus": float(snow_modulus),
            "route": route,
            "ski_model": ski_model,
            "route_note": note or "",
            "warnings": "\n".join(notes),
            "n_points": int(x.size),
            "unloaded_mass": UNLOADED_MASS,
            "base": "" if micro is None else micro[0].base,
            "snow": "" if micro is None else micro[0].snow,
            "friction": "" if micro is None else micro[1].assumptions(),
        },
    )
    return ds


def real_cycle_summary(ds: xr.Dataset) -> dict[str, float]:
    """The friction proxies over the cycle (a dataset of :func:`run_cycle` with a base).

    Each frame stands for the interval around it (as in :func:`kick_contact_summary`);
    unloaded frames carry no friction. Returns the time means over the cycle of the dry,
    viscous and lubricated forces [N], their impulses ∫F dt [N·s], the load impulse ∫W dt, and
    the cycle's µ = ∫(F_dry + F_visc) dt / ∫W dt and µ_lubricated.
    """
    if "viscous_force" not in ds:
        raise InputError("the cycle has no real contact (run it with a base and a snow)")
    t = np.asarray(ds["time"].values, dtype=float)
    edges = np.concatenate([[t[0]], 0.5 * (t[1:] + t[:-1]), [t[-1]]])
    dt = np.diff(edges)
    span = float(dt.sum())
    w = np.where(ds["loaded"].values, ds["load"].values, 0.0)
    out: dict[str, float] = {"load_impulse": float(np.sum(w * dt))}
    for k in ("dry_force", "viscous_force", "lubricated_force", "real_area"):
        v = np.asarray(ds[k].values, dtype=float)
        out[f"{k}_impulse" if k != "real_area" else "real_area_time"] = float(np.sum(v * dt))
        out[f"mean_{k}"] = float(np.sum(v * dt) / span) if span > 0 else float("nan")
    li = out["load_impulse"]
    out["mu"] = (out["dry_force_impulse"] + out["viscous_force_impulse"]) / li
    out["mu_lubricated"] = (out["lubricated_force_impulse"] + out["viscous_force_impulse"]) / li
    return out


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1, strict=True))


def kick_contact_summary(ds: xr.Dataset) -> dict[str, float | int]:
    """When and for how long the grip wax touches the snow over the cycle.

    Each frame stands for the time interval around it (half-way to its neighbours), so the
    contact time is the sum of those intervals over the frames with kick-zone contact; the
    resolution is one frame interval.

    Returns
    -------
    dict
        ``contact_time`` [s], ``loaded_time`` [s] (frames with load), ``fraction_of_loaded``,
        ``first_touch``/``last_touch`` [s] (NaN if never), ``episodes`` (separate touch-downs),
        ``max_kick_share`` and ``max_kick_length`` [m], ``resolution`` [s] (the longest frame
        interval: the times above are known to about that).
    """
    t = np.asarray(ds["time"].values, dtype=float)
    touch = np.asarray(ds["kick_contact"].values, dtype=bool)
    loaded = np.asarray(ds["loaded"].values, dtype=bool)
    edges = np.concatenate([[t[0]], 0.5 * (t[1:] + t[:-1]), [t[-1]]])
    dt = np.diff(edges)
    contact_time = float(dt[touch].sum())
    loaded_time = float(dt[loaded].sum())
    return {
        "contact_time": contact_time,
        "loaded_time": loaded_time,
        "fraction_of_loaded": contact_time / loaded_time if loaded_time > 0 else float("nan"),
        "first_touch": float(t[touch][0]) if touch.any() else float("nan"),
        "last_touch": float(t[touch][-1]) if touch.any() else float("nan"),
        "episodes": len(_runs(touch)),
        "max_kick_share": float(np.max(ds["load_share"].sel(zone="kick").values)),
        "max_kick_length": float(np.max(ds["length"].sel(zone="kick").values)),
        "resolution": float(np.max(np.diff(t))) if t.size > 1 else float("nan"),
    }
