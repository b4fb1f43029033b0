"""How many cores skisnow uses by default: one definition for the FFT threads of the contact
solver and the worker processes of a sweep; how those processes start."""

from __future__ import annotations

import contextlib
import functools
import os
from collections.abc import Iterator

__all__ = ["default_workers", "process_start_method", "single_threaded_blas"]


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


def process_start_method() -> str:
    """How skisnow's worker processes start: ``'forkserver'`` where the platform has it, else
    ``'spawn'`` — fresh processes, never forks of this one: a fork of a multithreaded process
    (JAX, Dask, BLAS pools) may deadlock, and JAX warns. Used by a sweep's local cluster
    (:func:`skisnow.sweep.run_sweep`) and the bootstrap's replicates
    (:func:`skisnow.identify.bootstrap_bands`)."""
    import multiprocessing

    return "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"


@functools.lru_cache(maxsize=1)
def _blas_controller():
    # SciPy's BLAS is a library of its own (the compiled flexible-ski kernels call it through
    # scipy.linalg.cython_blas): load it before the controller lists the loaded libraries
    import scipy.linalg  # noqa: F401
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextlib.contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Run the block with one BLAS thread (then restore the previous setting).

    The dense products and factorisations of the 1D contact solves are small (a few hundred
    cells): a second BLAS thread gains nothing there, and on a shared machine its spinning
    waits cost far more (measured: a flexible-ski solve of 9.5 ms took 530 ms at load 6 with
    OpenBLAS's default 2 threads). Costs ~10 µs (threadpoolctl, controller cached).
    """
    with _blas_controller().limit(limits=1, user_api="blas"):
        yield
