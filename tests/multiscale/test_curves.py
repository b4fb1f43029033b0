"""Micro curves per base × snow: limits, interpolation, the disk cache."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import InputError
from skisnow.micro import slope_factor
from skisnow.multiscale import Base, cache_dir, make_base, micro_curves
from skisnow.multiscale import _curves as curves_module
from skisnow.snow import snow_preset

PRESSURES = np.geomspace(2e3, 2e6, 4)
SMALL = {"pressures": PRESSURES, "pixel": 3e-6, "bearing_positions": 12, "grain_nodes": 2}


@pytest.fixture(scope="module")
def small_base() -> Base:
    return make_base("S3", size=0.3e-3, seed=4)


@pytest.fixture(scope="module")
def snow():
    return snow_preset("machine-made")


@pytest.fixture
def fresh(monkeypatch: pytest.MonkeyPatch, tmp_path):
    """An empty cache directory and an empty in-process memory."""
    monkeypatch.setattr(curves_module, "_MEMORY", {})
    return tmp_path / "cache"


def test_bearing_curve_is_p_over_h_times_a_slope_factor(small_base, snow, fresh) -> None:
    c = micro_curves(small_base, snow, cache_dir=fresh, **SMALL)
    ratio = c.bearing_fraction / (c.bearing_pressures / c.hardness)
    s = slope_factor(small_base.prepared)
    # eq. 8: the projected area is p/H exactly; the real one adds the slope factor
    assert np.all(ratio >= 1.0) and np.all(ratio <= s.max())
    # the flat-ice contact carries the load at most at H: its area is at least F/H
    assert np.all(c.fractional_area >= c.pressures / c.hardness)
    assert np.all(np.diff(c.mean_separation_grid) < 0)
    assert c.converged.all()


def test_interpolation_meets_the_grid_and_the_zero_load_limits(small_base, snow, fresh) -> None:
    c = micro_curves(small_base, snow, cache_dir=fresh, **SMALL)
    p = c.pressures
    assert c.real_fraction(p) == pytest.approx(np.minimum(c.real_fractional_area, 1.0))
    assert c.mean_separation(p) == pytest.approx(c.mean_separation_grid)
    uc = 1e-7
    assert c.reciprocal_separation(p, uc) == pytest.approx(c._reciprocal_grid(uc))
    # p → 0: no real area, the separation of the texture resting on its highest point
    h = np.asarray(c.rest_gaps)
    assert c.real_fraction(np.array([0.0]))[0] == 0.0
    assert c.mean_separation(np.array([0.0]))[0] == pytest.approx(c.rest_mean)
    assert c.rest_reciprocal(0.0, uc) == pytest.approx(np.mean(1 / np.maximum(h, uc)), rel=1e-9)
    # far above the texture the gap is the macroscopic one: 1/(G + ⟨h_max − h⟩) to first order
    g = 5e-3
    assert c.rest_reciprocal(g, uc) == pytest.approx(1.0 / (g + c.rest_mean), rel=1e-5)
    # below the grid the fraction is linear in p (plastic and elastic light-load limits)
    assert c.real_fraction(p[:1] / 4)[0] == pytest.approx(c.real_fractional_area[0] / 4)
    assert c.beyond(np.array([p[-1] * 2]))[0] and not c.beyond(p).any()
    # the fused evaluation of the along-ski coupling is the four separate ones
    q = np.geomspace(p[0] / 10, p[-1] * 2, 57)
    fr, frg, sep, rec = c.contact_values(q, uc)
    assert fr == pytest.approx(c.real_fraction(q), rel=1e-12)
    assert frg == pytest.approx(c.real_fraction(q, model="grains"), rel=1e-12)
    assert sep == pytest.approx(c.mean_separation(q), rel=1e-12)
    assert rec == pytest.approx(c.reciprocal_separation(q, uc), rel=1e-12)


def test_smooth_base_is_full_contact_on_flat_ice_and_p_over_h_on_grains(snow, fresh) -> None:
    c = micro_curves("smooth", snow, cache_dir=fresh, **SMALL)
    p = np.array([1e3, 3e4, 1e6])
    assert np.all(c.real_fraction(p) == 1.0)
    assert np.all(c.mean_separation(p) == 0.0)
    assert np.all(c.reciprocal_separation(p, 1e-7) == 0.0)
    assert c.real_fraction(c.bearing_pressures, model="grains") == pytest.approx(
        c.bearing_pressures / c.hardness, rel=1e-12
    )
    assert c.rest_reciprocal(2e-6, 1e-7) == pytest.approx(1 / 2e-6)
    fr, frg, sep, rec = c.contact_values(p, 1e-7)
    assert np.all(fr == 1.0) and np.all(sep == 0.0) and np.all(rec == 0.0)
    assert frg == pytest.approx(p / c.hardness, rel=1e-9)


def test_cache_round_trip_and_key(small_base, snow, fresh, monkeypatch) -> None:
    first = micro_curves(small_base, snow, cache_dir=fresh, **SMALL)
    assert not first.from_cache
    files = list((fresh / "micro-curves").glob("*.npz"))
    assert len(files) == 1 and not any(p.name.startswith(".") for p in fresh.rglob("*"))
    monkeypatch.setattr(curves_module, "_MEMORY", {})
    again = micro_curves(small_base, snow, cache_dir=fresh, **SMALL)
    assert again.from_cache
    for name in ("real_fractional_area", "mean_separation_grid", "gap_area", "bearing_fraction"):
        assert np.array_equal(getattr(first, name), getattr(again, name))
    # another temperature is another snow for the micro scale: another key, another file
    colder = micro_curves(small_base, snow.replace(temperature_c=-9.0), cache_dir=fresh, **SMALL)
    assert not colder.from_cache and colder.key != first.key
    assert colder.hardness > first.hardness
    # the macro modulus is not part of the micro key
    stiffer = micro_curves(small_base, snow.replace(modulus=300e6), cache_dir=fresh, **SMALL)
    assert stiffer.key == first.key
    # a corrupt file is recomputed, never trusted
    files[0].write_bytes(b"not an npz")
    monkeypatch.setattr(curves_module, "_MEMORY", {})
    redo = micro_curves(small_base, snow, cache_dir=fresh, **SMALL)
    assert not redo.from_cache
    assert np.array_equal(redo.real_fractional_area, first.real_fractional_area)


def test_cache_directory_follows_the_environment(monkeypatch, tmp_path) -> None:
    monkeypatch.setenv("SKISNOW_CACHE_DIR", str(tmp_path / "env"))
    assert cache_dir() == tmp_path / "env"
    assert cache_dir(tmp_path / "arg") == tmp_path / "arg"
    monkeypatch.delenv("SKISNOW_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_dir() == tmp_path / "xdg" / "skisnow"


def test_sampling_that_would_alias_the_texture_is_refused(small_base, snow, fresh) -> None:
    with pytest.raises(InputError, match="alias"):
        micro_curves(small_base, snow, cache_dir=fresh, **(SMALL | {"pixel": 12e-6}))


def test_base_from_every_kind_of_spec(tmp_path) -> None:
    from skisnow.micro import PRESETS, write_topography

    b = make_base("s2", size=0.2e-3)
    assert b.name == "S2" and b.prepared is not None and make_base("S2", size=0.2e-3) is b
    assert make_base("none").smooth and make_base(None).smooth
    g = make_base(PRESETS["S5"], size=0.2e-3)
    assert g.texture.shape == (200, 200)
    path = write_topography(b.texture, tmp_path / "base.npz")
    from_file = make_base(path)
    assert from_file.key == b.key  # the same heights: the same curves
    with pytest.raises(InputError, match="S1"):
        make_base("S9")
