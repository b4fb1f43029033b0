"""Generator of the shipped ski files, version 1 (``skisnow/ski/data/classic.json``, ``skate``).

The shipped skis are files, read by :func:`skisnow.ski.get_ski`; the files are the source of
truth. This module holds the parametric definitions the files of version 1 were generated from
(the skis of the first release, FROZEN on 2026-11-21 and calibrated on the contact numbers of
Kalliorinne et al. 2023, Figs. 4-7, with ``benchmarks/calibrate_skis.py``), and writes them:

    uv run python -m skisnow.ski._shipped            # rewrites skisnow/ski/data/*.json

A test checks that a file whose provenance names this generator is reproduced bit for bit. A
ski re-made another way replaces its file, and its provenance says how.
"""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from skisnow import __version__
from skisnow.ski._skis import Provenance, Ski

__all__ = ["GENERATOR", "SHIPPED_SOURCES", "build_shipped", "write_shipped_files"]

#: The provenance method of files generated here.
GENERATOR = "parametric definition (skisnow.ski._shipped)"

# FROZEN on 2026-11-21, classic RE-CALIBRATED the same day on the contact numbers of
# Kalliorinne et al. 2023, Figs. 4-7 (benchmarks/calibrate_skis.py): the camber networks are
# trained on bench data of these definitions.


def _bump(x: NDArray[np.float64], start: float, end: float, power: float) -> NDArray[np.float64]:
    """(1 - u²)^power on [start, end] (u in [-1, 1]), zero outside: a smooth compact arch."""
    c, w = 0.5 * (start + end), 0.5 * (end - start)
    u = (x - c) / w
    return np.where(np.abs(u) < 1.0, np.abs(1.0 - u**2) ** power, 0.0)


def rest_on_plane(x: NDArray[np.float64], z: NDArray[np.float64]) -> NDArray[np.float64]:
    """Subtract the lower-hull line under the balance point: the unloaded ski on the plane.

    ``z`` [m] over stations ``x`` [m] (ascending, the balance point at 0) less the line through
    the two points of its lower convex hull that bracket x = 0: the camber of a ski resting on
    a flat surface, as the bench of Kalliorinne et al. (2023) measures it unloaded.
    """
    hull: list[int] = []
    for i in range(x.size):
        while len(hull) >= 2:
            i0, i1 = hull[-2], hull[-1]
            if (x[i1] - x[i0]) * (z[i] - z[i0]) - (z[i1] - z[i0]) * (x[i] - x[i0]) <= 0.0:
                hull.pop()
            else:
                break
        hull.append(i)
    hx = x[hull]
    k = int(np.clip(np.searchsorted(hx, 0.0, side="right") - 1, 0, len(hull) - 2))
    i, j = hull[k], hull[k + 1]
    return z - (z[i] + (z[j] - z[i]) * (x - x[i]) / (x[j] - x[i]))


def _stiffness_stations(x_tail: float, x_tip: float) -> NDArray[np.float64]:
    """Stations [m] of the tabulated EI(x): every 20 mm from tail to tip."""
    return np.round(np.linspace(x_tail, x_tip, round((x_tip - x_tail) / 0.02) + 1), 6)


def _assemble(
    *,
    name: str,
    kind: Literal["classic", "skate"],
    x_tail: float,
    x_tip: float,
    x: NDArray[np.float64],
    z: NDArray[np.float64],
    ex: NDArray[np.float64],
    ei: NDArray[np.float64],
    kick_zone: tuple[float, float] | None,
    description: str,
) -> Ski:
    """Add the shovel (200 mm, 30 mm high) and tail (50 mm, 4 mm) rises to the running-surface
    shape z(x), rest it on the plane and build the :class:`Ski` (44 mm wide)."""
    shovel, tail = 0.20, 0.05  # lengths [m] of the tip (shovel) and tail rises
    z = z + 30e-3 * np.clip((x - (x_tip - shovel)) / shovel, 0.0, 1.0) ** 2.5
    z = z + 4e-3 * np.clip(((x_tail + tail) - x) / tail, 0.0, 1.0) ** 2
    return Ski(
        name=name,
        kind=kind,
        x_tail=x_tail,
        x_tip=x_tip,
        width=0.044,
        boot_plate=(-0.30, 0.0),
        stiffness_x=ex,
        stiffness_values=ei,
        camber_x=x,
        camber_values=rest_on_plane(x, z),
        kick_zone=kick_zone,
        description=description,
        provenance=Provenance(
            method=GENERATOR,
            data="none: chosen shapes, calibrated on the captions of Kalliorinne et al. 2023, "
            "Figs. 4-7 (benchmarks/calibrate_skis.py)",
            sources=tuple(SHIPPED_SOURCES),
            created="2026-11-21T00:00:00Z",
            software=f"skisnow {__version__}",
            details=(("boot_plate", "chosen: a boot from the balance point 300 mm back"),),
        ),
    )


