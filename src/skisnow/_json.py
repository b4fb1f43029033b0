"""JSON read with limits: a depth limit (no ``RecursionError`` from a nested bomb), a size limit,
duplicate keys refused, and messages that name the file, the line and the column.

Every JSON document skisnow reads from a file (ski files, model metadata, topography side-cars,
bench metadata, sweep specs) goes through :func:`load_json`. Python's :mod:`json` recurses once
per level of nesting, so ``[[[[...]]]]`` 100 000 levels deep ends in ``RecursionError``; the
depth is therefore measured first, by a regular expression that skips strings (linear time, no
recursion), and a document nested deeper than any skisnow file is refused.
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

from skisnow._errors import FileFormatError, InputError

__all__ = ["MAX_JSON_BYTES", "MAX_JSON_DEPTH", "json_depth", "load_json", "read_json_file"]

#: The deepest nesting of a skisnow JSON document (a ski file needs 3 levels, a model file 4).
MAX_JSON_DEPTH = 64
#: The largest JSON file skisnow reads (a ski file of 100 000 stations is about 3 MB).
MAX_JSON_BYTES = 256 << 20

_TOKENS = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]', re.DOTALL)


def json_depth(text: str, limit: int = MAX_JSON_DEPTH) -> tuple[int, int]:
    """The nesting depth of a JSON text (strings skipped), and the offset where it first passes
    ``limit`` (``-1`` if it never does). Linear time; malformed text is left to the parser."""
    depth = deepest = 0
    for m in _TOKENS.finditer(text):
        c = m.group()[0]
        if c in "[{":
            depth += 1
            if depth > deepest:
                deepest = depth
                if depth > limit:
                    return depth, m.start()
        elif c in "]}":
            depth -= 1
    return deepest, -1


def _line_col(text: str, offset: int) -> tuple[int, int]:
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _unique_keys(where: str, error: type[InputError]) -> Callable[[list[tuple[str, Any]]], dict]:
    def hook(pairs: list[tuple[str, Any]]) -> dict:
        out: dict[str, Any] = {}
        for key, value in pairs:
            if key in out:
                raise error(
                    f"{where}: the key {key!r} is given twice in one object; give each key once "
                    "(which of the two values was meant?)"
                )
            out[key] = value
        return out

    return hook


def load_json(
    text: str,
    *,
    where: str,
    max_depth: int = MAX_JSON_DEPTH,
    error: type[InputError] = FileFormatError,
    unique_keys: bool = True,
    **kwargs: Any,
) -> Any:
    """Parse JSON ``text`` with a depth limit; ``where`` names the file in messages.

    ``kwargs`` go to :func:`json.loads` (``parse_float``, ``parse_constant``). Raises ``error``
    (default :class:`FileFormatError`) for invalid JSON (line and column named), nesting deeper
    than ``max_depth``, or a key given twice in one object (``unique_keys``).
    """
    _, at = json_depth(text, max_depth)
    if at >= 0:
        line, col = _line_col(text, at)
        raise error(
            f"{where}: JSON nested deeper than {max_depth} levels (line {line}, column {col}); a "
            "skisnow file needs only a few levels (is this the right file?)"
        )
    if unique_keys:
        kwargs.setdefault("object_pairs_hook", _unique_keys(where, error))
    try:
        return json.loads(text, **kwargs)
    except json.JSONDecodeError as exc:
        raise error(
            f"{where}: not valid JSON at line {exc.lineno}, column {exc.colno}: {exc.msg}"
        ) from None
    except InputError:
        raise
    except (ValueError, ArithmeticError, RecursionError) as exc:  # from parse_* hooks
        raise error(f"{where}: {exc}") from None


def read_json_file(
    path: str | os.PathLike[str],
    *,
    what: str = "JSON file",
    max_bytes: int = MAX_JSON_BYTES,
    **kwargs: Any,
) -> Any:
    """Read and parse a JSON file with :func:`load_json` after checking its size; ``what``
    names the kind of file in messages (``"ski file"``)."""
    p = Path(path)
    where = f"{what} {p}"
    try:
        size = p.stat().st_size
        if size > max_bytes:
            raise FileFormatError(
                f"{where}: {size / 2**20:.1f} MiB, more than the {max_bytes / 2**20:.0f} MiB a "
                f"{what} can be; is this the right file?"
            )
        text = p.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise FileFormatError(f"{where}: not UTF-8 text (a {what} is JSON)") from None
    except OSError as exc:
        raise FileFormatError(f"{where}: cannot be read ({exc.strerror})") from None
    return load_json(text, where=where, **kwargs)
