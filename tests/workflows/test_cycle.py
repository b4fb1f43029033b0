"""Load cycles: balance laws frame by frame, warm starts, time reversal, the route outside the
network's domain, and when the grip wax touches the snow."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from _extras import needs_network
from skisnow import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.pipeline import solve_case
from skisnow.workflows import (
    UNLOADED_MASS,
    LoadHistory,
    kick_contact_summary,
    run_cycle,
    template_history,
)

N = 512  # stations: small grids keep the suite fast; the physics checked does not need more


@pytest.fixture(scope="module")
def skate_cycle() -> xr.Dataset:
    h = template_history("skate_g3", body_mass=70, n_frames=14)
    return run_cycle("classic", h, snow_modulus=100e6, n_points=N)


def test_every_loaded_frame_balances_force_and_moment(skate_cycle: xr.Dataset) -> None:
    ds = skate_cycle
    x = ds["x"].values
    dx = x[1] - x[0]
    width = 0.044
    loaded = ds["loaded"].values
    assert loaded.any() and (~loaded).any()
    for i in np.flatnonzero(loaded):
        p = ds["pressure"].values[i]
        w = ds["load"].values[i]
        xm = ds["load_position"].values[i]
        assert p.min() >= 0.0
        assert p.sum() * dx * width == pytest.approx(w, rel=1e-6)
        assert abs(((x - xm) * p).sum() * dx * width) <= 1e-6 * w * (x[-1] - x[0])
        shares = ds["load_share"].sel(zone=["rear", "middle", "front"]).values[i]
        assert shares.sum() == pytest.approx(1.0, abs=1e-9)
    for i in np.flatnonzero(~loaded):
        assert ds["load"].values[i] < UNLOADED_MASS * STANDARD_GRAVITY
        assert not ds["pressure"].values[i].any()
        assert ds["length"].sel(zone="total").values[i] == 0.0
        assert not ds["kick_contact"].values[i]


def test_warm_start_changes_the_cost_not_the_answer(skate_cycle: xr.Dataset) -> None:
    ds = skate_cycle
    for i in np.flatnonzero(ds["loaded"].values)[::3]:
        cold = solve_case(
            "classic",
            mass=float(ds["load"].values[i] / STANDARD_GRAVITY),
            load_position=float(ds["load_position"].values[i]),
            snow_modulus=100e6,
            n_points=N,
        )
        p = ds["pressure"].values[i]
        np.testing.assert_allclose(p, cold.solution.pressure, atol=1e-5 * p.max())


def test_time_reversal_reverses_the_results() -> None:
    h = template_history("double_poling", body_mass=70, n_frames=9)
    back = LoadHistory(
        time=h.time[-1] - h.time[::-1], force=h.force[::-1], load_position=h.load_position[::-1]
    )
    a = run_cycle("skate", h, snow_modulus=50e6, n_points=N, keep_fields=False)
    b = run_cycle("skate", back, snow_modulus=50e6, n_points=N, keep_fields=False)
    for var in ("length", "mean_pressure", "load_share"):
        np.testing.assert_allclose(a[var].values, b[var].values[::-1], rtol=1e-5, atol=1e-9)


@needs_network
def test_outside_the_trained_domain_the_beam_is_used_and_said() -> None:
    t = np.linspace(0, 0.2, 5)
    inside = LoadHistory(time=t, force=np.full(5, 80 * 9.81), load_position=np.full(5, -0.12))
    kick = LoadHistory(
        time=t, force=np.array([80, 100, 140, 100, 80]) * 9.81, load_position=np.full(5, -0.08)
    )
    a = run_cycle("classic", inside, snow_modulus=100e6, n_points=N, keep_fields=False,
                  profile_source="network")  # fmt: skip
    assert a.attrs["route"] == "network" and a.attrs["route_note"] == ""
    # the default route is the beam for every ski (issue 26), with nothing to say
    d = run_cycle("classic", kick, snow_modulus=100e6, n_points=N, keep_fields=False)
    assert d.attrs["route"] == "beam" and d.attrs["route_note"] == ""
    with pytest.raises(InputError, match="extrapolate"):
        run_cycle("classic", kick, snow_modulus=100e6, n_points=N, profile_source="network")


def test_kick_zone_contact_grows_with_load_and_comes_earlier_on_soft_snow() -> None:
    """The classic ski's wax pocket closes as the load grows; on softer snow the ski sinks
    deeper, so the grip wax touches at a lower load."""
    masses = np.linspace(20, 125, 15)
    ramp = LoadHistory(
        time=np.linspace(0, 1, masses.size),
        force=masses * STANDARD_GRAVITY,
        load_position=np.full(masses.size, -0.12),
    )
    first = {}
    for e in (30e6, 300e6):
        ds = run_cycle("classic", ramp, snow_modulus=e, n_points=N, keep_fields=False)
        kick = ds["length"].sel(zone="kick").values
        dx = ds["x"].values[1] - ds["x"].values[0]
        assert kick[0] == 0.0
        assert np.all(np.diff(kick) >= -dx)  # non-decreasing to one cell
        touched = ds["kick_contact"].values
        assert touched.any()
        first[e] = masses[np.argmax(touched)]
    assert first[30e6] <= first[300e6]


def test_kick_contact_summary_counts_frame_intervals() -> None:
    t = np.linspace(0.0, 1.0, 11)  # frames every 0.1 s; end frames stand for 0.05 s
    touch = np.zeros(11, dtype=bool)
    touch[[2, 3, 4, 8]] = True
    loaded = np.ones(11, dtype=bool)
    ds = xr.Dataset(
        {
            "kick_contact": ("time", touch),
            "loaded": ("time", loaded),
            "length": (("time", "zone"), np.where(touch, 0.1, 0.0)[:, None]),
            "load_share": (("time", "zone"), np.where(touch, 0.3, 0.0)[:, None]),
        },
        coords={"time": t, "zone": ["kick"]},
    )
    s = kick_contact_summary(ds)
    assert s["contact_time"] == pytest.approx(0.4)
    assert s["loaded_time"] == pytest.approx(1.0)
    assert s["episodes"] == 2
    assert s["first_touch"] == pytest.approx(0.2) and s["last_touch"] == pytest.approx(0.8)
    assert s["max_kick_share"] == pytest.approx(0.3)


def test_a_position_off_the_ski_is_refused() -> None:
    with pytest.raises(InputError, match=r"sample 1: -1500 mm is an implausible"):
        LoadHistory(time=[0, 0.1], force=[500, 500], load_position=[-0.12, -1.5])
    from skisnow import allow_implausible

    with allow_implausible():  # possible, if implausible: then the ski decides
        h = LoadHistory(time=[0, 0.1], force=[500, 500], load_position=[-0.12, -1.5])
        with pytest.raises(InputError, match=r"sample 1 .*off the ski"):
            run_cycle("skate", h, snow_modulus=100e6, n_points=N)


def test_flexible_route_balances_and_a_stiff_ski_gives_the_rigid_answer() -> None:
    """The flexible ski (beam and snow together) carries every frame's load; with EI × 10⁶ it
    no longer bends, and the contact is that of its rigid profile."""
    import dataclasses

    from skisnow.ski import get_ski
    from skisnow.workflows import FleetSki

    base = get_ski("skate")
    stiff = dataclasses.replace(
        base, name="stiff", stiffness_values=tuple(v * 1e6 for v in base.stiffness_values)
    )
    fs = FleetSki(label="stiff", ski=stiff, origin="test")
    h = LoadHistory(time=[0.0, 0.1, 0.2], force=[300.0, 600.0, 450.0], load_position=[-0.12] * 3)
    flex = run_cycle(fs, h, snow_modulus=100e6, n_points=N, ski_model="flexible")
    rigid = run_cycle(fs, h, snow_modulus=100e6, n_points=N, ski_model="rigid")
    assert flex.attrs["route"] == "flexible" and rigid.attrs["route"] == "beam"
    assert flex["converged"].all()
    x = flex["x"].values
    dx = x[1] - x[0]
    for i in range(3):
        p = flex["pressure"].values[i]
        assert p.min() >= 0.0
        assert p.sum() * dx * stiff.width == pytest.approx(h.force[i], rel=1e-6)
    for zone in ("rear", "front", "total"):
        np.testing.assert_allclose(
            flex["length"].sel(zone=zone).values, rigid["length"].sel(zone=zone).values, atol=dx
        )
    np.testing.assert_allclose(
        flex["mean_pressure"].sel(zone="total").values,
        rigid["mean_pressure"].sel(zone="total").values,
        rtol=0.02,
    )


def test_the_stated_time_resolution_bounds_the_error_under_refinement() -> None:
    """The summary states its time resolution (one frame interval); the wax's contact time and
    first touch of a coarse cycle agree with those of an 8x finer one to within the two
    resolutions (each frame stands for its interval, so each time is off by less than one)."""
    out = {}
    for n in (12, 96):
        h = template_history("diagonal", body_mass=70, n_frames=n)
        ds = run_cycle("classic", h, snow_modulus=100e6, n_points=N, keep_fields=False)
        out[n] = kick_contact_summary(ds)
        t = ds["time"].values
        assert out[n]["resolution"] == pytest.approx(np.max(np.diff(t)))
    coarse, fine = out[12], out[96]
    assert coarse["resolution"] > 7 * fine["resolution"]
    assert coarse["contact_time"] > 0 and np.isfinite(coarse["first_touch"])
    tol = coarse["resolution"] + fine["resolution"]
    assert abs(coarse["contact_time"] - fine["contact_time"]) <= tol
    assert abs(coarse["first_touch"] - fine["first_touch"]) <= tol
