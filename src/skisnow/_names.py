"""Names are labels, never paths or markup: a text that came from a file (a ski's name, a file
name, a description) made safe for each place it reaches.

* :func:`file_stem`: a ski's name as part of an output file name: letters, digits, ``.``, ``-``
  and ``_`` only, no leading dot, bounded length; the output always stays inside its folder;
* :func:`printable`: for a terminal: control characters (``ESC`` of a colour sequence, a
  carriage return that overwrites a line, ``NUL``) and the bidirectional overrides that reorder
  what is shown are written as visible escapes (``\\x1b``, ``\\u202e``);
* :func:`html_text`: for HTML text and quoted attributes: :func:`printable`, then ``<``, ``>``,
  ``&`` and quotes as entities; :func:`printable_lines` for texts laid out on lines (a
  figure's titles) and markup a trusted writer made from such texts (Matplotlib's SVG): its
  control characters shown, its tabs and line breaks kept;
* :func:`script_json`: JSON to embed in an HTML ``<script>`` block: ``<``, ``>``, ``&`` and the
  JavaScript line separators as ``\\u`` escapes, so no text can close the block (``</script>``)
  or switch the HTML parser into another state (``<!--``).
"""

from __future__ import annotations

import html
import json
import re
import unicodedata
from typing import Any

__all__ = ["file_stem", "html_text", "printable", "printable_lines", "script_json"]

_NOT_SAFE = re.compile(r"[^A-Za-z0-9._-]+")
#: Characters a terminal acts on instead of showing: C0 and C1 controls, DEL, and the Unicode
#: bidirectional embeddings, overrides and isolates (Trojan-source reordering).
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069]")


def file_stem(name: str, *, fallback: str = "ski", max_length: int = 80) -> str:
    """``name`` as a file-name stem that cannot leave its folder or hide itself.

    Letters and digits are kept (accents folded: ``Fischer Speedmax 3D`` →
    ``Fischer_Speedmax_3D``); every run of other characters (``/``, ``\\``, spaces, quotes,
    control characters) becomes ``_``; leading dots and separators are dropped; at most
    ``max_length`` characters; ``fallback`` when nothing is left (``..``, an empty name).
    """
    text = unicodedata.normalize("NFKD", str(name)).encode("ascii", "ignore").decode("ascii")
    stem = _NOT_SAFE.sub("_", text).lstrip("._-")[:max_length].rstrip("._-")
    return stem or fallback


def _escape(m: re.Match[str]) -> str:
    c = m.group()
    return f"\\x{ord(c):02x}" if ord(c) < 0x100 else f"\\u{ord(c):04x}"


def printable(text: Any) -> str:
    """``text`` with every control and bidirectional-override character shown as an escape
    (``\\x1b``, ``\\x00``, ``\\u202e``): what a terminal shows is what the text holds."""
    return _CONTROL.sub(_escape, str(text))


def html_text(text: Any) -> str:
    """``text`` for HTML element content or a quoted attribute: control and bidirectional
    characters shown as escapes (:func:`printable`: no raw ``NUL`` or ``ESC``, no reordered
    text), then ``<``, ``>``, ``&``, ``"`` and ``'`` as character references."""
    return html.escape(printable(text))


#: :data:`_CONTROL` less the whitespace markup is laid out with (tab, line feed, return).
_CONTROL_IN_MARKUP = re.compile(
    "[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069]"
)


def printable_lines(text: str) -> str:
    """``text`` (a figure's title, an SVG figure a trusted writer made) with its control and
    bidirectional characters shown as escapes, as :func:`printable` shows them; tabs and line
    breaks (and any markup) kept."""
    return _CONTROL_IN_MARKUP.sub(_escape, text)


_SCRIPT_ESCAPES = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028",
                   "\u2029": "\\u2029"}  # fmt: skip


def script_json(document: Any) -> str:
    """Compact JSON of ``document`` safe inside an HTML ``<script>`` element (any type): the
    characters that could end the element or change how the HTML parser reads it are escaped
    (``JSON.parse`` reads them back unchanged)."""
    text = json.dumps(document, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    return re.sub("[<>&\u2028\u2029]", lambda m: _SCRIPT_ESCAPES[m.group()], text)
