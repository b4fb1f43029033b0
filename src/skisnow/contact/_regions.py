"""The footprint of a ski by *region* and by *patch*: two views that never jump.

Kalliorinne et al. (2023), §4 and Figures 4–9, describe the apparent contact of a ski by zones
(rear, middle, front). A zone made of whole contact patches jumps when two patches join (the
whole footprint becomes "rear" and the front reads 0 mm), so skisnow reports two views beside
the paper's zones (:func:`skisnow.contact.contact_zones`):

* **regions**, fixed by the ski, not by the contact: for a classic ski the *rear glide* (tail to
  the rear kick-zone mark), the *kick zone* (between the marks) and the *front glide* (front
  mark to tip); for a ski without a kick zone, the *rear glide* and the *front glide* split at a
  stated point (the balance point, x = 0, by default). A station belongs to the region its
  centre lies in (a station exactly on a kick-zone mark belongs to the kick zone). Every region
  metric is a sum (or a maximum) over the stations of a fixed set, so it changes by at most one
  cell's worth when the contact edge moves by one cell: region metrics are continuous in the
  load wherever the contact is, and the region loads add up to the total;
* **patches**: every contiguous run of stations in contact, with its extent, length, area,
  load, pressures and the regions it spans.

Both are pure functions of per-station arrays (:func:`footprint`): the stations x, the contact
mask, and optionally the load, area, peak pressure and penetration carried by each station —
so the micro scale can aggregate its own per-station quantities (real contact area, …) with
the same regions (:func:`region_index`).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError

__all__ = [
    "CLASSIC_REGIONS",
    "SPLIT_REGIONS",
    "Footprint",
    "Patch",
    "Region",
    "footprint",
    "region_index",
    "region_marks",
    "runs",
]

#: Region names of a ski with a kick zone (tail → tip).
CLASSIC_REGIONS: tuple[str, str, str] = ("rear_glide", "kick_zone", "front_glide")
#: Region names of a ski without a kick zone (tail → tip), split at a stated point.
SPLIT_REGIONS: tuple[str, str] = ("rear_glide", "front_glide")


@dataclass(frozen=True, kw_only=True)
class Region:
    """Contact in one region of the ski (SI units).

    ``start``/``end`` are the region's bounds on the ski [m] (``-inf``/``+inf`` at the tail and
    the tip), fixed by the ski; ``contact_start``/``contact_end`` the outer cell edges of the
    contact inside it (NaN when none). ``mean_pressure``, ``max_pressure`` and ``penetration``
    are NaN without contact (no value: JSON null, "—" in a table); ``force`` and
    ``load_share`` are NaN when the footprint carries no load data (a contact mask only, e.g.
    the Breitschädel estimate), and so are the pressures.
    """

    name: str
    start: float
    end: float
    contact_start: float
    contact_end: float
    length: float
    area: float
    force: float
    load_share: float
    mean_pressure: float
    max_pressure: float
    penetration: float
    cells: int

    def as_dict(self) -> dict:
        """Plain dict (SI units)."""
        return asdict(self)


# The metric fields of Patch repeat those of Region (and of the paper's Zone in _zones.py) on
# purpose: each is a flat frozen record whose field order is its JSON and CSV column order;
# a shared base class would put the common fields first and change those columns.
@dataclass(frozen=True, kw_only=True)
class Patch:
    """One contiguous contact patch (SI units): extent (outer cell edges), metrics, regions."""

    start: float
    end: float
    length: float
    area: float
    force: float
    load_share: float
    mean_pressure: float
    max_pressure: float
    penetration: float
    regions: tuple[str, ...]

    def as_dict(self) -> dict:
        """Plain dict (SI units), ``regions`` as a list."""
        d = asdict(self)
        d["regions"] = list(self.regions)
        return d


@dataclass(frozen=True, kw_only=True)
class Footprint:
    """The footprint by region and by patch (:func:`footprint`).

    ``marks`` are the region boundaries [m] (the kick-zone marks, or the one split point);
    ``rule`` says in words where they come from.
    """

    regions: tuple[Region, ...]
    patches: tuple[Patch, ...]
    marks: tuple[float, ...]
    rule: str

    def region(self, name: str) -> Region:
        """The region called ``name`` (KeyError naming the valid ones otherwise)."""
        for r in self.regions:
            if r.name == name:
                return r
        raise KeyError(f"{name!r}: regions are {', '.join(r.name for r in self.regions)}")

    @property
    def names(self) -> tuple[str, ...]:
        """Region names, tail → tip."""
        return tuple(r.name for r in self.regions)

    def as_dict(self) -> dict:
        """Nested plain dict (SI units): ``regions`` by name, ``patches`` as a list."""
        return {
            "regions": {r.name: r.as_dict() for r in self.regions},
            "patches": [p.as_dict() for p in self.patches],
            "marks": list(self.marks),
            "rule": self.rule,
        }


def runs(mask: ArrayLike) -> list[tuple[int, int]]:
    """Connected runs of True in a 1D mask as ``(first, last)`` index pairs (inclusive)."""
    m = np.asarray(mask, dtype=bool).astype(np.int8)
    if m.ndim != 1:
        raise InputError(f"runs() needs a 1D mask, got shape {m.shape}")
    d = np.diff(np.concatenate([[0], m, [0]]))
    starts = np.flatnonzero(d == 1)
    ends = np.flatnonzero(d == -1) - 1
    return list(zip(starts.tolist(), ends.tolist(), strict=True))


def region_marks(
    kick_zone: tuple[float, float] | None, *, split: float = 0.0
) -> tuple[tuple[float, ...], tuple[str, ...], str]:
    """Region boundaries, names and the rule in words, from the ski's kick-zone marks.

    With a kick zone ``(start, end)`` [m]: its two marks and :data:`CLASSIC_REGIONS`; without
    one: the single ``split`` station (default the balance point, 0) and
    :data:`SPLIT_REGIONS`.
    """
    if kick_zone is not None:
        k0, k1 = float(kick_zone[0]), float(kick_zone[1])
        if not (np.isfinite(k0) and np.isfinite(k1) and k0 < k1):
            raise InputError(f"kick_zone must be (start, end) with start < end, got {kick_zone}")
        return (k0, k1), CLASSIC_REGIONS, "kick-zone marks"
    s = float(split)
    if not np.isfinite(s):
        raise InputError(f"split must be a finite station [m], got {split!r}")
    rule = "balance point" if s == 0.0 else f"split at {s * 1e3:+.1f} mm"
    return (s,), SPLIT_REGIONS, rule


def region_index(x: ArrayLike, marks: tuple[float, ...]) -> NDArray[np.intp]:
    """The region of every station: 0 … len(marks), by where the station's centre lies.

    With two marks (a kick zone) a station on a mark belongs to the kick zone (index 1); with
    one split point a station on it belongs to the front (index 1).
    """
    xs = np.asarray(x, dtype=float)
    if len(marks) == 2:
        return np.where(xs < marks[0], 0, np.where(xs <= marks[1], 1, 2)).astype(np.intp)
    if len(marks) == 1:
        return np.where(xs < marks[0], 0, 1).astype(np.intp)
    raise InputError(f"marks: need one split point or two kick-zone marks, got {marks}")


def _cell_widths(x: NDArray[np.float64], dx: float | None) -> float:
    if dx is not None:
        return float(dx)
    if x.size < 2:
        raise InputError("footprint: need dx for fewer than two stations")
    return float((x[-1] - x[0]) / (x.size - 1))


def footprint(
    x: ArrayLike,
    contact: ArrayLike,
    *,
    kick_zone: tuple[float, float] | None = None,
    split: float = 0.0,
    force: ArrayLike | None = None,
    area: ArrayLike | None = None,
    max_pressure: ArrayLike | None = None,
    penetration: ArrayLike | None = None,
    dx: float | None = None,
) -> Footprint:
    """The footprint by region and by patch from per-station arrays (pure function).

    Parameters
    ----------
    x
        Stations along the ski [m] (cell centres, evenly spaced by ``dx``), shape ``(n,)``.
    contact
        Whether each station touches the snow (bool, ``(n,)``; for a surface model: any cell
        across the width).
    kick_zone
        ``(start, end)`` [m] of the kick zone (classic): regions rear glide / kick zone / front
        glide. ``None``: rear glide / front glide split at ``split``.
    split
        The rear/front split [m] of a ski without a kick zone (default: the balance point).
    force
        Load carried by each station [N] (Σ p·ΔA over the station's cells); ``None``: a contact
        mask only (load, share, pressures, penetration NaN).
    area
        Contact area of each station [m²] (default: ``dx`` times 1 m, i.e. a length).
    max_pressure, penetration
        Largest pressure [Pa] and snow displacement [m] at each station (default: NaN).
    dx
        Station spacing [m] (default from ``x``).

    Returns
    -------
    Footprint
        Regions (tail → tip) and patches (tail → tip). The region loads add up to the total
        load exactly; the region lengths and areas to the total contact length and area.
    """
    xs = np.asarray(x, dtype=float)
    mask = np.asarray(contact, dtype=bool)
    if xs.ndim != 1 or mask.shape != xs.shape:
        raise InputError(f"footprint: x and contact must be 1-D of one length, got {xs.shape}, "
                         f"{mask.shape}")  # fmt: skip
    step = _cell_widths(xs, dx)
    marks, names, rule = region_marks(kick_zone, split=split)

    def along(values: ArrayLike | None, default: float) -> NDArray[np.float64]:
        if values is None:
            return np.full(xs.size, default)
        v = np.asarray(values, dtype=float)
        if v.shape != xs.shape:
            raise InputError(f"footprint: per-station arrays need shape {xs.shape}, got {v.shape}")
        return v

    has_load = force is not None
    f = along(force, np.nan)
    a = along(area, step)
    pmax = along(max_pressure, np.nan)
    pen = along(penetration, np.nan)
    total = float(f[mask].sum()) if has_load else float("nan")
    idx = region_index(xs, marks)
    bounds = [-np.inf, *marks, np.inf]

    def metrics(sel: NDArray[np.intp] | slice, n: int) -> dict[str, float]:
        # sel: the stations (indices in order, or the slice of one patch) and n their number:
        # the values a boolean mask would pick, in the same order, so the same sums to the last
        # bit, without a pass over the whole ski per array
        if n == 0:
            # no contact: nothing carried (0), no pressure or penetration to give (NaN)
            zero = 0.0 if has_load else float("nan")
            return {"length": 0.0, "area": 0.0, "force": zero, "load_share": zero,
                    "mean_pressure": float("nan"), "max_pressure": float("nan"),
                    "penetration": float("nan")}  # fmt: skip
        ar = float(a[sel].sum())
        fo = float(f[sel].sum()) if has_load else float("nan")
        return {
            "length": n * step,
            "area": ar,
            "force": fo,
            "load_share": fo / total if has_load and total > 0 else float("nan"),
            "mean_pressure": fo / ar if has_load and ar > 0 else float("nan"),
            "max_pressure": float(pmax[sel].max()) if max_pressure is not None else float("nan"),
            "penetration": float(pen[sel].max()) if penetration is not None else float("nan"),
        }

    regions = []
    for k, name in enumerate(names):
        sel = mask & (idx == k)
        where = np.flatnonzero(sel)
        regions.append(
            Region(
                name=name,
                start=float(bounds[k]),
                end=float(bounds[k + 1]),
                contact_start=float(xs[where[0]] - step / 2) if where.size else float("nan"),
                contact_end=float(xs[where[-1]] + step / 2) if where.size else float("nan"),
                cells=int(where.size),
                **metrics(where, int(where.size)),
            )
        )
    patch_list = []
    for i, j in runs(mask):
        # the regions it spans, in order (np.unique's values, without its sort)
        spanned = tuple(names[k] for k in np.flatnonzero(np.bincount(idx[i : j + 1])))
        patch_list.append(
            Patch(
                start=float(xs[i] - step / 2),
                end=float(xs[j] + step / 2),
                regions=spanned,
                **metrics(slice(i, j + 1), j + 1 - i),
            )
        )
    return Footprint(regions=tuple(regions), patches=tuple(patch_list), marks=marks, rule=rule)
