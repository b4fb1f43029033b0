"""Eq. 2 of Kalliorinne et al. (2023): the equivalent modulus E' = 2·E*."""

from __future__ import annotations

import pytest

from skisnow import InputError
from skisnow.contact import BASE, STONE, Material, contact_modulus, effective_modulus, snow


def test_stone_case_of_the_paper() -> None:
    # paper §3.2: E_base = 900 MPa, E_counter = 70 GPa, ν = 0.3 → E' ≈ 1.96 GPa (1.953 exactly)
    e = effective_modulus(STONE)
    assert e == pytest.approx(2 / (0.91 / 900e6 + 0.91 / 70e9), rel=1e-15)
    assert e == pytest.approx(1.953e9, rel=1e-3)


def test_equivalent_modulus_is_twice_the_contact_modulus() -> None:
    e_star = 1 / ((1 - 0.3**2) / 900e6 + (1 - 0.3**2) / 100e6)  # Johnson's E*
    assert effective_modulus(snow(100e6)) == pytest.approx(2 * e_star, rel=1e-15)
    assert contact_modulus(effective_modulus(snow(100e6))) == pytest.approx(e_star, rel=1e-15)
    # symmetric in the two bodies; numbers in Pa are accepted
    assert effective_modulus(100e6, 900e6) == pytest.approx(effective_modulus(snow(100e6)))
    assert BASE.modulus == 900e6 and BASE.poisson == 0.3


def test_invalid_materials() -> None:
    with pytest.raises(InputError, match="modulus"):
        Material(name="snow", modulus=-1.0)
    with pytest.raises(InputError, match="Poisson"):
        snow(100e6, poisson=0.5)
    with pytest.raises(InputError):
        effective_modulus(0.0)
