"""The report of a ski: what it shows, computed in one place, and one self-contained HTML file.

:func:`study_ski` computes everything the report of one ski shows (the practitioners' metrics of
the virtual bench, the cases at the standard loads, each a :func:`~skisnow.pipeline.solve_case`,
and the maps over load and snow, a resumable :mod:`skisnow.sweep`) as a :class:`SkiStudy`;
:func:`write_report` renders it as ``{ski}_report.html`` (figures inline, no network needed),
:func:`build_report` returns the HTML.

May import: ski, bench, pipeline, sweep, plot, workflows
"""

from skisnow.report._html import Link
from skisnow.report._report import build_report, write_report
from skisnow.report._study import (
    MAP_MASSES,
    MAP_MODULI,
    STANDARD_SNOWS,
    SkiStudy,
    standard_cases,
    study_ski,
)

__all__ = [
    "MAP_MASSES",
    "MAP_MODULI",
    "STANDARD_SNOWS",
    "Link",
    "SkiStudy",
    "build_report",
    "standard_cases",
    "study_ski",
    "write_report",
]
