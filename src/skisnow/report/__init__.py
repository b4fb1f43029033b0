"""The HTML report of a ski: one self-contained file (figures inline, no network needed).

It renders a :class:`skisnow.pipeline.SkiStudy` (computed by :func:`skisnow.pipeline.study_ski`):
:func:`write_report` writes ``{ski}_report.html``; :func:`build_report` returns the HTML.
"""

from skisnow.report._html import Link
from skisnow.report._report import build_report, write_report

__all__ = ["Link", "build_report", "write_report"]
