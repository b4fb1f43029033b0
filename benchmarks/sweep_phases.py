"""Where the Figure 8/9 sweep's time goes: CPU by phase in the client and in each worker.

    uv run python benchmarks/sweep_phases.py             # 1 and 2 workers, one run each
    uv run python benchmarks/sweep_phases.py --runs 3    # three runs each

The sweep of ``bench_speed.py --rows sweep`` (skate, 126 masses × 20 moduli, beam profiles, 4096
stations) on a local cluster of 1 and 2 worker processes. Timers are installed on the workers with
``client.run`` (the task functions are pickled by reference, so a worker runs the timed wrapper),
and in the client around the store's creation and each chunk's write. Printed per run:

* each worker: process CPU during the run, and within it the CPU of each task kind (profile
  parts, chunks; the chunks' longest and shortest; its writes of its own chunks), the rest
  being the worker's own event loop (receiving tasks, sending results, heartbeats), with the
  garbage collector's share, and its idle tail (wall); ``--detail``: CPU by thread and by chunk;
* the client process: CPU by thread (main thread: submission, waiting, writes where the client
  writes; the event-loop thread: the scheduler, the nannies and the client's communication;
  Zarr's I/O thread and the threads it writes files from: the store's creation), the writes and
  the garbage collector;
* the compute time and, per worker, when it finished its last task (its idle tail).

``--writes client,worker`` alternates who writes the chunks (``run_sweep(worker_writes=...)``);
``PYTHONPATH=<main checkout>/src`` runs it on another checkout (before the fifth pass: the
client writes).

Every CPU figure is load-independent to first order; wall times are printed with the load.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import psutil

DETAIL = False


def load() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def spec():
    """The benchmark's Figure 8/9 sweep (``bench_speed.figure89_spec``)."""
    from bench_speed import figure89_spec

    return figure89_spec()


def _install_worker_timers() -> None:
    """Runs on each worker: wrap the task functions with CPU/wall timers."""
    import time as _t

    import skisnow.sweep._point as point
    import skisnow.sweep._run as run

    try:
        import skisnow.sweep._writer as writer
    except ImportError:  # main before the fifth pass: the writer was in _store
        import skisnow.sweep._store as writer

    log = []

    def timed(kind, fn):
        if getattr(fn, "_timed", False):
            return fn

        def wrapper(*a, **k):
            c0, w0 = _t.thread_time(), _t.time()
            try:
                return fn(*a, **k)
            finally:
                key = a[2] if kind == "chunk" and len(a) > 2 else None
                log.append((kind, _t.thread_time() - c0, w0, _t.time(), key))

        wrapper._timed = True
        return wrapper

    point.loaded_profiles = timed("profiles", point.loaded_profiles)
    run._chunk_task = timed("chunk", run._chunk_task)
    writer.ChunkWriter.write = timed("write", writer.ChunkWriter.write)
    run._PHASE_LOG = log
    run._PHASE_THREADS = _thread_cpu()
    _gc_take()


def _take_worker_log():
    import threading
    import time as _t

    import skisnow.sweep._run as run

    log = list(run._PHASE_LOG)
    run._PHASE_LOG.clear()
    names = {t.native_id: t.name for t in threading.enumerate()}
    now, before = _thread_cpu(), run._PHASE_THREADS
    run._PHASE_THREADS = now
    threads = {names.get(i, "?"): c - before.get(i, 0.0) for i, c in now.items()}
    return {"log": log, "cpu": _t.process_time(), "threads": threads, "gc": _gc_take()}


def _gc_timer() -> dict:
    """Time the garbage collector's passes in this process (``gc.callbacks``): CPU of all
    passes and the number of full (generation 2) ones since the last :func:`_gc_take`."""
    import gc

    state = getattr(gc, "_sweep_phases", None)
    if state is None:
        state = gc._sweep_phases = {"cpu": 0.0, "full": 0, "t0": 0.0}

        def cb(phase, info):
            if phase == "start":
                state["t0"] = time.thread_time()
            else:
                state["cpu"] += time.thread_time() - state["t0"]
                state["full"] += info["generation"] == 2

        gc.callbacks.append(cb)
    return state


def _gc_take() -> tuple[float, int]:
    state = _gc_timer()
    out = (state["cpu"], state["full"])
    state["cpu"], state["full"] = 0.0, 0
    return out


def _thread_cpu() -> dict[int, float]:
    return {t.id: t.user_time + t.system_time for t in psutil.Process().threads()}


def _replay(out: dict, spec, ski, position, modulus) -> dict:
    """A chunk function that returns a chunk computed beforehand: the machinery alone."""
    return {k: v.copy() for k, v in out.items()}


