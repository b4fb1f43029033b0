"""Assembling one self-contained HTML page: inline CSS, inline SVG figures, no scripts, no
external resources (the report opens offline, from a USB stick, in any browser)."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from skisnow._names import html_text, printable_lines

CSS = """
body { font-family: -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; margin: 0;
       color: #1d2327; background: #fff; line-height: 1.45; }
header { background: #14365d; color: #fff; padding: 1.2em 2em; }
header h1 { margin: 0 0 .2em 0; font-size: 1.6em; }
header p { margin: 0; opacity: .85; }
main { max-width: 1100px; margin: 0 auto; padding: 1em 2em 3em 2em; }
h2 { border-bottom: 2px solid #14365d; padding-bottom: .2em; margin-top: 1.8em; }
table { border-collapse: collapse; margin: .6em 0 1em 0; font-size: .92em; }
th, td { border: 1px solid #ccd3da; padding: .25em .6em; text-align: right; }
th { background: #eef2f6; }
td:first-child, th:first-child { text-align: left; }
figure { margin: 1em 0; }
figure svg { width: 100%; max-width: 100%; height: auto; display: block; }
.scroll { overflow-x: auto; max-width: 100%; -webkit-overflow-scrolling: touch; }
.scroll table { margin: 0; }
.fig-narrow { display: none; }
@media (max-width: 600px) {
  header { padding: .8em 1em; } main { padding: .5em .8em 2em .8em; }
  figure { margin: 1em -.5em; }
  .fig-wide { display: none; } .fig-narrow { display: block; }
  .fig-scroll { overflow-x: auto; } .fig-scroll svg { min-width: var(--min-width); }
}
figcaption { font-size: .88em; color: #4a5560; margin-top: .3em; }
.note { font-size: .88em; color: #4a5560; }
footer { font-size: .8em; color: #6a747e; margin-top: 3em; }
"""


@dataclass(frozen=True)
class Table:
    """A table: column headers and rows of cells (floats formatted with ``floatfmt``)."""

    columns: Sequence[str]
    rows: Sequence[Sequence[Any]]
    floatfmt: str = ".3g"
    caption: str = ""


@dataclass(frozen=True)
class Figure:
    """An inline SVG figure with a caption; ``narrow``, the same figure drawn for a phone
    screen (shown instead below 600 px, so that no text in it is smaller than 12 px)."""

    svg: str
    caption: str = ""
    narrow: str = ""
    min_width_px: int = 0

    @classmethod
    def of(cls, fig: Any, caption: str = "") -> Figure:
        """Both drawings of a Matplotlib figure (:func:`skisnow.plot.figure_svg`); a figure
        whose panels do not fit a phone's width scrolls there inside its box, drawn wide enough
        for its smallest text to show at 12 px."""
        from skisnow.plot import figure_svg, smallest_text_pt

        pt = smallest_text_pt(fig)  # one draw, for both drawings
        narrow = figure_svg(fig, narrow=True, smallest_pt=pt)
        wide_px = float(fig.get_size_inches()[0]) * 72.0  # the SVG's width in pt
        min_px = 0 if narrow else int(np.ceil(12.0 * wide_px / pt))
        return cls(figure_svg(fig), caption, narrow, min_px)


@dataclass(frozen=True)
class Link:
    """A link to a file beside the page (a relative name such as ``explore.html``: the report
    stays offline; never a URL)."""

    href: str
    text: str

    def __post_init__(self) -> None:
        if ":" in self.href or self.href.startswith(("/", "\\")) or "/" in self.href:
            raise ValueError(f"Link: only a file name beside the page, got {self.href!r}")


@dataclass(frozen=True)
class Section:
    """A titled section: paragraphs (plain text), then tables and figures in order."""

    title: str
    paragraphs: Sequence[str] = ()
    items: Sequence[Table | Figure | Link] = field(default_factory=tuple)


def _cell(value: Any, floatfmt: str) -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "—"
    if isinstance(value, float):
        return format(value, floatfmt)
    return html_text(str(value))


def _table(t: Table) -> str:
    head = "".join(f"<th>{html_text(c)}</th>" for c in t.columns)
    body = "".join(
        "<tr>" + "".join(f"<td>{_cell(v, t.floatfmt)}</td>" for v in row) + "</tr>"
        for row in t.rows
    )
    cap = f"<caption>{html_text(t.caption)}</caption>" if t.caption else ""
    # the table scrolls inside its box on a narrow screen; the page itself never does
    return (f'<div class="scroll"><table>{cap}<thead><tr>{head}</tr></thead><tbody>{body}'
            "</tbody></table></div>")  # fmt: skip


def _figure(f: Figure) -> str:
    cap = f"<figcaption>{html_text(f.caption)}</figcaption>" if f.caption else ""
    # a figure's titles and legends may hold a ski's name: its control characters shown
    f = dataclasses.replace(f, svg=printable_lines(f.svg), narrow=printable_lines(f.narrow))
    if f.narrow:
        return (f'<figure><div class="fig-wide">{f.svg}</div><div class="fig-narrow">'
                f"{f.narrow}</div>{cap}</figure>")  # fmt: skip
    if f.min_width_px:
        return (f'<figure><div class="fig-scroll" style="--min-width: {f.min_width_px}px">'
                f"{f.svg}</div>{cap}</figure>")  # fmt: skip
    return f"<figure>{f.svg}{cap}</figure>"


def _link(link: Link) -> str:
    return f'<p><a href="{html_text(link.href)}">{html_text(link.text)}</a></p>'


def _item(item: Table | Figure | Link) -> str:
    if isinstance(item, Table):
        return _table(item)
    return _link(item) if isinstance(item, Link) else _figure(item)


def render_page(title: str, subtitle: str, sections: Sequence[Section], *, footer: str = "") -> str:
    """The whole HTML document as a string."""
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{html_text(title)}</title><style>{CSS}</style></head><body>",
        f"<header><h1>{html_text(title)}</h1><p>{html_text(subtitle)}</p></header><main>",
    ]
    for s in sections:
        parts.append(f"<section><h2>{html_text(s.title)}</h2>")
        parts += [f"<p>{html_text(p)}</p>" for p in s.paragraphs]
        for item in s.items:
            parts.append(_item(item))
        parts.append("</section>")
    if footer:
        parts.append(f"<footer>{html_text(footer)}</footer>")
    parts.append("</main></body></html>")
    return "\n".join(parts)
