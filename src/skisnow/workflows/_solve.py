"""The chain the workflows run per load case: loaded profile → contact → zones (SI units).

Kalliorinne et al. (2023): the loaded camber profile h = f(x, m, x_m) (eq. 1; the shipped
network, or the Euler–Bernoulli beam on the bench plane) pressed into the elastic half-space of
modulus E' (eq. 2) with force and moment balance about the load point (eq. 3). Profiles of many
load cases are computed in one batched network call; contacts can be warm-started.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Literal

import numpy as np

from skisnow._errors import DomainWarning, InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.workflows._skis import FleetSki

__all__ = [
    "KickContact",
    "ProfileRoute",
    "choose_route",
    "kick_zone_contact",
    "loaded_profiles",
    "solve_loaded",
    "stations",
]

ProfileRoute = Literal["network", "beam"]


def stations(fs: FleetSki, n_points: int) -> np.ndarray:
    """``n_points`` uniform stations [m] from tail to tip of the running surface."""
    if int(n_points) < 16:
        raise InputError(f"n_points must be at least 16, got {n_points}")
    return np.linspace(fs.ski.x_tail, fs.ski.x_tip, int(n_points))


def choose_route(
    fs: FleetSki,
    masses: np.ndarray,
    positions: np.ndarray,
    x: np.ndarray,
    *,
    requested: Literal["auto", "network", "beam"] = "auto",
) -> tuple[ProfileRoute, str | None]:
    """The profile route for these load cases and, if it had to change, why.

    The network route (the paper's method) is used where a shipped network exists and every
    load case lies in its trained domain; otherwise the beam (the virtual ski itself) — never a
    silent extrapolation of the network.

    Returns
    -------
    (route, note)
        ``note`` says why the beam replaced the network (``None`` when nothing changed).
    """
    if requested not in ("auto", "network", "beam"):
        raise InputError(f"profile source must be auto, network or beam, got {requested!r}")
    if requested == "beam":
        return "beam", None
    if fs.network is None:
        if requested == "network":
            raise InputError(f"{fs.label}: no camber network exists for this ski; use the beam")
        return "beam", None
    from skisnow.ski import shipped_network

    bad = shipped_network(fs.network).domain.violations(x, masses, positions)
    if not bad:
        return "network", None
    note = (
        f"{fs.label}: outside the camber network's trained domain ({'; '.join(bad)}): "
        "the beam route is used for every frame instead of extrapolating the network"
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
    """Loaded profiles h [m] of k load cases, shape ``(k, x.size)`` (eq. 1).

    The network predicts all cases in one call; the beam solves them one by one.
    """
    masses = np.atleast_1d(np.asarray(masses, dtype=float))
    positions = np.broadcast_to(np.asarray(positions, dtype=float), masses.shape)
    if masses.size == 0:
        return np.empty((0, x.size))
    if route == "network":
        from skisnow.ski import shipped_network

        with warnings.catch_warnings():
            warnings.simplefilter("error", DomainWarning)  # choose_route guarantees the domain
            h = shipped_network(fs.network).predict(x, masses, positions)  # type: ignore[arg-type]
        return np.asarray(h, dtype=float).reshape(masses.size, x.size)
    from skisnow.ski import solve_beam

    out = np.empty((masses.size, x.size))
    for row, m, p in zip(out, masses, positions, strict=True):
        row[:] = solve_beam(fs.ski, mass=float(m), load_position=float(p)).sample(x)
    return out


def solve_loaded(
    fs: FleetSki,
    x: np.ndarray,
    height: np.ndarray,
    *,
    mass: float,
    load_position: float,
    modulus: float,
    initial_pressure: np.ndarray | None = None,
):
    """Contact of one loaded profile on snow of equivalent modulus E' [Pa] (eq. 2–3).

    Returns ``(ContactSolution, ZoneMetrics)``; ``initial_pressure`` warm-starts the solver.
    """
    from skisnow.contact import contact_zones, solve_contact

    sol = solve_contact(
        x,
        height,
        load=float(mass) * STANDARD_GRAVITY,
        load_position=float(load_position),
        modulus=float(modulus),
        model="strip",
        width=fs.ski.width,
        initial_pressure=initial_pressure,
    )
    return sol, contact_zones(sol, kick_zone=fs.ski.kick_zone)


@dataclass(frozen=True, kw_only=True)
class KickContact:
    """Where the grip wax meets the snow: contact between the kick-zone marks (SI).

    Attributes
    ----------
    touching
        Any station between the marks carries pressure.
    length
        Contact length between the marks [m].
    force
        Force carried between the marks [N]; ``share`` = force / total load.
    """

    touching: bool
    length: float
    force: float
    share: float


def kick_zone_contact(solution, kick_zone: tuple[float, float] | None) -> KickContact:
    """Contact between the kick-zone marks of a :class:`~skisnow.contact.ContactSolution`.

    Counts every station in ``[start, end]`` whatever patch it belongs to — the question a
    classic skier asks is whether the grip wax touches, not how a patch is named. Skate skis
    (no kick zone): zeros.
    """
    if kick_zone is None:
        return KickContact(touching=False, length=0.0, force=0.0, share=0.0)
    x = solution.x
    inside = (x >= kick_zone[0]) & (x <= kick_zone[1]) & solution.contact_along
    q = solution.line_load
    force = float(q[inside].sum() * solution.dx)
    total = float(q.sum() * solution.dx)
    return KickContact(
        touching=bool(inside.any()),
        length=float(inside.sum() * solution.dx),
        force=force,
        share=force / total if total > 0 else 0.0,
    )
