"""What a run's solves said: a process-wide record the one door of a case
(:func:`skisnow.pipeline.solve_case`) writes to, so a command can say how many of its solves did
not converge, or gave an implausible result, and name the first, whatever route they took
(sweeps in this process, the standard loads of a report, a fleet, a pairing, every frame of a
cycle). Solves run by Dask workers in other processes are read from their sweep's store instead
(``converged`` per point)."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator

__all__ = [
    "note_implausible",
    "note_solved",
    "note_unconverged",
    "recording_implausible",
    "recording_solved",
    "recording_unconverged",
]

_LOCK = threading.Lock()
_LOGS: dict[str, list[list[str]]] = {"unconverged": [], "implausible": [], "solved": []}


@contextlib.contextmanager
def _recording(kind: str) -> Iterator[list[str]]:
    log: list[str] = []
    with _LOCK:
        _LOGS[kind].append(log)
    try:
        yield log
    finally:
        with _LOCK:
            _LOGS[kind].remove(log)


def _note(kind: str, label: str) -> None:
    with _LOCK:
        for log in _LOGS[kind]:
            log.append(label)


def recording_unconverged() -> contextlib.AbstractContextManager[list[str]]:
    """Collect, in the yielded list, a label for every solve that does not converge inside the
    block (in this process, any thread)."""
    return _recording("unconverged")


def note_unconverged(label: str) -> None:
    """Record an unconverged solve (``label`` names the case) in every open record."""
    _note("unconverged", label)


def recording_implausible() -> contextlib.AbstractContextManager[list[str]]:
    """Collect, in the yielded list, ``"case: finding"`` for every implausible result
    (:func:`skisnow.pipeline._plausible.pressure_notes`) of a solve inside the block."""
    return _recording("implausible")


def note_implausible(label: str) -> None:
    """Record an implausible result (``label``: the case and what was found)."""
    _note("implausible", label)


def recording_solved() -> contextlib.AbstractContextManager[list[str]]:
    """Collect, in the yielded list, a label for every solve inside the block, converged or not
    (a command's ``converged`` is ``null`` only when it solved nothing)."""
    return _recording("solved")


def note_solved(label: str) -> None:
    """Record a solve (``label`` names the case) in every open record."""
    _note("solved", label)
