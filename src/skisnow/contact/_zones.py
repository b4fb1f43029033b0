"""Contact zones and their metrics (Kalliorinne et al. 2023, §4, Figures 4–9).

A *patch* is a connected run of stations along the ski where the ski touches the snow (for the
surface model: where any cell across the width is in contact). Patches are grouped into zones:

* the paper's zones follow one rule, :func:`paper_zones`: with a kick (grip-wax) zone
  ``(start, end)`` (classic skis) and separate patches, patches are kept whole — a patch lying
  entirely between the marks is ``middle`` (the third zone of the paper's Figure 6, right), a
  glide patch reaching into the kick zone stays whole in its glide zone; without a kick zone the
  runs are cut at the top of the camber pocket between the outer patches. Once a patch runs
  across the ski's region boundaries (*merged*: rear glide joined to front glide), the zones are
  the regions (rear glide, kick zone, front glide; rear/front at the balance point without a
  kick zone) and ``merged`` is True — whole-patch zones would jump there (the entire footprint
  "rear", the front at 0 mm);
* ``kick`` is the contact between the marks whatever patch it belongs to (where the grip wax
  touches the snow);
* ``footprint`` carries the two views that never jump (:mod:`skisnow.contact._regions`): the
  regions fixed by the ski, and every patch with the regions it spans.

Per zone, in total and between the kick-zone marks (``kick``): start, end [m] (outer cell
edges), length [m] (sum of patch lengths — the paper's "two patches that amount to 132 mm"),
area [m²], force [N], load share, mean pressure (force/area) and max pressure [Pa], number of
patches and penetration depth (largest snow displacement in the zone) [m]. Beside them, the
Breitschädel (2012) criterion with the same grouping: contact wherever the loaded camber height,
measured from the plane the ski rests on (the line through the lowest points of its two glide
zones, :func:`skisnow.ski.support_line`), is below 50 µm.
"""

from __future__ import annotations

import itertools
from dataclasses import asdict, dataclass

import numpy as np

from skisnow._errors import InputError
from skisnow.contact._regions import Footprint, footprint, region_index, region_marks
from skisnow.contact._regions import runs as _runs
from skisnow.contact._solver import ContactSolution
from skisnow.ski import BREITSCHAEDEL_THRESHOLD, breitschaedel_contact

__all__ = [
    "BREITSCHAEDEL_THRESHOLD",
    "REGION_NAMES",
    "Zone",
    "ZoneMetrics",
    "contact_zones",
    "paper_zones",
    "patches",
]

ZONE_NAMES = ("rear", "middle", "front")
#: Every region name a ski can have (:mod:`skisnow.contact._regions`), tail → tip.
REGION_NAMES = ("rear_glide", "kick_zone", "front_glide")


@dataclass(frozen=True, kw_only=True)
class Zone:
    """Metrics of one zone (SI).

    A zone without contact has length, area, force and load share 0 and no pressure or
    penetration: ``mean_pressure``, ``max_pressure`` and ``penetration`` are NaN there (JSON
    null, an empty CSV cell, "—" in a table), as they are without load data (Breitschädel).
    """

    name: str
    start: float
    end: float
    length: float
    area: float
    force: float
    load_share: float
    mean_pressure: float
    max_pressure: float
    patches: int
    penetration: float
    intervals: tuple[tuple[float, float], ...]

    def as_dict(self) -> dict:
        """Plain dict (SI units), intervals as lists."""
        d = asdict(self)
        d["intervals"] = [list(iv) for iv in self.intervals]
        return d


