"""Patch topology in rankings: a patch-based criterion compares like with like, or says not.

The paper's zones (rear, middle, front; Kalliorinne et al. 2023, Figures 4-7) are made of
whole contact patches (:func:`skisnow.contact.paper_zones`): a glide patch reaching into the
kick zone stays whole in its glide zone, and once the kick contact separates from it the kick
part becomes a ``middle`` patch — so "the rear zone's load share" jumps (0.77 → 0.36 for the
shipped classic against its identification at 300 MPa, issue 25) when a few micrometres of
camber decide merge or split. Two skis (or the posterior samples of one) in different patch
topologies are not ranked apart by such a criterion: the pair is *not comparable by this
criterion* (it ties, and a warning names the zones and the share of samples in each topology),
and the regions (rear glide, kick zone, front glide: fixed by the ski, never jumping;
:func:`skisnow.contact.footprint`) are the robust alternative the message offers.

The topology of a contact is the number of patches of each paper zone and whether the zones are
merged into the regions (:func:`skisnow.pipeline.zone_topology`); a criterion on zone Z looks at
the zones that can exchange a patch with it: rear and middle for ``rear``, middle and front for
``front``, all three for ``middle``. A ski's answer *straddles* two topologies when more than
:data:`skisnow.pipeline.MIXED_SHARE` (2.5 %, one tail of a 95 % interval) of its posterior
samples are in another topology than its estimate.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from skisnow.pipeline import MIXED_SHARE, PATCH_ZONES, topology_shares, topology_text, zone_topology

__all__ = [
    "TOPOLOGY_ZONES",
    "SkiTopology",
    "comparable",
    "patch_zone",
    "ski_topology",
    "topology_warnings",
]

#: The zones whose patches decide a criterion on each paper zone.
TOPOLOGY_ZONES: dict[str, tuple[str, ...]] = {
    "rear": ("rear", "middle"),
    "middle": PATCH_ZONES,
    "front": ("middle", "front"),
}


def patch_zone(column: str) -> str | None:
    """The paper zone of a record column (``full_rear_load_share`` → ``'rear'``), ``None``
    when the column is not a patch-based zone's (the total, the kick contact, the regions)."""
    _, _, rest = column.partition("_")  # the load: half, full
    for quantity in ("length_mm", "area_cm2", "mean_pressure_kpa", "peak_pressure_kpa",
                     "load_share"):  # fmt: skip
        if rest.endswith("_" + quantity):
            zone = rest[: -len(quantity) - 1]
            return zone if zone in PATCH_ZONES else None
    return None


@dataclass(frozen=True, kw_only=True)
class SkiTopology:
    """The patch topology of one ski's answer on a patch-based criterion.

    ``text``: the estimate's topology of the criterion's zones; ``shares``: the posterior
    samples' share in each topology (the estimate's first; empty without samples)."""

    text: str
    shares: dict[str, float] = field(default_factory=dict)

    @property
    def mixed(self) -> bool:
        """Whether the samples straddle two topologies (module docstring)."""
        return bool(self.shares) and 1.0 - self.shares.get(self.text, 0.0) > MIXED_SHARE

    def describe(self) -> str:
        """The topology and, when the samples straddle, their shares."""
        if not self.mixed:
            return self.text
        return "; ".join(f"{100 * v:.1f} % of samples: {k}" for k, v in self.shares.items())


def ski_topology(zones: Any, samples: Sequence[Any], zone: str) -> SkiTopology:
    """The topology of a contact's ``zones`` (:class:`skisnow.contact.ZoneMetrics`) for a
    criterion on ``zone``, with the shares of its posterior ``samples``' topologies
    (:attr:`skisnow.pipeline.Intervals.sample_topologies`; empty: none)."""
    which = TOPOLOGY_ZONES[zone]
    est = zone_topology(zones)
    return SkiTopology(text=topology_text(est, which), shares=topology_shares(samples, est, which))


def comparable(tops: Sequence[SkiTopology | None]) -> np.ndarray:
    """``C[i, j]``: skis i and j can be ranked apart by the criterion — both in the same
    topology and neither straddling two (``None``: not a patch-based criterion, always
    comparable)."""
    n = len(tops)
    out = np.ones((n, n), dtype=bool)
    for i, a in enumerate(tops):
        for j, b in enumerate(tops):
            if a is not None and b is not None and i != j:
                out[i, j] = not (a.mixed or b.mixed or a.text != b.text)
    return out


def topology_warnings(
    labels: Sequence[str], tops: Sequence[SkiTopology | None], criterion: str, zone: str,
    where: str = "",
) -> list[str]:  # fmt: skip
    """One warning per pair of skis that a patch-based criterion cannot compare (``where``:
    appended to the pair's names, e.g. the snow modulus)."""
    ok = comparable(tops)
    out = []
    for i, j in zip(*np.nonzero(np.triu(~ok, 1)), strict=True):
        a, b = tops[i], tops[j]
        assert a is not None and b is not None  # comparable() is True for None
        out.append(
            f"{labels[i]} / {labels[j]}{where}: {criterion} not comparable (patch topology of "
            f"the {'/'.join(TOPOLOGY_ZONES[zone])} zones, {labels[i]}: {a.describe()}; "
            f"{labels[j]}: {b.describe()}): the {zone} zone's answer jumps when a glide patch "
            "joins the kick contact or splits from it, so the two tie by this criterion; "
            "compare the regions instead (the rear_glide, kick and front_glide load shares, "
            "which do not jump)"
        )
    return out