def one_run(
    n: int, tmp: Path, tag: str, machinery: dict | None = None, worker_writes: bool | None = None
) -> dict:
    import threading

    from distributed import Client

    import skisnow.sweep._run as runmod

    try:
        import skisnow.sweep._writer as store
    except ImportError:  # main before the fifth pass
        import skisnow.sweep._store as store
    from skisnow.sweep import run_sweep
    from skisnow.sweep._run import local_cluster

    t0 = time.perf_counter()
    cluster = local_cluster(n)
    client = Client(cluster)
    startup = time.perf_counter() - t0
    client.run(_install_worker_timers)
    s = spec()

    # client timers: the store's creation and each chunk's write
    writes: list[float] = []
    prep: list[float] = []
    orig_write, orig_prep = store.ChunkWriter.write, runmod.prepare_store

    def write(self, key, values):
        c0 = time.thread_time()
        orig_write(self, key, values)
        writes.append(time.thread_time() - c0)

    def prepare(*a, **k):
        c0 = time.thread_time()
        try:
            return orig_prep(*a, **k)
        finally:
            prep.append(time.thread_time() - c0)

    store.ChunkWriter.write, runmod.prepare_store = write, prepare
    names = {t.native_id: t.name for t in threading.enumerate()}
    w0 = client.run(time.process_time)
    _gc_take()
    th0, c0 = _thread_cpu(), time.process_time()
    try:
        if machinery is None:
            kw = {} if worker_writes is None else {"worker_writes": worker_writes}
            r = run_sweep(s, tmp / f"{tag}.zarr", client=client, **kw)
        else:  # 20 tasks that cost nothing: Dask's and Zarr's CPU alone
            import functools

            fn = functools.partial(_replay, machinery)
            fn.__module__, fn.__qualname__ = __name__, "_replay"  # type: ignore[attr-defined]
            kw = {} if worker_writes is None else {"worker_writes": worker_writes}
            r = run_sweep(s, tmp / f"{tag}.zarr", client=client, chunk_function=fn, **kw)
    finally:
        store.ChunkWriter.write, runmod.prepare_store = orig_write, orig_prep
    th1, c1 = _thread_cpu(), time.process_time()
    gc_client = _gc_take()
    end = time.time()
    logs = client.run(_take_worker_log)
    names.update({t.native_id: t.name for t in threading.enumerate()})
    client.close()
    cluster.close()

    out = {"n": n, "compute": r.compute_time, "startup": startup, "client": c1 - c0}
    out["mode"] = {None: "default", True: "worker writes", False: "client writes"}[worker_writes]
    out["gc"] = gc_client
    out["threads"] = sorted(
        ((names.get(i, str(i)), th1[i] - th0.get(i, 0.0)) for i in th1),
        key=lambda x: -x[1],
    )
    out["prep"], out["writes"] = sum(prep), sum(writes)
    out["workers"] = []
    for addr, d in logs.items():
        log = d["log"]
        prof = [c for k, c, _, _, _ in log if k == "profiles"]
        wr = [c for k, c, _, _, _ in log if k == "write"]
        chunks = [c for k, c, _, _, _ in log if k == "chunk"]
        last = max(e for _, _, _, e, _ in log) if log else end
        first = min(s_ for _, _, s_, _, _ in log) if log else end
        out["workers"].append(
            {
                "cpu": d["cpu"] - w0[addr],
                "profiles": sum(prof),
                "writes": sum(wr),
                "n_chunks": len(chunks),
                "chunks": sum(chunks),
                "chunk_max": max(chunks, default=0.0),
                "chunk_min": min(chunks, default=0.0),
                "first_task_after_end": first - end,
                "idle_tail": end - last,
                "threads": d["threads"],
                "gc": d["gc"],
                "by_chunk": [(key[2], c) for k, c, _, _, key in log if k == "chunk"],
            }
        )
    return out


def show(o: dict) -> None:
    print(
        f"  {o['n']} worker(s), {o['mode']}: compute {o['compute']:.2f} s (start-up "
        f"{o['startup']:.2f} s before), load {load()}"
    )
    for w in o["workers"]:
        rest = w["cpu"] - w["profiles"] - w["chunks"] - w["writes"]
        print(
            f"    worker: CPU {w['cpu']:.2f} s = profile part {w['profiles']:.3f} + "
            f"{w['n_chunks']} chunks {w['chunks']:.2f} (each {w['chunk_min']:.3f}-"
            f"{w['chunk_max']:.3f}) + writes {w['writes']:.3f} + rest {rest:.3f} (garbage "
            f"collector {w['gc'][0]:.3f}, {w['gc'][1]} full); idle tail {w['idle_tail']:.3f} s "
            "wall"
        )
        if DETAIL:
            th = ", ".join(f"{k} {c:.3f}" for k, c in w["threads"].items() if c >= 0.005)
            print(f"      by thread (since the previous run): {th}")
            print(
                "      chunks (modulus index: CPU s, in order run): "
                + ", ".join(f"{k}: {c:.3f}" for k, c in w["by_chunk"])
            )
    th = ", ".join(f"{name} {c:.3f}" for name, c in o["threads"] if c >= 0.005)
    print(
        f"    client: CPU {o['client']:.2f} s (store creation {o['prep']:.3f}, writes "
        f"{o['writes']:.3f}; garbage collector {o['gc'][0]:.3f}, {o['gc'][1]} full); by "
        f"thread: {th}"
    )