@dataclass(frozen=True, kw_only=True)
class ZoneMetrics:
    """Zones of a contact solution: ``rear``, ``middle``, ``front``, ``total``, Breitschädel.

    ``rear``/``middle``/``front`` are the paper's zones (:func:`paper_zones`); ``merged`` says
    that the patches have joined across the ski's regions and the zones are the regions.
    ``kick`` is the contact between the kick-zone marks whatever patch it belongs to (where the
    grip wax touches the snow; empty without a kick zone). ``footprint`` holds the two views
    that never jump: the regions fixed by the ski and every patch
    (:func:`skisnow.contact.footprint`).
    """

    rear: Zone
    middle: Zone
    front: Zone
    total: Zone
    kick: Zone
    breitschaedel: dict[str, Zone]
    split: float
    kick_zone: tuple[float, float] | None
    threshold: float
    footprint: Footprint
    merged: bool
    regions: dict[str, Zone]

    def __getitem__(self, name: str) -> Zone:
        """A zone by name, or a region (``rear_glide``, ``kick_zone``, ``front_glide``) as a
        :class:`Zone` (an empty one for ``kick_zone`` on a ski without a kick zone)."""
        if name in ("rear", "middle", "front", "total", "kick"):
            return getattr(self, name)
        if name in REGION_NAMES:
            return self.regions.get(name) or _empty_zone(name)
        raise KeyError(f"{name!r}: zones are rear, middle, front, total, kick, "
                       f"{', '.join(REGION_NAMES)}")  # fmt: skip

    def as_dict(self) -> dict:
        """Nested plain dict in SI units."""
        out = {n: self[n].as_dict() for n in ("rear", "middle", "front", "total", "kick")}
        out["breitschaedel"] = {k: v.as_dict() for k, v in self.breitschaedel.items()}
        out["split"] = self.split
        out["kick_zone"] = list(self.kick_zone) if self.kick_zone else None
        out["threshold"] = self.threshold
        out["merged"] = self.merged
        out.update(self.footprint.as_dict())  # "regions", "patches", "marks", "rule"
        return out


def patches(mask: np.ndarray) -> list[tuple[int, int]]:
    """Connected runs of True in a 1D mask as ``(first, last)`` index pairs (inclusive)."""
    m = np.asarray(mask, dtype=bool)
    if m.ndim != 1:
        raise InputError(f"patches() needs a 1D mask, got shape {m.shape}")
    return _runs(m)


def paper_zones(
    runs: list[tuple[int, int]],
    x: np.ndarray,
    height: np.ndarray,
    load_position: float,
    kick_zone: tuple[float, float] | None,
    split: float | None,
) -> tuple[dict[str, list[tuple[int, int]]], float, bool]:
    """The paper's rear / middle / front zones from the patches and the regions (one rule).

    Kalliorinne et al. (2023), Figures 4–7, compare zones made of whole patches. That holds
    while the patches are separate; once one patch runs across the ski's region boundaries (a
    *merged* footprint) a whole-patch zone would take the entire footprint and jump, so the
    zones become the regions (:mod:`skisnow.contact._regions`):

    * separate patches, with a kick zone: a patch lying between the marks is ``middle``; a patch
      starting behind the rear mark and ending before the front mark is ``rear``, one starting
      after the rear mark and ending beyond the front mark ``front`` (a glide patch reaching
      into the kick zone stays whole in its glide zone, as in the paper's captions);
    * separate patches, no kick zone: runs are cut at the top of the camber pocket between the
      rearmost and the frontmost patch (or at ``split``); a single patch not crossing the
      balance point goes whole to the side of the load point its centre lies on;
    * merged (a patch from behind the rear mark to beyond the front mark; without a kick zone,
      one patch across the balance point or ``split``): rear = the rear glide region, middle =
      the kick-zone region, front = the front glide region, and ``merged`` is True.

    Returns
    -------
    groups, split_used, merged
        Station runs per zone name, the rear/front split used [m] (NaN with a kick zone), and
        whether the footprint is merged.
    """
    groups: dict[str, list[tuple[int, int]]] = {n: [] for n in ZONE_NAMES}
    marks, _, _ = region_marks(kick_zone, split=0.0 if split is None else split)
    if kick_zone is not None:
        k0, k1 = kick_zone
        merged = any(x[i] < k0 and x[j] > k1 for i, j in runs)
    else:
        merged = len(runs) == 1 and x[runs[0][0]] < marks[0] <= x[runs[0][1]]
    if merged:
        idx = region_index(x, marks)
        names = ("rear", "middle", "front") if kick_zone is not None else ("rear", "front")
        for i, j in runs:
            seg = idx[i : j + 1]
            cuts = np.flatnonzero(np.diff(seg)) + 1
            bounds = [0, *cuts.tolist(), seg.size]
            for a, b in itertools.pairwise(bounds):
                groups[names[int(seg[a])]].append((i + a, i + b - 1))
        split_used = float("nan") if kick_zone is not None else float(marks[0])
        return groups, split_used, True
    if kick_zone is not None:
        k0, k1 = kick_zone
        for i, j in runs:
            first, last = x[i], x[j]
            if first >= k0 and last <= k1:
                name = "middle"
            elif first < k0 and last <= k1:
                name = "rear"
            else:  # first >= k0 and last > k1 (a run spanning both marks is merged)
                name = "front"
            groups[name].append((i, j))
        return groups, float("nan") if split is None else float(split), False
    centres = [0.5 * (x[i] + x[j]) for i, j in runs]
    if split is None and len(runs) >= 2:
        lo, hi = min(centres), max(centres)
        inside = (x >= lo) & (x <= hi)
        split = float(x[inside][np.argmax(height[inside])])
    if split is None:
        # a single patch (or none) goes whole to the side of the load point it lies on
        split_used = float(load_position)
        side = 0 if (runs and centres[0] < split_used) else 2
        zone_of = np.full(x.size, side)
    else:
        split_used = float(split)
        zone_of = np.where(x < split_used, 0, 2)
    for i, j in runs:
        seg = zone_of[i : j + 1]
        cuts = np.flatnonzero(np.diff(seg)) + 1
        bounds = [0, *cuts.tolist(), seg.size]
        for a, b in itertools.pairwise(bounds):
            groups[ZONE_NAMES[int(seg[a])]].append((i + a, i + b - 1))
    return groups, split_used, False


