"""One consistent look for skisnow's figures (Matplotlib, Agg, no pyplot state).

Colours follow Kalliorinne et al. 2023, Figures 4–9: camber profile blue, apparent pressure red,
snow surface black, the Breitschädel estimate a thick black line, and snow moduli on a sequential
colour map (one line per modulus, lighter = softer snow). Figures are :class:`matplotlib.figure.
Figure` objects created without pyplot, so plotting is thread-safe and never opens a window.
"""

from __future__ import annotations

import base64
import io
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg", force=False)

from matplotlib.figure import Figure

#: Colours of the physical quantities, as in the paper's figures.
COLORS: dict[str, str] = {
    "profile": "#1f5fbf",  # camber profile (ANN/beam)
    "measured": "black",  # measured profile (dashed)
    "pressure": "#c0392b",  # apparent pressure
    "snow": "black",  # deformed snow surface
    "breitschaedel": "black",
    "load": "#c0392b",  # the load arrow
}
#: Colour map of the snow modulus (one line per modulus).
MODULUS_CMAP = "viridis"
#: The one zone palette of skisnow: every figure and the explorer page (which receives it from
#: here, embedded in its data) colour a zone and its region alike — rear / rear glide blue,
#: middle / kick zone purple, front / front glide orange.
ZONE_COLORS: dict[str, str] = {
    "rear": "#1f5fbf",
    "middle": "#8e44ad",
    "front": "#e67e22",
    "total": "#000000",
    "rear_glide": "#1f5fbf",
    "kick_zone": "#8e44ad",
    "front_glide": "#e67e22",
    "kick": "#8e44ad",
}
#: The zones' and regions' names in the field's words (figures, tables, explorer).
ZONE_LABELS: dict[str, str] = {
    "rear": "rear zone",
    "middle": "middle zone (own patch in the kick zone)",
    "front": "front zone",
    "total": "total",
    "rear_glide": "rear glide (region)",
    "kick_zone": "kick zone (region)",
    "front_glide": "front glide (region)",
    "kick": "between the kick-zone marks",
}
#: Colour map of every map over (load, snow) in figures and the explorer.
MAP_CMAP = "viridis"


def cmap_stops(name: str = MAP_CMAP, n: int = 11) -> list[str]:
    """``n`` evenly spaced colours of the colour map ``name`` as hex strings (for the page)."""
    from matplotlib.colors import to_hex

    cmap = matplotlib.colormaps[name]
    return [to_hex(cmap(k / (n - 1))) for k in range(n)]


#: Output formats written by :func:`save_figure` by default.
FORMATS: tuple[str, ...] = ("png", "svg")

RC: dict[str, Any] = {
    "font.size": 9.0,
    "axes.titlesize": 10.0,
    "axes.labelsize": 9.0,
    "legend.fontsize": 8.0,
    "xtick.labelsize": 8.0,
    "ytick.labelsize": 8.0,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.5,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.linewidth": 1.2,
    "savefig.bbox": "standard",  # constrained layout already fits; "tight" costs a second draw
    "savefig.dpi": 150,
    "svg.fonttype": "none",  # text stays text in SVG: small, searchable, crisp in the report
    "svg.hashsalt": "skisnow",  # deterministic SVG ids
}


@contextmanager
def style() -> Iterator[None]:
    """Context in which skisnow's figures are drawn (rcParams of :data:`RC`)."""
    with matplotlib.rc_context(RC):
        yield


def new_figure(
    ncols: int = 1,
    nrows: int = 1,
    *,
    width: float = 7.0,
    height: float = 3.0,
    layout: str | None = None,
    **kw: Any,
) -> tuple[Figure, Any]:
    """A figure (no pyplot) and its axes array, drawn in skisnow's style.

    The default is a fixed layout (margins in inches, room for a right axis or a colour bar):
    Matplotlib's constrained layout measures every text on each save and made a figure 3-5×
    slower to write; pass ``layout="constrained"`` where a figure needs it.
    """
    with style():
        fig = Figure(figsize=(width, height), layout=layout)
        axes = fig.subplots(nrows, ncols, squeeze=False, **kw)
        if layout is None:
            shared = kw.get("sharey") in (True, "row", "all")
            fig.subplots_adjust(
                left=0.75 / width,
                right=1 - 0.8 / width,
                bottom=0.55 / height,
                top=1 - 0.6 / height,
                wspace=0.12 if shared else 0.38,
                hspace=0.45,
            )
    return fig, axes


