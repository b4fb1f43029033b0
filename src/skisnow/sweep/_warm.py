"""Warm the fork server of local clusters (imported through :data:`skisnow.sweep._run.PRELOAD`).

Importing this module solves one small case of the default sweep physics (a strip contact on a
beam profile, with its zones): the modules a chunk imports on its first call are then imported,
and numba's compiled kernels loaded from their on-disk cache, once in the fork server rather than
in every worker's first chunk (measured ~0.3 s of CPU a worker at load 9). It imports the chunk
writer of the workers (and its compressor, ~0.1 s), and then freezes the garbage collector's
view of everything imported so far (:func:`gc.freeze`): the workers forked from the server
inherit ~180,000 objects that never become garbage, and a full collection that walks them cost
a worker ~0.1 s of CPU once a Figure 8/9 sweep (a full collection or none, depending on where
the allocation counters stood at the fork). It never raises: a fork server whose preload fails
would start no worker, and a cold worker is only slower.

Only the fork server imports this module (its :func:`gc.freeze` is meant for a process that
forks workers, as Python's documentation of it says).
"""

from __future__ import annotations

import contextlib
import gc


def warm() -> None:
    """Solve one strip case (the skate at 60 kg, x_m = −120 mm, 100 MPa, 4096 stations)."""
    from skisnow.pipeline import solve_case

    solve_case("skate", mass=60.0, load_position=-0.12, snow_modulus=100e6, workers=1)


def writer() -> None:
    """Import what a worker needs to write its chunks (the compressor's codecs)."""
    import numcodecs  # noqa: F401

    import skisnow.sweep._writer  # noqa: F401


with contextlib.suppress(Exception):  # a cold worker is only slower (module docstring)
    warm()
with contextlib.suppress(Exception):
    writer()
gc.collect()
gc.freeze()  # the workers' collections skip what the server imported (module docstring)
