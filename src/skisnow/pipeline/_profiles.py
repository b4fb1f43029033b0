"""The grid of one case and the loaded camber profiles on it (the first link of the chain).

Grid convention (one for every door into skisnow: ``solve_case``, ``skisnow contact``, the
sweeps, the report, the demo and the examples): ``n_points`` stations evenly spaced from the
tail to the tip of the running surface, both ends included,

    x_i = x_tail + i·Δx,  Δx = (x_tip − x_tail)/(n_points − 1),  i = 0 … n_points − 1,

each the centre of one contact cell of length Δx (the solver's cells therefore overhang the
running surface by Δx/2 at either end). The default, 4096 stations (Δx ≈ 0.5 mm on a 2 m
ski), resolves the contact lengths of Kalliorinne et al. (2023), Figures 4–9, to better than
1 mm.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError, UnsupportedLoadError

#: Profile sources: the shipped camber network or the beam model of the virtual ski.
PROFILE_SOURCES: tuple[str, ...] = ("network", "beam")
#: The default profile route of every ski (issue 26): the beam. A ski is defined by its EI(x)
#: and z0(x); its beam on the rigid plane (the virtual bench) is the truth of its loaded
#: profile, and the camber network (Kalliorinne et al. 2023, eq. 1) an emulator trained on it,
#: so the beam is the route with the smaller error against the truth. The network stays
#: available on request (``profile_source='network'``), with its error against the beam
#: stated in the documentation (``benchmarks/route_error.py``: on the shipped classic a median
#: 7.8 mm and at most 82 mm of total contact length over 48 cases; 245 against 327 mm at
#: 61 kg, −95 mm, 140 MPa).
DEFAULT_PROFILE_SOURCE: str = "beam"
#: Default number of stations along the ski (see the module docstring for the grid).
DEFAULT_N_POINTS: int = 4096


def resolve_ski(ski: object):  # -> Ski (skisnow.ski imported lazily)
    """A :class:`~skisnow.ski.Ski` from a Ski or anything :func:`skisnow.ski.get_ski` accepts."""
    from skisnow.ski import Ski, get_ski

    return ski if isinstance(ski, Ski) else get_ski(ski)  # type: ignore[arg-type]


def stations(ski: object, n_points: int = DEFAULT_N_POINTS) -> NDArray[np.float64]:
    """The stations x [m] of the grid convention (module docstring) on ``ski``."""
    if isinstance(n_points, bool) or int(n_points) != n_points or n_points < 16:
        raise InputError(f"n_points: need an integer >= 16, got {n_points!r}")
    s = resolve_ski(ski)
    return np.linspace(s.x_tail, s.x_tip, int(n_points))


def _check_source(profile_source: str) -> None:
    if profile_source not in PROFILE_SOURCES:
        raise InputError(f"profile_source: {profile_source!r} is not one of {PROFILE_SOURCES}")


def shipped_twin(ski: object) -> str | None:
    """The shipped ski whose content equals ``ski``'s (its name aside), or ``None``.

    Results depend on a ski's content, never on its name: a renamed copy of a shipped ski is
    that ski (same EI(x), z0(x), geometry, kick zone), and may use its camber network.
    """
    from dataclasses import replace

    from skisnow.ski import SHIPPED_SKIS, get_ski

    s = resolve_ski(ski)
    for name in SHIPPED_SKIS:
        shipped = get_ski(name)
        if replace(s, name=shipped.name) == shipped:
            return name
    return None


def _network_name(ski: object) -> str:
    """The shipped network's name for ``ski`` (a network exists for the shipped skis only)."""
    from skisnow.ski import SHIPPED_SKIS

    s = resolve_ski(ski)
    twin = shipped_twin(s)
    if twin is not None:
        return twin
    raise InputError(
        f"profile_source='network': camber networks are shipped for {', '.join(SHIPPED_SKIS)} "
        f"only, not for ski {s.name!r}; use profile_source='beam'"
    )


@lru_cache(maxsize=1024)
def _beam_profile(
    ski: object, mass: float, load_position: float, n_points: int
) -> NDArray[np.float64]:
    """Beam profile h [m] on the stations (cached, read-only); UnsupportedLoadError passes."""
    from skisnow.network import camber_profile

    _, h = camber_profile(
        resolve_ski(ski),
        mass=mass,
        load_position=load_position,
        x=stations(ski, n_points),
        source="beam",
    )
    h = np.asarray(h, dtype=float)
    h.setflags(write=False)
    return h


def loaded_profiles(
    ski: object,
    masses: ArrayLike,
    load_position: float,
    *,
    profile_source: str = DEFAULT_PROFILE_SOURCE,
    n_points: int = DEFAULT_N_POINTS,
    missing: str = "nan",
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Loaded camber profiles h(x; m, x_m) of one ski at one load position for several masses.

    Kalliorinne et al. (2023), eq. 1: h = f(x, m, x_m) on the stations of the grid convention
    (module docstring). The network predicts all masses in one batched call (measured 0.17 s for
    126 masses × 4096 stations, against 9 s one mass at a time); the beam solves mass by mass
    (cached per process).

    Parameters
    ----------
    ski
        A :class:`~skisnow.ski.Ski` or a name :func:`skisnow.ski.get_ski` accepts.
    masses
        Loads m [kg], a 1-D sequence.
    load_position
        x_m [m] from the balance point, positive toward the tip.
    profile_source
        ``'beam'`` (default, the virtual ski: :data:`DEFAULT_PROFILE_SOURCE` says why) or
        ``'network'`` (the shipped camber network, an emulator of the beam).
    n_points
        Stations along the ski.
    missing
        What a load the beam cannot carry gives: ``'nan'`` a row of NaN, ``'raise'`` the
        :class:`~skisnow.UnsupportedLoadError`.

    Returns
    -------
    x, heights
        Stations [m], shape ``(n_points,)``, and heights [m], shape ``(len(masses), n_points)``.
    """
    _check_source(profile_source)
    x = stations(ski, n_points)
    m = np.atleast_1d(np.asarray(masses, dtype=float))
    if m.ndim != 1:
        raise InputError(f"masses: need a 1-D sequence [kg], got shape {m.shape}")
    if profile_source == "network":
        from skisnow.network import camber_profile

        _, heights = camber_profile(
            _network_name(ski), mass=m, load_position=float(load_position), x=x, source="network"
        )
        return x, np.asarray(heights, dtype=float).reshape(m.size, x.size)
    s = resolve_ski(ski)
    rows = []
    for mass in m:
        try:
            rows.append(_beam_profile(s, float(mass), float(load_position), int(n_points)))
        except UnsupportedLoadError:
            if missing == "raise":
                raise
            rows.append(np.full(x.size, np.nan))
    return x, np.vstack(rows)