def modulus_colors(moduli: Sequence[float]) -> list[Any]:
    """One colour per snow modulus, on :data:`MODULUS_CMAP`, in order of the values."""
    cmap = matplotlib.colormaps[MODULUS_CMAP]
    lo, hi = min(moduli), max(moduli)
    span = hi - lo if hi > lo else 1.0
    return [cmap(0.05 + 0.9 * (m - lo) / span) for m in moduli]


def modulus_colorbar(
    fig: Figure, axes: Any, moduli: Sequence[float], *, label: str = "snow modulus [MPa]"
) -> None:
    """A colour bar for the modulus lines, over the data's range (the smallest to the largest
    modulus drawn, both ends labelled), in the lines' colours (:func:`modulus_colors`)."""
    import matplotlib.colors as mcolors
    import numpy as np
    from matplotlib.cm import ScalarMappable

    lo, hi = min(moduli), max(moduli)
    if hi <= lo:
        lo, hi = lo - 1.0, hi + 1.0
    cmap = mcolors.ListedColormap(matplotlib.colormaps[MODULUS_CMAP](np.linspace(0.05, 0.95, 256)))
    sm = ScalarMappable(norm=mcolors.Normalize(vmin=lo, vmax=hi), cmap=cmap)
    with style():
        cb = fig.colorbar(sm, ax=axes, label=label, shrink=0.9, pad=0.02, fraction=0.04)
        ticks = [
            t for t in cb.get_ticks() if lo < t < hi and min(t - lo, hi - t) > 0.06 * (hi - lo)
        ]
        cb.set_ticks([lo, *ticks, hi])


def _metadata(fmt: str) -> dict[str, Any]:
    # No creation dates: the same data give byte-identical files.
    if fmt == "svg":
        return {"Date": None}
    if fmt == "png":
        return {"Software": "skisnow (matplotlib)"}
    return {}


#: Formats :func:`save_figure` recognises in a file name's suffix.
SUFFIX_FORMATS: tuple[str, ...] = ("png", "svg", "pdf")


def _printable_texts(fig: Figure) -> None:
    """The texts of ``fig`` a name from a file can reach (titles, axis labels, legends, free
    texts) with their control characters drawn as escapes
    (:func:`skisnow._names.printable_lines`), not as missing glyphs or an invisible
    reordering. Tick labels are made at draw time from their formatter: skisnow's are numbers."""
    from skisnow._names import printable_lines

    texts = [*fig.texts, *(t for leg in fig.legends for t in leg.texts)]
    if fig._suptitle is not None:
        texts.append(fig._suptitle)
    for ax in fig.axes:
        texts += [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label,
                  *ax.texts]  # fmt: skip
        if (leg := ax.get_legend()) is not None:
            texts += leg.texts
    for t in texts:
        text = t.get_text()
        if isinstance(text, str) and (shown := printable_lines(text)) != text:
            t.set_text(shown)


def save_figure(
    fig: Figure, path: str | Path, *, formats: Iterable[str] | None = None
) -> list[Path]:
    """Save ``fig`` and return the paths written: the one helper every caller saves through.

    ``path`` with a suffix of :data:`SUFFIX_FORMATS` (``contact.png``) and no ``formats``: that
    one file. Otherwise ``path`` is a stem and one file per format is written (default PNG and
    SVG: ``stem.png``, ``stem.svg``). Figures carry no creation date, so the same data give
    byte-identical files.
    """
    _printable_texts(fig)
    path = Path(path)
    suffix = path.suffix.lstrip(".").lower()
    if formats is None and suffix in SUFFIX_FORMATS:
        stem, formats = path.with_suffix(""), (suffix,)
    else:
        stem, formats = path, FORMATS if formats is None else tuple(formats)
    stem.parent.mkdir(parents=True, exist_ok=True)
    paths = []
    with style():
        for fmt in formats:
            out = stem.with_name(f"{stem.name}.{fmt}")
            from skisnow._atomic import atomic_path

            with atomic_path(out) as tmp:  # a killed save never leaves half a figure
                fig.savefig(tmp, format=fmt, metadata=_metadata(fmt))
            paths.append(out)
    return paths


#: Width [px] a figure takes on a phone (a 420 px wide screen less the page's margins).
PHONE_FIGURE_PX: float = 390.0
#: Smallest text [px] a figure may show.
MIN_TEXT_PX: float = 12.0