def _build(
    *,
    name: str,
    kind: Literal["classic", "skate"],
    x_tail: float,
    x_tip: float,
    camber: float,
    camber_span: tuple[float, float],
    pocket: float,
    pocket_span: tuple[float, float] | None,
    hump: tuple[float, float, float] | None,
    ei_mid: float,
    ei_end: float,
    kick_zone: tuple[float, float] | None,
    description: str,
) -> Ski:
    x = np.round(np.linspace(x_tail, x_tip, round((x_tip - x_tail) / 0.005) + 1), 6)
    z = camber * _bump(x, *camber_span, 2)
    if pocket_span is not None:
        z = z + pocket * _bump(x, *pocket_span, 2)
    if hump is not None:
        z = z + hump[0] * _bump(x, hump[1], hump[2], 2)
    ex = _stiffness_stations(x_tail, x_tip)
    ei = ei_end + (ei_mid - ei_end) * _bump(ex, -1.0, 1.0, 2) ** 0.5
    return _assemble(
        name=name, kind=kind, x_tail=x_tail, x_tip=x_tip, x=x, z=z, ex=ex, ei=ei,
        kick_zone=kick_zone, description=description,
    )  # fmt: skip


def _build_glide(
    *,
    name: str,
    kind: Literal["classic", "skate"],
    x_tail: float,
    x_tip: float,
    supports: tuple[float, float],
    camber: float,
    camber_power: float,
    glide_radii: tuple[float, float],
    glide_power: float,
    pocket: tuple[float, float, float] | None,
    hump: tuple[float, float, float] | None,
    ei_mid: float,
    ei_end: float,
    ei_power: float,
    kick_zone: tuple[float, float] | None,
    description: str,
) -> Ski:
    """A ski whose unloaded base rests on the plane at ``supports`` = (rear, front) [m].

    z0(x) = camber·(1 - u²)^camber_power between the supports (u in [-1, 1]; a power above 2
    makes the glide zones flat-bottomed next to the supports, a power of 2 gives them the
    curvature 8·camber/span²), plus a kick-wax pocket ``(height, start, end)`` [m] (power 2
    bump) and a ``hump`` (height, start, end) [m] that splits a glide zone; outside the supports
    the base rises as the parabola d²/(2·R) with the glide radii ``(R_rear, R_front)`` [m]
    (d = distance from the support), plus the 4 mm tail rise over the last 50 mm and the 30 mm
    shovel over the last 200 mm; ``glide_power`` != 2 turns the parabolas into the power law
    d_ref²/(2R)·(d/d_ref)^glide_power, d_ref = 100 mm. EI(x) = ei_end + (ei_mid - ei_end)·
    (1 - x²)^ei_power (x in m; ei_power = 1 is the profile of the first version, :func:`_build`).
    """
    x = np.round(np.linspace(x_tail, x_tip, round((x_tip - x_tail) / 0.005) + 1), 6)
    r, f = supports
    z = camber * _bump(x, r, f, camber_power)
    if pocket is not None:
        z = z + pocket[0] * _bump(x, pocket[1], pocket[2], 2)
    if hump is not None:
        z = z + hump[0] * _bump(x, hump[1], hump[2], 2)
    d_ref = 0.1  # [m]: the glide rise equals the parabola d²/(2R) at d = 100 mm
    for d, radius in (
        (np.clip(r - x, 0.0, None), glide_radii[0]),
        (np.clip(x - f, 0.0, None), glide_radii[1]),
    ):
        z = z + d_ref**2 / (2.0 * radius) * (d / d_ref) ** glide_power
    ex = _stiffness_stations(x_tail, x_tip)
    ei = ei_end + (ei_mid - ei_end) * _bump(ex, -1.0, 1.0, ei_power)
    return _assemble(
        name=name, kind=kind, x_tail=x_tail, x_tip=x_tip, x=x, z=z, ex=ex, ei=ei,
        kick_zone=kick_zone, description=description,
    )  # fmt: skip


