"""Rendering helpers for the CLI: Rich tables, and the one-JSON-document rule for ``--json``."""

from __future__ import annotations

import json
import math
import signal
import threading
from collections.abc import Callable, Mapping, Sequence
from typing import Annotated, Any

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from skisnow._names import printable

#: Options several commands share (one wording, one default): ``name: JsonOption = False``.
JsonOption = Annotated[
    bool, typer.Option("--json", help="Print one JSON document to stdout, nothing else.")
]
ProfileSourceOption = Annotated[
    str,
    typer.Option(
        "--profile-source",
        help="Loaded profile route: beam (the ski's EI(x), z0(x) on the rigid plane: the "
        "truth), network (the shipped camber network, an emulator of the beam; for a ski whose "
        "content is a shipped one's) or auto (= beam, for every ski).",
    ),
]
#: The grids of the sweep, its report's maps and the explorer: ``start:stop:step``, a value or a
#: list (parsed by :func:`skisnow.sweep.parse_values`); each command keeps its own default.
MassGridOption = Annotated[
    str, typer.Option("--mass-kg", help="Masses (kg): start:stop:step, a value or a list.")
]
LoadPositionGridOption = Annotated[
    str, typer.Option("--load-position-mm", help="Load positions x_m (mm), + toward tip.")
]
SnowModulusGridOption = Annotated[
    str | None, typer.Option("--snow-modulus-mpa", help="Snow moduli E_counter (MPa).")
]
NPointsOption = Annotated[
    int,
    typer.Option("--points", help="Stations along the ski, tail to tip, both ends included."),
]
#: Dask options shared by the commands that sweep (sweep, report, explore); defaults per command.
DaskWorkersOption = Annotated[
    int | None,
    typer.Option(
        "--workers", help="Local Dask workers (0: in this process, no Dask; unset: one per core)."
    ),
]
SchedulerOption = Annotated[
    str | None,
    typer.Option(
        "--scheduler",
        envvar="SKISNOW_SCHEDULER",
        help="Address of an existing dask.distributed scheduler (default: a local cluster).",
    ),
]
#: The identification's splines and smoothness (``skisnow identify`` and ``skisnow bench-plan``).
NStiffnessOption = Annotated[
    int, typer.Option("--n-stiffness", help="Spline coefficients of log EI(x).")
]
NCamberOption = Annotated[int, typer.Option("--n-camber", help="Spline coefficients of z0(x).")]
RegularisationOption = Annotated[
    float | None,
    typer.Option("--regularisation", help="λ of the log-EI smoothness (default: chosen by GCV)."),
]
SkiModelOption = Annotated[
    str,
    typer.Option(
        "--ski-model",
        help="rigid (the paper's method: the profile loaded on the stone pressed into the "
        "snow) or flexible (the ski's beam bends on the snow; no network).",
    ),
]

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


def say(text: str, *, style: str = "") -> None:
    """One line on stderr (Rich), ``text`` shown literally: no markup, control characters
    escaped (names and messages come from files)."""
    from rich.text import Text

    err_console.print(Text(printable(text), style=style), highlight=False)


def show(text: str, *, style: str = "") -> None:
    """One line on stdout, ``text`` shown literally (see :func:`say`)."""
    from rich.text import Text

    console.print(Text(printable(text), style=style), highlight=False)


def emit_json(document: Mapping[str, Any] | Sequence[Any]) -> None:
    """Print exactly one JSON document to stdout and nothing else (NaN/inf become null).

    A document (mapping) always carries ``skisnow_version``, ``converged`` (``true``/``false``
    after a solve, ``null`` when the command solves nothing iteratively) and ``warnings`` (the
    domain and extrapolation warnings of the run), whatever the command put in it.
    """
    if isinstance(document, Mapping):
        from skisnow.cli._app import run_annotations

        extra = run_annotations()
        own = document.get("warnings") or []
        merged = [*own, *(w for w in extra["warnings"] if w not in own)]
        converged = document.get("converged", extra["converged"])
        document = {**document, "skisnow_version": extra["skisnow_version"],
                    "converged": converged, "warnings": merged}  # fmt: skip
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


def _cell(v: Any, floatfmt: str | None) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "—"
    if isinstance(v, (float, np.floating)):
        return format(float(v), floatfmt) if floatfmt else format_number(float(v))
    return printable(v)  # a name from a file: its control characters shown, never acted on


def _span(text: str, wraps: bool) -> int:
    return max((len(w) for w in text.split()), default=0) if wraps else len(text)


def fit_columns(
    columns: Sequence[str],
    cells: Sequence[Sequence[str]],
    width: int,
    *,
    wraps: Sequence[bool] | None = None,
) -> tuple[list[int], list[str], list[int]]:
    """The columns of a table that fit ``width`` characters without cutting a number.

    A column needs its longest number (numbers are never cut), its texts' and header's longest
    word (texts and headers wrap at spaces), plus 3 characters of border and padding. Columns
    are dropped from the right (the first, the row's name, always stays) until the table fits.
    ``wraps[k]`` says whether column k holds text. Returns the kept column indices, the dropped
    column names and every column's tight width.
    """
    wraps = [False] * len(columns) if wraps is None else list(wraps)
    tight = [
        max(max((_span(r[k], wraps[k]) for r in cells), default=0), _span(col, True))
        for k, col in enumerate(columns)
    ]
    keep = list(range(len(columns)))
    while len(keep) > 1 and sum(tight[k] + 3 for k in keep) + 1 > width:
        keep.pop()
    return keep, [columns[k] for k in range(len(columns)) if k not in keep], tight


