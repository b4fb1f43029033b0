"""Practitioners' camber metrics, from a ski (beam model) or from a bench file.

What ski technicians read off a camber bench (SkiSelector) and what Breitschädel (2012,
Procedia Eng. 34, 391-396) tabulated for national-team skis:

* camber height at the balance point h(0) under a load;
* wax-pocket ("kick zone") length: the connected stretch around the balance point where the
  base stands higher than 0.1 mm (the industry's "closed" limit) or 0.2 mm;
* the closing load: the mass at which h(0) drops below 0.1 mm for a given load position;
* the stiffness k = (F_full - F_half) / (h_half - h_full) between half and full body weight
  (Breitschädel's measure, in N/mm in the field; SI N/m here);
* the glide-zone contact lengths with Breitschädel's criterion: contact wherever h < 50 µm
  (seed paper 000, §1 and §3.2), split into rear / middle (kick zone) / front.

All functions take SI inputs (m, kg) and return SI; :meth:`SkiMetrics.as_field_units` converts.
The practitioners' default load case is half or full body weight 80 mm behind the balance point.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.io import BenchData
from skisnow.ski._beam import DEFAULT_BOOT_LENGTH, DEFAULT_N_ELEMENTS, solve_beam
from skisnow.ski._skis import SHIPPED_SKIS, Ski, get_ski

__all__ = [
    "BREITSCHAEDEL_THRESHOLD",
    "CLOSED_THRESHOLD",
    "SkiMetrics",
    "camber_height",
    "closing_load",
    "closing_load_from_bench",
    "contact_lengths",
    "contact_patches",
    "ski_metrics",
    "ski_stiffness",
    "wax_pocket",
]

#: Breitschädel's contact criterion [m]: contact wherever the camber height is below 50 µm.
BREITSCHAEDEL_THRESHOLD: float = 50e-6
#: The industry's "closed" kick zone [m]: camber height below 0.1 mm.
CLOSED_THRESHOLD: float = 0.1e-3
#: Default practitioners' load position [m]: 80 mm behind the balance point.
DEFAULT_METRIC_POSITION: float = -0.080


def _profile(x: ArrayLike, height: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    xa = np.asarray(x, dtype=float)
    ha = np.asarray(height, dtype=float)
    if xa.ndim != 1 or xa.shape != ha.shape or xa.size < 2:
        raise InputError("x and height must be 1-D arrays of the same length >= 2")
    if not (np.all(np.isfinite(xa)) and np.all(np.isfinite(ha))):
        raise InputError("x and height must be finite")
    if np.any(np.diff(xa) <= 0):
        raise InputError("x must be strictly increasing")
    return xa, ha


def camber_height(x: ArrayLike, height: ArrayLike, *, at: float = 0.0) -> float:
    """Camber height [m] at position ``at`` [m] (default: the balance point), linear in samples."""
    xa, ha = _profile(x, height)
    if not (xa[0] <= at <= xa[-1]):
        raise InputError(f"position {at} m is outside the profile [{xa[0]}, {xa[-1]}] m")
    return float(np.interp(at, xa, ha))


def _cell_widths(xa: NDArray[np.float64]) -> NDArray[np.float64]:
    edges = np.concatenate([[xa[0]], 0.5 * (xa[1:] + xa[:-1]), [xa[-1]]])
    return np.diff(edges)


def wax_pocket(
    x: ArrayLike, height: ArrayLike, *, threshold: float = CLOSED_THRESHOLD, at: float = 0.0
) -> tuple[float, float] | None:
    """The wax pocket: (start, end) [m] of the connected stretch around ``at`` with h > threshold.

    The ends are located by linear interpolation between samples. ``None`` when h(at) <=
    threshold (the pocket is closed at the balance point).
    """
    xa, ha = _profile(x, height)
    if camber_height(xa, ha, at=at) <= threshold:
        return None
    above = ha > threshold
    i = int(np.clip(np.searchsorted(xa, at), 0, xa.size - 1))
    if not above[i]:
        i = i - 1 if i > 0 and above[i - 1] else i
    lo = i
    while lo > 0 and above[lo - 1]:
        lo -= 1
    hi = i
    while hi < xa.size - 1 and above[hi + 1]:
        hi += 1

    def cross(j0: int, j1: int) -> float:
        h0, h1 = ha[j0] - threshold, ha[j1] - threshold
        return float(xa[j0] + (xa[j1] - xa[j0]) * h0 / (h0 - h1))

    start = cross(lo, lo - 1) if lo > 0 else float(xa[0])
    end = cross(hi, hi + 1) if hi < xa.size - 1 else float(xa[-1])
    return start, end


def wax_pocket_length(
    x: ArrayLike, height: ArrayLike, *, threshold: float = CLOSED_THRESHOLD, at: float = 0.0
) -> float:
    """Length [m] of :func:`wax_pocket` (0 when closed)."""
    pocket = wax_pocket(x, height, threshold=threshold, at=at)
    return 0.0 if pocket is None else pocket[1] - pocket[0]


def contact_patches(
    x: ArrayLike, height: ArrayLike, *, threshold: float = BREITSCHAEDEL_THRESHOLD
) -> tuple[tuple[float, float], ...]:
    """Runs of samples with h <= threshold as ((start, end), ...) [m] (first and last sample)."""
    xa, ha = _profile(x, height)
    idx = np.flatnonzero(ha <= threshold)
    if idx.size == 0:
        return ()
    cut = np.flatnonzero(np.diff(idx) > 1)
    starts = np.concatenate([[idx[0]], idx[cut + 1]])
    ends = np.concatenate([idx[cut], [idx[-1]]])
    return tuple((float(xa[s]), float(xa[e])) for s, e in zip(starts, ends, strict=True))


def contact_lengths(
    x: ArrayLike,
    height: ArrayLike,
    *,
    threshold: float = BREITSCHAEDEL_THRESHOLD,
    kick_zone: tuple[float, float] | None = None,
) -> dict[str, float]:
    """Contact lengths [m] with Breitschädel's criterion h <= threshold, per zone.

    Zones: ``rear`` (x < kick start), ``middle`` (inside the kick zone), ``front`` (x > kick
    end), ``total``. Without a kick zone (skate skis) ``middle`` is 0 and rear/front are split,
    as in :func:`skisnow.contact.contact_zones`, at the top of the camber arch: the sample of
    greatest height between the centres of the rearmost and the frontmost contact patch (at the
    balance point if there are fewer than two patches). Each sample stands for its cell
    (half-way to its neighbours).
    """
    xa, ha = _profile(x, height)
    if kick_zone is None:
        patches = contact_patches(xa, ha, threshold=threshold)
        split = 0.0
        if len(patches) >= 2:
            lo = 0.5 * sum(patches[0])
            hi = 0.5 * sum(patches[-1])
            inside = (xa >= lo) & (xa <= hi)
            split = float(xa[inside][np.argmax(ha[inside])])
        a = b = split
    else:
        a, b = kick_zone
    w = _cell_widths(xa) * (ha <= threshold)
    return {
        "rear": float(np.sum(w[xa < a])),
        "middle": float(np.sum(w[(xa >= a) & (xa <= b)])) if kick_zone is not None else 0.0,
        "front": float(np.sum(w[xa > b])),
        "total": float(np.sum(w)),
    }


def ski_stiffness(height_half: float, height_full: float, body_mass: float) -> float:
    """Breitschädel's stiffness k [N/m]: ½·m·g over the camber drop from half to full weight."""
    drop = height_half - height_full
    if drop <= 0:
        return float("inf")
    return 0.5 * body_mass * STANDARD_GRAVITY / drop


