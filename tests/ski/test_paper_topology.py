"""The shipped skis reproduce the contact TOPOLOGY of the real skis of Kalliorinne et al. (2023),
Figs. 5 and 6.

The skis were calibrated on the paper's contact numbers (benchmarks/calibrate_skis.py); these
tests check what does not depend on the fit's exact numbers: which zones carry load and how many
patches the front glide zone has, with the paper's contact model (strip, E_base = 900 MPa,
ν = 0.3, 2048 stations along the ski — the contact CLI's default).
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.constants import STANDARD_GRAVITY
from skisnow.contact import contact_zones, effective_modulus, solve_contact
from skisnow.network import camber_profile
from skisnow.ski import get_ski


def _zones(name: str, mass: float, pos: float, e_snow: float):  # type: ignore[no-untyped-def]
    ski = get_ski(name)
    edges = np.linspace(ski.x_tail, ski.x_tip, 2049)
    x, h = camber_profile(name, mass=mass, load_position=pos, x=0.5 * (edges[1:] + edges[:-1]))
    sol = solve_contact(
        x,
        h,
        load=mass * STANDARD_GRAVITY,
        load_position=pos,
        modulus=effective_modulus(e_snow, 900e6, poisson=0.3),
        width=ski.width,
    )
    assert sol.converged
    return contact_zones(sol, kick_zone=ski.kick_zone)


def test_classic_three_zones_when_the_load_moves_forward() -> None:
    # Fig. 6 right: 60 kg at -70 mm, 100 MPa -> rear, middle (kick zone) and front carry load
    z = _zones("classic", 60.0, -0.070, 100e6)
    for name in ("rear", "middle", "front", "kick"):
        assert z[name].length > 0 and z[name].load_share > 0.05, name
    assert z["middle"].patches == 1  # a separate third patch under the foot
    # Fig. 6 left: 60 kg at -210 mm -> the kick zone stays free, the rear zone carries most
    z = _zones("classic", 60.0, -0.210, 100e6)
    assert z["middle"].length == 0.0
    assert z["rear"].load_share > 0.6 > z["front"].load_share


@pytest.mark.parametrize(("mass", "front_patches"), [(30.0, 1), (60.0, 2)])
def test_skate_front_zone_splits_between_30_and_60_kg(mass: float, front_patches: int) -> None:
    # Fig. 5: 120 mm behind the balance point on 100 MPa snow, one front patch at 30 kg, two at
    # 60 kg; the rear zone carries the larger share in both (paper: 67 % and 71 %).
    z = _zones("skate", mass, -0.120, 100e6)
    assert z["front"].patches == front_patches
    assert z["middle"].length == 0.0  # no kick zone on a skate ski
    assert z["rear"].load_share > z["front"].load_share
    assert z["rear"].load_share + z["front"].load_share == pytest.approx(1.0, abs=1e-9)
