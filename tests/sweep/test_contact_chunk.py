"""The physics chunk function: profile + contact solve + zones along the load path.

Checks balance laws on the stored (field-unit) values, that warm starts along the masses do not
change the answer (path independence against cold single solves), the paper's trend that softer
snow gives a larger apparent area (Figure 7), and that the Breitschädel estimate depends on the
profile only, not on the snow.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.constants import STANDARD_GRAVITY
from skisnow.sweep import SweepSpec
from skisnow.sweep._point import contact_chunk, solve_point

SOURCE = "beam"  # the beam is always there; the network source is tested in the CLI test


def _spec(**kw) -> SweepSpec:
    base = dict(
        skis=("skate", "classic"),
        masses=(20.0, 30.0, 45.0, 60.0),
        load_positions=(-0.12,),
        snow_moduli=(50e6, 200e6),
        n_points=1024,
        profile_source=SOURCE,
    )
    base.update(kw)
    return SweepSpec(**base)


@pytest.fixture(scope="module")
def chunks() -> dict:
    spec = _spec()
    return {
        (ski, e): contact_chunk(spec, ski, -0.12, e) for ski in spec.skis for e in spec.snow_moduli
    }


def test_balance_laws_on_stored_values(chunks) -> None:
    spec = _spec()
    m = np.asarray(spec.masses)
    total = spec.zones.index("total")
    for out in chunks.values():
        assert out["converged"].all()
        # force balance, eq. 3: the zones carry the whole load (solver tol 1e-8 -> 1e-6 margin)
        np.testing.assert_allclose(out["load_share"][:, total], 1.0, atol=1e-6)
        np.testing.assert_allclose(out["load_share"][:, :total].sum(axis=1), 1.0, atol=1e-6)
        # units of the store: mean [kPa] · area [cm²] = share · m·g [N] (round-off only)
        force = out["mean_pressure_kpa"] * 1e3 * out["area_cm2"] * 1e-4
        want = out["load_share"] * (m * STANDARD_GRAVITY)[:, None]
        ok = out["area_cm2"] > 0
        np.testing.assert_allclose(force[ok], want[ok], rtol=1e-9)
        # lengths and areas add up over the zones; max >= mean
        np.testing.assert_allclose(
            out["area_cm2"][:, :total].sum(axis=1), out["area_cm2"][:, total], rtol=1e-12
        )
        assert np.all(out["max_pressure_kpa"][ok] >= out["mean_pressure_kpa"][ok])


def test_warm_start_does_not_change_the_answer(chunks) -> None:
    spec = _spec()
    for ski in spec.skis:
        out = chunks[(ski, 200e6)]
        a = 2  # 45 kg, reached by warm starts from 20 and 30 kg
        zones = solve_point(spec, ski, 45.0, -0.12, 200e6, initial_pressure=None).zones
        # same contact set to within one station (dx = 1.86 m / 1023 ≈ 1.8 mm) per patch end
        dx_mm = 1.9
        assert abs(zones.total.length * 1e3 - out["length_mm"][a, 3]) <= 2 * dx_mm
        # pressures agree to the solver tolerance scale (1e-8 on Σ|Δp|/Σp -> 1e-5 margin)
        np.testing.assert_allclose(zones.rear.mean_pressure / 1e3, out["mean_pressure_kpa"][a, 0],
                                   rtol=1e-5)  # fmt: skip


def test_softer_snow_gives_larger_area_and_lower_pressure(chunks) -> None:
    # Kalliorinne et al. 2023, Figure 7: 50 MPa vs 200 MPa -> larger area, lower mean pressure.
    for ski in ("skate", "classic"):
        soft, stiff = chunks[(ski, 50e6)], chunks[(ski, 200e6)]
        assert np.all(soft["area_cm2"][:, 3] > stiff["area_cm2"][:, 3])
        assert np.all(soft["mean_pressure_kpa"][:, 3] < stiff["mean_pressure_kpa"][:, 3])


def test_breitschaedel_depends_on_the_profile_only(chunks) -> None:
    for ski in ("skate", "classic"):
        a, b = chunks[(ski, 50e6)], chunks[(ski, 200e6)]
        np.testing.assert_array_equal(a["breitschaedel_area_cm2"], b["breitschaedel_area_cm2"])
        assert np.all(a["breitschaedel_area_cm2"][:, 3] > 0)


def test_profiles_computed_once_give_the_same_chunk(chunks) -> None:
    # The sweep computes the loaded profiles of a (ski, x_m) once, in the client, and hands
    # them to every chunk; the chunk must equal the one that computes its own profiles.
    from skisnow.sweep._point import loaded_profiles

    spec = _spec()
    profiles = loaded_profiles(spec, "classic", -0.12)
    assert profiles["height"].shape == (len(spec.masses), spec.n_points)
    out = contact_chunk(spec, "classic", -0.12, 200e6, profiles)
    for name, want in chunks[("classic", 200e6)].items():
        np.testing.assert_array_equal(out[name], want, err_msg=name)


@pytest.mark.parametrize("n_parts", [2, 3])
def test_profiles_computed_in_parts_give_the_same_chunk(chunks, n_parts) -> None:
    # On Dask the workers compute the beam profiles in one part of the masses each; the parts
    # joined must be the whole (the same rows in the same order), and the chunk the same.
    from skisnow.sweep._point import loaded_profiles, merge_profiles, split_profiles

    spec = _spec()
    assert split_profiles(spec)  # beam profiles: computed on the workers
    whole = loaded_profiles(spec, "classic", -0.12)
    parts = [loaded_profiles(spec, "classic", -0.12, part=(k, n_parts)) for k in range(n_parts)]
    assert sum(len(p["height"]) for p in parts) == len(spec.masses)
    merged = merge_profiles(parts)
    np.testing.assert_array_equal(merged["x"], whole["x"])
    np.testing.assert_array_equal(merged["height"], whole["height"])
    out = contact_chunk(spec, "classic", -0.12, 200e6, parts)
    for name, want in chunks[("classic", 200e6)].items():
        np.testing.assert_array_equal(out[name], want, err_msg=name)
    assert not split_profiles(_spec(profile_source="network"))  # JAX stays in the client


@pytest.mark.slow
def test_two_worker_processes_store_what_one_process_stores(tmp_path) -> None:
    # The Dask path of the physics (beam profiles in one part per worker on a local cluster of
    # forked processes, chunks softest snow first in whatever order they finish, profile-only
    # variables written once per writer) must store the very numbers of the in-process path:
    # every array equal to the last bit, iteration counts and residuals included.
    import zarr

    from skisnow.sweep import open_sweep, run_sweep

    spec = _spec(masses=(20.0, 45.0, 70.0, 95.0), snow_moduli=(20e6, 100e6, 400e6))
    run_sweep(spec, tmp_path / "one.zarr", workers=0)
    run = run_sweep(spec, tmp_path / "two.zarr", workers=2)
    assert run.workers == 2 and len(run.computed) == 6
    a, b = open_sweep(tmp_path / "one.zarr"), open_sweep(tmp_path / "two.zarr")
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
    # and the profile-only variables were written (the total zone has a Breitschädel area)
    group = zarr.open_group(str(tmp_path / "two.zarr"), mode="r")
    total = spec.zones.index("total")
    assert (group["breitschaedel_area_cm2"][..., total] > 0).all()