_SOURCES = """\
Sources: Kalliorinne et al. 2023 (§3.1, Fig. 2 and 4): SkiSelector bench, load
sequence, short contact patches on the stone; Breitschädel, F., "Variation of Nordic classic ski
characteristics from Norwegian national team athletes", Procedia Eng. 34 (2012) 391-396 (camber
height at the balance point, stiffness, contact zones, classic skis) and "Variation of cross
country ski characteristics" (sponet.fi record 3047843; skating skis: stiffness k = Δload/Δcamber
between 0.5 and 1 body weight 225-251 N/mm, net contact about half the ski length); the
practitioners' note "Classic ski pressure distribution & wax pocket" (half body weight 80 mm behind
the balance point; hard-wax pocket 0.3-0.7 mm high; wax from the 0.2 mm mark at the rear to the
0.1 mm mark in front); J. Galanes, "Defining the wax pocket", New England Nordic News 1996 (pocket
45-55 cm, from the heel plate to 20-30 cm in front of the binding)."""


#: The sources of the shipped skis' numbers (their files' provenance).
SHIPPED_SOURCES: tuple[str, ...] = (
    "Kalliorinne, K., et al. (2023): SkiSelector camber bench, load sequence, contact on the "
    "stone (§3.1, Figs. 2 and 4) and on snow (Figs. 4-7)",
    "Breitschädel, F. (2012): Variation of Nordic classic ski characteristics from Norwegian "
    "national team athletes, Procedia Engineering 34, 391-396",
    "Breitschädel, F.: Variation of cross country ski characteristics (sponet.fi record 3047843)",
    "Practitioners' note: Classic ski pressure distribution & wax pocket",
    "Galanes, J. (1996): Defining the wax pocket, New England Nordic News",
)


_CALIBRATION = """\
Calibration target: the contact numbers of the paper's real Fischer skis (Kalliorinne et al. 2023,
captions of Figs. 4-7: apparent contact lengths, mean pressures and load shares of the
rear / middle / front zones at 30 kg, x_m = -120 mm on the stone (70 GPa) and on 50 / 100 /
200 MPa snow, and at 60 kg, x_m = -210 / -70 mm on 100 MPa snow), computed here as in the paper:
the beam's rigid loaded profile pressed into the snow with the strip model, E_base = 900 MPa,
ν = 0.3. The shape parameters were fitted with Nelder-Mead on the log-ratios ski/paper with the
practitioners' numbers as constraints: reproduce with `uv run python benchmarks/calibrate_skis.py`
(it prints the table paper vs ski). The numbers below are its fit, rounded."""


