"""Warm the fork server of local clusters (imported through :data:`skisnow.sweep._run.PRELOAD`).

Importing this module solves one small case of the default sweep physics (a strip contact on a
beam profile, with its zones): the modules a chunk imports on its first call are then imported,
and numba's compiled kernels loaded from their on-disk cache, once in the fork server rather than
in every worker's first chunk (measured ~0.3 s of CPU a worker at load 9). The workers forked
from the server inherit them. It never raises: a fork server whose preload fails would start no
worker, and a cold worker is only slower.
"""

from __future__ import annotations

import contextlib


def warm() -> None:
    """Solve one strip case (the skate at 60 kg, x_m = −120 mm, 100 MPa, 4096 stations)."""
    from skisnow.pipeline import solve_case

    solve_case("skate", mass=60.0, load_position=-0.12, snow_modulus=100e6, workers=1)


with contextlib.suppress(Exception):  # a cold worker is only slower (module docstring)
    warm()