def _resolve_ski(ski: Ski | str) -> Ski:
    return get_ski(ski) if isinstance(ski, str) else ski


def closing_load(
    ski: Ski | str,
    *,
    load_position: float = DEFAULT_METRIC_POSITION,
    threshold: float = CLOSED_THRESHOLD,
    at: float = 0.0,
    mass_max: float = 300.0,
    tolerance: float = 0.01,
    boot_length: float = DEFAULT_BOOT_LENGTH,
    n_elements: int = DEFAULT_N_ELEMENTS,
) -> float:
    """Mass [kg] at which h(at) first drops below ``threshold`` on the beam, by bisection.

    Returns ``inf`` when the ski is still open at ``mass_max``. Assumes h(at) decreases with
    the mass (true for a beam pressed on a plane).
    """
    sk = _resolve_ski(ski)

    def h(m: float) -> float:
        sol = solve_beam(
            sk, mass=m, load_position=load_position, boot_length=boot_length, n_elements=n_elements
        )
        return float(sol.sample(np.array([at]))[0])

    if h(mass_max) >= threshold:
        return float("inf")
    lo, hi = 0.0, float(mass_max)
    while hi - lo > tolerance:
        mid = 0.5 * (lo + hi)
        if mid > 0 and h(mid) < threshold:
            hi = mid
        else:
            lo = mid
    return hi


