"""Resuming after a kill at ANY write yields the store of an uninterrupted run.

A hook in the writers (zarr's LocalStore, which creates the store, and the chunk files' writer:
the only things that write a sweep store's files) stops the sweep right after its k-th file
write, as a SIGKILL would (no clean-up runs), for every k of a small two-chunk sweep, including
every write of the store's creation; the same sweep is then run again. Every kill point must end
with the dataset of an uninterrupted run, and no finished chunk may be recomputed. A second sweep
on a locked store is refused; a NetCDF export killed midway leaves no file.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
import zarr.storage

from skisnow import SkisnowError
from skisnow._atomic import temporary_siblings
from skisnow.sweep import VARIABLES, SweepSpec, open_sweep, run_sweep, save_netcdf
from skisnow.sweep._store import StoreLock
from skisnow.sweep._zarr_io import ChunkFiles


class Killed(Exception):
    """Stands for SIGKILL: raised right after a write, nothing of the sweep's own runs after."""


def _chunk(spec: SweepSpec, ski: str, position: float, modulus: float) -> dict[str, np.ndarray]:
    """A cheap deterministic chunk (the store, not the physics, is under test here)."""
    n_mass, n_zone = len(spec.masses), len(spec.zones)
    base = np.outer(np.asarray(spec.masses), np.arange(1, n_zone + 1)) * (modulus / 1e8)
    out: dict[str, np.ndarray] = {}
    for name, var in VARIABLES.items():
        shape = (n_mass, n_zone) if "zone" in var.dims else (n_mass,)
        value = base if "zone" in var.dims else base[:, 0] + position
        out[name] = np.asarray(value, dtype=float).reshape(shape).astype(var.dtype)
    return out


SPEC = SweepSpec(
    skis=("skate",), masses=(20.0, 60.0), load_positions=(-0.12,), snow_moduli=(50e6, 100e6),
    n_points=64, profile_source="beam",
)  # fmt: skip


def _drain_zarr_loop() -> None:
    """Wait until every task on Zarr's I/O loop has ended (the writes a gather left running
    after the kill's exception)."""
    import asyncio

    from zarr.core.sync import _get_loop

    async def wait() -> None:
        others = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
        await asyncio.gather(*others, return_exceptions=True)

    asyncio.run_coroutine_threadsafe(wait(), _get_loop()).result(timeout=60)


@pytest.fixture
def kill_after(monkeypatch):
    """``kill_after(k)`` arms the hook: the k-th file write of the store completes, then
    :class:`Killed` is raised; returns a counter dict whose ``"n"`` counts writes."""
    original = zarr.storage.LocalStore._set
    original_chunk = ChunkFiles.write
    state = {"n": 0, "k": None, "dead": False, "chunk_files": 0}

    async def _set(self, key, value, exclusive=False):
        if state["dead"]:  # a killed process writes nothing more (zarr's other pending writes)
            raise Killed(f"write of {key} after the kill")
        await original(self, key, value, exclusive=exclusive)
        state["n"] += 1
        if state["k"] is not None and state["n"] == state["k"]:
            state["dead"] = True
            raise Killed(f"killed after write {state['n']} ({key})")

    def write(self, name, index, value):  # one chunk file replaced (or an empty one removed)
        if state["dead"]:
            raise Killed(f"write of {name} after the kill")
        original_chunk(self, name, index, value)
        state["n"] += 1
        state["chunk_files"] += 1
        if state["k"] is not None and state["n"] == state["k"]:
            state["dead"] = True
            raise Killed(f"killed after write {state['n']} ({name} {index})")

    monkeypatch.setattr(zarr.storage.LocalStore, "_set", _set)
    monkeypatch.setattr(ChunkFiles, "write", write)

    def arm(k: int | None) -> dict:
        if state["dead"]:  # a SIGKILL stops every write in flight: let the killed run's
            _drain_zarr_loop()  # remaining writes fail (dead) before the next run may write
        state.update(n=0, k=k, dead=False, chunk_files=0)
        return state

    return arm


@pytest.mark.slow
def test_every_kill_point_resumes_to_the_uninterrupted_store(tmp_path, kill_after) -> None:
    reference = tmp_path / "reference.zarr"
    count = kill_after(None)
    run_sweep(SPEC, reference, chunk_function=_chunk, workers=0)
    n_writes = count["n"]
    expected = open_sweep(reference)
    assert n_writes > 20  # creation (metadata, coordinates) and two chunks of 12 arrays
    assert count["chunk_files"] >= 2 * 10  # the chunks' own files (two profile-only skipped)
    killed_with_temporaries = 0
    for k in range(1, n_writes + 1):
        store = tmp_path / f"k{k}.zarr"
        kill_after(k)
        with pytest.raises(Killed):
            run_sweep(SPEC, store, chunk_function=_chunk, workers=0)
        kill_after(None)
        killed_with_temporaries += bool(temporary_siblings(store))
        before = set()
        if store.exists():  # the skeleton is complete, or the store does not exist at all
            from skisnow.sweep._store import done_chunks

            before = done_chunks(store, SPEC)
        run = run_sweep(SPEC, store, chunk_function=_chunk, workers=0)
        assert set(run.computed).isdisjoint(before), f"kill point {k}: a chunk was recomputed"
        xr.testing.assert_identical(open_sweep(store), expected)
        left = temporary_siblings(store)  # every temporary name the code can make (one function)
        assert not left, f"kill point {k}: temporaries left after the resumed run: {left}"
    print(
        f"{n_writes} kill points, all resumed to the uninterrupted store; "
        f"{killed_with_temporaries} kills left a temporary, none survived the next run"
    )


def test_a_second_sweep_on_a_locked_store_is_refused(tmp_path) -> None:
    store = tmp_path / "busy.zarr"
    with StoreLock(store), pytest.raises(SkisnowError, match="another skisnow sweep"):
        run_sweep(SPEC, store, chunk_function=_chunk, workers=0)
    assert not store.exists()
    run_sweep(SPEC, store, chunk_function=_chunk, workers=0)  # the lock is gone with its holder


def test_a_killed_netcdf_export_leaves_no_file(tmp_path, monkeypatch) -> None:
    store = tmp_path / "s.zarr"
    run_sweep(SPEC, store, chunk_function=_chunk, workers=0)
    ds = open_sweep(store)
    target = tmp_path / "s.nc"

    def dies(self, path, **kwargs):
        with open(path, "wb") as fh:
            fh.write(b"CDF\x01 half of a file")
        raise Killed("killed mid-export")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", dies)
    with pytest.raises(Killed):
        save_netcdf(ds, target)
    assert sorted(p.name for p in tmp_path.iterdir() if p.suffix == ".nc") == []
    monkeypatch.undo()
    save_netcdf(ds, target)
    with xr.open_dataset(target) as back:
        np.testing.assert_array_equal(back["length_mm"].values, ds["length_mm"].values)
