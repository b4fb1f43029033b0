"""Rendering helpers for the CLI: Rich tables, and the one-JSON-document rule for ``--json``."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from rich.console import Console
from rich.table import Table

#: Human output goes to stdout through this console; progress bars go to stderr.
console = Console()
err_console = Console(stderr=True)


def _jsonable(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None  # JSON has no NaN/inf; null means "not defined"
    return value


def emit_json(document: Mapping[str, Any] | Sequence[Any]) -> None:
    """Print exactly one JSON document to stdout and nothing else (NaN/inf become null)."""
    print(json.dumps(_jsonable(document), indent=2, allow_nan=False))


def format_number(value: float, *, digits: int = 4) -> str:
    """Format a float for a table: ``digits`` significant digits, plain notation from 1e-3 to 1e6.

    Plain numbers read better than ``2e+03`` in a table of millimetres; trailing zeros are dropped.
    """
    v = float(value)
    if v == 0.0:
        return "0"
    mag = abs(v)
    if 1e-3 <= mag < 1e6:
        decimals = max(0, digits - 1 - math.floor(math.log10(mag)))
        text = f"{v:.{decimals}f}"
        return text.rstrip("0").rstrip(".") if "." in text else text
    return f"{v:.{digits - 1}e}"


def print_table(
    title: str,
    columns: Sequence[str],
    rows: Sequence[Sequence[Any]],
    *,
    floatfmt: str | None = None,
) -> None:
    """Print a Rich table: floats via :func:`format_number` or ``floatfmt``, None as a dash."""
    table = Table(title=title)
    for col in columns:
        table.add_column(col, justify="right" if col != columns[0] else "left")
    for row in rows:
        cells = []
        for v in row:
            if v is None or (isinstance(v, float) and not math.isfinite(v)):
                cells.append("—")
            elif isinstance(v, (float, np.floating)):
                cells.append(format(float(v), floatfmt) if floatfmt else format_number(float(v)))
            else:
                cells.append(str(v))
        table.add_row(*cells)
    console.print(table)
