"""The virtual camber bench: the paper's measurement sequence run on the beam model.

Kalliorinne et al. (2023), §3.1: the SkiSelector measured the camber profile of
each ski "at loads ranging from 5 kg to 130 kg, positioned between 40 mm and 240 mm behind the
balance point"; the complete specification was in Fig. 2 (middle), which the text extraction
lost. The defaults here are therefore skisnow's choice: masses 5, 10, ..., 130 kg (5 kg steps,
26 masses) at positions -40, -80, ..., -240 mm (40 mm steps, 6 positions), i.e. 156 profiles per
ski, each sampled every 1 mm over the whole running surface (a bench-like step).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Literal

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from skisnow import __version__
from skisnow._errors import InputError
from skisnow._values import sorted_unique
from skisnow.bench._data import BenchData
from skisnow.ski import (
    DEFAULT_BOOT_LENGTH,
    DEFAULT_N_ELEMENTS,
    BeamSolution,
    Ski,
    get_ski,
    solve_beam,
)

__all__ = ["DEFAULT_LOAD_POSITIONS", "DEFAULT_MASSES", "bench_grid", "run_bench"]

#: Default bench masses [kg]: 5 to 130 kg in 5 kg steps.
DEFAULT_MASSES: tuple[float, ...] = tuple(float(m) for m in range(5, 131, 5))
#: Default load positions [m]: 40 to 240 mm behind the balance point in 40 mm steps.
DEFAULT_LOAD_POSITIONS: tuple[float, ...] = tuple(-p / 1000.0 for p in range(40, 241, 40))


def bench_grid(ski: Ski, dx: float = 1e-3) -> NDArray[np.float64]:
    """Sample positions [m] of a bench profile: every ``dx`` from the tail, within the ski.

    Positions are multiples of ``dx`` measured from the balance point (so x = 0 is sampled),
    covering [x_tail, x_tip].
    """
    if not (np.isfinite(dx) and dx > 0):
        raise InputError(f"dx must be > 0 m, got {dx}")
    k0 = int(np.ceil(ski.x_tail / dx - 1e-9))
    k1 = int(np.floor(ski.x_tip / dx + 1e-9))
    if k1 - k0 < 2:
        raise InputError(f"dx = {dx} m is too coarse for a {ski.length} m ski")
    return np.clip(np.arange(k0, k1 + 1) * dx, ski.x_tail, ski.x_tip)


def run_bench(
    ski: Ski | str,
    *,
    masses: Sequence[float] | ArrayLike = DEFAULT_MASSES,
    load_positions: Sequence[float] | ArrayLike = DEFAULT_LOAD_POSITIONS,
    dx: float = 1e-3,
    noise: float = 0.0,
    seed: int | None = None,
    progress: Callable[[int, int], None] | None = None,
    boot_length: float = DEFAULT_BOOT_LENGTH,
    n_elements: int = DEFAULT_N_ELEMENTS,
    contact: Literal["continuous", "nodal"] = "nodal",
) -> BenchData:
    """Run the virtual camber bench on ``ski`` and return the tidy bench table.

    Parameters
    ----------
    ski
        a :class:`Ski` or the name of a shipped ski.
    masses
        masses m [kg] (each > 0); default 5..130 kg in 5 kg steps.
    load_positions
        positions x_m [m] from the balance point (negative = behind);
        default -0.040..-0.240 m in 40 mm steps.
    dx
        sampling step [m] along the ski (default 1 mm).
    noise
        standard deviation [m] of Gaussian height noise added to every sample (a bench's
        resolution is about 1e-5 m); 0 (default) for exact beam heights. With noise, heights
        are not clipped, so samples in contact can read slightly below 0 as on a real bench.
    seed
        seed of the noise generator (NumPy ``default_rng``).
    progress
        called as ``progress(done, total)`` after each profile (e.g. a Rich bar).
    boot_length, n_elements, contact
        passed to :func:`~skisnow.ski.solve_beam` (``contact='continuous'``: no dip through the
        stone between nodes, the beam of the identification; the default ``'nodal'`` is
        :func:`~skisnow.ski.solve_beam`'s, whose numbers the bench reproduces exactly).

    Returns
    -------
    BenchData
        Columns ski, mass_kg, load_position_mm, x_mm, height_mm (profiles ordered by
        position, then mass) and metadata.

    The masses at one position are solved in increasing order, each warm-started from the
    previous contact set; the profile is sampled with the Hermite shape functions of the beam.
    """
    ski = get_ski(ski) if isinstance(ski, str) else ski
    if not isinstance(ski, Ski):
        raise InputError(f"ski must be a Ski or a shipped ski name, got {type(ski).__name__}")
    ms = sorted_unique(masses, name="masses", unit="kg")
    if np.any(ms <= 0):
        raise InputError(f"masses must be > 0 kg, got {ms[ms <= 0].tolist()}")
    ps = sorted_unique(load_positions, name="load_positions", unit="m")[::-1]
    if not (np.isfinite(noise) and noise >= 0):
        raise InputError(f"noise must be >= 0 m, got {noise}")
    x = bench_grid(ski, dx)
    rng = np.random.default_rng(seed)
    total = ms.size * ps.size
    heights = np.empty((ps.size, ms.size, x.size))
    done = 0
    for i, p in enumerate(ps):
        prev: BeamSolution | None = None
        for j, m in enumerate(ms):
            sol = solve_beam(
                ski,
                mass=float(m),
                load_position=float(p),
                boot_length=boot_length,
                n_elements=n_elements,
                warm_start=prev,
                contact=contact,
            )
            heights[i, j] = sol.sample(x)
            prev = sol
            done += 1
            if progress is not None:
                progress(done, total)
    if noise > 0:
        heights = heights + rng.normal(0.0, noise, size=heights.shape)
    n = x.size
    table = pd.DataFrame(
        {
            "ski": np.full(total * n, ski.name, dtype=object),
            "mass_kg": np.tile(np.repeat(ms, n), ps.size),
            "load_position_mm": np.repeat(ps * 1e3, ms.size * n),
            "x_mm": np.tile(x * 1e3, total),
            "height_mm": heights.reshape(-1) * 1e3,
        }
    )
    metadata = {
        **ski.summary_mm(),
        "balance_point": "x_mm = 0; x_mm and load_position_mm positive toward the tip",
        "kick_zone_mm": None if ski.kick_zone is None else [v * 1e3 for v in ski.kick_zone],
        "source": "virtual bench: skisnow Euler-Bernoulli beam on a rigid plane",
        "device": "skisnow.ski.run_bench",  # what bench files record (kept when it moved)
        "skisnow_version": __version__,
        "boot_length_mm": boot_length * 1e3,
        "n_elements": int(n_elements),
        "dx_mm": dx * 1e3,
        "noise_mm": noise * 1e3,
        "seed": seed,
        "units": {
            "mass_kg": "kg",
            "load_position_mm": "mm",
            "x_mm": "mm",
            "height_mm": "mm",
        },
    }
    return BenchData(table=table, metadata=metadata)