def _between(
    runs: list[tuple[int, int]], x: np.ndarray, kick_zone: tuple[float, float] | None
) -> list[tuple[int, int]]:
    """The parts of the runs whose stations lie between the kick-zone marks (none without)."""
    if kick_zone is None:
        return []
    inside = (x >= kick_zone[0]) & (x <= kick_zone[1])
    mask = np.zeros(x.size, dtype=bool)
    for i, j in runs:
        mask[i : j + 1] = True
    return patches(mask & inside)


def _empty_zone(name: str) -> Zone:
    return Zone(
        name=name,
        start=float("nan"),
        end=float("nan"),
        length=0.0,
        area=0.0,
        force=0.0,
        load_share=0.0,
        mean_pressure=float("nan"),  # no contact: no pressure to average, none to peak
        max_pressure=float("nan"),
        patches=0,
        penetration=float("nan"),
        intervals=(),
    )


def _zone(
    name: str,
    runs: list[tuple[int, int]],
    x: np.ndarray,
    dx: float,
    line_force: np.ndarray | None,
    line_area: np.ndarray,
    pmax_along: np.ndarray | None,
    pen_along: np.ndarray | None,
    total_force: float,
) -> Zone:
    if not runs:
        return _empty_zone(name)

    def picked(values: np.ndarray) -> np.ndarray:
        # the stations of the runs in order: the same contiguous values a boolean mask would
        # pick (the same sums to the last bit), without a pass over the whole ski per array
        if len(runs) == 1:
            i, j = runs[0]
            return values[i : j + 1]
        return np.concatenate([values[i : j + 1] for i, j in runs])

    area = float(picked(line_area).sum())
    intervals = tuple((float(x[i] - dx / 2), float(x[j] + dx / 2)) for i, j in runs)
    if line_force is not None:
        force = float(picked(line_force).sum())
        mean_p = force / area if area > 0 else float("nan")
        max_p = float(picked(pmax_along).max())  # type: ignore[arg-type]
        share = force / total_force if total_force > 0 else float("nan")
        pen = float(picked(pen_along).max())  # type: ignore[arg-type]
    else:
        force, mean_p, max_p, share, pen = 0.0, float("nan"), float("nan"), 0.0, float("nan")
    return Zone(
        name=name,
        start=intervals[0][0],
        end=intervals[-1][1],
        length=float(sum(j - i + 1 for i, j in runs) * dx),
        area=area,
        force=force,
        load_share=share,
        mean_pressure=mean_p,
        max_pressure=max_p,
        patches=len(runs),
        penetration=pen,
        intervals=intervals,
    )


