"""Snow presets: the snow types a technician names, each with its sources and its range.

A preset is one representative :class:`~skisnow.snow.Snow` and the range it stands for
(``Snow.ranges``, field units). Where a value is a choice inside a published range, the
preset says so (``modulus_source``). Sources:

* grain shapes and size classes — Fierz et al. (2009), *The International Classification for
  Seasonal Snow on the Ground*, UNESCO IHP-VII Tech. Doc. Hydrol. 83: very fine < 0.2 mm,
  fine 0.2–0.5, medium 0.5–1.0, coarse 1.0–2.0, very coarse 2.0–5.0 mm; decomposing fragments
  (DF), rounded grains (RG), faceted crystals (FC), melt forms (MF); wet snow is at 0 °C;
* moduli of machine-made snow — Lintzén & Edeskär (2015), J. Cold Reg. Eng. 29, 04014020:
  100–250 MPa new, 50–350 MPa old, as Kalliorinne et al. (2023, §3.2) quote them for their
  20–400 MPa range;
* dry-snow modulus from density — Scapozza (2004) (:func:`~skisnow.snow.modulus_from_density`);
* the granular snow of the glide tests — Scherge et al. (2021, §2.3, eq. 12): −2 °C, grains
  mostly 500–750 µm, the fit f(D) with mode 625 µm, b = 24.9;
* ice hardness from the temperature — Scherge et al. (2021), eq. 2 (Poirier et al. 2011).

The grain distributions are the eq. 12 form with the paper's exponent b = 24.9 (20 % relative
spread) about the preset's mode (:func:`~skisnow.snow.gamma_grains`) — the shape is an
assumption for every preset but machine-made snow.
"""

from __future__ import annotations

import warnings

from skisnow._errors import DomainWarning, InputError
from skisnow.snow._snow import Snow, gamma_grains, modulus_from_density

__all__ = ["SNOW_ALIASES", "SNOW_PRESETS", "snow_preset"]

_FIERZ = "Fierz et al. (2009), International Classification for Seasonal Snow on the Ground"
_LINTZEN = "Lintzén & Edeskär (2015), J. Cold Reg. Eng. 29 (machine-made snow moduli)"
_SCAPOZZA = "Scapozza (2004), ETH Zürich thesis, eq. 5-7 (dry-snow modulus from density)"
_SCHERGE = "Scherge et al. (2021), Front. Mech. Eng. 7:659995, §2.3 and eq. 2, 12"
_KALLIORINNE = "Kalliorinne et al. (2023), Lubricants, macro-scale paper, §3.2 (20–400 MPa)"


def _dry(
    name: str,
    *,
    density: float,
    density_range: tuple[float, float],
    mode_um: float,
    mode_range: tuple[float, float],
    temperature_c: float,
    temperature_range: tuple[float, float],
    description: str,
) -> Snow:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DomainWarning)
        e_lo, e_hi = (modulus_from_density(r) for r in density_range)
    return Snow.from_density(
        name=name,
        density=density,
        temperature_c=temperature_c,
        grains=gamma_grains(mode_um * 1e-6),
        sources=(_FIERZ, _SCAPOZZA, _SCHERGE),
        ranges={
            "density_kg_m3": density_range,
            "modulus_mpa": (round(e_lo / 1e6, 1), round(e_hi / 1e6, 1)),
            "grain_mode_um": mode_range,
            "temperature_c": temperature_range,
        },
        description=description,
    )


def _presets() -> dict[str, Snow]:
    new = _dry(
        "new",
        density=350.0,
        density_range=(250.0, 400.0),
        mode_um=400.0,
        mode_range=(200.0, 1000.0),
        temperature_c=-8.0,
        temperature_range=(-15.0, -3.0),
        description="new snow on a groomed track: decomposing fragments (DF), fine–medium",
    )
    fine = _dry(
        "fine-grained",
        density=450.0,
        density_range=(400.0, 490.0),
        mode_um=350.0,
        mode_range=(200.0, 500.0),
        temperature_c=-5.0,
        temperature_range=(-15.0, -1.0),
        description="fine-grained old snow: small rounded grains (RG), fine class",
    )
    coarse = _dry(
        "coarse",
        density=480.0,
        density_range=(430.0, 490.0),
        mode_um=1300.0,
        mode_range=(1000.0, 2000.0),
        temperature_c=-3.0,
        temperature_range=(-10.0, -1.0),
        description="coarse transformed snow: melt-freeze or faceted grains (MF/FC), coarse",
    )
    machine = Snow(
        name="machine-made",
        modulus=175e6,
        temperature_c=-2.0,
        grains=gamma_grains(625e-6),
        modulus_source="mid-range of 100–250 MPa for new machine-made snow (Lintzén & "
        "Edeskär 2015)",
        sources=(_LINTZEN, _SCHERGE, _KALLIORINNE),
        ranges={
            "modulus_mpa": (100.0, 250.0),
            "grain_mode_um": (500.0, 750.0),
            "temperature_c": (-10.0, -1.0),
        },
        description="machine-made (granular) snow, as in Scherge et al.'s glide tests",
    )
    wet = Snow(
        name="wet",
        modulus=50e6,
        temperature_c=0.0,
        grains=gamma_grains(1500e-6),
        modulus_source="a choice in the soft end of the 20–400 MPa simulated by Kalliorinne "
        "et al. (2023); no density relation applies to wet snow",
        sources=(_FIERZ, _KALLIORINNE, _SCHERGE),
        ranges={
            "modulus_mpa": (20.0, 100.0),
            "grain_mode_um": (1000.0, 2000.0),
            "temperature_c": (0.0, 0.0),
        },
        description="wet snow at 0 °C: clustered melt forms (MF), coarse; ice hardness "
        "extrapolated (eq. 2 is fitted below -1 °C)",
    )
    return {s.name: s for s in (new, fine, coarse, machine, wet)}


#: The presets by name (``new``, ``fine-grained``, ``coarse``, ``machine-made``, ``wet``).
SNOW_PRESETS: dict[str, Snow] = _presets()
#: Other names a technician may type.
SNOW_ALIASES: dict[str, str] = {
    "new-snow": "new",
    "fresh": "new",
    "fine": "fine-grained",
    "old": "fine-grained",
    "old-fine": "fine-grained",
    "coarse-grained": "coarse",
    "transformed": "coarse",
    "machine": "machine-made",
    "artificial": "machine-made",
    "wet-snow": "wet",
}


def snow_preset(name: str) -> Snow:
    """The preset ``name`` (or one of its aliases, case-insensitive)."""
    key = name.strip().lower().replace("_", "-").replace(" ", "-")
    key = SNOW_ALIASES.get(key, key)
    if key not in SNOW_PRESETS:
        raise InputError(
            f"snow preset {name!r} unknown; valid: {', '.join(SNOW_PRESETS)} (or a snow file, "
            ".json)"
        )
    return SNOW_PRESETS[key]