def print_table(
    title: str,
    columns: Sequence[str],
    rows: Sequence[Sequence[Any]],
    *,
    floatfmt: str | None = None,
) -> None:
    """Print a Rich table: floats via :func:`format_number` or ``floatfmt``, None as a dash.

    Texts are printed literally: units in brackets (``length [mm]``) are not Rich markup. The
    table fits the terminal (80 columns when piped): headers wrap, numbers are never cut, and
    columns that do not fit are dropped with a note naming them (``--json`` and the CSV files
    keep everything).
    """
    from rich.markup import escape

    cells = [[_cell(v, floatfmt) for v in row] for row in rows]
    wraps = [k == 0 or any(isinstance(row[k], str) for row in rows) for k in range(len(columns))]
    keep, dropped, tight = fit_columns(columns, cells, console.width, wraps=wraps)
    title, columns = printable(title), [printable(c) for c in columns]
    table = Table(title=escape(title))
    natural = sum(max(max((len(r[k]) for r in cells), default=0), len(columns[k])) + 3
                  for k in keep) + 1  # fmt: skip
    spare = console.width - (sum(tight[k] + 3 for k in keep) + 1)
    for k in keep:
        # too wide on one line each: numbers at their width, texts share what is left
        w = tight[k]
        if natural > console.width and wraps[k] and k == keep[-1]:
            w += max(spare, 0)
        table.add_column(escape(columns[k]), justify="left" if wraps[k] else "right",
                         width=w if natural > console.width else None,
                         overflow="fold")  # fmt: skip
    for row in cells:
        table.add_row(*(escape(row[k]) for k in keep))
    console.print(table)
    if dropped:
        console.print(
            f"({len(dropped)} column(s) left out to fit {console.width} characters: "
            f"{', '.join(dropped)}; --json or the CSV output has them)",
            markup=False, highlight=False,
        )  # fmt: skip


def _without_ctrl_c(step: Callable[[], None]) -> None:
    """Run ``step`` with SIGINT held back (delivered right after it), in the main thread.

    Rich's ``Live.start`` marks itself started before it pushes itself on the console's live
    stack; a Ctrl-C between the two left a bar that ``stop`` then popped from an empty stack
    (``IndexError: pop from empty list``, reported as an internal error instead of "interrupted":
    seen once in tests/sweep/test_kill_resume.py, where the signal comes with the first chunk).
    Starting and stopping the bar are therefore not interruptible; the Ctrl-C is raised as
    ``KeyboardInterrupt`` as soon as they are done.
    """
    if threading.current_thread() is not threading.main_thread() or not hasattr(
        signal, "pthread_sigmask"
    ):
        step()  # signals are handled in the main thread only; nothing to hold back here
        return
    held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        step()
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


class ProgressBar:
    """The one progress bar of the CLI (Rich, on stderr), called like a library progress callback.

    ``bar(done, total)`` — the signature of the ``progress=`` callbacks of ``run_bench``,
    ``bearing_sweep`` and ``run_sweep``'s ``on_progress`` (extra positional arguments are
    ignored) — updates it; ``status=`` sets a trailing text and ``label=`` the description. The
    bar appears at the first update (not before the work has started), and never with
    ``disable=True`` (``--json``). Use it as a context manager::

        with progress_bar("bench skate", disable=json_out) as bar:
            run_bench(ski, progress=bar)
    """

    def __init__(
        self,
        label: str,
        *,
        total: float | None = None,
        disable: bool = False,
        transient: bool = True,
    ) -> None:
        self.label, self.total, self.disable, self.transient = label, total, disable, transient
        self.completed: float = 0
        self._bar: Any = None
        self._task: Any = None

    def __call__(
        self,
        done: float,
        total: float | None = None,
        *_: Any,
        status: str | None = None,
        label: str | None = None,
    ) -> None:
        self.completed = done
        if total is not None:
            self.total = total
        if self.disable:
            return
        if self._bar is None:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self._bar = Progress(
                TextColumn("[bold]{task.description}"),
                BarColumn(),
                MofNCompleteColumn(),
                TimeElapsedColumn(),
                TimeRemainingColumn(),
                TextColumn("{task.fields[status]}"),
                console=err_console,
                transient=self.transient,
            )
            _without_ctrl_c(self._bar.start)
            self._task = self._bar.add_task(self.label, total=self.total, status="")
        fields: dict[str, Any] = {"completed": done, "total": self.total}
        if status is not None:
            fields["status"] = status
        if label is not None:
            fields["description"] = label
        self._bar.update(self._task, **fields)

    def close(self) -> None:
        """Stop the bar (idempotent)."""
        if self._bar is not None and self._bar.live.is_started:
            _without_ctrl_c(self._bar.stop)

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def progress_bar(
    label: str, *, total: float | None = None, disable: bool = False, transient: bool = True
) -> ProgressBar:
    """A :class:`ProgressBar` (the CLI's one progress helper)."""
    return ProgressBar(label, total=total, disable=disable, transient=transient)
