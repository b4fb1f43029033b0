"""What a case needs of the snow and the base, and its real contact (:func:`solve_case`'s glue).

:func:`resolve_media` turns the caller's ``snow_modulus``/``snow`` and ``base`` into the snow
material of eq. 2, the base material of eq. 2, and — when the base carries a texture (a
:class:`~skisnow.multiscale.Base`, ``'S3'``, ``'smooth'``, a topography file) and a snow is
given — the micro curves of that base × snow. :func:`case_real_contact` then evaluates them on
the apparent contact (:func:`skisnow.multiscale.real_contact`). :func:`station_masks` gives the
station masks the real contact is summarised over: regions fixed by the ski (rear glide / kick
zone / front glide for a classic; rear / front glide split at the balance point otherwise) and
every contact patch — the two views of issue 26; once its regions are in
:mod:`skisnow.contact`, the masks come from there.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from skisnow._errors import InputError

__all__ = [
    "Media",
    "case_real_contact",
    "resolve_media",
    "station_masks",
    "zone_station_masks",
]


@dataclass(frozen=True)
class Media:
    """The resolved snow and base of a case."""

    snow_modulus: float
    counter: Any  # the snow as eq. 2 sees it: a Material, or a modulus [Pa] with ``poisson``
    base_material: Any  # Material | float | None (None: the default BASE)
    snow: Any  # skisnow.snow.Snow | None
    base: Any  # skisnow.multiscale.Base | None (a texture was asked for)


def _is_texture(base: Any) -> bool:
    from skisnow.materials import Material
    from skisnow.multiscale import Base

    if isinstance(base, Base | str):
        return True
    if base is None or isinstance(base, Material):
        return False
    try:
        float(base)
    except (TypeError, ValueError):
        return True  # a Path, a GrindSpec, a Topography: make_base says whether it is one
    return False


def resolve_media(snow_modulus: Any, snow: Any, base: Any) -> Media:
    """Resolve the snow (modulus or :class:`~skisnow.snow.Snow`) and the base of a case."""
    from skisnow._checks import positive_finite

    s = None
    if snow is not None:
        from skisnow.snow import get_snow

        s = get_snow(snow)
        if snow_modulus is not None:
            raise InputError(
                f"give snow_modulus or snow, not both (the snow {s.name!r} carries its modulus, "
                f"{s.modulus / 1e6:g} MPa; use snow.replace(modulus=...) to change it)"
            )
        e = s.modulus
        counter: Any = s.material
    else:
        if snow_modulus is None:
            raise InputError("give the snow: snow_modulus [Pa] or snow (a preset, file or Snow)")
        e = positive_finite("snow_modulus [Pa]", snow_modulus)
        counter = e
    b = None
    base_material = base
    if _is_texture(base):
        from skisnow.multiscale import make_base

        b = make_base(base)
        base_material = b.material
        if s is None:
            raise InputError(
                f"base {b.name!r}: the real contact needs the snow's temperature and grains; "
                "give snow= (a preset, a snow file or a Snow) instead of snow_modulus"
            )
    return Media(snow_modulus=e, counter=counter, base_material=base_material, snow=s, base=b)


def case_real_contact(
    solution: Any,
    media: Media,
    *,
    friction: Any = None,
    curves: Any = None,
    cache_dir: Any = None,
) -> Any:
    """The real contact of a solved case, or ``None`` when no texture was asked for."""
    if media.base is None:
        return None
    from skisnow.multiscale import FrictionParameters, micro_curves, real_contact

    if curves is not None and (curves.base, curves.snow) != (media.base.name, media.snow.name):
        raise InputError(
            f"curves: computed for base {curves.base!r} × snow {curves.snow!r}, but the case has "
            f"base {media.base.name!r} × snow {media.snow.name!r}"
        )
    c = curves if curves is not None else micro_curves(media.base, media.snow, cache_dir=cache_dir)
    f = friction if friction is not None else FrictionParameters()
    resolved = f.resolve(temperature_c=media.snow.temperature_c, hardness=c.hardness)
    return real_contact(solution, c, resolved)


#: Region names (tail → tip), as issue 26's regions will name them in skisnow.contact.
REGIONS_CLASSIC: tuple[str, str, str] = ("rear_glide", "kick_zone", "front_glide")
REGIONS_SPLIT: tuple[str, str] = ("rear_glide", "front_glide")


def station_masks(
    x: np.ndarray,
    pressure: np.ndarray,
    *,
    kick_zone: tuple[float, float] | None,
    split: float = 0.0,
) -> dict[str, np.ndarray]:
    """Boolean station masks: ``total``; the regions fixed by the ski — ``rear_glide``,
    ``kick_zone``, ``front_glide`` (a station on a mark belongs to the kick zone) for a classic,
    else ``rear_glide``/``front_glide`` split at ``split`` (default the balance point, x = 0; a
    station on it belongs to the front); and ``patch 1``… for every contiguous run of stations
    in contact, from the tail. The regions partition the ski; the patches hold its contact."""
    from skisnow.contact import patches

    x = np.asarray(x)
    along = np.asarray(pressure)
    along = along.any(axis=1) if along.ndim == 2 else along > 0
    masks: dict[str, np.ndarray] = {"total": np.ones(x.shape, dtype=bool)}
    if kick_zone is not None:
        k0, k1 = kick_zone
        masks["rear_glide"] = x < k0
        masks["kick_zone"] = (x >= k0) & (x <= k1)
        masks["front_glide"] = x > k1
    else:
        masks["rear_glide"] = x < split
        masks["front_glide"] = x >= split
    for k, (i, j) in enumerate(patches(along), start=1):
        m = np.zeros(x.shape, dtype=bool)
        m[i : j + 1] = True
        masks[f"patch {k}"] = m
    return masks


def zone_station_masks(case: Any, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Station masks of contact zones (the sweep's zone dimension): the stations inside a
    zone's contact intervals; ``total`` is the whole ski."""
    x = np.asarray(case.solution.x)
    out: dict[str, np.ndarray] = {}
    for name in names:
        if name == "total":
            out[name] = np.ones(x.shape, dtype=bool)
            continue
        m = np.zeros(x.shape, dtype=bool)
        for lo, hi in case.zones[name].intervals:
            m |= (x >= lo) & (x <= hi)
        out[name] = m
    return out
