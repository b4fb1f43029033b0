"""Running a sweep on Dask, chunk by chunk into a Zarr store, resumable after any interruption.

The client (this process) creates the store and holds its lock for the run. On a local cluster
each worker writes the chunks it computes into their own Zarr chunks of the store, then the
chunk's completion marker, and sends nothing back but the chunk's key; on a remote
``dask.distributed`` cluster, which may share no file system with this machine, workers return
each chunk's small result arrays and the client writes them as they arrive. Either way a Zarr
chunk belongs to one task, so no two writers ever race on a file.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from skisnow._errors import InputError, SkisnowError
from skisnow._parallel import default_workers
from skisnow.sweep._grid import SweepSpec
from skisnow.sweep._store import (
    SPEC_ATTR,
    StoreLock,
    check_same_sweep,
    check_skeleton,
    create_store,
    done_chunks,
)
from skisnow.sweep._writer import ChunkWriter, run_writer

#: A chunk function computes one chunk: (spec, ski name, load position [m], snow modulus [Pa]) ->
#: {variable: array of shape (n_mass, n_zone) or (n_mass,)} (see ``skisnow.sweep.VARIABLES``).
ChunkFunction = Callable[[SweepSpec, str, float, float], Mapping[str, np.ndarray]]

#: Progress callback: (chunks done so far, chunks to do in this run, key of the chunk just done).
ProgressCallback = Callable[[int, int, tuple[int, int, int]], None]


@dataclass(frozen=True, kw_only=True)
class SweepRun:
    """What a call of :func:`run_sweep` did.

    Attributes:
        path: the Zarr store.
        spec: the sweep.
        computed: chunk keys computed (and written) in this run, in completion order.
        skipped: chunk keys found complete in the store and not recomputed.
        wall_time: seconds from start to the last write (cluster start-up included).
        compute_time: seconds from the first submitted task to the last write.
        workers: number of Dask workers used (0 = in-process).
    """

    path: Path
    spec: SweepSpec
    computed: tuple[tuple[int, int, int], ...]
    skipped: tuple[tuple[int, int, int], ...]
    wall_time: float
    compute_time: float
    workers: int


def _chunk_task(
    fn: ChunkFunction, spec: SweepSpec, key: tuple[int, int, int], shared: Any = None
) -> tuple[tuple[int, int, int], dict[str, np.ndarray]]:
    i, j, k = key
    args = (spec, spec.skis[i], spec.load_positions[j], spec.snow_moduli[k])
    out = fn(*args) if shared is None else fn(*args, shared)  # type: ignore[call-arg]
    return key, {name: np.asarray(v) for name, v in out.items()}


def _chunk_store_task(
    fn: ChunkFunction,
    spec: SweepSpec,
    key: tuple[int, int, int],
    shared: Any,
    path: str,
    token: str,
) -> tuple[int, int, int]:
    """A worker's task when workers write: compute the chunk, write it into the store (data,
    then marker) and return only its key."""
    key, values = _chunk_task(fn, spec, key, shared)
    run_writer(path, spec, token).write(key, values)
    return key


def _writes_on_workers(client: Any, own_cluster: Any) -> bool:
    """Whether the workers share this machine's file system: a local cluster's do."""
    if own_cluster is not None:
        return True
    from distributed import LocalCluster

    return isinstance(getattr(client, "cluster", None), LocalCluster)


@contextlib.contextmanager
def _gc_frozen() -> Iterator[None]:
    """Keep the objects that exist before the run out of the garbage collector's full
    collections during it (:func:`gc.freeze`, undone at the end): in a client process with
    Dask, xarray and Zarr imported (~230,000 objects) a full collection costs ~0.15 s of CPU,
    taken from the workers' cores when it falls in a run. Nothing is done where the process
    has frozen objects of its own."""
    import gc

    if gc.get_freeze_count():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def _flat(items: Any) -> list[Any]:
    return [f for item in items for f in (item if isinstance(item, list) else [item])]


def _function_name(fn: Callable[..., Any]) -> str:
    return f"{getattr(fn, '__module__', '?')}.{getattr(fn, '__qualname__', repr(fn))}"


def _attrs(spec: SweepSpec, fn: ChunkFunction) -> dict[str, Any]:
    from skisnow import __version__
    from skisnow.constants import STANDARD_GRAVITY

    return {
        "title": "skisnow sweep of the apparent ski–snow contact",
        "skisnow_version": __version__,
        SPEC_ATTR: spec.to_json(),
        "chunk_function": _function_name(fn),
        "skis": ", ".join(spec.skis),
        "model": spec.model,
        "profile_source": spec.profile_source,
        "ski_model": spec.ski_model,
        "n_points": spec.n_points,
        "base_modulus_mpa": spec.base_modulus / 1e6,
        "poisson_ratio": spec.poisson,
        "standard_gravity_m_s2": STANDARD_GRAVITY,
        "source": "Kalliorinne et al., Lubricants 2023 (eq. 2-3, Figures 8-9): method",
    }


def prepare_store(
    path: str | Path, spec: SweepSpec, fn: ChunkFunction
) -> set[tuple[int, int, int]]:
    """Create the store (atomically, see :func:`~skisnow.sweep._store.create_store`), or
    check that an existing one holds the same sweep and is complete. Call it holding the
    store's lock (:func:`run_sweep` does).

    Returns the set of chunk keys already complete.
    """
    import zarr

    path = Path(path)
    attrs = _attrs(spec, fn)
    if path.exists():
        try:
            stored = dict(zarr.open_group(str(path), mode="r").attrs)
        except Exception as exc:
            raise InputError(
                f"{path} exists but is not a Zarr store ({type(exc).__name__}); choose another "
                "--out"
            ) from None
        check_same_sweep(path, spec, stored)
        check_skeleton(path, spec)
        if stored.get("skisnow_version") != attrs["skisnow_version"]:
            raise InputError(
                f"{path} was started by skisnow {stored.get('skisnow_version')}, this is "
                f"{attrs['skisnow_version']}; resuming would mix results of two versions. Use "
                "another --out, or delete the store to start afresh."
            )
        if stored.get("chunk_function") != attrs["chunk_function"]:
            raise InputError(
                f"{path} was computed with chunk function {stored.get('chunk_function')!r}, not "
                f"{attrs['chunk_function']!r}; resuming would mix two computations"
            )
        return done_chunks(path, spec)
    create_store(path, spec, attrs=attrs)
    return set()


#: Modules imported once by the fork server of local clusters, so that workers start warm.
PRELOAD = (
    "distributed",
    "numpy",
    "scipy",
    "skisnow.sweep._point",
    "skisnow.contact",
    "skisnow.contact._pk_kernel",  # numba and the compiled 1D loop (0.14 s a worker otherwise)
    "threadpoolctl",
    "skisnow.ski",
    # last: one solve (the chunk's imports and the numba kernels' cache loaded), the writer's
    # imports (workers write their chunks), then gc.freeze() of everything imported
    "skisnow.sweep._warm",
)


#: glibc's trim and mmap thresholds for the workers of local clusters [bytes] (see
#: :func:`local_cluster`); a worker keeps at most this much freed memory before returning it.
MALLOC_TRIM_THRESHOLD = 32 << 20
MALLOC_MMAP_THRESHOLD = 16 << 20


def local_cluster(n_workers: int) -> Any:
    """A :class:`dask.distributed.LocalCluster` of ``n_workers`` processes, one thread each.

    Where the platform has it, workers are forked from a fork server that has already imported
    the solvers (:data:`PRELOAD`): they start in a fraction of the time of freshly spawned
    interpreters, and each does not import JAX/SciPy again.
    """

    import dask
    from distributed import LocalCluster

    from skisnow._parallel import process_start_method

    method = process_start_method()
    settings = {
        "distributed.worker.multiprocessing-method": method,
        # Dask sets glibc's trim threshold to 64 KiB, which also pins the mmap threshold at
        # 128 KiB: every FFT buffer and dense block of the solver is then mmap-ed, faulted in
        # and given back on each call. Measured on the Figure 8/9 chunks: 15.7 s with Dask's
        # setting (or a 1 MiB trim threshold alone) against 13.4 s with these two.
        "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": MALLOC_TRIM_THRESHOLD,
        "distributed.nanny.pre-spawn-environ.MALLOC_MMAP_THRESHOLD_": MALLOC_MMAP_THRESHOLD,
        # the workers' statistical profiler samples every thread's stack every 10 ms (the
        # dashboard's profile page): ~10 % of a worker's CPU on the Figure 8/9 chunks (3.63,
        # 3.71 s without against 4.02, 4.13 s with it, one worker, load 6-7)
        "distributed.worker.profile.enabled": False,
        # the event loops' housekeeping: a tick every 20 ms in the client's loop and in every
        # worker (a diagnostic of blocked loops), a system monitor every 500 ms (the
        # dashboard's CPU and memory plots), the nannies' and workers' memory checks every
        # 100 ms. An idle 2-worker cluster costs 0.014 s of CPU a second per worker and
        # 0.025-0.033 s in the client with these defaults, 0.0035 s and 0.009 s with the
        # settings below (6 s idle, load 5-7): ~0.1 s of CPU on a 2 s Figure 8/9 sweep. A
        # worker running out of memory is still stopped by its nanny, 1 s later at most.
        "distributed.admin.tick.interval": "200ms",
        "distributed.admin.system-monitor.interval": "2s",
        "distributed.worker.memory.monitor-interval": "1s",
    }
    with dask.config.set(settings):
        if method == "forkserver":
            from distributed.utils import get_mp_context

            get_mp_context().set_forkserver_preload(list(PRELOAD))
        return LocalCluster(
            n_workers=n_workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",  # any free port: never clash with another cluster
            silence_logs=40,  # logging.ERROR
        )


def run_sweep(
    spec: SweepSpec,
    path: str | Path,
    *,
    chunk_function: ChunkFunction | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    client: Any = None,
    retries: int = 2,
    on_progress: ProgressCallback | None = None,
    shared_function: Callable[[SweepSpec, str, float], Any] | None = None,
    worker_writes: bool | None = None,
) -> SweepRun:
    """Compute the chunks of ``spec`` that are missing from the Zarr store at ``path``.

    A new store is created; an existing one must hold the same sweep (else :class:`InputError`)
    and only its chunks without completion marker are computed. Interrupting this function at any
    point (Ctrl-C, SIGKILL) loses at most the chunks in flight.

    Args:
        spec: the sweep.
        path: the Zarr store (directory).
        chunk_function: computes one chunk; default :func:`skisnow.sweep.contact_chunk` (loaded
            profile + contact solve per mass, warm-started along the masses).
        scheduler: address of an existing ``dask.distributed`` scheduler (``tcp://host:8786``).
            Default: a new :class:`dask.distributed.LocalCluster` of ``workers`` processes.
            Start the workers of your own cluster with ``MALLOC_TRIM_THRESHOLD_=33554432`` and
            ``MALLOC_MMAP_THRESHOLD_=16777216`` in their environment (as the local cluster
            does, see :func:`local_cluster`): with Dask's default the solves run ~15 % slower;
            ``DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED=False`` spares another ~10 %, and
            ``DASK_DISTRIBUTED__ADMIN__TICK__INTERVAL=200ms`` the event loops' idle ticks
            (the other settings of :func:`local_cluster` likewise).
        workers: workers of the local cluster (default :func:`default_workers`); ``0`` computes
            in this process without Dask (for small grids and debugging).
        client: an existing ``distributed.Client`` to use (overrides ``scheduler``/``workers``).
        retries: Dask retries of a chunk whose worker failed.
        on_progress: called after each chunk is written.
        shared_function: computes, in this process, data shared by all chunks of one (ski,
            load position), passed to ``chunk_function`` as a fifth argument (scattered once to
            the Dask workers). The default physics uses it for the loaded profiles of all
            masses: the camber network (JAX) then runs once here and never on the workers,
            which only solve contacts; beam profiles are computed by the workers instead, in
            one part of the masses per worker (:func:`skisnow.sweep._point.split_profiles`),
            so that nothing serial precedes the chunks.
        worker_writes: whether the Dask workers write their chunks into the store themselves
            (no result is sent back; the client only waits) instead of returning them to this
            process, which writes them. Default: on a local cluster (the store's file system
            is theirs), not on a remote one. Set it for a remote cluster whose workers see the
            store at the same path. Ignored with ``workers=0``.
    """
    split = False
    if chunk_function is None:
        from skisnow.sweep._point import contact_chunk, loaded_profiles, split_profiles

        chunk_function = contact_chunk
        if shared_function is None:
            shared_function = loaded_profiles
            split = split_profiles(spec)
    if workers is not None and workers < 0:
        raise InputError(f"workers: need >= 0, got {workers}")
    if retries < 0:
        raise InputError(f"retries: need >= 0, got {retries}")
    import uuid

    # One sweep per store at a time: a second one is refused with a clear message. The run's
    # token in the lock file tells the workers' writers that the store is still this run's.
    token = uuid.uuid4().hex
    with StoreLock(Path(path), token=token), _gc_frozen():
        return _run_locked(
            spec, Path(path), chunk_function=chunk_function, scheduler=scheduler,
            workers=workers, client=client, retries=retries, on_progress=on_progress,
            shared_function=shared_function, split=split, worker_writes=worker_writes,
            token=token,
        )  # fmt: skip


def _run_locked(
    spec: SweepSpec,
    path: Path,
    *,
    chunk_function: ChunkFunction,
    scheduler: str | None,
    workers: int | None,
    client: Any,
    retries: int,
    on_progress: ProgressCallback | None,
    shared_function: Callable[[SweepSpec, str, float], Any] | None,
    split: bool = False,
    worker_writes: bool | None = None,
    token: str = "",
) -> SweepRun:
    t0 = time.perf_counter()
    done = prepare_store(path, spec, chunk_function)
    todo = [key for key in spec.chunks() if key not in done]
    skipped = tuple(key for key in spec.chunks() if key in done)
    computed: list[tuple[int, int, int]] = []

    writer: ChunkWriter | None = None

    def _done(key: tuple[int, int, int]) -> None:
        computed.append(key)
        if on_progress is not None:
            on_progress(len(computed), len(todo), key)

    def _record(key: tuple[int, int, int], values: Mapping[str, np.ndarray]) -> None:
        nonlocal writer
        if writer is None:
            writer = ChunkWriter(path, spec)
        writer.write(key, values)
        _done(key)

    if not todo:
        wall = time.perf_counter() - t0
        return SweepRun(
            path=path, spec=spec, computed=(), skipped=skipped, wall_time=wall,
            compute_time=0.0, workers=0,
        )  # fmt: skip

    if client is None and scheduler is None and workers == 0:
        t1 = time.perf_counter()
        cache: dict[tuple[int, int], Any] = {}
        for key in todo:
            shared = None
            if shared_function is not None:
                if key[:2] not in cache:
                    cache.clear()  # chunks come ordered by (ski, position): keep one
                    i, j = key[:2]
                    cache[key[:2]] = shared_function(spec, spec.skis[i], spec.load_positions[j])
                shared = cache[key[:2]]
            _record(*_chunk_task(chunk_function, spec, key, shared))
        end = time.perf_counter()
        return SweepRun(
            path=path, spec=spec, computed=tuple(computed), skipped=skipped,
            wall_time=end - t0, compute_time=end - t1, workers=0,
        )  # fmt: skip

    own_client, own_cluster = None, None
    try:
        if client is None:
            from distributed import Client

            if scheduler is not None:
                own_client = Client(scheduler)
            else:
                n = default_workers() if workers is None else workers
                own_cluster = local_cluster(n)
                own_client = Client(own_cluster)
            client = own_client
        n_workers = len(client.scheduler_info(n_workers=-1).get("workers", {}))
        n_parts = max(n_workers, 1)  # shared data split in one part per worker
        if worker_writes is None:
            worker_writes = _writes_on_workers(client, own_cluster)
        where = (str(path.resolve()), token) if worker_writes else ()
        keys: dict[str, tuple[int, int, int]] = {}
        t1 = time.perf_counter()
        futures = []
        shared_futures: dict[tuple[int, int], Any] = {}
        # ordered by (ski, position): submit as soon as its profiles exist; and run in this
        # order (Dask's priority: the chunks of one (ski, position) become ready together and
        # would run in any order): the softest snow first, the largest contacts and the
        # longest chunks (2.7x the stiffest on the Figure 8/9 map), so that the short ones
        # even out the workers' ends (longest processing time first).
        for rank, key in enumerate(todo):
            shared = None
            if shared_function is not None:
                if key[:2] not in shared_futures:
                    i, j = key[:2]
                    args = (spec, spec.skis[i], spec.load_positions[j])
                    if split:  # computed by the workers, one part each: nothing serial here
                        shared_futures[key[:2]] = [
                            client.submit(
                                shared_function,
                                *args,
                                part=(p, n_parts),
                                pure=False,
                                key=f"skisnow-shared-{path.name}-{i}-{j}-{p}-{time.time_ns()}",
                                retries=retries,
                                priority=len(todo) + 1,  # before any chunk: they wait on it
                            )
                            for p in range(n_parts)
                        ]
                    else:
                        data = shared_function(*args)
                        # a list of one: a dict would be scattered item by item
                        shared_futures[key[:2]] = client.scatter([data], hash=False)[0]
                shared = shared_futures[key[:2]]
            futures.append(
                client.submit(
                    _chunk_store_task if worker_writes else _chunk_task,
                    chunk_function,
                    spec,
                    key,
                    shared,
                    *where,
                    key=f"skisnow-chunk-{path.name}-{key[0]}-{key[1]}-{key[2]}-{time.time_ns()}",
                    retries=retries,
                    pure=False,
                    priority=len(todo) - rank,
                )
            )
            keys[futures[-1].key] = key
        from distributed import as_completed

        try:
            for future in as_completed(futures):
                if worker_writes and future.status == "finished":
                    _done(keys[future.key])  # written by its worker: nothing to fetch
                    continue
                try:
                    key, values = future.result()
                except SkisnowError:
                    raise
                except Exception as exc:
                    raise SkisnowError(
                        f"a sweep chunk failed after {retries} retries: {type(exc).__name__}: "
                        f"{exc} (finished chunks are kept in {path}; re-run to resume)"
                    ) from exc
                _record(key, values)
        finally:
            for future in [*futures, *_flat(shared_futures.values())]:
                future.cancel()
        end = time.perf_counter()
        return SweepRun(
            path=path, spec=spec, computed=tuple(computed), skipped=skipped,
            wall_time=end - t0, compute_time=end - t1, workers=n_workers,
        )  # fmt: skip
    finally:
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()
