"""The ``skisnow`` command line: thin, it parses, calls the library and renders.

Each concern has its own module that adds commands to the shared Typer :data:`app`; importing
them here registers the commands. Typer reads a command's options from its signature, so the
shared option types (``cli/_media.py``: snow, base, friction; ``cli/_render.py``: the rest) are
defined once and listed, by name, in every command that takes them: the same import lists and
signature lines in several command modules are that listing, not repeated logic.

May import: ski, bench, network, identify, contact, micro, pipeline, sweep, paper, workflows,
explore, plot, report, calibrate, snow, multiscale
"""

from skisnow.cli import (  # noqa: F401  (registers)
    _bench_plan,
    _calibrate,
    _contact,
    _demo,
    _explore,
    _identify,
    _micro,
    _multiscale,
    _network,
    _paper,
    _ski,
    _sweep,
    _workflows,
    _workflows_cycle,
)
from skisnow.cli._app import app, main

__all__ = ["app", "main"]
