"""The real contact along the ski: balance laws, the plastic invariance, partitions, proxies."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.micro import slope_factor
from skisnow.multiscale import FrictionParameters, make_base, micro_curves, water_viscosity
from skisnow.pipeline import solve_case
from skisnow.snow import snow_preset

SMALL = {
    "pressures": np.geomspace(1e3, 3e6, 6),
    "pixel": 3e-6,
    "bearing_positions": 12,
    "grain_nodes": 2,
}


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    cache = tmp_path_factory.mktemp("cache")
    snow = snow_preset("machine-made")
    base = make_base("S3", size=0.3e-3, seed=5)
    smooth = make_base("smooth")
    return {
        "snow": snow,
        "base": base,
        "smooth": smooth,
        "curves": micro_curves(base, snow, cache_dir=cache, **SMALL),
        "smooth_curves": micro_curves(smooth, snow, cache_dir=cache, **SMALL),
    }


def _case(setup, *, base="base", ski="skate", **kw):
    curves = setup["curves"] if base == "base" else setup["smooth_curves"]
    args = {"mass": 60.0, "load_position": -0.12, "snow": setup["snow"], "curves": curves} | kw
    return solve_case(ski, base=setup[base], **args)


def test_load_is_carried_and_the_plastic_real_area_ignores_the_camber(setup) -> None:
    snow, curves = setup["snow"], setup["curves"]
    w = 60.0 * STANDARD_GRAVITY
    s_max = slope_factor(setup["base"].prepared).max()
    totals = []
    for xm in (-0.2, -0.12, 0.0):
        case = _case(setup, load_position=xm)
        r = case.real
        assert r.load.sum() == pytest.approx(w, rel=1e-6)  # force balance carried through
        # the bearing model: A_r = Σ p·dA·s(p)/H = W·s/H whatever the pressure distribution
        grains = r.real_area_grains.sum()
        assert w / curves.hardness <= grains <= w / curves.hardness * s_max
        totals.append(grains)
        # the flat-ice contact carries at most H: its real area is at least W/H
        assert r.real_area.sum() >= w / snow.hardness
    assert np.ptp(totals) / np.mean(totals) < s_max - 1.0


def test_regions_partition_the_ski_and_patches_hold_the_contact(setup) -> None:
    for ski in ("skate", "classic"):
        case = _case(setup, ski=ski)
        parts = case.real_summary()
        total = parts["total"]
        regions = [k for k in ("rear_glide", "kick_zone", "front_glide") if k in parts]
        patches = [k for k in parts if k.startswith("patch")]
        assert patches
        for field in ("apparent_area", "real_area", "reciprocal_separation", "load"):
            value = getattr(total, field)
            assert sum(getattr(parts[k], field) for k in regions) == pytest.approx(value)
        # every station in apparent contact lies in a patch: the patches hold all the area,
        # load and real area; the viscous term also counts gaps outside them
        for field in ("apparent_area", "real_area", "load"):
            assert sum(getattr(parts[k], field) for k in patches) == pytest.approx(
                getattr(total, field)
            )
        assert sum(parts[k].reciprocal_separation for k in patches) < total.reciprocal_separation
        assert 0 < total.real_fraction < 1


def test_smooth_base_touches_everywhere_it_bears(setup) -> None:
    case = _case(setup, base="smooth")
    r = case.real
    assert r.real_area == pytest.approx(r.apparent_area)
    sol = case.solution
    uc = r.friction.film_cutoff
    outside = sol.pressure == 0
    expected = np.sum(1.0 / np.maximum(sol.gap[outside], uc)) * sol.cell_area
    assert r.reciprocal.sum() == pytest.approx(expected, rel=1e-4)


def test_proxies_are_their_stated_formulas(setup) -> None:
    case = _case(setup)
    r = case.real
    t = r.total
    f = r.friction
    assert f.viscosity == pytest.approx(water_viscosity(-2.0))
    assert f.shear_strength == pytest.approx(0.3 * setup["snow"].hardness)
    assert t.dry_force == pytest.approx(f.shear_strength * t.real_area_grains)
    assert t.viscous_force == pytest.approx(f.viscosity * f.sliding_speed * t.reciprocal_separation)
    est = r.friction_estimate()
    assert est["mu"] == pytest.approx((t.dry_force + t.viscous_force) / (60 * STANDARD_GRAVITY))
    assert "τ =" in est["assumptions"] and "film cut-off" in est["assumptions"]
    # overriding a parameter changes only its term, linearly
    fast = _case(setup, friction=FrictionParameters(sliding_speed=2 * f.sliding_speed)).real.total
    assert fast.viscous_force == pytest.approx(2 * t.viscous_force)
    assert fast.dry_force == pytest.approx(t.dry_force)
    # a thicker film cut-off can only lower ∫1/u dA
    thick = _case(setup, friction=FrictionParameters(film_cutoff=1e-6)).real.total
    assert thick.reciprocal_separation < t.reciprocal_separation


def test_every_route_gives_the_real_contact(setup) -> None:
    rigid = _case(setup, ski="classic")
    beam = _case(setup, ski="classic", profile_source="beam")
    flexible = _case(setup, ski="classic", ski_model="flexible")
    for case in (rigid, beam, flexible):
        assert case.real is not None and case.converged
        assert case.real.load.sum() == pytest.approx(60 * STANDARD_GRAVITY, rel=1e-6)
    surface = _case(setup, model="surface", n_points=512, n_across=8)
    assert surface.real.load.sum() == pytest.approx(60 * STANDARD_GRAVITY, rel=1e-6)
    assert surface.real.x.shape == (512,)


def test_inputs_that_cannot_make_a_real_contact_are_refused(setup) -> None:
    with pytest.raises(InputError, match="snow"):
        solve_case("skate", mass=60.0, load_position=-0.12, snow_modulus=1e8, base="S3")
    with pytest.raises(InputError, match="not both"):
        solve_case("skate", mass=60.0, load_position=-0.12, snow_modulus=1e8, snow="wet")
    with pytest.raises(InputError, match="curves"):
        _case(setup, base="smooth", curves=setup["curves"])
    plain = solve_case("skate", mass=60.0, load_position=-0.12, snow=setup["snow"])
    assert plain.real is None and plain.snow_modulus == setup["snow"].modulus
    with pytest.raises(InputError, match="real contact"):
        plain.real_summary()
