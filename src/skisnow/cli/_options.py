"""The option gate: every numeric option of every command checked before the command runs.

One table, :data:`OPTION_QUANTITIES`, says which quantity of :mod:`skisnow._quantities` each
numeric option holds (by option name; :data:`COMMAND_OPTION_QUANTITIES` where one name means two
things in two commands). :func:`install_gate` attaches to every parameter of the Click command
that Typer builds from :data:`skisnow.cli.app` a callback that checks its value with
:func:`skisnow._checks.check_value` (a number) or :func:`~skisnow._checks.check_option_values`
(a grid ``start:stop:step``, a list or one value), so NaN, inf, impossible values and unit slips
are refused with exit 2, naming the option, before anything is computed or written — whatever
the command does next. A numeric option missing from the table is still refused NaN and inf, and
``tests/fuzz/test_option_enumeration.py`` (which lists the options from the CLI application
itself) fails until it is added here: a new option cannot be forgotten.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from skisnow._errors import InputError

__all__ = [
    "COMMAND_OPTION_QUANTITIES",
    "LIST_OPTIONS",
    "OPTION_QUANTITIES",
    "install_gate",
    "numeric_kind",
    "quantity_of",
]

#: Option name -> quantity key of :data:`skisnow._quantities.QUANTITIES` (field units).
OPTION_QUANTITIES: dict[str, str] = {
    "--mass-kg": "mass",
    "--body-mass-kg": "mass",
    "--load-position-mm": "load_position",
    "--snow-modulus-mpa": "snow_modulus",
    "--snow-range-mpa": "snow_modulus",
    "--day-snow-mpa": "snow_modulus",
    "--base-modulus-mpa": "base_modulus",
    "--width-mm": "width",
    "--points": "grid_points",
    "--n-across": "cells_across",
    "--workers": "workers",
    "--stations": "display_stations",
    "--frames": "frames",
    "--cycle-s": "cycle_time",
    "--animation-speed": "animation_speed",
    "--dx-mm": "step_along_ski",
    "--step-mm": "step_along_ski",
    "--noise-mm": "noise",
    "--noise-um": "noise_um",
    "--seed": "seed",
    "--samples": "posterior_samples",
    "--x-tail-mm": "x",
    "--x-tip-mm": "x",
    "--stations-mm": "x",
    "--regularisation": "regularisation",
    "--n-stiffness": "spline_coefficients",
    "--n-camber": "spline_coefficients",
    "--max-nfev": "evaluations",
    "--mesh-mm": "beam_element_length",
    "--bootstrap": "bootstrap_replicates",
    "--bootstrap-workers": "workers",
    "--target-ei-percent": "percent",
    "--target-z0-um": "noise_um",
    "--temperature-c": "temperature",
    "--snow-temperature-c": "temperature",
    "--shear-strength-mpa": "shear_strength",
    "--viscosity-mpa-s": "viscosity",
    "--sliding-speed-m-s": "sliding_speed",
    "--film-cutoff-nm": "film_cutoff",
    "--pressure-kpa": "pressure",
    "--grain-um": "grain",
    "--cutoff-um": "cutoff",
    "--pixel-um": "pixel",
    "--size-um": "map_size",
    "--alpha": "alpha",
    "--adam-steps": "optimizer_steps",
    "--lm-steps": "optimizer_steps",
    "--ensemble": "ensemble_members",
    "--widths": "layer_width",
    "--generations": "population",
    "--popsize": "population",
    "--hinge-weight": "weight",
    "--topology-weight": "weight",
    "--ei-shape-weight": "weight",
    "--max-minutes": "minutes",
    "--front-pressure-growth-min": "ratio",
    "--k-range": "ski_stiffness",
    "--sigma": "fraction",
    "--kick-gap-max": "camber_height",
}
#: (command, option) -> quantity, where an option name means another quantity in one command.
COMMAND_OPTION_QUANTITIES: dict[tuple[str, str], str] = {
    ("bearing", "--stride"): "pixel_stride",
}
#: Options that hold a comma-separated list of whole numbers (not a grid).
LIST_OPTIONS: frozenset[str] = frozenset({"--widths", "--stations-mm"})

_UNIT_SUFFIX = re.compile(r"-(kg|mm|um|mpa|kpa|c|s|percent|min|n)$")


def numeric_kind(param: Any) -> str | None:
    """``'number'``, ``'grid'`` or ``'list'`` for a numeric option of a Typer/Click command,
    ``None`` for any other parameter. A number: an ``int``/``float`` annotation (optional or a
    tuple of them); a grid or list: a text option named with a unit suffix (``--mass-kg``) or
    listed in :data:`LIST_OPTIONS`."""
    if not getattr(param, "opts", None) or not param.opts[0].startswith("--"):
        return None
    name = param.opts[0]
    annotation = str(getattr(getattr(param, "type_descriptor", None), "annotation", ""))
    if getattr(param, "is_flag", False) or "bool" in annotation:
        return None
    if name in LIST_OPTIONS:
        return "list"
    if "int" in annotation or "float" in annotation:
        return "number"
    if "str" in annotation and _UNIT_SUFFIX.search(name) and "list[" not in annotation:
        return "grid"
    return None


def quantity_of(command: str, option: str) -> str | None:
    """The quantity key of ``option`` in ``command`` (``None``: not in the table)."""
    return COMMAND_OPTION_QUANTITIES.get((command, option), OPTION_QUANTITIES.get(option))


def _check(command: str, option: str, kind: str, value: Any) -> None:
    from skisnow._checks import check_option_values, check_value
    from skisnow._quantities import QUANTITIES
    from skisnow._values import parse_values

    key = quantity_of(command, option)
    if value is None or (key is None and kind != "number"):
        return
    values = value if isinstance(value, tuple | list) else (value,)
    if key is None:  # not in the table: at least a finite number
        for v in values:
            if isinstance(v, float) and not math.isfinite(v):
                raise InputError(f"{option}: {v} is not a finite number")
        return
    q = QUANTITIES[key]
    if kind == "number":
        for v in values:
            check_value(v, q, where=option)
        return
    parsed = [] if not str(value).strip() and kind == "list" else None
    if parsed is None:
        if kind == "list":
            try:
                parsed = [float(p) for p in str(value).split(",")]
            except ValueError:
                need = f"a comma-separated list of numbers ({q.describe_possible()})"
                raise InputError(f"{option}: cannot read {value!r}; need {need}") from None
        else:
            parsed = parse_values(str(value), name=option).tolist()
    for v in parsed:
        check_value(v, q, where=option)
    if kind == "grid":
        import numpy as np

        check_option_values(np.asarray(parsed, dtype=float), q, option)


def _callback(command: str, option: str, kind: str, previous: Callable | None) -> Callable:
    def gate(ctx: Any, param: Any, value: Any) -> Any:
        if previous is not None:
            value = previous(ctx, param, value)
        _check(command, option, kind, value)
        return value

    return gate


def install_gate(group: Any) -> Any:
    """Attach the option gate to every numeric parameter of every command of ``group`` (the
    Click group Typer builds from :data:`skisnow.cli.app`); returns ``group``."""
    for name, command in group.commands.items():
        for param in command.params:
            kind = numeric_kind(param)
            if kind is not None:
                param.callback = _callback(name, param.opts[0], kind, param.callback)
    return group