def contact_zones(
    solution: ContactSolution,
    *,
    kick_zone: tuple[float, float] | None = None,
    split: float | None = None,
    threshold: float = BREITSCHAEDEL_THRESHOLD,
) -> ZoneMetrics:
    """Group the contact patches of ``solution`` into rear / middle / front zones with metrics.

    Parameters
    ----------
    solution
        A :class:`~skisnow.contact.ContactSolution`.
    kick_zone
        ``(start, end)`` [m] of the kick-wax zone (classic skis, e.g. ``Ski.kick_zone``): a
        patch lying entirely inside it forms the ``middle`` zone, glide patches reaching into it
        stay whole in their glide zone, and ``kick`` measures the contact between its marks.
        ``None``: rear/front only.
    split
        Override the rear/front split station [m] (default: the top of the camber pocket).
    threshold
        Breitschädel height threshold [m] (default 50 µm).

    Returns
    -------
    ZoneMetrics
        ``rear``, ``middle``, ``front``, ``total``, ``kick`` (:class:`Zone`, SI units),
        ``breitschaedel`` (dict of the same four names; lengths and areas only), ``merged``
        (the zones are the regions), ``footprint`` (regions and patches,
        :func:`skisnow.contact.footprint`) and ``regions`` (the regions as :class:`Zone`).
    """
    if kick_zone is not None:
        k0, k1 = (float(kick_zone[0]), float(kick_zone[1]))
        if not (np.isfinite(k0) and np.isfinite(k1) and k0 < k1):
            raise InputError(f"kick_zone must be (start, end) with start < end, got {kick_zone}")
        kick_zone = (k0, k1)
    if not (np.isfinite(threshold) and threshold > 0):
        raise InputError(f"threshold must be positive, got {threshold!r}")
    x = solution.x
    dx = solution.dx
    p = solution.pressure
    if p.ndim == 2:
        assert solution.y is not None
        dy = solution.cell_area / dx
        contact = p > 0
        along = contact.any(axis=1)
        line_area = contact.sum(axis=1) * dx * dy
        line_force = p.sum(axis=1) * dx * dy
        pmax = p.max(axis=1)
        pen = np.where(contact, solution.displacement, -np.inf).max(axis=1)
        h_along = np.where(solution.footprint, solution.height, np.inf).min(axis=1)
        footprint_width = solution.footprint.sum(axis=1) * dy
    else:
        along = p > 0
        w = float(solution.width)  # type: ignore[arg-type]
        line_area = np.full(x.size, dx * w)
        line_force = p * dx * w
        pmax = p
        pen = solution.displacement
        h_along = solution.height
        footprint_width = np.full(x.size, w)
    total_force = float(line_force.sum())
    found = patches(along)
    groups, split_used, merged = paper_zones(
        found, x, h_along, solution.load_position, kick_zone, split
    )
    zones = {
        n: _zone(n, groups[n], x, dx, line_force, line_area, pmax, pen, total_force)
        for n in ZONE_NAMES
    }
    total = _zone("total", found, x, dx, line_force, line_area, pmax, pen, total_force)
    kick = _zone(
        "kick", _between(found, x, kick_zone), x, dx, line_force, line_area, pmax, pen, total_force
    )
    fp = footprint(
        x, along, kick_zone=kick_zone, split=0.0 if kick_zone is not None or split is None
        else split, force=line_force, area=line_area, max_pressure=np.where(along, pmax, 0.0),
        penetration=np.where(along, pen, 0.0), dx=dx,
    )  # fmt: skip
    # the regions as zones (the same numbers as fp.regions, with their contact intervals)
    ridx = region_index(x, fp.marks)
    regions = {}
    for k, region in enumerate(fp.regions):
        cut = patches(along & (ridx == k))
        regions[region.name] = _zone(
            region.name, cut, x, dx, line_force, line_area, pmax, pen, total_force
        )

    # Breitschädel (2012): contact wherever the gap to the plane the ski rests on is below the
    # threshold (one definition: skisnow.ski.breitschaedel_contact)
    rows = np.isfinite(h_along)
    b_mask = np.zeros(x.size, dtype=bool)
    b_mask[rows] = breitschaedel_contact(
        x[rows], h_along[rows], kick_zone=kick_zone, threshold=threshold
    )
    b_runs = patches(b_mask)
    b_groups, _, _ = paper_zones(
        b_runs, x, h_along, solution.load_position, kick_zone,
        split_used if found and not merged else split,
    )  # fmt: skip
    b_area = footprint_width * dx
    breit = {
        n: _zone(n, b_groups[n], x, dx, None, b_area, None, None, total_force) for n in ZONE_NAMES
    }
    breit["total"] = _zone("total", b_runs, x, dx, None, b_area, None, None, total_force)
    return ZoneMetrics(
        rear=zones["rear"],
        middle=zones["middle"],
        front=zones["front"],
        total=total,
        kick=kick,
        breitschaedel=breit,
        split=split_used,
        kick_zone=kick_zone,
        threshold=float(threshold),
        footprint=fp,
        merged=merged,
        regions=regions,
    )
