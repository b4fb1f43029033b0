"""How many cores skisnow uses by default: one definition for the FFT threads of the contact
solver and the worker processes of a sweep."""

from __future__ import annotations

import os

__all__ = ["default_workers"]


def default_workers() -> int:
    """The cores this process may run on (≥ 1).

    ``os.sched_getaffinity`` where the platform has it (Linux: it honours ``taskset``, cgroups'
    cpusets and batch schedulers' CPU binding), else ``os.cpu_count()``. Used as the default
    number of FFT threads (:class:`skisnow.contact.Convolution`) and of the processes of a
    sweep's local cluster (:func:`skisnow.sweep.run_sweep`).
    """
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)
