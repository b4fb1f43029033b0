"""What a case needs of the snow and the base, and its real contact (:func:`solve_case`'s glue).

:func:`resolve_media` turns the caller's ``snow_modulus``/``snow`` and ``base`` into the snow
material of eq. 2, the base material of eq. 2, and — when the base carries a texture (a
:class:`~skisnow.multiscale.Base`, ``'S3'``, ``'smooth'``, a topography file) and a snow is
given — the micro curves of that base × snow. :func:`case_real_contact` then evaluates them on
the apparent contact (:func:`skisnow.multiscale.real_contact`). :func:`station_masks` gives the
station masks the real contact is summarised over: the regions fixed by the ski and every
contact patch — the two views of the apparent contact's footprint
(:func:`skisnow.contact.footprint`), taken from it.
"""

from __future__ import annotations

import functools
import sys
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from skisnow._errors import DomainWarning, InputError

__all__ = [
    "Media",
    "case_real",
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

    # A Base exists only once skisnow.multiscale is imported: checking without importing it
    # spares a plain case (and every sweep worker's first chunk) ~1 s of SciPy imports.
    multiscale = sys.modules.get("skisnow.multiscale")
    if isinstance(base, str) or (multiscale is not None and isinstance(base, multiscale.Base)):
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


@functools.lru_cache(maxsize=64)
def _hardness_notes(temperature_c: float, model: str) -> tuple[str, ...]:
    """The DomainWarnings of the ice hardness at this temperature (once per temperature)."""
    from skisnow.micro import ice_hardness

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DomainWarning)
        ice_hardness(temperature_c, model=model)
    return tuple(str(w.message) for w in caught if issubclass(w.category, DomainWarning))


def case_real(solution: Any, media: Any, notes: list[str], real_kw: dict[str, Any]) -> Any:
    """The real contact of a solved case (None without a texture), noting what lies outside a
    model's range: the ice hardness's temperature range, pressures beyond the micro curves."""
    if media.base is None:
        return None
    notes.extend(_hardness_notes(media.snow.temperature_c, media.snow.hardness_model))
    real = case_real_contact(solution, media, **real_kw)
    if real.beyond.any():
        notes.append(
            f"apparent pressure above the micro curves' last point at {int(real.beyond.sum())} "
            "station(s): the real contact there is held at that point's values"
        )
    return real


def station_masks(case: Any, *, patches: bool = True) -> dict[str, np.ndarray]:
    """Boolean station masks of a solved case: ``total``; the regions fixed by the ski, as the
    apparent contact reports them (``case.zones.footprint``: ``rear_glide``, ``kick_zone``,
    ``front_glide`` between the kick-zone marks, or rear/front glide split at the balance point;
    :func:`skisnow.contact.region_index`); and (``patches``) ``patch 1``… — every contiguous
    contact patch of the footprint, from the tail. The regions partition the ski; the patches
    hold its contact."""
    from skisnow.contact import region_index

    x = np.asarray(case.solution.x)
    fp = case.zones.footprint
    masks: dict[str, np.ndarray] = {"total": np.ones(x.shape, dtype=bool)}
    idx = region_index(x, fp.marks)
    for k, name in enumerate(fp.names):
        masks[name] = idx == k
    if patches:
        for k, patch in enumerate(fp.patches, start=1):
            masks[f"patch {k}"] = (x >= patch.start) & (x <= patch.end)
    return masks


def zone_station_masks(case: Any, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Station masks of the sweep's zone dimension: a region (``rear_glide``, ``kick_zone``,
    ``front_glide``) is all its stations (:func:`station_masks`); a paper zone (``rear``,
    ``middle``, ``front``, ``kick``) the stations inside its contact intervals; ``total`` the
    whole ski."""
    x = np.asarray(case.solution.x)
    regions = station_masks(case, patches=False)
    out: dict[str, np.ndarray] = {}
    for name in names:
        if name in regions:
            out[name] = regions[name]
        elif name in ("rear_glide", "kick_zone", "front_glide"):  # a region this ski lacks
            out[name] = np.zeros(x.shape, dtype=bool)
        else:
            m = np.zeros(x.shape, dtype=bool)
            for lo, hi in case.zones[name].intervals:
                m[np.searchsorted(x, lo, "left") : np.searchsorted(x, hi, "right")] = True
            out[name] = m
    return out
