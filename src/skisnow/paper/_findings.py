"""The twelve findings of Kalliorinne et al. (2023), §4, Figures 8–9, as numerical criteria.

The paper reads its skate ski's maps (rear and front zone, apparent contact area and mean
apparent pressure against the load m at x_m = -120 mm, snow 20–400 MPa) as twelve statements.
They are NOT fitting targets of any skisnow ski (the captions of Figures 4–7 are): whether the
maps of a ski show them is a prediction. :func:`figure89_findings` is the one function that
reads them; each statement is written next to its criterion (:data:`STATEMENTS`), with these
definitions, the same for every statement:

* **about X kg**: X ± 5 kg.
* **local maximum** of y(m) at m*: y(m*) is the largest value within ±3 kg of m*, and y falls
  by at least 3 % of y(m*) within the next 10 kg (a prominence: a wiggle of a station or two of
  the contact grid is no maximum). **Local minimum**: the same, mirrored (y rises by 3 %).
* **increases** (a trend): Spearman's rank correlation of y with m at least 0.9.
* **about constant**: the range (max - min) at most 25 % of the mean.
* **splits**: the first load at which the zone has two or more patches and keeps them for the
  next 5 kg.
* **tracks** (follows a similar trend): Pearson's r at least 0.9 over the loads named.
* **follows closely**: the median relative deviation at most 15 %, and at least 80 % of the
  loads within 25 %.
* **sweet spot**: the relative range (max - min)/mean over 260–400 MPa of the total area and of
  the total mean pressure at 30 kg at most 10 % ("almost the same"), and at 60 kg at least
  twice that at 30 kg ("a large difference").

**Verdicts.** A statement about "every E in a range" is *yes* on a grid when its criterion holds
at every modulus of the range (and its numerical part holds), *partly* when it holds at some
(or at all but its number misses), *no* when at none. Over grids: *yes* only when yes on every
grid (the 1 kg and the 2 kg grids), *no* when no on every grid, else *partly*. The maps come
from :func:`skisnow.paper.zone_maps`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.stats import spearmanr

from skisnow._errors import InputError
from skisnow.paper._maps import ZoneMaps

__all__ = ["STATEMENTS", "Finding", "figure89_findings"]

ABOUT_KG = 5.0  # "about X kg" = X ± 5 kg
PEAK_HALFWIDTH_KG = 3.0  # a local extremum is the extreme value within ± 3 kg
PEAK_DROP = 0.03  # ... and y moves away from it by >= 3 % within the next 10 kg
PEAK_LOOKAHEAD_KG = 10.0
TREND_RHO = 0.9  # "increases": Spearman rho >= 0.9
CONSTANT_RANGE = 0.25  # "about constant": range <= 25 % of the mean
SPLIT_PERSIST_KG = 5.0  # "splits": >= 2 patches from that load on for 5 kg
TRACK_R = 0.9  # "tracks": Pearson r >= 0.9
CLOSE_MEDIAN, CLOSE_BAND, CLOSE_SHARE = 0.15, 0.25, 0.8  # "follows closely"
SWEET_RANGE, SWEET_RATIO = 0.10, 2.0  # "sweet spot"
PRESSURE_BOUND_KPA = 55.0 * 1.10  # "does not exceed 55 kPa", with 10 % tolerance

#: The twelve statements: key → (figure, the paper's words, the criterion applied).
STATEMENTS: dict[str, tuple[str, str, str]] = {
    "rear-area-increases": (
        "8 left",
        "The rear interface has, in general, an increasing apparent contact area with "
        "increasing load.",
        "every E: rear area increases with m (Spearman rho >= 0.9)",
    ),
    "rear-local-max-35-40kg": (
        "8 left",
        "For E > 260 MPa there is a local maximum at about 35 to 40 kg; thereafter a local "
        "minimum at about 40 to 45 kg before it increases again.",
        "every E > 260 MPa: a local maximum of the rear area in 30-45 kg, then a local minimum "
        "in 35-50 kg",
    ),
    "breitschaedel-rear-trend": (
        "8 left",
        "The Breitschädel rear estimate follows a similar trend for 50-150 MPa and loads above "
        "20 kg.",
        "every E in 50-150 MPa: the Breitschädel rear area tracks the rear area above 20 kg "
        "(Pearson r >= 0.9)",
    ),
    "front-area-increases-to-30kg": (
        "8 right",
        "The front area increases with increasing load up to about 30 kg for all moduli.",
        "every E: front area increases with m from the smallest load to 25 kg (Spearman rho "
        ">= 0.9)",
    ),
    "front-local-max-30kg": (
        "8 right",
        "For E > 40 MPa a local maximum appears, which converges to about 50 cm² at 30 kg as "
        "E -> 400 MPa.",
        "every E > 40 MPa: a local maximum of the front area in 25-35 kg; at 400 MPa its value "
        "in 40-60 cm² (50 ± 20 %)",
    ),
    "front-area-flat-after": (
        "8 right",
        "Thereafter the front area decreases somewhat and flattens out at a more-or-less "
        "constant level.",
        "every E > 40 MPa: from 10 kg after the 25-35 kg maximum to the largest load the front "
        "area stays below the maximum and about constant (range <= 25 % of its mean)",
    ),
    "front-splits-35kg": (
        "8 right",
        "For E > 260 MPa the front interface splits from one to two patches at approximately "
        "35 kg.",
        "every E > 260 MPa: the front splits (>= 2 patches held for 5 kg) in 30-40 kg",
    ),
    "breitschaedel-front-soft-snow": (
        "8 right",
        "The Breitschädel front estimate quite closely follows the prediction for 20 MPa, "
        "except at the high end of the load range.",
        "Breitschädel front area follows the 20 MPa front area closely (median deviation "
        "<= 15 %, >= 80 % of the loads within 25 %) over the lower three quarters of the loads",
    ),
    "rear-pressure-min-at-area-max": (
        "9",
        "At the load of the rear area's local maximum the rear mean pressure has its global "
        "minimum.",
        "every E > 260 MPa with a rear local maximum (statement 2): the global minimum of the "
        "rear mean pressure within 3 kg of it",
    ),
    "rear-pressure-constant-55kpa": (
        "9",
        "The rear mean pressure remains almost constant above 30 kg and does not exceed 55 kPa, "
        "even at 400 MPa.",
        "every E: rear mean pressure above 30 kg about constant (range <= 25 % of its mean); "
        "and at most 60.5 kPa (55 + 10 %) above 30 kg at every E",
    ),
    "front-pressure-min-30kg": (
        "9",
        "The front mean pressure decreases to a global minimum at approximately 30 kg (clearly "
        "for E > 200 MPa), then increases more-or-less linearly.",
        "every E > 200 MPa: the global minimum of the front mean pressure in 25-35 kg, and "
        "above it the pressure rising linearly with m (Pearson r >= 0.9)",
    ),
    "sweet-spot-30kg": (
        "8-9",
        "A sweet spot around 30 kg: the area and mean pressure remain almost the same for "
        "260-400 MPa, whereas at 60 kg they differ much.",
        "total area and total mean pressure over 260-400 MPa: relative range at 30 kg <= 10 %, "
        "and at 60 kg >= 2x that at 30 kg",
    ),
}

VERDICTS = ("yes", "partly", "no")


@dataclass(frozen=True, kw_only=True)
class Finding:
    """One statement of the paper read on one ski's maps.

    ``verdict`` is ``'yes'``, ``'partly'`` or ``'no'`` over every grid given (yes only when yes
    on each); ``per_grid`` holds ``(step_kg, verdict, measured)`` for each grid; ``measured``
    joins their numbers.
    """

    key: str
    figure: str
    statement: str
    criterion: str
    verdict: str
    measured: str
    per_grid: tuple[tuple[float, str, str], ...]

    @property
    def shown(self) -> bool:
        """True when the verdict is yes."""
        return self.verdict == "yes"


# ---------------------------------------------------------------------------------------------
# the definitions (module docstring)


def local_max(
    y: NDArray[np.float64], m: NDArray[np.float64], lo: float, hi: float, *, mirror: bool = False
) -> float:
    """Load [kg] of the first local maximum of y(m) in [lo, hi] (NaN if none).

    A local maximum: the largest value within ±3 kg, followed within 10 kg by a fall of at least
    3 % of it. ``mirror``: a local minimum (the smallest value, followed by a rise of 3 %).
    """
    s = -1.0 if mirror else 1.0
    for k in np.flatnonzero((m >= lo) & (m <= hi) & np.isfinite(y)):
        near = np.abs(m - m[k]) <= PEAK_HALFWIDTH_KG
        if s * y[k] < np.nanmax(s * y[near]):
            continue
        if k > 0 and s * y[k - 1] >= s * y[k]:  # a plateau counts at its first load
            continue
        after = (m > m[k]) & (m <= m[k] + PEAK_LOOKAHEAD_KG)
        if not after.any():
            continue
        if s * (y[k] - (np.nanmin(y[after]) if s > 0 else np.nanmax(y[after]))) >= PEAK_DROP * abs(
            y[k]
        ):
            return float(m[k])
    return float("nan")


def increases(y: NDArray[np.float64], m: NDArray[np.float64]) -> float:
    """Spearman's rank correlation of y with m (NaN for fewer than 3 finite points)."""
    ok = np.isfinite(y)
    if ok.sum() < 3 or np.ptp(y[ok]) == 0:
        return float("nan")
    return float(spearmanr(m[ok], y[ok]).statistic)