def figure_svg(fig: Figure, *, narrow: bool = False, smallest_pt: float | None = None) -> str:
    """The figure as an SVG document string (for inline embedding in HTML).

    ``narrow``: the same figure redrawn for a phone (constrained layout, text at its size in
    points), as wide as lets its smallest text show at :data:`MIN_TEXT_PX` on
    :data:`PHONE_FIGURE_PX` (8 pt: 3.6 in) and taller by the room the text needs; ``""`` when
    its panels do not fit that width (several side by side). The figure is left as it was.
    ``smallest_pt``: :func:`smallest_text_pt` of the figure, if the caller has it (it costs a
    draw).
    """
    import warnings

    _printable_texts(fig)
    buf = io.StringIO()
    size, engine = fig.get_size_inches().copy(), fig.get_layout_engine()
    legends = [(leg, leg._ncols) for ax in fig.axes if (leg := ax.get_legend()) is not None]
    if narrow:
        w, h = size
        pt = smallest_text_pt(fig) if smallest_pt is None else smallest_pt
        width = PHONE_FIGURE_PX * pt / (MIN_TEXT_PX * 72.0)
        fig.set_size_inches(width, h * (1.0 + 0.6 * max(0.0, w / width - 1.0)))
        moved = []
        for ax in fig.axes:  # a legend under its axes: a figure legend under the figure
            leg = ax.get_legend()
            if leg is not None and leg.get_bbox_to_anchor().y0 < ax.bbox.y0:
                leg.set_visible(False)
                moved.append((leg, fig.legend(
                    leg.legend_handles, [t.get_text() for t in leg.texts], ncols=1,
                    loc="outside lower center", frameon=False,
                    fontsize=leg.texts[0].get_fontsize() if leg.texts else None)))  # fmt: skip
        for leg, _ in legends:  # a legend of several columns: one on a phone
            leg.set_ncols(1)
        titles = _wrap_titles(fig, width * 72.0)
        fig.set_layout_engine("constrained")
    try:
        with style(), warnings.catch_warnings():
            if narrow:
                warnings.filterwarnings("error", message="constrained_layout not applied")
            fig.savefig(buf, format="svg", metadata=_metadata("svg"))
    except UserWarning:
        return ""  # the panels collapse at this width: no phone drawing
    finally:
        if narrow:
            fig.set_layout_engine(engine if engine is not None else "none")
            fig.set_size_inches(*size)
            for leg, ncols in legends:
                leg.set_ncols(ncols)
            for t, text in titles:
                t.set_text(text)
            for leg, figure_legend in moved:
                figure_legend.remove()
                leg.set_visible(True)
    text = buf.getvalue()
    text = text[text.index("<svg") :]  # drop the XML prolog and DOCTYPE for inline use
    # drop the RDF metadata block (its namespace URLs are noise in an offline page)
    start, end = text.find("<metadata>"), text.find("</metadata>")
    if start >= 0 and end > start:
        text = text[:start] + text[end + len("</metadata>") :]
    return text


def _wrap_titles(fig: Figure, width_pt: float) -> list[tuple[Any, str]]:
    """Wrap the titles of ``fig`` to lines that fit ``width_pt`` (a title wider than the figure
    leaves constrained layout no room); returns (text, original) to restore."""
    import textwrap

    texts = [t for ax in fig.axes for t in (ax.title, ax._left_title, ax._right_title)]
    if fig._suptitle is not None:
        texts.append(fig._suptitle)
    changed = []
    for t in texts:
        text = t.get_text()
        if not text:
            continue
        chars = max(12, int(width_pt / (0.55 * t.get_fontsize())))
        lines = [w for line in text.split("\n") for w in textwrap.wrap(line, chars) or [""]]
        if len(lines) > text.count("\n") + 1:
            changed.append((t, text))
            t.set_text("\n".join(lines))
    return changed


def smallest_text_pt(fig: Figure) -> float:
    """The smallest font size [pt] of the visible texts of a figure (ticks, labels, legends)."""
    from matplotlib.text import Text

    _printable_texts(fig)
    with style():
        fig.draw_without_rendering()  # tick labels exist only once drawn
    sizes = [t.get_fontsize() for t in fig.findobj(Text) if t.get_visible() and t.get_text()]
    return float(min(sizes)) if sizes else float(RC["font.size"])


def figure_png_base64(fig: Figure, *, dpi: float = 110) -> str:
    """The figure as a base64 PNG (for ``<img src="data:image/png;base64,...">``)."""
    buf = io.BytesIO()
    with style():
        fig.savefig(buf, format="png", dpi=dpi, metadata=_metadata("png"))
    return base64.b64encode(buf.getvalue()).decode("ascii")
