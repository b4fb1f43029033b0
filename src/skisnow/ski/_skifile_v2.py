"""The optional fields of version 2 of the ski file: an identified ski's uncertainty.

``stiffness.determined`` / ``camber.determined``: one true/false per station, false where the
bench the ski was identified from does *not determine* EI / z0 (no load case bends the ski
there, no station measures it; the band there is the prior's width). ``stiffness.modes`` (log
EI) and ``camber.modes_mm`` (z0 [mm]): k rows of one value per station, the square root of the
joint Laplace posterior (a sample adds Σ ξ_i row_i, ξ_i ~ N(0, 1);
:func:`~skisnow.ski.sample_skis`). A ski without them is written as version 1
(:mod:`skisnow.ski._skifile`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from skisnow.ski._skis import Ski

__all__ = ["read_uncertainty", "write_uncertainty"]


def write_uncertainty(
    ski: Ski, stiffness: dict[str, Any], camber: dict[str, Any], mm: Callable[[Any], Any]
) -> bool:
    """Add the version-2 fields of ``ski`` to its ``stiffness`` and ``camber`` sections
    (``mm`` the exact-millimetre marker); whether there were any (the file is then version 2)."""
    if all(
        getattr(ski, k) is None
        for k in ("stiffness_determined", "camber_determined", "stiffness_modes")
    ):
        return False

    def flags(values: tuple[bool, ...] | None) -> list[bool] | None:
        return None if values is None else [bool(v) for v in values]

    stiffness["determined"] = flags(ski.stiffness_determined)
    camber["determined"] = flags(ski.camber_determined)
    stiffness["modes"] = (
        None if ski.stiffness_modes is None else [list(row) for row in ski.stiffness_modes]
    )
    camber["modes_mm"] = None if ski.camber_modes is None else [mm(r) for r in ski.camber_modes]
    return True


def _flags(r: Any, value: Any, field: str, n: int) -> tuple[bool, ...] | None:
    if value is None:
        return None
    if not isinstance(value, list) or len(value) != n:
        raise r.fail(field, f"must be a list of {n} true/false (one per station) or null")
    for i, v in enumerate(value):
        if not isinstance(v, bool):
            raise r.fail(f"{field}[{i}]", f"must be true or false, got {v!r}")
    return tuple(value)


def _rows(r: Any, value: Any, field: str, n: int, *, mm: bool) -> Any:
    if value is None:
        return None
    if not isinstance(value, list) or not value:
        raise r.fail(field, f"must be a list of rows of {n} numbers or null")
    out = []
    for k, row in enumerate(value):
        vals = r.numbers(row, f"{field}[{k}]", mm=mm, min_len=n)
        if len(vals) != n:
            raise r.fail(f"{field}[{k}]", f"needs {n} values (one per station)")
        out.append(vals)
    return tuple(out)


def read_uncertainty(
    r: Any, st: Mapping[str, Any], cb: Mapping[str, Any], n_e: int, n_z: int
) -> tuple[Any, Any, Any, Any]:
    """``(stiffness_determined, camber_determined, stiffness_modes, camber_modes)`` of the
    ``stiffness`` and ``camber`` sections, validated by the reader ``r`` (errors name the
    field); ``None`` where absent."""
    det_e = _flags(r, st.get("determined"), "stiffness.determined", n_e)
    det_z = _flags(r, cb.get("determined"), "camber.determined", n_z)
    modes_e = _rows(r, st.get("modes"), "stiffness.modes", n_e, mm=False)
    modes_z = _rows(r, cb.get("modes_mm"), "camber.modes_mm", n_z, mm=True)
    if (modes_e is None) != (modes_z is None) or (
        modes_e is not None and modes_z is not None and len(modes_e) != len(modes_z)
    ):
        raise r.fail("stiffness.modes", "needs as many rows as camber.modes_mm (or both null)")
    return det_e, det_z, modes_e, modes_z
