"""The load cases of a workflow through the one-case pipeline (SI units).

Every case is :func:`skisnow.pipeline.solve_case` (Kalliorinne et al. 2023: the loaded camber
profile h = f(x, m, x_m), eq. 1, pressed into the elastic half-space with force and moment
balance, eq. 2–3, and grouped into zones). What the workflows add: the profiles of many load
cases at once (one batched network call even when the load position changes from case to case,
as along a stride), the choice of the profile route, and warm starts along a sequence.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Literal

import numpy as np

from skisnow._errors import DomainWarning, InputError
from skisnow.workflows._skis import FleetSki

if TYPE_CHECKING:
    from skisnow.pipeline import Case

__all__ = ["ProfileRoute", "choose_route", "loaded_profiles", "solve_loaded", "stations"]

ProfileRoute = Literal["network", "beam"]


def stations(fs: FleetSki, n_points: int) -> np.ndarray:
    """The stations [m] of the pipeline's grid convention on the ski."""
    from skisnow.pipeline import stations as pipeline_stations

    return pipeline_stations(fs.ski, n_points)


def choose_route(
    fs: FleetSki,
    masses: np.ndarray,
    positions: np.ndarray,
    x: np.ndarray,
    *,
    requested: Literal["auto", "network", "beam"] = "auto",
) -> tuple[ProfileRoute, str | None]:
    """The profile route for these load cases and, if it had to change, why.

    ``auto`` is the default route of every ski, the beam (the truth of a ski defined by EI(x)
    and z0(x), :data:`skisnow.pipeline.DEFAULT_PROFILE_SOURCE`); ``network`` asks for the
    shipped camber network (the paper's method, an emulator of the beam) where one exists for
    the ski's content and every load case lies in its trained domain — never a silent
    extrapolation of the network.

    Returns
    -------
    (route, note)
        ``note`` says why the beam replaced the network (``None`` when nothing changed).
    """
    if requested not in ("auto", "network", "beam"):
        raise InputError(f"profile source must be auto, network or beam, got {requested!r}")
    if requested in ("beam", "auto"):
        return "beam", None
    if fs.network is None:
        if requested == "network":
            raise InputError(f"{fs.label}: no camber network exists for this ski; use the beam")
        return "beam", None
    if masses.size == 0:
        return "network", None
    from skisnow.network import shipped_network

    bad = shipped_network(fs.network).domain.violations(x, masses, positions)
    if not bad:
        return "network", None
    if requested == "network":
        raise InputError(
            f"{fs.label}: the camber network would extrapolate ({'; '.join(bad)}); use the "
            "beam (profile source auto or beam)"
        )
    note = (
        f"{fs.label}: outside the camber network's trained domain ({'; '.join(bad)}): "
        "the beam route is used instead of extrapolating the network"
    )
    return "beam", note


def loaded_profiles(
    fs: FleetSki,
    masses: np.ndarray,
    positions: np.ndarray,
    x: np.ndarray,
    *,
    route: ProfileRoute,
) -> np.ndarray:
    """Loaded profiles h [m] of k load cases (m_k, x_m,k), shape ``(k, x.size)`` (eq. 1).

    The network predicts all cases in one call, whatever their load positions; the beam solves
    them one by one through :func:`skisnow.pipeline.loaded_profiles` (cached per process).
    """
    masses = np.atleast_1d(np.asarray(masses, dtype=float))
    positions = np.broadcast_to(np.asarray(positions, dtype=float), masses.shape)
    if masses.size == 0:
        return np.empty((0, x.size))
    if route == "network":
        from skisnow.network import shipped_network

        with warnings.catch_warnings():
            warnings.simplefilter("error", DomainWarning)  # choose_route guarantees the domain
            h = shipped_network(fs.network).predict(x, masses, positions)  # type: ignore[arg-type]
        return np.asarray(h, dtype=float).reshape(masses.size, x.size)
    from skisnow.pipeline import loaded_profiles as pipeline_profiles

    out = np.empty((masses.size, x.size))
    for row, m, p in zip(out, masses, positions, strict=True):
        _, h = pipeline_profiles(
            fs.ski, (float(m),), float(p), profile_source="beam", n_points=x.size, missing="raise"
        )
        row[:] = h[0]
    return out


def solve_loaded(
    fs: FleetSki,
    x: np.ndarray,
    height: np.ndarray | None,
    *,
    mass: float,
    load_position: float,
    snow_modulus: float,
    route: ProfileRoute | Literal["flexible"],
    start: np.ndarray | None = None,
) -> Case:
    """One case on snow of modulus E [Pa] (``start`` warm-starts the contact iteration).

    ``route`` ``'network'``/``'beam'``: the rigid loaded profile ``height`` through
    :func:`skisnow.pipeline.solve_case` (the paper's method). ``'flexible'``: the free
    Euler–Bernoulli ski and the half-space solved together, through
    ``solve_case(..., ski_model="flexible")`` on the same stations (``height`` is not used);
    the :class:`~skisnow.pipeline.Case`'s ``height`` is the bent ski z0 + w.

    Returns the :class:`~skisnow.pipeline.Case`.
    """
    from skisnow.pipeline import solve_case

    if route == "flexible":
        return solve_case(
            fs.ski,
            mass=float(mass),
            load_position=float(load_position),
            snow_modulus=float(snow_modulus),
            n_points=int(x.size),
            start=start,
            ski_model="flexible",
        )
    return solve_case(
        fs.ski,
        mass=float(mass),
        load_position=float(load_position),
        snow_modulus=float(snow_modulus),
        profile_source=route,
        profile=(x, height),
        start=start,
    )
