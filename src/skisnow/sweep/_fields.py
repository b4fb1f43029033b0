"""Fields along the ski on display stations: what a sweep stores when asked for fields
(``SweepSpec.field_stations``) and the explorer page draws.

The display stations are block means of the solver's cells: a block mean of the pressure keeps
the force balance Σ p dA = m·g of Kalliorinne et al. (2023), eq. 3 (peak pressures stay in the
zone metrics, from the full-resolution solve).
"""

from __future__ import annotations

import numpy as np

#: Zones coded per station: 0 none, then these in order (1 rear, 2 middle, 3 front).
CODED_ZONES: tuple[str, ...] = ("rear", "middle", "front")


def block_mean(values: np.ndarray, n_blocks: int) -> np.ndarray:
    """Means of ``n_blocks`` equal consecutive blocks along the last axis (its length must be
    a multiple of ``n_blocks``)."""
    v = np.asarray(values, dtype=float)
    return v.reshape(*v.shape[:-1], n_blocks, v.shape[-1] // n_blocks).mean(axis=-1)


def zone_codes(x: np.ndarray, zones, n_blocks: int) -> np.ndarray:
    """Zone of each display station: 0 none, 1 rear, 2 middle, 3 front — the zone of the
    contact cells in the block (the most forward zone where a block holds two). ``zones`` is a
    :class:`skisnow.contact.ZoneMetrics` on the cells ``x``."""
    code = np.zeros(x.size, dtype=np.int8)
    for k, name in enumerate(CODED_ZONES, start=1):
        for a, b in zones[name].intervals:
            code[(x >= a) & (x <= b)] = k
    return code.reshape(n_blocks, -1).max(axis=-1)


def station_fields(solution, zones, n_stations: int) -> dict[str, np.ndarray]:
    """The stored fields of one solved case on ``n_stations`` display stations: pressure [kPa],
    ski base above the undeformed snow h − δ − θ(x − x_m) [µm] (for a flexible ski h is the
    bent ski), snow surface −u [µm] and zone code (strip and line models)."""
    s = solution
    base = s.height - s.translation - s.rotation * (s.x - s.load_position)
    return {
        "pressure_kpa": block_mean(s.pressure, n_stations) * 1e-3,
        "base_um": block_mean(base, n_stations) * 1e6,
        "snow_um": -block_mean(s.displacement, n_stations) * 1e6,
        "zone_code": zone_codes(s.x, zones, n_stations),
    }


def unconverged_points(ds) -> tuple[list[str], int]:
    """The points of a sweep dataset whose contact solve ran and did not converge, named
    (``"skate 60 kg at -120 mm on 100 MPa"``), and the number of points whose load the ski
    could not carry (not solved: ``iterations`` 0; a corner of a map, not a failure)."""
    conv = ds["converged"]
    its = ds["iterations"] if "iterations" in ds else conv.astype(int) + 1  # all were solved
    failed = (~conv.astype(bool)) & (its > 0)
    not_carried = int(((~conv.astype(bool)) & (its == 0)).sum())
    labels = []
    for point in failed.where(failed, drop=True).stack(p=failed.dims)["p"].values:
        where = dict(zip(failed.dims, point, strict=True))
        model = "".join(f" ({where[k]})" for k in ("model", "base") if where.get(k, "") != "")
        labels.append(
            f"{where['ski']}{model} {where['mass_kg']:g} kg at {where['load_position_mm']:g} mm "
            f"on {where['snow_modulus_mpa']:g} MPa"
        )
    return labels, not_carried
