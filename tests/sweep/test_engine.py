"""The sweep engine: grid, Zarr layout, chunk placement, Dask, resume, mismatch.

The engine is tested with an analytic chunk function (two Hertz line contacts sharing the load by
the lever rule, ``_hertz_chunk.py``): every value of the dataset is recomputed independently from
the coordinates, so a chunk written to the wrong region, a lost chunk or a resumed chunk that
differs is caught. The physics chunk function is tested in ``test_contact_chunk.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import zarr

from _hertz_chunk import G, W, effective, hertz, hertz_chunk
from skisnow import InputError
from skisnow.sweep import SweepSpec, open_sweep, parse_values, run_sweep, save_netcdf


def _spec(**kw) -> SweepSpec:
    base = dict(
        skis=("classic", "skate"),
        masses=np.arange(5.0, 41.0, 5.0),
        load_positions=(-0.21, -0.12, -0.07),
        snow_moduli=(20e6, 100e6, 400e6),
    )
    base.update(kw)
    return SweepSpec(**base)


def _expected_mean_pressure_kpa(ds: xr.Dataset, spec: SweepSpec) -> np.ndarray:
    """Rear-zone mean pressure recomputed from the coordinates alone (broadcast over the grid)."""
    m = ds.mass_kg.values[:, None, None]
    x_m = ds.load_position_mm.values[None, :, None] * 1e-3
    e = ds.snow_modulus_mpa.values[None, None, :] * 1e6
    share_rear = 1 - (x_m + 0.5) / 1.1
    e_prime = effective(e, spec)
    _, mean, _ = hertz(share_rear * m * G, e_prime)
    return mean / 1e3


def test_parse_values_field_units() -> None:
    # 5:130:1 is the paper's mass axis: 126 values, both ends included.
    masses = parse_values("5:130:1")
    assert masses.size == 126 and masses[0] == 5 and masses[-1] == 130
    moduli = parse_values("20:400:20")
    assert moduli.size == 20 and moduli[-1] == 400.0 and moduli[6] == 140.0  # no float drift
    assert parse_values("-120").tolist() == [-120.0]
    assert parse_values("30, 60").tolist() == [30.0, 60.0]
    for bad in ("5:1:1", "1:2", "a", "1:5:0", ""):
        with pytest.raises(InputError):
            parse_values(bad, name="--mass-kg")


def test_spec_validates_and_sorts() -> None:
    spec = _spec(masses=(30.0, 5.0, 60.0))
    assert spec.masses == (5.0, 30.0, 60.0)  # ascending: the warm-start path
    assert spec.shape == (2, 3, 3, 3, 7)  # zones: rear, middle, front, total and 3 regions
    assert SweepSpec.from_json(spec.to_json()) == spec
    with pytest.raises(InputError, match="masses"):
        _spec(masses=(5.0, -1.0))
    with pytest.raises(InputError, match="distinct"):
        _spec(snow_moduli=(20e6, 20e6))
    with pytest.raises(InputError, match="model"):
        _spec(model="3d")


def test_in_process_sweep_places_every_chunk(tmp_path: Path) -> None:
    spec = _spec()
    run = run_sweep(spec, tmp_path / "s.zarr", chunk_function=hertz_chunk, workers=0)
    assert len(run.computed) == 2 * 3 * 3 and run.skipped == ()
    ds = open_sweep(tmp_path / "s.zarr")
    assert ds.sizes == {
        "ski": 2,
        "mass_kg": 8,
        "load_position_mm": 3,
        "snow_modulus_mpa": 3,
        "zone": 7,
    }
    assert ds.load_position_mm.values.tolist() == [-210.0, -120.0, -70.0]
    assert ds.snow_modulus_mpa.values.tolist() == [20.0, 100.0, 400.0]
    assert ds.attrs["skisnow_version"] and ds.attrs["model"] == "strip"
    # every chunk in its place: the rear mean pressure equals the closed form to round-off
    got = ds.mean_pressure_kpa.sel(zone="rear").values  # (ski, mass, pos, E)
    want = _expected_mean_pressure_kpa(ds, spec)
    np.testing.assert_allclose(got, np.broadcast_to(want, got.shape), rtol=1e-12)
    # dtypes survive the store (no _FillValue masking of integers and booleans)
    assert ds.patches.dtype == np.int32 and ds.converged.dtype == bool
    assert (ds.iterations.sel(ski="skate") == 2).all() and (
        ds.iterations.sel(ski="classic") == 1
    ).all()
    # balance law of the data written: Σ mean·area over rear+front = m·g (tolerance: round-off)
    force = (
        (ds.mean_pressure_kpa * 1e3 * ds.area_cm2 * 1e-4).sel(zone=["rear", "front"]).sum("zone")
    )
    np.testing.assert_allclose(force, (ds.mass_kg * G).broadcast_like(force), rtol=1e-12)
    assert (ds.chunk_done == 1).all()


def test_dask_cluster_gives_the_same_dataset(tmp_path: Path) -> None:
    from distributed import Client, LocalCluster

    spec = _spec()
    run_sweep(spec, tmp_path / "a.zarr", chunk_function=hertz_chunk, workers=0)
    with (
        LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0"
        ) as cluster,
        Client(cluster) as client,
    ):
        seen: list[int] = []
        run = run_sweep(
            spec,
            tmp_path / "b.zarr",
            chunk_function=hertz_chunk,
            client=client,
            on_progress=lambda done, total, key: seen.append(done),
        )
    assert run.workers == 2 and seen == list(range(1, 19))
    xr.testing.assert_identical(open_sweep(tmp_path / "a.zarr"), open_sweep(tmp_path / "b.zarr"))


def test_resume_computes_only_missing_chunks(tmp_path: Path) -> None:
    spec = _spec()
    path = tmp_path / "s.zarr"
    run_sweep(spec, path, chunk_function=hertz_chunk, workers=0)
    reference = open_sweep(path)
    # Simulate a crash that lost three chunks: clear their markers and spoil their data.
    lost = [(0, 1, 2), (1, 0, 0), (1, 2, 1)]
    group = zarr.open_group(str(path), mode="r+")
    for i, j, k in lost:
        group["chunk_done"][i, j, k] = 0
        group["area_cm2"][i, :, j, k, :] = -1.0
    with pytest.raises(InputError, match="3 of 18 chunks"):
        open_sweep(path)
    run = run_sweep(spec, path, chunk_function=hertz_chunk, workers=0)
    assert sorted(run.computed) == sorted(lost) and len(run.skipped) == 15
    xr.testing.assert_identical(open_sweep(path), reference)
    # and once complete, the same command computes nothing
    assert run_sweep(spec, path, chunk_function=hertz_chunk, workers=0).computed == ()


def test_mismatched_restart_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "s.zarr"
    run_sweep(_spec(), path, chunk_function=hertz_chunk, workers=0)
    with pytest.raises(InputError, match=r"different sweep \(differs in: snow_moduli\)"):
        run_sweep(_spec(snow_moduli=(20e6, 200e6)), path, chunk_function=hertz_chunk, workers=0)
    with pytest.raises(InputError, match="chunk function"):
        run_sweep(_spec(), path, chunk_function=lambda *a: {}, workers=0)
    (tmp_path / "plain").mkdir()
    with pytest.raises(InputError, match=r"not a Zarr store|not a skisnow sweep"):
        run_sweep(_spec(), tmp_path / "plain", chunk_function=hertz_chunk, workers=0)


def test_failing_chunk_keeps_finished_chunks(tmp_path: Path) -> None:
    calls = {"n": 0}

    def flaky(spec, ski, x_m, e):
        calls["n"] += 1
        if calls["n"] == 4:
            raise RuntimeError("worker lost")
        return hertz_chunk(spec, ski, x_m, e)

    path = tmp_path / "s.zarr"
    spec = _spec()
    with pytest.raises(RuntimeError, match="worker lost"):
        run_sweep(spec, path, chunk_function=flaky, workers=0)
    run = run_sweep(spec, path, chunk_function=flaky, workers=0)
    assert len(run.skipped) == 3 and len(run.computed) == 15


def test_netcdf_export_round_trip(tmp_path: Path) -> None:
    spec = _spec(skis=("skate",), load_positions=(-0.12,))
    run_sweep(spec, tmp_path / "s.zarr", chunk_function=hertz_chunk, workers=0)
    ds = open_sweep(tmp_path / "s.zarr")
    out = save_netcdf(ds, tmp_path / "s.nc")
    back = xr.open_dataset(out).load()
    back.close()
    np.testing.assert_array_equal(back.area_cm2.values, ds.area_cm2.values)
    assert back.attrs["skisnow_sweep_spec"] == ds.attrs["skisnow_sweep_spec"]
    assert W > 0


def test_dask_retries_a_failing_chunk(tmp_path: Path) -> None:
    """A chunk whose first attempt fails (a lost worker, a transient error) is retried by Dask
    and the sweep ends with the same dataset as a clean run."""
    from distributed import Client, LocalCluster

    marks = tmp_path / "attempts"  # the task is serialised, so count attempts on disk
    marks.mkdir()

    def flaky_once(spec, ski, x_m, e):
        mark = marks / f"{ski}_{x_m}_{e}"
        with mark.open("a") as f:
            f.write("x")
        if e == 100e6 and mark.stat().st_size == 1:
            raise OSError("transient failure on a worker")
        return hertz_chunk(spec, ski, x_m, e)

    spec = _spec()
    run_sweep(spec, tmp_path / "ref.zarr", chunk_function=hertz_chunk, workers=0)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster, Client(cluster) as client:  # fmt: skip
        run = run_sweep(spec, tmp_path / "s.zarr", chunk_function=flaky_once, client=client,
                        retries=1)  # fmt: skip
    assert len(run.computed) == 18
    sizes = {p.name: p.stat().st_size for p in marks.iterdir()}
    assert len(sizes) == 18
    assert sorted(n for k, n in sizes.items() if k.endswith("_100000000.0")) == [2] * 6
    a, b = open_sweep(tmp_path / "s.zarr"), open_sweep(tmp_path / "ref.zarr")
    xr.testing.assert_equal(a, b)  # attrs differ only in the chunk function's name


def test_profile_only_variables_hold_the_last_chunk_written(tmp_path: Path) -> None:
    # The Breitschädel variables have no snow dimension: every chunk of a (ski, position)
    # carries them. A writer skips the files it has already written with the same values (the
    # earlier write ended before that chunk's marker), and writes values that differ: the store
    # ends as if every chunk had written them, whatever the order the chunks arrive in.
    from skisnow.sweep._run import prepare_store
    from skisnow.sweep._writer import ChunkWriter

    spec = _spec()
    path = tmp_path / "p.zarr"
    prepare_store(path, spec, hertz_chunk)
    group = zarr.open_group(str(path), mode="r")
    writer = ChunkWriter(path, spec)
    first = hertz_chunk(spec, "classic", -0.21, 20e6)
    writer.write((0, 0, 0), first)
    stored = group["breitschaedel_area_cm2"][0, :, 0, :]
    np.testing.assert_array_equal(stored, first["breitschaedel_area_cm2"])
    changed = dict(first, breitschaedel_area_cm2=first["breitschaedel_area_cm2"] * 2)
    writer.write((0, 0, 1), changed)  # differs: written
    np.testing.assert_array_equal(
        group["breitschaedel_area_cm2"][0, :, 0, :], changed["breitschaedel_area_cm2"]
    )
    writer.write((0, 0, 2), first)  # differs from the last written again: written
    np.testing.assert_array_equal(group["breitschaedel_area_cm2"][0, :, 0, :], stored)
    # unchanged values are not rewritten: a file spoiled behind the writer's back stays so
    zarr.open_group(str(path), mode="r+")["breitschaedel_length_mm"][0, :, 0, :] = -1.0
    writer.write((0, 0, 1), first)
    assert (group["breitschaedel_length_mm"][0, :, 0, :] == -1.0).all()
    # a new writer (a resumed sweep) writes them again with its first chunk
    ChunkWriter(path, spec).write((0, 0, 1), first)
    np.testing.assert_array_equal(
        group["breitschaedel_length_mm"][0, :, 0, :], first["breitschaedel_length_mm"]
    )
    # the other (ski, position)s are untouched (still the fill value)
    assert np.isnan(group["breitschaedel_length_mm"][1, :, 0, :]).all()
    assert np.isnan(group["breitschaedel_length_mm"][0, :, 1, :]).all()
