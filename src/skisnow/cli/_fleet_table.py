"""The side-by-side table of a fleet (``skisnow compare``): one row per quantity, one column
per ski, field units."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

__all__ = ["ZONE_ROWS", "comparison_rows"]

_SIDE_BY_SIDE = (
    ("camber_half_mm", "camber at ½ BW [mm]"),
    ("camber_full_mm", "camber at 1 BW [mm]"),
    ("pocket_0.1mm_half_mm", "wax pocket (0.1 mm) at ½ BW [mm]"),
    ("closing_load_kg", "closing load [kg]"),
    ("stiffness_n_per_mm", "stiffness [N/mm]"),
)
#: Rows of derived metrics computed at the load position (named in their label).
_AT_POSITION = ("closing_load_kg",)
#: Zones and regions of the side-by-side table (``kick`` is the kick-zone region).
ZONE_ROWS = ("rear", "middle", "front", "total", "rear_glide", "kick", "front_glide")
_CONTACT_ROWS = (
    ("length_mm", "length [mm]"),
    ("area_cm2", "area [cm²]"),
    ("mean_pressure_kpa", "mean p [kPa]"),
    ("peak_pressure_kpa", "peak p [kPa]"),
    ("load_share", "load share"),
)


def comparison_rows(
    records: Sequence[dict[str, Any]], *, load_position_mm: float | None = None
) -> list[list[Any]]:
    """The side-by-side table: one row per quantity, one column per ski (field units); the
    load position of the derived metrics is named in their rows. No value (NaN, ``None``: the
    pressures of a zone without contact, the kick zone of a skate ski) is shown as "—"; the
    kick-zone rows are left out when no ski of the fleet has a kick zone."""
    at = "" if load_position_mm is None else f" at {load_position_mm:g} mm"
    rows: list[list[Any]] = [["profile route", *[r["profile_route"] for r in records]]]
    rows += [[label.replace(" [", f"{at} [", 1) if key in _AT_POSITION else label,
              *[r[key] for r in records]] for key, label in _SIDE_BY_SIDE]  # fmt: skip
    kick = any(r["full_kick_contact"] is not None for r in records)  # any ski with a kick zone
    for load, tag in (("half", "½ BW"), ("full", "1 BW")):
        for zone in ZONE_ROWS:
            if zone == "kick" and not kick:
                continue
            for key, label in _CONTACT_ROWS:
                name = zone.replace("_", " ") if zone != "kick" else "kick zone"
                rows.append(
                    [f"{tag} {name} {label}", *[r[f"{load}_{zone}_{key}"] for r in records]]
                )
        if kick:
            rows.append([f"{tag} grip wax touches", *[r[f"{load}_kick_contact"] for r in records]])
    return rows
