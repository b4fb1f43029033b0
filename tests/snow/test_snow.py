"""The snow across scales: relations against their published values, presets, files."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
from scipy import integrate

from skisnow import DomainWarning, FileFormatError, InputError
from skisnow.micro import ice_hardness
from skisnow.snow import (
    SNOW_PRESETS,
    Snow,
    gamma_grains,
    get_snow,
    modulus_from_density,
    read_snow,
    snow_preset,
    write_snow,
)


def test_density_relations_give_their_published_values() -> None:
    # Scapozza (2004): E = 0.1873·exp(0.0149 ρ) MPa; Gerling et al. (2017): 6.0e-10·ρ^4.6 MPa
    assert modulus_from_density(400.0) == pytest.approx(0.1873e6 * math.exp(5.96), rel=1e-12)
    assert modulus_from_density(300.0, relation="gerling2017") == pytest.approx(
        6.0e-10 * 300.0**4.6 * 1e6, rel=1e-12
    )
    # the quasi-static relation is monotone and lands in Lintzén & Edeskär's 50–350 MPa at the
    # densities of a prepared track
    e = [modulus_from_density(r) for r in (400.0, 450.0, 490.0)]
    assert e == sorted(e) and e[0] > 50e6 and e[-1] < 350e6


def test_density_relation_warns_outside_its_range_and_refuses_impossible_densities() -> None:
    with pytest.warns(DomainWarning, match="180–490"):
        modulus_from_density(600.0)
    for bad in (0.0, -10.0, 950.0, float("nan")):
        with pytest.raises(InputError, match="density"):
            modulus_from_density(bad)
    with pytest.raises(InputError, match="relation"):
        modulus_from_density(400.0, relation="nobody2020")


def test_gamma_grains_is_eq_12_normalised_with_the_given_mode() -> None:
    f = gamma_grains(400e-6)
    assert f.mode == pytest.approx(400e-6, rel=1e-12)
    area, _ = integrate.quad(f, 0, 5e-3, points=[400e-6], limit=200)
    assert area == pytest.approx(1.0, rel=1e-8)


def test_grain_nodes_average_exactly_low_polynomials_of_the_diameter() -> None:
    s = snow_preset("fine-grained")
    d, w = s.grain_nodes(3)
    assert w.sum() == pytest.approx(1.0)
    f = s.grains
    for k in range(6):  # Gauss–Laguerre with 3 nodes: exact below degree 6
        exact, _ = integrate.quad(lambda x, k=k: x**k * f(x), 0, 5e-3, limit=200)
        assert np.sum(w * d**k) == pytest.approx(exact, rel=1e-8)
    measured = Snow(name="m", modulus=1e8, grain_diameters=(3e-4, 1e-4, 2e-4, 4e-4))
    dm, wm = measured.grain_nodes(2)
    assert np.sum(wm * dm) == pytest.approx(2.5e-4) and measured.grain_diameters[0] == 1e-4


def test_presets_carry_sources_and_ranges_that_hold_their_own_values() -> None:
    assert set(SNOW_PRESETS) == {"new", "fine-grained", "coarse", "machine-made", "wet"}
    for s in SNOW_PRESETS.values():
        assert s.sources and s.description
        lo, hi = s.ranges["modulus_mpa"]
        assert lo <= s.modulus / 1e6 <= hi
        t_lo, t_hi = s.ranges["temperature_c"]
        assert t_lo <= s.temperature_c <= t_hi
        g_lo, g_hi = s.ranges["grain_mode_um"]
        assert g_lo <= s.grains.mode * 1e6 <= g_hi
    # the machine-made preset is the granular snow of the glide tests: −2 °C, H = 15.9 MPa
    m = snow_preset("machine")
    assert m.hardness == pytest.approx(15.9e6)
    assert m.grains.b == pytest.approx(24.922)
    # wet snow sits at 0 °C, outside eq. 2's fitted range: it says so
    with pytest.warns(DomainWarning):
        _ = snow_preset("wet").hardness
    with pytest.raises(InputError, match="fine-grained"):
        snow_preset("slush")


def test_snow_hardness_is_eq_2_or_3_at_its_temperature() -> None:
    s = Snow(name="x", modulus=1e8, temperature_c=-8.0, hardness_model="makkonen")
    assert s.hardness == pytest.approx(ice_hardness(-8.0, model="makkonen"))
    with pytest.raises(InputError, match="temperature"):
        Snow(name="x", modulus=1e8, temperature_c=3.0)
    with pytest.raises(InputError, match="modulus"):
        Snow(name="x", modulus=0.0)


def test_snow_file_round_trip_and_preset_overrides(tmp_path) -> None:
    s = snow_preset("coarse").replace(modulus=123e6, temperature_c=-7.5)
    path = write_snow(s, tmp_path / "track.json")
    back = read_snow(path)
    assert back.modulus == pytest.approx(123e6)
    assert back.temperature_c == -7.5
    assert back.grains.mode == pytest.approx(s.grains.mode)
    (tmp_path / "over.json").write_text(
        json.dumps(
            {"preset": "fine-grained", "temperature_c": -12, "grain_diameters_um": [300, 400]}
        )
    )
    over = get_snow(tmp_path / "over.json")
    assert over.modulus == snow_preset("fine-grained").modulus
    assert over.temperature_c == -12
    assert over.grain_diameters == pytest.approx((3e-4, 4e-4), rel=1e-12)
    (tmp_path / "rho.json").write_text(json.dumps({"density_kg_m3": 420, "temperature_c": -4}))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rho = read_snow(tmp_path / "rho.json")
    assert rho.modulus == pytest.approx(modulus_from_density(420.0))
    assert "Scapozza" in rho.modulus_source


@pytest.mark.parametrize(
    ("doc", "match"),
    [
        ({"temperature_c": -3}, "modulus_mpa"),
        ({"modulus_mpa": "hard"}, "modulus_mpa"),
        ({"modulus_mpa": 100, "colour": "white"}, "colour"),
        ({"modulus_mpa": 100, "temperature_c": 5}, "temperature"),
        ({"modulus_mpa": 100, "grain_diameters_um": [300, "x"]}, r"grain_diameters_um\[1\]"),
        ({"preset": "slush"}, "slush"),
    ],
)
def test_snow_file_errors_name_the_file_and_key(tmp_path, doc, match) -> None:
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match=match) as info:
        read_snow(path)
    assert "bad.json" in str(info.value)