def _chunks(moduli, profiles, q=None) -> float:
    from skisnow.sweep import contact_chunk

    s = spec()
    c0 = time.process_time()
    for e in moduli:
        contact_chunk(s, "skate", -0.120, float(e), profiles)
    c = time.process_time() - c0
    if q is not None:
        q.put(c)
    return c


def _fft(q=None) -> float:
    a = np.random.default_rng(0).random(8192)
    c0 = time.process_time()
    for _ in range(6000):
        np.fft.irfft(np.fft.rfft(a) * 1.0001)
    c = time.process_time() - c0
    if q is not None:
        q.put(c)
    return c


def concurrency(repeats: int = 2) -> None:
    """CPU of the same work alone and as two processes at once (forked, warm)."""
    from multiprocessing import get_context

    from skisnow.sweep import contact_chunk
    from skisnow.sweep._point import loaded_profiles

    s = spec()
    profiles = loaded_profiles(s, "skate", -0.120)
    contact_chunk(s, "skate", -0.120, 100e6, profiles)  # warm: imports, kernels, caches
    halves = (s.snow_moduli[0::2], s.snow_moduli[1::2])
    ctx = get_context("fork")
    for _ in range(repeats):
        for name, jobs in (
            ("20 chunks (10 + 10)", [(_chunks, (h, profiles)) for h in halves]),
            ("FFT loop (control)", [(_fft, ()), (_fft, ())]),
        ):
            alone = [fn(*a) for fn, a in jobs]
            q = ctx.Queue()
            procs = [ctx.Process(target=fn, args=(*a, q)) for fn, a in jobs]
            for p in procs:
                p.start()
            for p in procs:
                p.join()
            both = [q.get() for _ in procs]
            seq = []  # forked too, one after the other: a fresh process's own costs
            for fn, a in jobs:
                p = ctx.Process(target=fn, args=(*a, q))
                p.start()
                p.join()
                seq.append(q.get())
            print(
                f"  {name}: in this process one after the other {sum(alone):.2f} s CPU; two "
                f"forked processes one after the other {sum(seq):.2f} s "
                f"({100 * (sum(seq) / sum(alone) - 1):+.0f} %), at once {sum(both):.2f} s "
                f"({100 * (sum(both) / sum(alone) - 1):+.0f} %); load {load()}"
            )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--workers", default="1,2")
    ap.add_argument("--detail", action="store_true", help="print every chunk's CPU")
    ap.add_argument(
        "--machinery",
        action="store_true",
        help="chunks that return a chunk computed beforehand: the CPU of Dask and Zarr alone",
    )
    ap.add_argument(
        "--concurrency",
        action="store_true",
        help="the 20 chunks' CPU in one process against two processes at once (no Dask), "
        "and an FFT loop that fits in the cores' own caches as a control; then exit",
    )
    ap.add_argument(
        "--writes",
        default="default",
        help="who writes the chunks, alternated run by run: default (workers on a local "
        "cluster), worker, client; e.g. client,worker",
    )
    args = ap.parse_args()
    if args.concurrency:
        concurrency()
        return
    machinery = None
    if args.machinery:
        from skisnow.sweep import contact_chunk

        machinery = contact_chunk(spec(), "skate", -0.120, 100e6)
    global DETAIL
    DETAIL = args.detail
    ns = [int(v) for v in args.workers.split(",")]
    modes = {"default": None, "worker": True, "client": False}
    ms = [modes[m] for m in args.writes.split(",")]
    print(f"load {load()}")
    res: dict[tuple[int, bool | None], list[dict]] = {(n, m): [] for n in ns for m in ms}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.runs):
            for n in ns:
                for m in ms:
                    o = one_run(n, Path(tmp), f"r{r}w{n}{m}", machinery, m)
                    res[(n, m)].append(o)
                    show(o)
    for (n, _m), os_ in res.items():
        c = [o["compute"] for o in os_]
        w = [sum(x["cpu"] for x in o["workers"]) for o in os_]
        cl = [o["client"] for o in os_]
        print(
            f"{n} worker(s), {os_[0]['mode']}: compute median {statistics.median(c):.2f} s of "
            f"{len(c)} ({', '.join(f'{v:.2f}' for v in c)}); workers' CPU summed median "
            f"{statistics.median(w):.2f} s; client CPU median {statistics.median(cl):.2f} s; "
            f"workers + client {statistics.median(a + b for a, b in zip(w, cl, strict=True)):.2f} s"
        )
    print(f"load {load()}")


if __name__ == "__main__":
    main()
