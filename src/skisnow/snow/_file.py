"""Snow files (JSON, field units) and the one resolver of a snow given by name or file.

A snow file is a JSON object; every key is optional except what makes a modulus::

    {"format": "skisnow-snow", "name": "Holmenkollen 2024-02-03",
     "preset": "fine-grained",                  # start from a preset (optional)
     "modulus_mpa": 120,                        # or "density_kg_m3": 430 (+ "density_relation")
     "poisson": 0.3, "temperature_c": -6.5, "hardness_model": "poirier",
     "grain_diameters_um": [310, 350, 420],     # measured, or "grain_mode_um" (+ "grain_shape")
     "description": "..."}

Keys carry their field unit; a wrong key, type or value is reported with the file and key.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from skisnow._errors import FileFormatError, InputError
from skisnow.snow._presets import snow_preset
from skisnow.snow._snow import DENSITY_RELATIONS, Snow, gamma_grains, modulus_from_density

__all__ = [
    "SNOW_FILE_KEYS",
    "get_snow",
    "read_snow",
    "snow_from_record",
    "snow_record",
    "write_snow",
]

#: Keys a snow file may hold, with what they mean.
SNOW_FILE_KEYS: dict[str, str] = {
    "format": "'skisnow-snow' (optional)",
    "name": "a name for tables",
    "preset": "a preset to start from (new, fine-grained, coarse, machine-made, wet)",
    "modulus_mpa": "E_counter in MPa",
    "density_kg_m3": "density in kg/m³ (gives the modulus when modulus_mpa is absent)",
    "density_relation": f"one of {', '.join(DENSITY_RELATIONS)}",
    "poisson": "Poisson ratio",
    "temperature_c": "snow temperature in °C (<= 0)",
    "hardness_model": "poirier or makkonen",
    "grain_diameters_um": "measured grain diameters in µm (a list)",
    "grain_mode_um": "mode of the grain-size distribution in µm",
    "grain_shape": "exponent b of f(D) = a·D^b·e^(-cD) (default 24.9)",
    "description": "one line",
}


def _number(doc: dict, key: str, where: str) -> float | None:
    if key not in doc:
        return None
    v = doc[key]
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(float(v)):
        raise FileFormatError(f"{where}: key {key!r} must be a finite number, got {v!r}")
    return float(v)


def read_snow(path: str | Path) -> Snow:
    """Read a snow file (see the module docstring)."""
    path = Path(path)
    where = str(path)
    try:
        doc = json.loads(path.read_text(encoding="utf-8-sig"))
    except FileNotFoundError:
        raise FileFormatError(f"{where}: no such file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise FileFormatError(f"{where}: not a JSON snow file ({exc})") from None
    if not isinstance(doc, dict):
        raise FileFormatError(f"{where}: a snow file holds one JSON object")
    unknown = sorted(set(doc) - set(SNOW_FILE_KEYS))
    if unknown:
        raise FileFormatError(
            f"{where}: unknown key{'s' * (len(unknown) != 1)} {unknown}; valid: "
            f"{', '.join(SNOW_FILE_KEYS)}"
        )
    if doc.get("format", "skisnow-snow") != "skisnow-snow":
        raise FileFormatError(f"{where}: 'format' must be 'skisnow-snow', got {doc['format']!r}")
    try:
        return _from_doc(doc, where, default_name=path.stem)
    except FileFormatError:
        raise
    except InputError as exc:
        raise FileFormatError(f"{where}: {exc}") from None


def snow_from_record(doc: dict[str, Any], *, where: str = "(snow record)") -> Snow:
    """A :class:`Snow` from a snow-file document (:func:`snow_record`'s inverse)."""
    unknown = sorted(set(doc) - set(SNOW_FILE_KEYS))
    if unknown:
        raise FileFormatError(f"{where}: unknown key{'s' * (len(unknown) != 1)} {unknown}")
    return _from_doc(doc, where, default_name="snow")


def _from_doc(doc: dict[str, Any], where: str, *, default_name: str) -> Snow:
    from skisnow._checks import check_value

    base = snow_preset(str(doc["preset"])) if "preset" in doc else None
    changes: dict[str, Any] = {"name": str(doc.get("name", default_name))}
    e = _number(doc, "modulus_mpa", where)
    rho = _number(doc, "density_kg_m3", where)
    relation = str(doc.get("density_relation", "scapozza2004"))
    if e is not None:
        changes["modulus"] = check_value(e, "snow_modulus", where=f"{where}: modulus_mpa") * 1e6
        changes["modulus_source"] = f"given in {where}"
    elif rho is not None:
        changes["modulus"] = modulus_from_density(rho, relation=relation)
        changes["modulus_source"] = f"{DENSITY_RELATIONS[relation][2]} at {rho:g} kg/m³"
    elif base is None:
        raise FileFormatError(
            f"{where}: give 'modulus_mpa', 'density_kg_m3' or a 'preset' (the apparent contact "
            "needs the snow's modulus)"
        )
    if rho is not None:
        changes["density"] = rho
    for key, attr in (("poisson", "poisson"), ("temperature_c", "temperature_c")):
        v = _number(doc, key, where)
        if v is not None:
            if key == "temperature_c":
                check_value(v, "temperature", where=f"{where}: temperature_c")
            changes[attr] = v
    if "hardness_model" in doc:
        changes["hardness_model"] = str(doc["hardness_model"])
    if "grain_diameters_um" in doc:
        d = doc["grain_diameters_um"]
        if not isinstance(d, list) or not d:
            raise FileFormatError(f"{where}: 'grain_diameters_um' must be a non-empty list")
        values = []
        for i, v in enumerate(d):
            ok = isinstance(v, int | float) and not isinstance(v, bool)
            if not ok:
                raise FileFormatError(f"{where}: grain_diameters_um[{i}] = {v!r} is not a number")
            values.append(check_value(v, "grain", where=f"{where}: grain_diameters_um[{i}]") * 1e-6)
        changes["grain_diameters"] = tuple(values)
    mode = _number(doc, "grain_mode_um", where)
    if mode is not None:
        shape = _number(doc, "grain_shape", where) or 24.922
        changes["grains"] = gamma_grains(
            check_value(mode, "grain", where=f"{where}: grain_mode_um") * 1e-6, shape=shape
        )
        changes["grain_diameters"] = None
    if "description" in doc:
        changes["description"] = str(doc["description"])
    if base is not None:
        if "modulus" not in changes:
            changes["modulus_source"] = base.modulus_source
        changes.setdefault("sources", base.sources)
        return base.replace(**changes)
    return Snow(**changes)


def snow_record(snow: Snow) -> dict[str, Any]:
    """A snow in field units (the snow-file keys; JSON documents and tables)."""
    rec: dict[str, Any] = {
        "format": "skisnow-snow",
        "name": snow.name,
        "modulus_mpa": snow.modulus / 1e6,
        "poisson": snow.poisson,
        "temperature_c": snow.temperature_c,
        "hardness_model": snow.hardness_model,
    }
    if snow.density is not None:
        rec["density_kg_m3"] = snow.density
    if snow.grain_diameters is not None:
        rec["grain_diameters_um"] = [d * 1e6 for d in snow.grain_diameters]
    else:
        rec["grain_mode_um"] = snow.grains.mode * 1e6
        rec["grain_shape"] = snow.grains.b
    if snow.description:
        rec["description"] = snow.description
    return rec


def write_snow(snow: Snow, path: str | Path) -> Path:
    """Write ``snow`` as a snow file (atomic)."""
    from skisnow._atomic import atomic_write

    path = Path(path)
    atomic_write(path, json.dumps(snow_record(snow), indent=2, ensure_ascii=False) + "\n")
    return path


def get_snow(spec: Snow | str | Path) -> Snow:
    """A :class:`Snow` from itself, a preset name (``fine-grained``, ...) or a snow file."""
    if isinstance(spec, Snow):
        return spec
    text = str(spec)
    path = Path(text)
    if path.suffix.lower() == ".json" or path.is_file():
        return read_snow(path)
    return snow_preset(text)
