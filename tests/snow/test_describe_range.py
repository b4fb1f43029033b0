"""A snow preset's one-line description says what its modulus is worth: the span of the
published relations for that snow (README "Which snow modulus?"), which the preset's modulus
lies inside. Before, ``contact --snow fine-grained`` printed "E 152.9 MPa" with no range for a
modulus the relations place anywhere in 73-278 MPa."""

from __future__ import annotations

import re

import pytest

from skisnow.snow import SNOW_PRESETS, get_snow


@pytest.mark.parametrize("name", sorted(SNOW_PRESETS))
def test_description_names_the_modulus_span(name: str) -> None:
    snow = get_snow(name)
    lo, hi = snow.ranges["modulus_mpa"]
    assert lo <= snow.modulus / 1e6 <= hi  # the preset's value is one point of its span
    m = re.search(r"spans E ([\d.]+)-([\d.]+) MPa", snow.describe())
    assert m is not None, snow.describe()
    assert float(m[1]) == pytest.approx(lo, rel=5e-3) and float(m[2]) == pytest.approx(hi, rel=5e-3)
