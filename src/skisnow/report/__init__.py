"""The HTML report of a ski: one self-contained file (figures inline, no network needed).

:func:`write_report` computes what it needs (metrics, contact at standard loads, a resumable
sweep for the maps) and writes ``{ski}_report.html``; :func:`build_report` returns the HTML.
"""

from skisnow.report._report import (
    MAP_MASSES,
    MAP_MODULI,
    STANDARD_SNOWS,
    build_report,
    write_report,
)

__all__ = ["MAP_MASSES", "MAP_MODULI", "STANDARD_SNOWS", "build_report", "write_report"]
