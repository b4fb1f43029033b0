"""Which solves of a run did not converge: a process-wide record the one door of a case
(:func:`skisnow.pipeline.solve_case`) writes to, so a command can say how many of its solves did
not converge and name the first, whatever route they took (sweeps in this process, the standard
loads of a report, a fleet, a pairing, every frame of a cycle). Solves run by Dask workers in
other processes are read from their sweep's store instead (``converged`` per point)."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

__all__ = ["note_unconverged", "recording_unconverged"]

_LOCK = threading.Lock()
_LOG: list[list[str]] = []


@contextlib.contextmanager
def recording_unconverged() -> Iterator[list[str]]:
    """Collect, in the yielded list, a label for every solve that does not converge inside the
    block (in this process, any thread)."""
    log: list[str] = []
    with _LOCK:
        _LOG.append(log)
    try:
        yield log
    finally:
        with _LOCK:
            _LOG.remove(log)


def note_unconverged(label: str) -> None:
    """Record an unconverged solve (``label`` names the case) in every open record."""
    with _LOCK:
        for log in _LOG:
            log.append(label)