@functools.cache
def _classic() -> Ski:
    return _build_glide(
        name="classic",
        kind="classic",
        x_tail=-0.98,
        x_tip=1.02,
        supports=(-0.588, 0.514),
        camber=3.0e-3,
        camber_power=2.65,
        glide_radii=(43.0, 29.5),
        glide_power=2.0,
        pocket=None,
        hump=None,
        ei_mid=1450.0,
        ei_end=137.0,
        ei_power=1.0,
        kick_zone=(-0.265, 0.255),
        description=(
            "Virtual classic ski, 2.00 m running surface (tail -980 mm, tip +1020 mm from the "
            "balance point), 44 mm wide. Unloaded it rests on the plane at -588 mm and +514 mm; "
            "between, a 3.0 mm camber arch 3.0·(1-u²)^2.65 mm whose flat-bottomed ends are the "
            "inner glide zones; outside, glide zones rising as parabolas of radius 43 m (rear) "
            "and 29.5 m (front), then the 4 mm tail rise (last 50 mm) and 30 mm shovel (last "
            "200 mm). EI(x) = 137 N m² at the ends rising to 1450 N m² at the balance point. "
            "The classic ski's double camber is the high stiffness of the closing arch (k about "
            "590 N/mm between half and full body weight) rather than a separate pocket bump. "
            "Practitioners' numbers on the virtual bench (65 kg skier, -80 mm): camber 0.61 mm "
            "at half and 0.06 mm at full body weight, closing (< 0.1 mm) at 60.6 kg; wax "
            "pocket 561 mm (0.1 mm) / 474 mm (0.2 mm) long at half weight (Galanes: 45-55 cm); "
            "kick zone (-265, +255) mm from the 0.2 mm rear to the 0.1 mm front mark. Paper "
            "fit: stone 30 kg rear/front 24/18 mm (paper 28/15), 60 kg at -210 mm load share "
            "80/20 % (paper 84/16), at -70 mm rear/middle/front 47/27/27 % (paper 45/28/27); "
            "on soft snow the contact lengths stay about 30-45 % shorter and the pressures "
            "higher than the paper's (its glide zones are flatter far from the contact point "
            "than a parabola). CHOSEN, not measured: no public EI(x) or camber table of a XC "
            "ski was found.\n" + _CALIBRATION + "\n" + _SOURCES
        ),
    )


@functools.cache
def _skate() -> Ski:
    return _build(
        name="skate",
        kind="skate",
        x_tail=-0.92,
        x_tip=0.94,
        camber=5.5e-3,
        camber_span=(-0.80, 0.76),
        pocket=0.0,
        pocket_span=None,
        hump=(0.4e-3, 0.52, 0.68),
        ei_mid=8000.0,
        ei_end=200.0,
        kick_zone=None,
        description=(
            "Virtual skate ski, 1.86 m running surface (tail -920 mm, tip +940 mm), 44 mm wide. "
            "Single 5.5 mm camber, no kick zone, 30 mm shovel and 4 mm tail rise, and a 0.4 mm "
            "hump in the front glide zone (+520..+680 mm) so that the front contact splits into "
            "two patches as the load rises (Kalliorinne et al. 2023, Fig. 5). EI(x) = 200 N m² "
            "at the "
            "ends rising to 8000 N m²: much stiffer than the classic ski. CHOSEN, not measured: "
            "fitted so that Breitschädel's stiffness between half and full body weight (65 kg, "
            "-80 mm) is about 210 N/mm, in the measured range of skating skis, and the ski does "
            "not close within the bench range. Paper calibration (benchmarks/calibrate_skis.py, "
            "Kalliorinne et al. 2023, Figs. 4-5): NOT reached — its glide zones are too curved: "
            "30 kg at "
            "-120 mm gives rear/front 19/15 mm on the stone (paper 53/46 mm) and 54/35 mm on "
            "100 MPa snow (paper 146/162 mm), load share 58/42 % (paper 67/33 %); only the "
            "topology holds (front zone one patch at 30 kg, two at 60 kg). Re-shaping the glide "
            "zones (arch power, glide radii, EI at the ends) did not lower the misfit while "
            "keeping the stiffness k and the never-closing camber, so this shape was kept.\n"
            + _SOURCES
        ),
    )


_SHIPPED_BUILDERS: dict[str, Callable[[], Ski]] = {"classic": _classic, "skate": _skate}


def build_shipped(name: str) -> Ski:
    """The shipped ski ``name`` as generated from its parametric definition (version 1)."""
    return _SHIPPED_BUILDERS[name]()


def write_shipped_files(directory: Path | None = None) -> list[Path]:
    """Write the generated shipped skis as ski files into ``directory`` (default: the package's
    ``skisnow/ski/data``); return the paths."""
    from skisnow.ski._skifile import write_ski

    directory = Path(__file__).with_name("data") if directory is None else Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, build in _SHIPPED_BUILDERS.items():
        path = directory / f"{name}.json"
        write_ski(build(), path)
        paths.append(path)
    return paths


if __name__ == "__main__":  # pragma: no cover - maintenance command
    for p in write_shipped_files(Path(sys.argv[1]) if len(sys.argv) > 1 else None):
        print(p)
