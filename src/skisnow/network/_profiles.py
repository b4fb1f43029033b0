"""The one entry point downstream code calls for a loaded camber profile."""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError
from skisnow.ski import SHIPPED_SKIS, Ski, get_ski

__all__ = ["camber_profile"]


def camber_profile(
    ski_name: str | Ski,
    *,
    mass: float | ArrayLike,
    load_position: float,
    x: ArrayLike | None = None,
    source: Literal["beam", "network"] = "beam",
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Loaded camber profile h(x) of a ski: Kalliorinne et al. 2023, eq. 1, h = f(x, m, x_m).

    Parameters
    ----------
    ski_name
        a shipped ski name (``'classic'``, ``'skate'``) or, for ``source='beam'``,
        a :class:`~skisnow.ski.Ski` or the path of a ski file.
    mass
        load m [kg]; a 1-D array of k masses gives k profiles at once (the network
        predicts them in one call, ~50x faster than one call per mass).
    load_position
        x_m [m] from the balance point, positive toward the tip.
    x
        positions [m] on the ski; default: every 1 mm over the running surface.
    source
        ``'beam'`` — the virtual ski (Euler–Bernoulli beam on the rigid bench plane,
        :func:`~skisnow.ski.solve_beam`, Hermite-interpolated); ``'network'`` — the shipped
        camber network trained on the virtual bench.

    Returns
    -------
    x, height : ndarray
        Positions [m] and heights [m] (>= 0 for the beam); height has shape ``(n,)`` for a
        scalar mass and ``(k, n)`` for k masses.

    Raises
    ------
    UnsupportedLoadError
        (beam) a load the ski cannot carry on the bench plane.
    """
    if source not in ("beam", "network"):
        raise InputError(f"source must be 'beam' or 'network', got {source!r}")
    ski = ski_name if isinstance(ski_name, Ski) else get_ski(ski_name)
    if x is None:
        from skisnow.bench import bench_grid

        xs = bench_grid(ski)
    else:
        xs = np.asarray(x, dtype=float)
        if xs.ndim != 1 or xs.size == 0:
            raise InputError(f"x must be a non-empty 1-D array of positions [m], got {xs.shape}")
    masses = np.asarray(mass, dtype=float)
    if masses.ndim > 1:
        raise InputError(f"mass must be a number or a 1-D array [kg], got shape {masses.shape}")
    if source == "beam":
        from skisnow.ski import solve_beam

        if masses.ndim == 1:
            heights = np.empty((masses.size, xs.size))
            for row, m in zip(heights, masses, strict=True):
                row[:] = solve_beam(ski, mass=float(m), load_position=load_position).sample(xs)
            return xs, heights
        sol = solve_beam(ski, mass=float(masses), load_position=load_position)
        return xs, sol.sample(xs)
    if isinstance(ski_name, Ski) or ski_name not in SHIPPED_SKIS:
        what = ski.name if isinstance(ski_name, Ski) else ski_name
        raise InputError(
            f"ski {what!r}: the camber network exists only for the shipped skis "
            f"({', '.join(SHIPPED_SKIS)}); use the beam (source 'beam', --profile-source beam)"
        )
    from skisnow.network._files import shipped_network

    height = shipped_network(ski_name).predict(xs, masses, load_position)
    return xs, np.asarray(height, dtype=float)
