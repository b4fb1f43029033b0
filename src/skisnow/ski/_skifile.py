"""Ski files: a :class:`~skisnow.ski.Ski` as a versioned, validated JSON document.

Format ``skisnow-ski``, versions 1 and 2 (version 2 adds the optional fields of an identified
ski's uncertainty, below; a ski without them is written as version 1, so every file of version
1, the shipped skis among them, reads and writes unchanged). One JSON object; lengths in
millimetres, stiffness in N m², the unit in every key; x is measured from the balance point
(x_mm = 0), positive toward the tip::

    {
      "format": "skisnow-ski",
      "format_version": 1,
      "name": "classic",                     # any non-empty text
      "kind": "classic",                     # "classic" (kick zone) or "skate"
      "x_tail_mm": -980.0,                   # running surface: tail end (< 0) ...
      "x_tip_mm": 1020.0,                    # ... and tip end (> 0); length = x_tip - x_tail
      "width_mm": 44.0,                      # base width used by the contact models
      "width_profile": null,                 # or {"x_mm": [...], "width_mm": [...]}
      "kick_zone_mm": [-265.0, 255.0],       # classic: [start, end]; skate: null
      "boot_plate_mm": [-300.0, 0.0],        # binding / boot plate [start, end] or null
      "stiffness": {"x_mm": [...], "ei_nm2": [...], "log_ei_sd": null},
      "camber": {"x_mm": [...], "z0_mm": [...], "z0_sd_mm": null},
      "description": "free text",
      "provenance": {"method": "...", "data": "...", "sources": ["..."],
                     "created_utc": "...", "software": "...", "details": {"key": value}}
    }

* ``stiffness``: EI(x) [N m²] at stations x_mm (strictly increasing, covering the running
  surface), interpolated by PCHIP in log EI; ``log_ei_sd`` (optional) the standard deviation
  of log EI at the stations (an identified ski's uncertainty).
* ``camber``: the free camber z0(x) [mm] (the unloaded base above the plane it rests on),
  interpolated by PCHIP; ``z0_sd_mm`` its optional standard deviation.
* ``provenance.details``: scalar values only (numbers, text, true/false, null).
* Version 2 (optional, an identified ski): ``stiffness.determined`` / ``camber.determined``, one
  true/false per station: false where the bench the ski was identified from does *not
  determine* EI / z0 (no load case bends the ski there, no station measures it; the band there
  is the prior's width); ``stiffness.modes`` (log EI) and ``camber.modes_mm`` (z0 [mm]): k rows
  of one value per station, the square root of the joint posterior (a sample of the ski adds
  Σ ξ_i row_i with ξ_i ~ N(0, 1); :func:`~skisnow.ski.sample_skis`).

Exact round trip. A length in metres is written as the shortest decimal that reads back to the
same double (``repr``) with its decimal point moved by three places, and read back by moving the
point back in decimal arithmetic before rounding once to a double, so ``Ski -> file -> Ski``
returns bit-identical numbers (a plain ``x * 1000`` / ``x / 1000`` misses about 2 % of doubles by
one ulp). EI values are written as they are.

Validation is written out here rather than with a JSON-Schema library (not a dependency of
skisnow): each message names the file, the field (``stiffness.ei_nm2[3]``) and what would be
valid, in the file's units.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from decimal import Decimal
from pathlib import Path
from typing import Any

import numpy as np

from skisnow._atomic import atomic_write
from skisnow._checks import check_array, check_value
from skisnow._errors import FileFormatError, InputError
from skisnow._json import load_json, read_json_file
from skisnow.ski._skifile_v2 import read_uncertainty, write_uncertainty
from skisnow.ski._skis import Provenance, Ski

__all__ = [
    "SKI_FILE_FORMAT",
    "SKI_FILE_VERSION",
    "read_ski",
    "ski_from_document",
    "ski_from_json",
    "ski_to_document",
    "ski_to_json",
    "write_ski",
]

#: The value of the ``format`` key of a ski file.
SKI_FILE_FORMAT = "skisnow-ski"
#: The newest version of the format, read and written (a ski without the fields of version 2
#: is written as version 1).
SKI_FILE_VERSION = 2

_KEYS = (
    "format",
    "format_version",
    "name",
    "kind",
    "x_tail_mm",
    "x_tip_mm",
    "width_mm",
    "width_profile",
    "kick_zone_mm",
    "boot_plate_mm",
    "stiffness",
    "camber",
    "description",
    "provenance",
)
_REQUIRED = ("format", "format_version", "name", "kind", "x_tail_mm", "x_tip_mm", "width_mm")
_PROVENANCE_KEYS = ("method", "data", "sources", "created_utc", "software", "details")


class _Mm:
    """A length [m] to be written in millimetres with an exact decimal shift."""

    __slots__ = ("metres",)

    def __init__(self, metres: float) -> None:
        self.metres = float(metres)

    def text(self) -> str:
        d = Decimal(repr(self.metres)).scaleb(3).normalize()
        if d == 0:
            return "0.0"
        text = format(d, "f") if -7 <= d.adjusted() <= 15 else str(d)
        return text if any(c in text for c in ".eE") else text + ".0"


def _mm(values: Any) -> Any:
    if values is None:
        return None
    if isinstance(values, tuple | list):
        return [_Mm(v) for v in values]
    return _Mm(values)


def ski_to_document(ski: Ski) -> dict[str, Any]:
    """The ski-file document of ``ski`` as plain Python values (what ``json.load`` of its file
    gives): for code that inspects the fields. :func:`ski_to_json` gives the exact text."""
    return json.loads(ski_to_json(ski))


def _document(ski: Ski) -> dict[str, Any]:
    """The document with lengths as exact-millimetre markers (see the module docstring)."""
    prov = ski.provenance
    width_profile = None
    if ski.width_x is not None:
        width_profile = {"x_mm": _mm(ski.width_x), "width_mm": _mm(ski.width_values)}
    stiffness: dict[str, Any] = {
        "x_mm": _mm(ski.stiffness_x),
        "ei_nm2": list(ski.stiffness_values),
        "log_ei_sd": None if ski.stiffness_log_sd is None else list(ski.stiffness_log_sd),
    }
    camber: dict[str, Any] = {
        "x_mm": _mm(ski.camber_x),
        "z0_mm": _mm(ski.camber_values),
        "z0_sd_mm": _mm(ski.camber_sd),
    }
    v2 = write_uncertainty(ski, stiffness, camber, _mm)
    return {
        "format": SKI_FILE_FORMAT,
        "format_version": 2 if v2 else 1,
        "name": ski.name,
        "kind": ski.kind,
        "x_tail_mm": _mm(ski.x_tail),
        "x_tip_mm": _mm(ski.x_tip),
        "width_mm": _mm(ski.width),
        "width_profile": width_profile,
        "kick_zone_mm": _mm(ski.kick_zone),
        "boot_plate_mm": _mm(ski.boot_plate),
        "stiffness": stiffness,
        "camber": camber,
        "description": ski.description,
        "provenance": {
            "method": prov.method,
            "data": prov.data,
            "sources": list(prov.sources),
            "created_utc": prov.created,
            "software": prov.software,
            "details": dict(prov.details),
        },
    }


def _encode(obj: Any, indent: int = 0) -> str:
    """JSON text: objects indented, lists of numbers on one line, exact millimetres."""
    pad = "  " * (indent + 1)
    if isinstance(obj, dict):
        if not obj:
            return "{}"
        items = [f"{pad}{json.dumps(k)}: {_encode(v, indent + 1)}" for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + "  " * indent + "}"
    if isinstance(obj, list):
        if all(isinstance(v, bool) for v in obj) and obj:
            return "[" + ", ".join("true" if v else "false" for v in obj) + "]"
        if all(isinstance(v, _Mm | int | float) for v in obj):
            return "[" + ", ".join(_encode(v) for v in obj) + "]"
        inner = ",\n".join(pad + _encode(v, indent + 1) for v in obj)
        return "[\n" + inner + "\n" + "  " * indent + "]"
    if isinstance(obj, _Mm):
        return obj.text()
    if isinstance(obj, float):
        if not math.isfinite(obj):
            raise InputError(f"a ski file holds finite numbers only, got {obj}")
        return repr(float(obj))  # a NumPy float's repr is not JSON
    return json.dumps(obj, ensure_ascii=False)


def ski_to_json(ski: Ski) -> str:
    """The text of the ski file of ``ski`` (UTF-8 JSON, ends with a newline)."""
    return _encode(_document(ski)) + "\n"


def write_ski(ski: Ski, path: str | os.PathLike[str]) -> Path:
    """Write ``ski`` to the ski file ``path`` (``.json``), atomically (a crash never leaves half
    a file; the parent directory is created). Returns the path."""
    if not isinstance(ski, Ski):
        raise InputError(f"write_ski needs a Ski, got {type(ski).__name__}")
    path = Path(path)
    if path.suffix.lower() != ".json":
        raise InputError(f"ski file {str(path)!r}: use a .json file name")
    return atomic_write(path, ski_to_json(ski))


# --------------------------------------------------------------------------- reading


class _Reader:
    """Field-by-field validation of a ski document, with messages naming the field."""

    def __init__(self, where: str) -> None:
        self.where = where

    def fail(self, field: str, message: str) -> FileFormatError:
        return FileFormatError(f"ski file {self.where}: {field}: {message}")

    def plausible(
        self, values: Any, quantity: str, field: str, *, scale: float = 1e3, span: bool = False
    ) -> None:
        """The plausibility ranges of :mod:`skisnow._checks` on a field (read in SI, checked in
        the file's unit: ``scale`` 1e3 for millimetres; ``span``: also the column's spread)."""
        where = f"ski file {self.where}: {field}"
        if np.ndim(values) == 0:
            check_value(float(values) * scale, quantity, where=where)
            return
        check_array(np.asarray(values, dtype=float) * scale, quantity, where=where,
                    check_span=span, row_label=lambda i: f"[{i}]",
                    impossible=FileFormatError)  # fmt: skip

    def number(self, value: Any, field: str, *, mm: bool) -> float:
        if isinstance(value, bool) or not isinstance(value, Decimal | int):
            raise self.fail(field, f"must be a number, got {value!r}")
        d = Decimal(value)
        out = float(d.scaleb(-3)) if mm else float(d) if d.is_finite() else math.inf
        if not math.isfinite(out):
            raise self.fail(field, f"must be a finite number, got {value}")
        return out

    def numbers(self, value: Any, field: str, *, mm: bool, min_len: int = 1) -> tuple[float, ...]:
        if not isinstance(value, list) or len(value) < min_len:
            got = repr(value)[:80]
            raise self.fail(field, f"must be a list of at least {min_len} numbers, got {got}")
        return tuple(self.number(v, f"{field}[{i}]", mm=mm) for i, v in enumerate(value))

    def text(self, value: Any, field: str, *, empty: bool = True) -> str:
        if not isinstance(value, str) or (not empty and not value.strip()):
            what = "text" if empty else "non-empty text"
            raise self.fail(field, f"must be {what}, got {value!r}")
        return value

    def mapping(self, value: Any, field: str, keys: tuple[str, ...]) -> Mapping[str, Any]:
        if not isinstance(value, dict):
            got = repr(value)[:80]
            raise self.fail(field, f"must be an object with keys {', '.join(keys)}, got {got}")
        unknown = [k for k in value if k not in keys]
        if unknown:
            raise self.fail(
                f"{field}.{unknown[0]}", f"unknown key; valid keys are {', '.join(keys)}"
            )
        return value

    def pair(self, value: Any, field: str) -> tuple[float, float] | None:
        if value is None:
            return None
        if not isinstance(value, list) or len(value) != 2:
            raise self.fail(field, f"must be [start, end] in mm or null, got {value!r}")
        a, b = self.numbers(value, field, mm=True, min_len=2)
        if not a < b:
            raise self.fail(field, f"start must be < end, got [{a * 1e3:g}, {b * 1e3:g}] mm")
        return a, b

    def stations(
        self, section: Mapping[str, Any], field: str, key: str, *, mm: bool
    ) -> tuple[tuple[float, ...], tuple[float, ...]]:
        if "x_mm" not in section or key not in section:
            raise self.fail(field, f"needs the lists x_mm and {key}")
        x = self.numbers(section["x_mm"], f"{field}.x_mm", mm=True, min_len=2)
        v = self.numbers(section[key], f"{field}.{key}", mm=mm, min_len=2)
        if len(v) != len(x):
            raise self.fail(
                f"{field}.{key}", f"needs one value per station ({len(x)}), got {len(v)}"
            )
        for i in range(1, len(x)):
            if not x[i] > x[i - 1]:
                raise self.fail(
                    f"{field}.x_mm[{i}]",
                    f"stations must strictly increase: {x[i] * 1e3:g} mm after "
                    f"{x[i - 1] * 1e3:g} mm",
                )
        return x, v


def ski_from_document(doc: Any, *, where: str = "<document>") -> Ski:
    """Validate a parsed ski document (numbers as :class:`decimal.Decimal` or int) and build the
    :class:`Ski`. ``where`` names the file in error messages.

    Raises:
        FileFormatError: a missing, unknown or invalid field; the message names the field and
            what would be valid.
    """
    r = _Reader(where)
    if not isinstance(doc, dict):
        raise r.fail("document", "must be a JSON object")
    if doc.get("format") != SKI_FILE_FORMAT:
        raise r.fail("format", f"must be {SKI_FILE_FORMAT!r}, got {doc.get('format')!r}")
    version = doc.get("format_version")
    valid_version = isinstance(version, int) and not isinstance(version, bool)
    if not (valid_version and 1 <= version <= SKI_FILE_VERSION):
        raise r.fail(
            "format_version", f"this skisnow reads versions 1..{SKI_FILE_VERSION}, got {version!r}"
        )
    unknown = [k for k in doc if k not in _KEYS]
    if unknown:
        raise r.fail(unknown[0], f"unknown key; valid keys are {', '.join(_KEYS)}")
    for key in _REQUIRED:
        if key not in doc:
            raise r.fail(key, "missing (required)")
    for key in ("stiffness", "camber"):
        if key not in doc:
            raise r.fail(key, "missing (required)")
    name = r.text(doc["name"], "name", empty=False)
    kind = doc["kind"]
    if kind not in ("classic", "skate"):
        raise r.fail("kind", f"must be 'classic' or 'skate', got {kind!r}")
    x_tail = r.number(doc["x_tail_mm"], "x_tail_mm", mm=True)
    x_tip = r.number(doc["x_tip_mm"], "x_tip_mm", mm=True)
    if not x_tail < 0:
        raise r.fail("x_tail_mm", f"must be < 0 (behind the balance point), got {x_tail * 1e3:g}")
    if not x_tip > 0:
        raise r.fail("x_tip_mm", f"must be > 0 (before the balance point), got {x_tip * 1e3:g}")
    width = r.number(doc["width_mm"], "width_mm", mm=True)
    if not width > 0:
        raise r.fail("width_mm", f"must be > 0 mm, got {width * 1e3:g}")
    r.plausible([x_tail, x_tip], "x", "x_tail_mm, x_tip_mm")
    check_value((x_tip - x_tail) * 1e3, "ski_length", where=f"ski file {where}: x_tip_mm - "
                "x_tail_mm (the length of the running surface)")  # fmt: skip
    r.plausible(width, "width", "width_mm")

    v2_keys = version >= 2
    st = r.mapping(
        doc["stiffness"], "stiffness",
        ("x_mm", "ei_nm2", "log_ei_sd") + (("determined", "modes") if v2_keys else ()),
    )  # fmt: skip
    ex, ei = r.stations(st, "stiffness", "ei_nm2", mm=False)
    for i, v in enumerate(ei):
        if not v > 0:
            raise r.fail(f"stiffness.ei_nm2[{i}]", f"EI must be > 0 N m², got {v:g}")
    r.plausible(ei, "bending_stiffness", "stiffness.ei_nm2", scale=1.0)
    log_sd = None
    if st.get("log_ei_sd") is not None:
        log_sd = r.numbers(st["log_ei_sd"], "stiffness.log_ei_sd", mm=False)
        if len(log_sd) != len(ex) or min(log_sd) < 0:
            raise r.fail("stiffness.log_ei_sd", f"needs {len(ex)} values >= 0 (one per station)")
        r.plausible(log_sd, "log_ei_sd", "stiffness.log_ei_sd", scale=1.0)
    cb = r.mapping(
        doc["camber"], "camber",
        ("x_mm", "z0_mm", "z0_sd_mm") + (("determined", "modes_mm") if v2_keys else ()),
    )  # fmt: skip
    cx, z0 = r.stations(cb, "camber", "z0_mm", mm=True)
    r.plausible(z0, "camber_height", "camber.z0_mm", span=True)  # span: heights in m?
    z_sd = None
    if cb.get("z0_sd_mm") is not None:
        z_sd = r.numbers(cb["z0_sd_mm"], "camber.z0_sd_mm", mm=True)
        if len(z_sd) != len(cx) or min(z_sd) < 0:
            raise r.fail("camber.z0_sd_mm", f"needs {len(cx)} values >= 0 (one per station)")
        r.plausible(z_sd, "camber_sd", "camber.z0_sd_mm")
    r.plausible([ex[0], ex[-1], cx[0], cx[-1]], "x", "stiffness.x_mm, camber.x_mm (ends)")
    det_e, det_z, modes_e, modes_z = read_uncertainty(r, st, cb, len(ex), len(cx))
    for field, xs in (("stiffness.x_mm", ex), ("camber.x_mm", cx)):
        if xs[0] > x_tail or xs[-1] < x_tip:
            raise r.fail(
                field,
                f"stations must cover the running surface [{x_tail * 1e3:g}, {x_tip * 1e3:g}] "
                f"mm (x_tail_mm, x_tip_mm), cover [{xs[0] * 1e3:g}, {xs[-1] * 1e3:g}] mm",
            )

    width_x = width_values = None
    if doc.get("width_profile") is not None:
        wp = r.mapping(doc["width_profile"], "width_profile", ("x_mm", "width_mm"))
        width_x, width_values = r.stations(wp, "width_profile", "width_mm", mm=True)
        for i, v in enumerate(width_values):
            if not v > 0:
                raise r.fail(f"width_profile.width_mm[{i}]", f"must be > 0 mm, got {v * 1e3:g}")
        r.plausible(width_values, "width", "width_profile.width_mm")
    kick = r.pair(doc.get("kick_zone_mm"), "kick_zone_mm")
    boot = r.pair(doc.get("boot_plate_mm"), "boot_plate_mm")
    for field, span in (("kick_zone_mm", kick), ("boot_plate_mm", boot)):
        if span is not None and not (x_tail <= span[0] and span[1] <= x_tip):
            raise r.fail(
                field,
                f"must lie on the ski, within [{x_tail * 1e3:g}, {x_tip * 1e3:g}] mm, got "
                f"[{span[0] * 1e3:g}, {span[1] * 1e3:g}]",
            )
        if span is not None:
            r.plausible(span[1] - span[0], "zone_length", f"{field} (end - start)")
    description = r.text(doc.get("description", ""), "description")

    pv = r.mapping(doc.get("provenance", {}), "provenance", _PROVENANCE_KEYS)
    sources = pv.get("sources", [])
    if not isinstance(sources, list):
        raise r.fail("provenance.sources", "must be a list of text")
    details_raw = pv.get("details", {})
    if not isinstance(details_raw, dict):
        raise r.fail("provenance.details", "must be an object of scalar values")
    details = []
    for k, v in details_raw.items():
        if isinstance(v, Decimal):
            v = float(v)
        if not (v is None or isinstance(v, str | int | float | bool)):
            raise r.fail(
                f"provenance.details.{k}",
                f"must be a number, text, true/false or null, got {repr(v)[:60]}",
            )
        details.append((k, v))
    provenance = Provenance(
        method=r.text(pv.get("method", ""), "provenance.method"),
        data=r.text(pv.get("data", ""), "provenance.data"),
        sources=tuple(r.text(s, f"provenance.sources[{i}]") for i, s in enumerate(sources)),
        created=r.text(pv.get("created_utc", ""), "provenance.created_utc"),
        software=r.text(pv.get("software", ""), "provenance.software"),
        details=tuple(details),
    )
    try:
        return Ski(
            name=name,
            kind=kind,
            x_tail=x_tail,
            x_tip=x_tip,
            width=width,
            stiffness_x=ex,
            stiffness_values=ei,
            camber_x=cx,
            camber_values=z0,
            kick_zone=kick,
            boot_plate=boot,
            width_x=width_x,
            width_values=width_values,
            stiffness_log_sd=log_sd,
            camber_sd=z_sd,
            stiffness_determined=det_e,
            camber_determined=det_z,
            stiffness_modes=modes_e,
            camber_modes=modes_z,
            description=description,
            provenance=provenance,
        )
    except FileFormatError:
        raise
    except InputError as exc:  # a rule of Ski the checks above do not spell out
        raise FileFormatError(f"ski file {where}: {exc}") from None


def ski_from_json(text: str, *, where: str = "<text>") -> Ski:
    """The :class:`Ski` of a ski file's text (validated as :func:`read_ski` does)."""
    doc = load_json(text, where=f"ski file {where}", parse_float=Decimal,
                    parse_constant=_reject_constant)  # fmt: skip
    return ski_from_document(doc, where=where)


def read_ski(path: str | os.PathLike[str]) -> Ski:
    """Read and validate a ski file (format ``skisnow-ski``, see the module docstring).

    Raises:
        FileFormatError: unreadable, not JSON, or an invalid field (the message names the file,
            the field and what would be valid).
    """
    path = Path(path)
    doc = read_json_file(path, what="ski file", parse_float=Decimal,
                         parse_constant=_reject_constant)  # fmt: skip
    return ski_from_document(doc, where=str(path))


def _reject_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a valid number in a ski file (numbers must be finite)")