def relative_range(y: NDArray[np.float64]) -> float:
    """(max - min) / mean of the finite values."""
    y = y[np.isfinite(y)]
    return float(np.ptp(y) / np.mean(y)) if y.size and np.mean(y) > 0 else float("inf")


def split_load(patches: NDArray[np.int64], m: NDArray[np.float64]) -> float:
    """First load with >= 2 patches held for the next 5 kg, after a load with one (NaN: none)."""
    for k in range(1, m.size):
        hold = (m >= m[k]) & (m <= m[k] + SPLIT_PERSIST_KG)
        if patches[k] >= 2 and np.all(patches[hold] >= 2) and np.any(patches[:k] == 1):
            return float(m[k])
    return float("nan")


def pearson(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Pearson's r of the finite pairs (NaN when undefined)."""
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < 3 or np.std(a[ok]) == 0 or np.std(b[ok]) == 0:
        return float("nan")
    return float(np.corrcoef(a[ok], b[ok])[0, 1])


# ---------------------------------------------------------------------------------------------
# the statements, each on one grid → (verdict, measured)


def _grade(hits: Sequence[bool], number_ok: bool = True) -> str:
    if hits and all(hits) and number_ok:
        return "yes"
    return "partly" if any(hits) else "no"


def _span(values: Sequence[float], fmt: str = ".0f", unit: str = "") -> str:
    finite = [v for v in values if np.isfinite(v)]
    missing = len(values) - len(finite)
    if not finite:
        return "none"
    lo, hi = format(min(finite), fmt), format(max(finite), fmt)
    text = (lo if lo == hi else f"{lo}-{hi}") + unit
    return text + (f" ({missing} of {len(values)} none)" if missing else "")


def _mod(e: NDArray[np.float64], sel: NDArray[np.bool_]) -> str:
    if not sel.any():
        return "no moduli"
    lo, hi = e[sel].min(), e[sel].max()
    return f"{lo:g} MPa" if lo == hi else f"{lo:g}-{hi:g} MPa"


def _rear_area_increases(mp: ZoneMaps) -> tuple[str, str]:
    rho = [increases(mp.area_cm2["rear"][:, j], mp.masses_kg) for j in range(mp.moduli_mpa.size)]
    hits = [r >= TREND_RHO for r in rho]
    return _grade(hits), f"rho {_span(rho, '.2f')}, {sum(hits)}/{len(hits)} moduli"


def _rear_peaks(mp: ZoneMaps) -> tuple[NDArray[np.bool_], list[float], list[float]]:
    m, ar = mp.masses_kg, mp.area_cm2["rear"]
    stiff = mp.moduli_mpa > 260
    peaks = [local_max(ar[:, j], m, 35 - ABOUT_KG, 40 + ABOUT_KG) for j in np.flatnonzero(stiff)]
    mins = [
        local_max(ar[:, j], m, max(p, 40 - ABOUT_KG), 45 + ABOUT_KG, mirror=True)
        if np.isfinite(p)
        else float("nan")
        for j, p in zip(np.flatnonzero(stiff), peaks, strict=True)
    ]
    return stiff, peaks, mins


def _rear_local_max(mp: ZoneMaps) -> tuple[str, str]:
    stiff, peaks, mins = _rear_peaks(mp)
    hits = [bool(np.isfinite(p) and np.isfinite(q)) for p, q in zip(peaks, mins, strict=True)]
    return _grade(hits), (
        f"{_mod(mp.moduli_mpa, stiff)}: maxima at {_span(peaks, unit=' kg')}, "
        f"minima at {_span(mins, unit=' kg')}"
    )


def _breit_rear(mp: ZoneMaps) -> tuple[str, str]:
    m, e = mp.masses_kg, mp.moduli_mpa
    sel_m, sel_e = m > 20, (e >= 50) & (e <= 150)
    b = mp.breitschaedel_cm2["rear"][sel_m]
    rs = [pearson(b, mp.area_cm2["rear"][sel_m, j]) for j in np.flatnonzero(sel_e)]
    hits = [r >= TRACK_R for r in rs]
    return _grade(hits), f"{_mod(e, sel_e)}: r = {_span(rs, '.2f')}"


def _front_increases(mp: ZoneMaps) -> tuple[str, str]:
    m = mp.masses_kg
    up = m <= 30 - ABOUT_KG
    rho = [increases(mp.area_cm2["front"][up, j], m[up]) for j in range(mp.moduli_mpa.size)]
    hits = [r >= TREND_RHO for r in rho]
    return _grade(hits), f"rho {_span(rho, '.2f')} up to {m[up].max():g} kg"


def _front_peaks(mp: ZoneMaps) -> tuple[NDArray[np.bool_], list[float]]:
    sel = mp.moduli_mpa > 40
    af = mp.area_cm2["front"]
    lo, hi = 30 - ABOUT_KG, 30 + ABOUT_KG
    return sel, [local_max(af[:, j], mp.masses_kg, lo, hi) for j in np.flatnonzero(sel)]


def _front_local_max(mp: ZoneMaps) -> tuple[str, str]:
    sel, peaks = _front_peaks(mp)
    m, af = mp.masses_kg, mp.area_cm2["front"]
    j = int(np.argmax(mp.moduli_mpa))
    win = (m >= 30 - ABOUT_KG) & (m <= 30 + ABOUT_KG)
    a400 = float(np.nanmax(af[win, j]))
    hits = [bool(np.isfinite(p)) for p in peaks]
    value_ok = 40.0 <= a400 <= 60.0
    return _grade(hits, value_ok), (
        f"{_mod(mp.moduli_mpa, sel)}: maxima at {_span(peaks, unit=' kg')}; {a400:.1f} cm² at "
        f"{mp.moduli_mpa[j]:g} MPa (25-35 kg)"
    )


def _front_flat(mp: ZoneMaps) -> tuple[str, str]:
    sel, peaks = _front_peaks(mp)
    m, af = mp.masses_kg, mp.area_cm2["front"]
    hits, spreads = [], []
    for j, p in zip(np.flatnonzero(sel), peaks, strict=True):
        if not np.isfinite(p):
            hits.append(False)
            continue
        seg = af[m >= p + PEAK_LOOKAHEAD_KG, j]
        spread = relative_range(seg)
        spreads.append(spread)
        hits.append(
            bool(seg.size) and np.nanmax(seg) < af[m == p, j][0] and spread <= CONSTANT_RANGE
        )
    return _grade(hits), (
        f"{sum(hits)}/{len(hits)} moduli; range after the maximum {_span(spreads, '.0%')} of "
        "its mean"
    )


def _front_split(mp: ZoneMaps) -> tuple[str, str]:
    stiff = mp.moduli_mpa > 260
    at = [split_load(mp.patches["front"][:, j], mp.masses_kg) for j in np.flatnonzero(stiff)]
    hits = [bool(np.isfinite(s) and 35 - ABOUT_KG <= s <= 35 + ABOUT_KG) for s in at]
    return _grade(hits), f"{_mod(mp.moduli_mpa, stiff)}: split at {_span(at, unit=' kg')}"


def _breit_front(mp: ZoneMaps) -> tuple[str, str]:
    m = mp.masses_kg
    j20 = int(np.argmin(np.abs(mp.moduli_mpa - 20.0)))
    low = m <= m.min() + 0.75 * np.ptp(m)
    ref = mp.area_cm2["front"][low, j20]
    dev = np.abs(mp.breitschaedel_cm2["front"][low] - ref) / np.maximum(ref, 1e-9)
    med, share = float(np.median(dev)), float(np.mean(dev <= CLOSE_BAND))
    close = med <= CLOSE_MEDIAN and share >= CLOSE_SHARE
    verdict = "yes" if close else ("partly" if med <= 2 * CLOSE_MEDIAN else "no")
    return verdict, (
        f"median deviation {med:.0%}, {share:.0%} of the loads <= {m[low].max():g} kg within "
        f"{CLOSE_BAND:.0%} (vs {mp.moduli_mpa[j20]:g} MPa)"
    )


def _rear_pressure_min(mp: ZoneMaps) -> tuple[str, str]:
    stiff, peaks, _ = _rear_peaks(mp)
    m, pr = mp.masses_kg, mp.pressure_kpa["rear"]
    offsets = []
    for j, p in zip(np.flatnonzero(stiff), peaks, strict=True):
        k = int(np.nanargmin(pr[:, j]))
        offsets.append(abs(float(m[k]) - p) if np.isfinite(p) else float("nan"))
    hits = [bool(np.isfinite(o) and o <= PEAK_HALFWIDTH_KG) for o in offsets]
    return _grade(hits), (
        f"{_mod(mp.moduli_mpa, stiff)}: minimum {_span(offsets, unit=' kg')} from the area maximum"
    )


def _rear_pressure_constant(mp: ZoneMaps) -> tuple[str, str]:
    m, pr = mp.masses_kg, mp.pressure_kpa["rear"]
    seg = pr[m > 30]
    spreads = [relative_range(seg[:, j]) for j in range(mp.moduli_mpa.size)]
    hits = [s <= CONSTANT_RANGE for s in spreads]
    top = float(np.nanmax(seg))
    j = int(np.nanargmax(np.nanmax(seg, axis=0)))
    return _grade(hits, top <= PRESSURE_BOUND_KPA), (
        f"range above 30 kg {_span(spreads, '.0%')} of the mean ({sum(hits)}/{len(hits)} "
        f"moduli); max {top:.1f} kPa at {mp.moduli_mpa[j]:g} MPa"
    )


def _front_pressure_min(mp: ZoneMaps) -> tuple[str, str]:
    m, pf = mp.masses_kg, mp.pressure_kpa["front"]
    sel = mp.moduli_mpa > 200
    where, rs, hits = [], [], []
    for j in np.flatnonzero(sel):
        k = int(np.nanargmin(pf[:, j]))
        where.append(float(m[k]))
        r = pearson(m[k:], pf[k:, j])
        rs.append(r)
        hits.append(30 - ABOUT_KG <= m[k] <= 30 + ABOUT_KG and r >= TRACK_R)
    return _grade(hits), (
        f"{_mod(mp.moduli_mpa, sel)}: minima at {_span(where, unit=' kg')}, "
        f"r above = {_span(rs, '.2f')}"
    )


def _sweet_spot(mp: ZoneMaps) -> tuple[str, str]:
    m, e = mp.masses_kg, mp.moduli_mpa
    band = (e >= 260) & (e <= 400)
    ar, af = mp.area_cm2["rear"], mp.area_cm2["front"]
    total = ar + af
    force = (
        np.nan_to_num(mp.pressure_kpa["rear"]) * ar + np.nan_to_num(mp.pressure_kpa["front"]) * af
    )
    pressure = force / np.maximum(total, 1e-12)
    k30, k60 = int(np.argmin(np.abs(m - 30))), int(np.argmin(np.abs(m - 60)))
    parts, text = [], []
    for name, arr in (("area", total), ("pressure", pressure)):
        s30, s60 = relative_range(arr[k30, band]), relative_range(arr[k60, band])
        parts += [s30 <= SWEET_RANGE, s60 >= SWEET_RATIO * s30]
        text.append(f"{name} {s30:.0%} at 30 kg vs {s60:.0%} at 60 kg")
    verdict = "yes" if all(parts) else ("partly" if any(parts) else "no")
    return verdict, "; ".join(text)


_CRITERIA: dict[str, Callable[[ZoneMaps], tuple[str, str]]] = {
    "rear-area-increases": _rear_area_increases,
    "rear-local-max-35-40kg": _rear_local_max,
    "breitschaedel-rear-trend": _breit_rear,
    "front-area-increases-to-30kg": _front_increases,
    "front-local-max-30kg": _front_local_max,
    "front-area-flat-after": _front_flat,
    "front-splits-35kg": _front_split,
    "breitschaedel-front-soft-snow": _breit_front,
    "rear-pressure-min-at-area-max": _rear_pressure_min,
    "rear-pressure-constant-55kpa": _rear_pressure_constant,
    "front-pressure-min-30kg": _front_pressure_min,
    "sweet-spot-30kg": _sweet_spot,
}


def figure89_findings(*maps: ZoneMaps) -> list[Finding]:
    """Read the twelve Figure 8–9 statements of Kalliorinne et al. (2023), §4, on the maps.

    Parameters
    ----------
    *maps
        The maps of one ski and route on one or more mass grids (:func:`zone_maps`; the
        documented table uses the 1 kg and the 2 kg grid over 5–130 kg, 20–400 MPa in 20 MPa
        steps). Each statement's criterion (:data:`STATEMENTS`, the definitions in the module
        docstring) is applied on every grid.

    Returns
    -------
    list of Finding
        In the order of :data:`STATEMENTS`; the verdict is yes only when yes on every grid.
    """
    if not maps:
        raise InputError("figure89_findings: give the maps of at least one grid")
    for mp in maps:
        if not isinstance(mp, ZoneMaps):
            raise InputError(f"figure89_findings: expected ZoneMaps, got {type(mp).__name__}")
        if mp.moduli_mpa.size < 2 or mp.masses_kg.size < 10:
            raise InputError(
                "figure89_findings: the maps need >= 10 masses and >= 2 moduli, got "
                f"{mp.masses_kg.size} x {mp.moduli_mpa.size}"
            )
    out = []
    for key, (fig, statement, criterion) in STATEMENTS.items():
        per = tuple((mp.step_kg, *_CRITERIA[key](mp)) for mp in maps)
        verdicts = {v for _, v, _ in per}
        verdict = verdicts.pop() if len(verdicts) == 1 else "partly"
        measured = "; ".join(f"{step:g} kg grid: {text}" for step, _, text in per)
        found = Finding(
            key=key, figure=fig, statement=statement, criterion=criterion,
            verdict=verdict, measured=measured, per_grid=per,
        )  # fmt: skip
        out.append(found)
    return out
