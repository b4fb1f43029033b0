"""The snow, the base and the friction parameters as every command takes them (one wording).

One rule for every command that takes ``--snow-modulus-mpa``: ``--snow`` names a preset (new,
fine-grained, coarse, machine-made, wet) or a snow file; ``--snow-modulus-mpa``, when given too,
overrides its modulus (grid commands: it is the modulus axis); ``--snow-temperature-c``
overrides its temperature. ``--base`` (S1..S5, smooth, a topography file) asks for the real
contact and needs ``--snow``. Field units at this edge, SI behind it.
"""

from __future__ import annotations

from typing import Annotated, Any

import typer

from skisnow._errors import InputError

__all__ = [
    "BaseOption",
    "FilmCutoffOption",
    "ShearStrengthOption",
    "SlidingSpeedOption",
    "SnowOption",
    "SnowTemperatureOption",
    "ViscosityOption",
    "friction_parameters",
    "friction_record",
    "resolve_base",
    "resolve_snow",
    "snow_line",
]

SnowOption = Annotated[
    str | None,
    typer.Option(
        "--snow",
        help="Snow preset (new, fine-grained, coarse, machine-made, wet) or a snow file "
        "(.json); --snow-modulus-mpa, if given too, overrides its modulus.",
    ),
]
SnowTemperatureOption = Annotated[
    float | None,
    typer.Option(
        "--snow-temperature-c", help="Override the snow's temperature in °C (ice hardness)."
    ),
]
BaseOption = Annotated[
    str | None,
    typer.Option(
        "--base",
        help="Base texture for the real contact: S1..S5 (synthetic grinds), smooth, or a "
        "topography file; needs --snow.",
    ),
]
ShearStrengthOption = Annotated[
    float | None,
    typer.Option(
        "--shear-strength-mpa",
        help="τ of the real contact in MPa (default 0.3·H_ice, dry cold snow).",
    ),
]
ViscosityOption = Annotated[
    float | None,
    typer.Option(
        "--viscosity-mpa-s", help="Meltwater viscosity in mPa·s (default: water at T_snow)."
    ),
]
SlidingSpeedOption = Annotated[
    float | None,
    typer.Option("--sliding-speed-m-s", help="Sliding speed in m/s (default 10 km/h)."),
]
FilmCutoffOption = Annotated[
    float | None,
    typer.Option(
        "--film-cutoff-nm",
        help="Film-thickness cut-off of the reciprocal separation in nm (default 100).",
    ),
]


def resolve_snow(
    snow: str | None,
    snow_modulus_mpa: float | None,
    *,
    temperature_c: float | None = None,
    required: bool = True,
) -> tuple[Any, float | None]:
    """(Snow or None, E_counter [Pa] or None) from the options, by the module's rule."""
    from skisnow._checks import check_value

    e = None
    if snow_modulus_mpa is not None:
        e = check_value(snow_modulus_mpa, "snow_modulus", where="--snow-modulus-mpa") * 1e6
    if temperature_c is not None:
        check_value(temperature_c, "temperature", where="--snow-temperature-c")
    if snow is None:
        if temperature_c is not None:
            raise InputError("--snow-temperature-c goes with --snow (a preset or a snow file)")
        if e is None and required:
            raise InputError(
                "give the snow: --snow-modulus-mpa, or --snow (a preset: new, fine-grained, "
                "coarse, machine-made, wet; or a snow file)"
            )
        return None, e
    from skisnow.snow import get_snow

    try:
        s = get_snow(snow)
    except InputError as exc:
        raise type(exc)(f"--snow: {exc}") from None
    changes: dict[str, Any] = {}
    if e is not None:
        changes["modulus"] = e
        changes["modulus_source"] = "--snow-modulus-mpa"
    if temperature_c is not None:
        changes["temperature_c"] = float(temperature_c)
    if changes:
        s = s.replace(**changes)
    return s, s.modulus


def resolve_base(base: str | None, snow: Any) -> Any:
    """The :class:`~skisnow.multiscale.Base` of ``--base`` (None without it)."""
    if base is None:
        return None
    if snow is None:
        raise InputError(
            f"--base {base}: the real contact needs the snow's temperature and grains; give "
            "--snow (a preset or a snow file)"
        )
    from skisnow.multiscale import make_base

    try:
        return make_base(base)
    except InputError as exc:
        raise type(exc)(f"--base: {exc}") from None


def friction_parameters(
    *,
    shear_strength_mpa: float | None,
    viscosity_mpa_s: float | None,
    sliding_speed_m_s: float | None,
    film_cutoff_nm: float | None,
    area_model: str = "grains",
) -> Any:
    """:class:`~skisnow.multiscale.FrictionParameters` from the options (field → SI)."""
    from skisnow._checks import check_value
    from skisnow.multiscale import FrictionParameters

    values = {
        "--shear-strength-mpa": (shear_strength_mpa, "shear_strength"),
        "--viscosity-mpa-s": (viscosity_mpa_s, "viscosity"),
        "--sliding-speed-m-s": (sliding_speed_m_s, "sliding_speed"),
        "--film-cutoff-nm": (film_cutoff_nm, "film_cutoff"),
    }
    for name, (v, quantity) in values.items():
        if v is not None:
            check_value(v, quantity, where=name)
    return FrictionParameters(
        shear_strength=None if shear_strength_mpa is None else shear_strength_mpa * 1e6,
        viscosity=None if viscosity_mpa_s is None else viscosity_mpa_s * 1e-3,
        sliding_speed=sliding_speed_m_s,
        film_cutoff=None if film_cutoff_nm is None else film_cutoff_nm * 1e-9,
        area_model=area_model,
    )


def snow_line(snow: Any) -> str:
    """One line on the snow (for human output)."""
    return snow.describe()


def friction_record(real: Any) -> dict[str, Any]:
    """The µ estimate with its terms, parameters and assumptions (never a bare number)."""
    return real.friction_estimate()
