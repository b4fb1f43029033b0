"""Downstream check (issue 4, item 6): the contact solver fed with the shipped network's profile
gives the zone lengths and mean pressures of the beam profile, within a stated tolerance.

Tolerance and why. A profile error δh inside a contact zone changes how deep that part of the
ski sinks into the snow. Near a zone edge the snow surface is pressed down by the penetration
d of the zone; for a smooth (locally parabolic) profile pressed into a half-space, the contact
half-length grows like a ∝ √d, so a height error δh moves a zone edge by δa/a ≈ ½ δh/d. With
the network's largest error near contact (δh, measured here over the stations where the beam
profile is below 0.2 mm) and the zone's penetration d (from the beam solution), a zone's length
may change relatively by ½·δh/d per edge, i.e. δh/d for both edges, plus one station spacing
per edge from the discretisation. Mean pressure = force/area: the force of a zone is fixed by
the balance laws up to the load share, so its relative change is bounded by the same amount
(doubled, as length and share both move). The check is also capped at 15 %: a larger change
would alter the engineering conclusion whatever the profile error.
"""

from __future__ import annotations

import numpy as np
import pytest

from skisnow.constants import STANDARD_GRAVITY

E_SNOW = 100e6  # Pa, the snow
LOADS = [(40.0, -0.100), (70.0, -0.150), (110.0, -0.200)]  # (kg, m): inside the bench domain
N_STATIONS = 1024


def _zones(ski_name: str, mass: float, position: float, source: str):
    from skisnow.contact import contact_zones, effective_modulus, snow, solve_contact
    from skisnow.network import camber_profile
    from skisnow.ski import get_ski

    ski = get_ski(ski_name)
    edges = np.linspace(ski.x_tail, ski.x_tip, N_STATIONS + 1)
    x = 0.5 * (edges[1:] + edges[:-1])
    x, h = camber_profile(ski_name, mass=mass, load_position=position, x=x, source=source)
    sol = solve_contact(
        x,
        h,
        load=mass * STANDARD_GRAVITY,
        load_position=position,
        modulus=effective_modulus(snow(E_SNOW)),
        width=ski.width,
    )
    assert sol.converged
    return x, h, contact_zones(sol, kick_zone=ski.kick_zone)


@pytest.mark.slow
@pytest.mark.parametrize("ski_name", ["classic", "skate"])
@pytest.mark.parametrize(("mass", "position"), LOADS)
def test_network_profile_gives_beam_zones(ski_name, mass, position):
    x, h_beam, z_beam = _zones(ski_name, mass, position, "beam")
    _, h_net, z_net = _zones(ski_name, mass, position, "network")
    dx = x[1] - x[0]
    near = h_beam < 0.2e-3
    delta_h = float(np.max(np.abs(h_net - h_beam)[near]))
    for name in ("rear", "middle", "front"):
        zb, zn = z_beam[name], z_net[name]
        if zb.length < 10 * dx:  # no zone (or a sliver) under the beam profile
            assert zn.length < 20 * dx, f"{name}: network makes a {zn.length * 1e3:.0f} mm zone"
            continue
        rel = min(delta_h / zb.penetration + 2 * dx / zb.length, 0.15)
        assert abs(zn.length - zb.length) <= rel * zb.length, (
            f"{ski_name} {mass} kg {position * 1e3:.0f} mm {name}: length "
            f"{zn.length * 1e3:.1f} vs beam {zb.length * 1e3:.1f} mm (tol {rel:.1%}, "
            f"δh {delta_h * 1e6:.1f} µm, d {zb.penetration * 1e6:.0f} µm)"
        )
        rel_p = min(2 * rel, 0.15)
        assert abs(zn.mean_pressure - zb.mean_pressure) <= rel_p * zb.mean_pressure, (
            f"{ski_name} {name}: mean pressure {zn.mean_pressure / 1e3:.1f} vs beam "
            f"{zb.mean_pressure / 1e3:.1f} kPa (tol {rel_p:.1%})"
        )
