"""Materials (eq. 1–4) against the seed's Table 2 and its stated ranges."""

from __future__ import annotations

import pytest

from skisnow._errors import DomainWarning, InputError
from skisnow.micro import (
    contact_time,
    deformation_regime,
    ice_hardness,
    scherge2021,
    uhmwpe_hardness,
)


def test_table2_values_at_minus_two() -> None:
    assert ice_hardness(-2.0) == pytest.approx(scherge2021.TABLE2["ice"]["hardness_mpa"] * 1e6)
    assert uhmwpe_hardness(-2.0) == pytest.approx(
        scherge2021.TABLE2["UHMWPE"]["hardness_mpa"] * 1e6,
        rel=1e-3,  # 42.32 printed as 42.3
    )


def test_makkonen_in_range_and_warnings_outside() -> None:
    assert ice_hardness(-10.0, model="makkonen") == pytest.approx(35.61e6)
    with pytest.warns(DomainWarning, match="-10 to -3"):
        ice_hardness(-12.0, model="makkonen")
    with pytest.warns(DomainWarning, match="below -1"):
        ice_hardness(-0.5)
    # above −2.99 °C the Makkonen–Tikanmäki line is negative (the seed's remark)
    with pytest.warns(DomainWarning), pytest.raises(InputError, match="<= 0"):
        ice_hardness(-2.0, model="makkonen")
    with pytest.raises(InputError, match="melting"):
        ice_hardness(1.0)
    with pytest.raises(InputError, match="unknown"):
        ice_hardness(-5.0, model="vickers")


def test_regime_and_contact_time() -> None:
    r = deformation_regime(-2.0)
    assert r.yielding == "ice" and r.bearing_model_applies
    assert r.hardness_ratio == pytest.approx(42.32 / 15.9)
    assert r.ice_stiffness_to_hardness == pytest.approx(9.5e9 / 15.9e6)
    # eq. 1: 500 µm at 10 km/h → 1.8·10⁻⁴ s
    assert contact_time(500e-6, 10 / 3.6) == pytest.approx(1.8e-4)
    with pytest.raises(InputError):
        contact_time(0.0, 1.0)
