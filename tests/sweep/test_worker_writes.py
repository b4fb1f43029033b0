"""Who writes a sweep's chunks, and how: the same store, file for file.

The chunk files are written whole (``skisnow.sweep._zarr_io.ChunkFiles``), by the client or by
the workers of a local cluster into their own chunks. The store must be the very store Zarr's own
write path makes — the same files with the same bytes — whoever writes it; a failed chunk on a
worker must leave a store that says it is incomplete and loses no finished chunk; a writer of a
run that no longer holds the store writes nothing.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

from _hertz_chunk import hertz_chunk
from skisnow import InputError, SkisnowError
from skisnow.sweep import SweepSpec, open_sweep, run_sweep
from skisnow.sweep._run import prepare_store
from skisnow.sweep._store import StoreLock, done_chunks
from skisnow.sweep._writer import ChunkWriter
from skisnow.sweep._zarr_io import ChunkFiles


def _spec(**kw) -> SweepSpec:
    base = dict(
        skis=("classic", "skate"),
        masses=np.arange(5.0, 41.0, 5.0),
        load_positions=(-0.21, -0.12),
        snow_moduli=(20e6, 100e6, 400e6),
    )
    base.update(kw)
    return SweepSpec(**base)


def _files(path: Path) -> dict[str, bytes]:
    """Every file of a store by its relative name (metadata and chunks), with its bytes."""
    return {str(p.relative_to(path)): p.read_bytes() for p in path.rglob("*") if p.is_file()}


def _same_store(a: Path, b: Path) -> None:
    fa, fb = _files(a), _files(b)
    assert sorted(fa) == sorted(fb)
    spec_attr = {n for n in fa if n.endswith(".zattrs") and "/" not in n}  # chunk_function
    differ = [n for n in fa if fa[n] != fb[n] and n not in spec_attr]
    assert not differ, f"files that differ: {differ}"


def test_chunk_files_are_the_bytes_zarr_writes(tmp_path, monkeypatch) -> None:
    # The same chunks through ChunkFiles and through Zarr's own path (the writer's fallback):
    # the same files with the same bytes, an all-NaN chunk stored as no file by both, and a
    # chunk overwritten with fill values removed by both (Zarr's write_empty_chunks=False).
    spec = _spec()
    fast, slow = tmp_path / "fast.zarr", tmp_path / "slow.zarr"
    for path in (fast, slow):
        prepare_store(path, spec, hertz_chunk)
    writers = {fast: ChunkWriter(fast, spec)}
    assert writers[fast]._files is not None
    with monkeypatch.context() as m:
        m.setattr(ChunkFiles, "open", classmethod(lambda cls, root, names: None))
        writers[slow] = ChunkWriter(slow, spec)
    assert writers[slow]._files is None
    empty = {k: np.full_like(v, np.nan) if v.dtype.kind == "f" else np.zeros_like(v)
             for k, v in hertz_chunk(spec, "classic", -0.21, 20e6).items()}  # fmt: skip
    for writer in writers.values():
        for key in spec.chunks():
            i, j, k = key
            out = hertz_chunk(spec, spec.skis[i], spec.load_positions[j], spec.snow_moduli[k])
            writer.write(key, out)
        writer.write((1, 1, 2), empty)  # a chunk of fill values only, over a written one
    _same_store(fast, slow)
    assert not (fast / "area_cm2" / "1.0.1.2.0").exists()  # no file, as Zarr does
    assert (fast / "area_cm2" / "1.0.1.1.0").exists()
    assert not list(fast.rglob("*.partial"))
    np.testing.assert_array_equal(
        open_sweep(fast)["area_cm2"].values, open_sweep(slow)["area_cm2"].values
    )


@pytest.mark.parametrize("worker_writes", [True, False])
def test_workers_store_what_the_client_stores(tmp_path, monkeypatch, worker_writes) -> None:
    # A local cluster's workers write their own chunks (the client only waits), or return them
    # to the client, which writes them: the same files with the same bytes as in one process.
    from distributed import Client, LocalCluster

    import skisnow.sweep._run as run_module

    spec = _spec()
    run_sweep(spec, tmp_path / "one.zarr", chunk_function=hertz_chunk, workers=0)
    if worker_writes:  # the client writes nothing: its writer would fail
        monkeypatch.setattr(run_module, "ChunkWriter", None)
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0"
        ) as cluster,
        Client(cluster) as client,
    ):
        done: list[tuple[int, int, int]] = []
        run = run_sweep(
            spec, tmp_path / "two.zarr", chunk_function=hertz_chunk, client=client,
            worker_writes=None if worker_writes else False,  # on a local cluster: the default
            on_progress=lambda n, total, key: done.append(key),
        )  # fmt: skip
    assert run.workers == 2 and sorted(done) == sorted(spec.chunks()) == sorted(run.computed)
    _same_store(tmp_path / "one.zarr", tmp_path / "two.zarr")


_FAIL = {"on": True}


def fails_at_400(spec: SweepSpec, ski: str, x_m: float, e: float) -> dict[str, np.ndarray]:
    """``hertz_chunk``, except at 400 MPa on the skate while ``_FAIL["on"]``."""
    if _FAIL["on"] and e == 400e6 and ski == "skate":
        raise RuntimeError("worker lost")
    return hertz_chunk(spec, ski, x_m, e)


def test_a_failed_chunk_on_a_worker_leaves_an_incomplete_store(tmp_path) -> None:
    # A chunk that fails on a worker ends the run with an error; the chunks its workers
    # finished are in the store with their markers, the store says it is incomplete, and the
    # next run computes only the rest, to the store of an uninterrupted run.
    from distributed import Client, LocalCluster

    spec = _spec()
    _FAIL["on"] = False
    run_sweep(spec, tmp_path / "ref.zarr", chunk_function=fails_at_400, workers=0)
    _FAIL["on"] = True
    path = tmp_path / "s.zarr"

    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0"
        ) as cluster,
        Client(cluster) as client,
    ):
        with pytest.raises(SkisnowError, match="worker lost"):
            run_sweep(spec, path, chunk_function=fails_at_400, client=client, retries=0)
        _FAIL["on"] = False
        for _ in range(500):  # the chunk in flight on the other worker may still end
            if not any(client.processing().values()):
                break
            time.sleep(0.01)
        finished = done_chunks(path, spec)
        assert 0 < len(finished) < 12 and (1, 0, 2) not in finished
        with pytest.raises(InputError, match=f"{12 - len(finished)} of 12 chunks"):
            open_sweep(path)
        run = run_sweep(spec, path, chunk_function=fails_at_400, client=client)
    assert set(run.computed).isdisjoint(finished) and len(run.computed) == 12 - len(finished)
    _same_store(tmp_path / "ref.zarr", path)


def test_a_writer_of_another_run_writes_nothing(tmp_path) -> None:
    # A task that outlives its run (a Ctrl-C'ed sweep on a cluster the user keeps) must not
    # write into the store once another run holds it: neither data nor marker.
    spec = _spec()
    path = tmp_path / "s.zarr"
    prepare_store(path, spec, hertz_chunk)
    before = _files(path)
    out = hertz_chunk(spec, "classic", -0.21, 20e6)
    with StoreLock(path, token="new-run"):
        with pytest.raises(SkisnowError, match="no longer held by the sweep run"):
            ChunkWriter(path, spec, token="old-run").write((0, 0, 0), out)
        assert _files(path) == before
        ChunkWriter(path, spec, token="new-run").write((0, 0, 0), out)
    assert done_chunks(path, spec) == {(0, 0, 0)}
    # once a later run holds it
    with pytest.raises(SkisnowError, match="no longer held"), StoreLock(path, token="later"):
        ChunkWriter(path, spec, token="new-run").write((0, 0, 1), out)
