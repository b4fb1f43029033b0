"""The findings of Kalliorinne et al. (2023), §4, Figures 8–9, as checks on load × snow maps.

The paper reads its skate ski's maps (rear and front zone, apparent contact area and mean
apparent pressure against the load m at x_m = -120 mm, snow 20–400 MPa) as a list of findings.
They are NOT fitting targets of skisnow's skis (the captions of Figures 4–7 are): whether the
maps of a fitted ski show them is the validation. Each finding is written here as an
operational criterion on the arrays (the windows in kg are the paper's "about" widened by
±5 kg); :func:`figure89_findings` evaluates all of them, :func:`zone_maps` computes the maps with
the paper's pipeline (the beam on the rigid plane → rigid profile → strip half-space).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from skisnow._errors import InputError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.contact import contact_zones, effective_modulus, solve_contact
from skisnow.ski import Ski, solve_beam

__all__ = ["Finding", "ZoneMaps", "figure89_findings", "zone_maps"]


@dataclass(frozen=True, kw_only=True)
class ZoneMaps:
    """Rear and front maps over load (rows) × snow modulus (columns), field units.

    ``area_cm2``, ``pressure_kpa`` and ``patches`` map ``"rear"``/``"front"`` to arrays of shape
    ``(n_mass, n_modulus)``; ``breitschaedel_cm2`` to arrays of shape ``(n_mass,)`` (a property
    of the profile alone).
    """

    masses_kg: NDArray[np.float64]
    moduli_mpa: NDArray[np.float64]
    area_cm2: dict[str, NDArray[np.float64]]
    pressure_kpa: dict[str, NDArray[np.float64]]
    patches: dict[str, NDArray[np.int64]]
    breitschaedel_cm2: dict[str, NDArray[np.float64]]


@dataclass(frozen=True, kw_only=True)
class Finding:
    """One finding of the paper: its statement, the criterion applied, shown or not, and why."""

    key: str
    figure: str
    statement: str
    criterion: str
    shown: bool
    measured: str


def zone_maps(
    ski: Ski,
    masses_kg: ArrayLike,
    moduli_mpa: ArrayLike,
    *,
    load_position: float = -0.120,
    n_points: int = 2048,
) -> ZoneMaps:
    """Rear/front area, mean pressure, patches and Breitschädel area over load × snow.

    The paper's pipeline (Kalliorinne et al. 2023, §3): the loaded ski on the rigid plane (the
    virtual bench), its rigid profile pressed into the half-space of E' from E_base = 900 MPa,
    ν = 0.3 (eq. 2) with force and moment balance (eq. 3), strip model, ``n_points`` stations.
    """
    masses = np.asarray(masses_kg, dtype=float)
    moduli = np.asarray(moduli_mpa, dtype=float)
    if masses.ndim != 1 or moduli.ndim != 1 or masses.size < 3 or moduli.size < 1:
        raise InputError("zone_maps: need 1-D masses (>= 3) and moduli (>= 1)")
    shape = (masses.size, moduli.size)
    area = {z: np.zeros(shape) for z in ("rear", "front")}
    press = {z: np.full(shape, np.nan) for z in ("rear", "front")}
    npatch = {z: np.zeros(shape, dtype=np.int64) for z in ("rear", "front")}
    breit = {z: np.zeros(masses.size) for z in ("rear", "front")}
    edges = np.linspace(ski.x_tail, ski.x_tip, n_points + 1)
    x = 0.5 * (edges[1:] + edges[:-1])
    for i, m in enumerate(masses):
        h = solve_beam(ski, mass=m, load_position=load_position).sample(x)
        for j, e in enumerate(moduli):
            sol = solve_contact(
                x, h, load=m * STANDARD_GRAVITY, load_position=load_position,
                modulus=effective_modulus(e * 1e6, 900e6, poisson=0.3), width=ski.width,
            )  # fmt: skip
            zones = contact_zones(sol, kick_zone=ski.kick_zone)
            for z in ("rear", "front"):
                area[z][i, j] = zones[z].area * 1e4
                press[z][i, j] = zones[z].mean_pressure * 1e-3
                npatch[z][i, j] = zones[z].patches
            if j == 0:
                for z in ("rear", "front"):
                    breit[z][i] = zones.breitschaedel[z].area * 1e4
    return ZoneMaps(
        masses_kg=masses, moduli_mpa=moduli, area_cm2=area, pressure_kpa=press,
        patches=npatch, breitschaedel_cm2=breit,
    )  # fmt: skip


def _local_max(y: NDArray[np.float64], m: NDArray[np.float64], lo: float, hi: float) -> float:
    """Load [kg] of the first interior local maximum of y(m) in [lo, hi] (NaN if none)."""
    for k in range(1, y.size - 1):
        if lo <= m[k] <= hi and y[k] > y[k - 1] and y[k] >= y[k + 1]:
            return float(m[k])
    return float("nan")


def _local_min_after(y: NDArray[np.float64], m: NDArray[np.float64], after: float) -> float:
    for k in range(1, y.size - 1):
        if m[k] > after and y[k] < y[k - 1] and y[k] <= y[k + 1]:
            return float(m[k])
    return float("nan")


def figure89_findings(maps: ZoneMaps) -> list[Finding]:
    """Evaluate the Figure 8–9 findings of Kalliorinne et al. (2023), §4, on ``maps``.

    The criteria (stated in each :class:`Finding`) are the paper's sentences made operational;
    "about X kg" is read as X ± 5 kg.
    """
    m, e = maps.masses_kg, maps.moduli_mpa
    ar, af = maps.area_cm2["rear"], maps.area_cm2["front"]
    pr, pf = maps.pressure_kpa["rear"], maps.pressure_kpa["front"]
    nf = maps.patches["front"]
    out: list[Finding] = []

    def add(key: str, fig: str, statement: str, criterion: str, shown: bool, measured: str) -> None:
        out.append(
            Finding(
                key=key,
                figure=fig,
                statement=statement,
                criterion=criterion,
                shown=bool(shown),
                measured=measured,
            )
        )

    # F1 rear area increases with load
    rises = [float(np.mean(np.diff(ar[:, j]) >= 0)) for j in range(e.size)]
    grows = [ar[-1, j] > ar[0, j] for j in range(e.size)]
    add(
        "rear-area-increases",
        "8 left",
        "rear area increases, in general, with the load",
        "for every snow: area at the largest load > at the smallest, and >= 70 % of the load "
        "steps non-decreasing",
        all(grows) and min(rises) >= 0.7,
        f"non-decreasing steps {min(rises):.0%}-{max(rises):.0%}",
    )

    # F2 rear local max at 35-40 kg then local min at 40-45 kg for E > 260 MPa
    stiff = e > 260
    peaks = [_local_max(ar[:, j], m, 30, 45) for j in np.flatnonzero(stiff)]
    mins = [
        _local_min_after(ar[:, j], m, p) for j, p in zip(np.flatnonzero(stiff), peaks, strict=True)
    ]
    ok = bool(stiff.any()) and all(
        np.isfinite(p) and np.isfinite(q) and q <= 50 for p, q in zip(peaks, mins, strict=True)
    )
    add(
        "rear-local-max-35-40kg",
        "8 left",
        "E > 260 MPa: rear area has a local maximum at about 35-40 kg and a local minimum at "
        "about 40-45 kg",
        "every E > 260 MPa: a local maximum in 30-45 kg followed by a local minimum at <= 50 kg",
        ok,
        f"maxima at {_fmt(peaks)} kg, minima at {_fmt(mins)} kg",
    )

    # F3 Breitschädel rear follows the trend for 50-150 MPa, loads > 20 kg
    sel_m = m > 20
    sel_e = (e >= 50) & (e <= 150)
    rs = [_corr(maps.breitschaedel_cm2["rear"][sel_m], ar[sel_m, j]) for j in np.flatnonzero(sel_e)]
    add(
        "breitschaedel-rear-trend",
        "8 left",
        "the Breitschädel rear area follows a similar trend for 50-150 MPa above 20 kg",
        "Pearson r >= 0.9 between the Breitschädel and the snow rear area over m > 20 kg, every "
        "E in 50-150 MPa",
        bool(rs) and min(rs) >= 0.9,
        f"r = {_fmt(rs, '.2f')}",
    )

    # F4 front area increases with load up to about 30 kg, every snow
    up = m <= 30
    inc = [bool(np.all(np.diff(af[up, j]) >= -0.02 * af[up, j].max())) for j in range(e.size)]
    add(
        "front-area-increases-to-30kg",
        "8 right",
        "front area increases with the load up to about 30 kg for every snow",
        "every snow: front area non-decreasing (2 % slack) from the smallest load to 30 kg",
        all(inc),
        f"{sum(inc)}/{len(inc)} snows",
    )

    # F5 local maximum at about 30 kg for E > 40 MPa, about 50 cm² at 400 MPa
    sel = np.flatnonzero(e > 40)
    fpeaks = [_local_max(af[:, j], m, 25, 40) for j in sel]
    j400 = int(np.argmax(e))
    a400 = float(np.nanmax(af[(m >= 25) & (m <= 40), j400]))
    ok = bool(sel.size) and all(np.isfinite(fpeaks)) and 40 <= a400 <= 60
    add(
        "front-local-max-30kg",
        "8 right",
        "E > 40 MPa: front area has a local maximum at about 30 kg, converging to about 50 cm² "
        "as E -> 400 MPa",
        "every E > 40 MPa: a local maximum in 25-40 kg; at the stiffest snow "
        "its value in 40-60 cm²",
        ok,
        f"maxima at {_fmt(fpeaks)} kg; {a400:.1f} cm² at {e[j400]:g} MPa",
    )

    # F6 thereafter it decreases somewhat and flattens
    late = (m >= 45) & (m <= 80)
    flat = []
    for j in sel:
        peak = float(np.nanmax(af[(m >= 25) & (m <= 40), j]))
        seg = af[late, j]
        flat.append(bool(seg.size) and seg.mean() < peak and np.ptp(seg) <= 0.25 * seg.mean())
    add(
        "front-area-flat-after",
        "8 right",
        "after the maximum the front area decreases somewhat and stays about constant",
        "every E > 40 MPa: mean over 45-80 kg below the 25-40 kg maximum and its range <= 25 % "
        "of its mean",
        bool(flat) and all(flat),
        f"{sum(flat)}/{len(flat)} snows",
    )

    # F7 front splits into two patches at about 35 kg for E > 260 MPa
    split_at = []
    for j in np.flatnonzero(stiff):
        two = np.flatnonzero(nf[:, j] >= 2)
        split_at.append(float(m[two[0]]) if two.size else float("nan"))
    ok = bool(split_at) and all(np.isfinite(split_at)) and all(30 <= s <= 45 for s in split_at)
    add(
        "front-splits-35kg",
        "8 right",
        "E > 260 MPa: the front zone splits from one into two patches at about 35 kg",
        "every E > 260 MPa: the first load with >= 2 front patches in 30-45 kg",
        ok,
        f"split at {_fmt(split_at)} kg",
    )

    # F8 Breitschädel front close to the 20 MPa prediction except at high loads
    j20 = int(np.argmin(e))
    lo_m = m <= 60
    ref = af[lo_m, j20]
    dev = np.abs(maps.breitschaedel_cm2["front"][lo_m] - ref) / np.maximum(ref, 1e-9)
    add(
        "breitschaedel-front-soft-snow",
        "8 right",
        "the Breitschädel front area follows the 20 MPa prediction closely except at high loads",
        f"|Breitschädel - area at {e[j20]:g} MPa| <= 25 % of it at >= 80 % of the loads <= 60 kg",
        float(np.mean(dev <= 0.25)) >= 0.8,
        f"median deviation {np.median(dev):.0%}",
    )

    # F9 rear pressure minimum where the rear area has its local maximum (E > 260 MPa)
    lag = []
    for j, p in zip(np.flatnonzero(stiff), peaks, strict=True):
        k = int(np.nanargmin(np.where(m >= 10, pr[:, j], np.inf)))
        lag.append(abs(float(m[k]) - p) if np.isfinite(p) else float("inf"))
    add(
        "rear-pressure-min-at-area-max",
        "9",
        "the rear mean pressure has its global minimum at the load of the rear area's local "
        "maximum",
        "every E > 260 MPa: the pressure minimum over m >= 10 kg within 5 kg of the area maximum",
        bool(lag) and max(lag) <= 5,
        f"offsets {_fmt(lag)} kg",
    )

    # F10 rear pressure about constant above 30 kg, <= 55 kPa even at 400 MPa
    hi_m = m > 30
    seg = pr[hi_m]
    spread = np.ptp(seg, axis=0) / np.nanmean(seg, axis=0)
    add(
        "rear-pressure-constant-55kpa",
        "9",
        "rear mean pressure about constant above 30 kg and below 55 kPa even at 400 MPa",
        "every snow: range over m > 30 kg <= 25 % of its mean, and max <= 55 kPa",
        bool(np.all(spread <= 0.25)) and float(np.nanmax(seg)) <= 55,
        f"range {np.nanmax(spread):.0%} of the mean at most, max {np.nanmax(seg):.1f} kPa",
    )

    # F11 front pressure minimum at about 30 kg (pronounced above 200 MPa), then ~linear rise
    sel2 = np.flatnonzero(e > 200)
    where = [float(m[int(np.nanargmin(pf[:, j]))]) for j in sel2]
    after = m >= 35
    lin = [_corr(m[after], pf[after, j]) for j in sel2]
    ok = bool(sel2.size) and all(25 <= w <= 40 for w in where) and min(lin) >= 0.9
    add(
        "front-pressure-min-30kg",
        "9",
        "front mean pressure falls to a global minimum at about 30 kg, then rises about linearly",
        "every E > 200 MPa: the minimum in 25-40 kg and r(m, p) >= 0.9 above 35 kg",
        ok,
        f"minima at {_fmt(where)} kg, r = {_fmt(lin, '.2f')}",
    )

    # F12 the sweet spot: at 30 kg area and pressure vary little over 260-400 MPa, at 60 kg a lot
    band = (e >= 260) & (e <= 400)
    k30, k60 = int(np.argmin(np.abs(m - 30))), int(np.argmin(np.abs(m - 60)))
    ratios = []
    for arr in (ar + af, (pr * ar + pf * af) / np.maximum(ar + af, 1e-12)):
        s30 = np.ptp(arr[k30, band]) / np.mean(arr[k30, band])
        s60 = np.ptp(arr[k60, band]) / np.mean(arr[k60, band])
        ratios.append((s30, s60))
    ok = bool(band.any()) and all(a < 0.5 * b for a, b in ratios)
    add(
        "sweet-spot-30kg",
        "8-9",
        "at 30 kg the total area and mean pressure hardly change over 260-400 MPa, at 60 kg "
        "they differ much",
        "relative range over 260-400 MPa at 30 kg < half that at 60 kg, for "
        "the total area and the total mean pressure",
        ok,
        "area {:.0%} vs {:.0%}, pressure {:.0%} vs {:.0%}".format(*ratios[0], *ratios[1]),
    )
    return out


def _corr(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    if a.size < 3 or np.std(a) == 0 or np.std(b) == 0:
        return float("nan")
    return float(np.corrcoef(a, b)[0, 1])


def _fmt(values: list[float], spec: str = ".0f") -> str:
    vals = [v for v in values]
    if not vals:
        return "-"
    finite = [v for v in vals if np.isfinite(v)]
    missing = len(vals) - len(finite)
    if not finite:
        return "none"
    text = f"{format(min(finite), spec)}-{format(max(finite), spec)}"
    return text + (f" ({missing} none)" if missing else "")