def closing_load_from_bench(
    bench: BenchData,
    *,
    load_position: float = DEFAULT_METRIC_POSITION,
    threshold: float = CLOSED_THRESHOLD,
    at: float = 0.0,
    ski: str | None = None,
) -> float:
    """Closing load [kg] read off a bench: first crossing of h(at) below ``threshold``.

    Linear interpolation in mass between the two bench masses around the crossing. ``inf`` if
    the ski never closes within the bench's masses; the smallest mass if already closed there.
    """
    ms, hs_mm = bench.heights_at(load_position_mm=load_position * 1e3, x_mm=at * 1e3, ski=ski)
    hs = hs_mm * 1e-3
    below = np.flatnonzero(hs < threshold)
    if below.size == 0:
        return float("inf")
    j = int(below[0])
    if j == 0:
        return float(ms[0])
    m0, m1, h0, h1 = ms[j - 1], ms[j], hs[j - 1], hs[j]
    return float(m0 + (m1 - m0) * (h0 - threshold) / (h0 - h1))


def _bench_profile_at_mass(
    bench: BenchData, ski: str, mass: float, load_position: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Profile (x [m], h [m]) at ``mass`` [kg] interpolated between the bench's masses."""
    x_mm, h_mm = bench.profile_at_mass(mass_kg=mass, load_position_mm=load_position * 1e3, ski=ski)
    return x_mm * 1e-3, h_mm * 1e-3


def _bench_kick_zone(bench: BenchData, name: str) -> tuple[float, float] | None:
    """Kick zone [m] of ski ``name``: from the metadata if it describes that ski, else from the
    shipped ski of that name, else none."""
    if bench.describes_kick_zone(name):
        kz = bench.kick_zone_mm(name)
        return None if kz is None else (kz[0] * 1e-3, kz[1] * 1e-3)
    if name in SHIPPED_SKIS:
        return get_ski(name).kick_zone
    return None


@dataclass(frozen=True, kw_only=True)
class SkiMetrics:
    """The practitioners' numbers of one ski for one body mass and load position (SI units).

    Heights [m], lengths [m], masses [kg], stiffness [N/m]. ``*_half`` / ``*_full``: under half
    / full body weight at ``load_position``. Contact lengths use Breitschädel's 50 µm criterion.
    """

    ski: str
    source: str
    body_mass: float
    load_position: float
    camber_half: float
    camber_full: float
    pocket_length_01_half: float
    pocket_length_02_half: float
    pocket_length_01_full: float
    pocket_length_02_full: float
    closing_load: float
    stiffness: float
    rear_contact_half: float
    front_contact_half: float
    rear_contact_full: float
    front_contact_full: float

    def as_field_units(self) -> dict[str, Any]:
        """The metrics with field units in the keys (mm, kg, N/mm), for tables and JSON."""
        mm = 1e3
        return {
            "ski": self.ski,
            "source": self.source,
            "body_mass_kg": self.body_mass,
            "load_position_mm": self.load_position * mm,
            "camber_half_mm": self.camber_half * mm,
            "camber_full_mm": self.camber_full * mm,
            "pocket_length_0.1mm_half_mm": self.pocket_length_01_half * mm,
            "pocket_length_0.2mm_half_mm": self.pocket_length_02_half * mm,
            "pocket_length_0.1mm_full_mm": self.pocket_length_01_full * mm,
            "pocket_length_0.2mm_full_mm": self.pocket_length_02_full * mm,
            "closing_load_kg": self.closing_load,
            "stiffness_n_per_mm": self.stiffness / mm,
            "rear_contact_half_mm": self.rear_contact_half * mm,
            "front_contact_half_mm": self.front_contact_half * mm,
            "rear_contact_full_mm": self.rear_contact_full * mm,
            "front_contact_full_mm": self.front_contact_full * mm,
        }


def _metrics_from_profiles(
    *,
    name: str,
    source: str,
    body_mass: float,
    load_position: float,
    half: tuple[NDArray[np.float64], NDArray[np.float64]],
    full: tuple[NDArray[np.float64], NDArray[np.float64]],
    closing: float,
    kick_zone: tuple[float, float] | None,
) -> SkiMetrics:
    ch, cf = camber_height(*half), camber_height(*full)
    lh = contact_lengths(*half, kick_zone=kick_zone)
    lf = contact_lengths(*full, kick_zone=kick_zone)
    return SkiMetrics(
        ski=name,
        source=source,
        body_mass=body_mass,
        load_position=load_position,
        camber_half=ch,
        camber_full=cf,
        pocket_length_01_half=wax_pocket_length(*half, threshold=0.1e-3),
        pocket_length_02_half=wax_pocket_length(*half, threshold=0.2e-3),
        pocket_length_01_full=wax_pocket_length(*full, threshold=0.1e-3),
        pocket_length_02_full=wax_pocket_length(*full, threshold=0.2e-3),
        closing_load=closing,
        stiffness=ski_stiffness(ch, cf, body_mass),
        rear_contact_half=lh["rear"],
        front_contact_half=lh["front"],
        rear_contact_full=lf["rear"],
        front_contact_full=lf["front"],
    )


def ski_metrics(
    source: Ski | str | BenchData,
    *,
    body_mass: float = 65.0,
    load_position: float = DEFAULT_METRIC_POSITION,
    ski: str | None = None,
) -> SkiMetrics:
    """Practitioners' metrics of a ski from the beam (a :class:`Ski` or a shipped name) or a bench.

    Parameters
    ----------
    source
        a :class:`Ski`, a shipped ski name, or :class:`~skisnow.io.BenchData`.
    body_mass
        the skier's mass [kg] (half and full body weight are applied).
    load_position
        x_m [m] of both loads (default -0.080 m, the practitioners' position).
    ski
        which ski of a multi-ski bench.

    From a bench, the profiles at ½ and 1 body mass are interpolated linearly between the two
    nearest bench masses at ``load_position`` (which must be one of the bench's positions) and
    the kick zone is taken from the metadata (``kick_zone_mm``) when it describes that ski, else
    from the shipped ski of the same name, else there is none.
    """
    if not (np.isfinite(body_mass) and body_mass > 0):
        raise InputError(f"body_mass must be > 0 kg, got {body_mass}")
    if isinstance(source, BenchData):
        name = source.ski_name(ski)
        kick = _bench_kick_zone(source, name)
        return _metrics_from_profiles(
            name=name,
            source="bench",
            body_mass=body_mass,
            load_position=load_position,
            half=_bench_profile_at_mass(source, name, 0.5 * body_mass, load_position),
            full=_bench_profile_at_mass(source, name, body_mass, load_position),
            closing=closing_load_from_bench(source, load_position=load_position, ski=name),
            kick_zone=kick,
        )
    if isinstance(source, str) and source not in SHIPPED_SKIS:
        raise InputError(f"unknown ski {source!r}; shipped skis are: {', '.join(SHIPPED_SKIS)}")
    sk = _resolve_ski(source)
    if not isinstance(sk, Ski):
        raise InputError(f"source must be a Ski, a ski name or BenchData, not {type(source)}")
    from skisnow.ski._bench import bench_grid

    x = bench_grid(sk)
    profiles = []
    for m in (0.5 * body_mass, body_mass):
        sol = solve_beam(sk, mass=m, load_position=load_position)
        profiles.append((x, sol.sample(x)))
    return _metrics_from_profiles(
        name=sk.name,
        source="beam",
        body_mass=body_mass,
        load_position=load_position,
        half=profiles[0],
        full=profiles[1],
        closing=closing_load(sk, load_position=load_position),
        kick_zone=sk.kick_zone,
    )
