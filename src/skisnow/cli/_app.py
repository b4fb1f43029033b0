"""The Typer application shared by all command modules, its error handling and exit codes.

The CLI only parses, calls the library and renders. Each command module (``_ski.py``,
``_contact.py``, ...) adds its commands to :data:`app`; :func:`main` runs it, turns
:class:`~skisnow.SkisnowError` (and any other exception) into a one-line message, and returns an
exit code that says what happened (:data:`EXIT_CODES`), unless ``--debug`` is given.

Exit codes:

====  ======================================================================================
0     done, and every solve converged inside the domain its models were fitted on
1     internal error: an exception that is not one of skisnow's (a bug; please report it)
2     bad input: a file or an option is wrong, impossible or implausible (nothing computed)
3     a solver did not converge (the result is printed, flagged ``converged: false``)
4     a result lies outside the trained or valid domain of a model (DomainWarning; printed)
5     the computation failed for another reason (e.g. a sweep chunk failed; kept work says so)
130   interrupted (Ctrl-C); finished work is kept where the message says
====  ======================================================================================
"""

from __future__ import annotations

import sys
import warnings
from typing import Any

import typer

from skisnow import __version__

EXIT_OK = 0
EXIT_INTERNAL = 1
EXIT_INPUT = 2
EXIT_NOT_CONVERGED = 3
EXIT_OUT_OF_DOMAIN = 4
EXIT_FAILED = 5
EXIT_INTERRUPTED = 130

#: Exit code -> meaning (the table of ``skisnow --help`` and the README).
EXIT_CODES: dict[int, str] = {
    EXIT_OK: "done; every solve converged inside its models' domain",
    EXIT_INTERNAL: "internal error (a bug: please report it with --debug output)",
    EXIT_INPUT: "bad input: a file or option is wrong, impossible or implausible",
    EXIT_NOT_CONVERGED: "a solver did not converge (result printed, converged: false)",
    EXIT_OUT_OF_DOMAIN: "result outside a model's trained/valid domain (warning printed)",
    EXIT_FAILED: "the computation failed (e.g. a sweep chunk); kept work is named",
    EXIT_INTERRUPTED: "interrupted (Ctrl-C); finished work is kept",
}

_EPILOG = "Exit codes: " + "; ".join(f"{k} {v}" for k, v in EXIT_CODES.items()) + "."

app = typer.Typer(
    name="skisnow",
    help="How a cross-country ski meets the snow: camber, apparent contact, real contact.",
    epilog=_EPILOG,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

#: Per-run state: --debug, the convergence reported by commands, the warnings (domain,
#: extrapolation) raised or reported during the run.
_state: dict[str, Any] = {"debug": False, "converged": None, "warnings": [], "shown": set(),
                          "unconverged": []}  # fmt: skip


def report_converged(converged: bool) -> None:
    """Called by a command after a solve: an unconverged one makes the run exit with 3."""
    prev = _state.get("converged")
    _state["converged"] = bool(converged) if prev is None else (prev and bool(converged))


def report_unconverged(labels: list[str] | tuple[str, ...], *, solved: bool = False) -> None:
    """Called by a command whose solves ran elsewhere (Dask workers; read from a sweep's store):
    each label names an unconverged solve; any makes the run exit with 3. ``solved``: the
    labels are all the unconverged solves of a set that was solved (a sweep's store), so none
    means every one converged."""
    for label in labels:
        if label not in _state["unconverged"]:
            _state["unconverged"].append(label)
    if labels:
        report_converged(False)
    elif solved:
        report_converged(True)


def report_domain_warnings(messages: list[str] | tuple[str, ...], *, shown: bool = False) -> None:
    """Called by a command that caught DomainWarnings itself: the run exits with 4 and
    ``--json`` lists them; ``shown``: the command printed them already (not printed again)."""
    for m in messages:
        if m not in _state["warnings"]:
            _state["warnings"].append(m)
        if shown:
            _state["shown"].add(m)


def _report_implausible() -> None:
    """One domain warning for the implausible results the run's solves recorded
    (:mod:`skisnow.pipeline._plausible`): how many and the first, unless a command reported
    each already (``contact`` lists its case's warnings)."""
    found = _state.get("implausible") or []
    old = _state.get("implausible_summary")
    if old in _state["warnings"]:
        _state["warnings"].remove(old)
    told = _state["warnings"]
    new = [e for e in found if not any(w in e for w in told)]
    if not new:
        return
    summary = (
        new[0]
        if len(new) == 1
        else f"{len(new)} implausible results of the run's solves (first: {new[0]})"
    )
    _state["implausible_summary"] = summary
    report_domain_warnings([summary])


def run_annotations() -> dict[str, Any]:
    """What every ``--json`` document carries: skisnow version, convergence, warnings."""
    caught = _state.get("caught") or []
    _collect(caught)
    _report_implausible()
    converged = _state.get("converged")
    # the solves of this process so far (the one door of a case records each): a document
    # printed before main() reads the record must not say null, or true, when one failed
    if _state.get("unconverged_log"):
        converged = False
    elif converged is None and _state.get("solved_log"):
        converged = True
    return {
        "skisnow_version": __version__,
        "converged": converged,
        "warnings": list(_state["warnings"]),
    }


def _collect(caught: list[warnings.WarningMessage]) -> None:
    from skisnow._errors import DomainWarning

    for w in caught:
        if issubclass(w.category, DomainWarning):
            report_domain_warnings([str(w.message)])


def _version_callback(value: bool) -> None:
    if value:
        typer.echo(f"skisnow {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    debug: bool = typer.Option(False, "--debug", help="Show full tracebacks on errors."),
    version: bool = typer.Option(
        False, "--version", callback=_version_callback, is_eager=True, help="Print the version."
    ),
    allow_implausible: bool = typer.Option(
        False,
        "--allow-implausible",
        help="Accept values that are possible but implausible for a ski (e.g. a 3 m ski); "
        "impossible ones are still refused.",
    ),
) -> None:
    """skisnow: how a cross-country ski meets the snow."""
    _state["debug"] = debug
    if allow_implausible:
        from skisnow._checks import _ALLOW

        _ALLOW.set(True)


def interrupted_by_user(exc: BaseException) -> bool:
    """Whether ``exc`` is, or was caused by, a Ctrl-C.

    A ``KeyboardInterrupt`` raised while a compiled numba kernel runs comes back as
    ``SystemError: CPUDispatcher(...) returned a result with an exception set``, chained from the
    ``KeyboardInterrupt`` (CPython's check of a C function's result): it is an interruption, not
    an internal error.
    """
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return False


def _exit_code_of(exc: BaseException) -> int:
    from skisnow._errors import ConvergenceError, InputError, SkisnowError

    if isinstance(exc, InputError):
        return EXIT_INPUT
    if isinstance(exc, ConvergenceError):
        return EXIT_NOT_CONVERGED
    if isinstance(exc, SkisnowError):
        return EXIT_FAILED
    return EXIT_INTERNAL


#: Old option names kept as hidden aliases (one name per concept across commands): old → new.
DEPRECATED_OPTIONS: dict[str, str] = {"--n-points": "--points"}


def _renamed(args: list[str]) -> list[str]:
    """``args`` with deprecated option names replaced by the current ones (a note on stderr)."""
    out = []
    for a in args:
        name, eq, value = a.partition("=")
        if name in DEPRECATED_OPTIONS:
            new = DEPRECATED_OPTIONS[name]
            typer.echo(f"skisnow: note: {name} is now {new} (the old name still works)", err=True)
            a = new + eq + value
        out.append(a)
    return out


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; return the exit code (see :data:`EXIT_CODES`; errors: one line on stderr)."""
    args = _renamed(sys.argv[1:] if argv is None else argv)
    _state.update(debug="--debug" in args, converged=None, warnings=[], shown=set(),
                  unconverged=[], implausible=None, implausible_summary=None,
                  unconverged_log=None, solved_log=None)  # fmt: skip
    from skisnow._checks import _ALLOW
    from skisnow._errors import DomainWarning

    token = _ALLOW.set(None)  # each run starts strict (or as SKISNOW_ALLOW_IMPLAUSIBLE says)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DomainWarning)
        _state["caught"] = caught
        try:
            from skisnow.pipeline import (
                recording_implausible,
                recording_solved,
                recording_unconverged,
            )

            with (
                recording_unconverged() as log,
                recording_implausible() as odd,
                recording_solved() as solved,
            ):
                _state.update(implausible=odd, unconverged_log=log, solved_log=solved)
                code = _run(args)
            report_unconverged(log)  # every solve of this process that did not converge
            _report_implausible()  # every solve whose result was implausible (exit 4)
        finally:
            _ALLOW.reset(token)
            _state["caught"] = None
    _collect(caught)
    for w in caught:  # other warnings are the user's to see, as they would be without us
        if not issubclass(w.category, DomainWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)
    if code != EXIT_OK:
        return code
    from skisnow._names import printable

    for m in _state["warnings"]:
        if m not in _state["shown"]:
            typer.echo(f"skisnow: warning: {printable(m)}", err=True)
    if _state["converged"] is False:
        bad = _state["unconverged"]
        which = (
            f"{len(bad)} solve{'s' * (len(bad) != 1)} did not converge (first: "
            f"{printable('; '.join(bad[:3]))})"
            if bad
            else "the solver did not converge"
        )
        typer.echo(f"skisnow: warning: {which} (exit code 3)", err=True)
        return EXIT_NOT_CONVERGED
    if _state["warnings"]:
        return EXIT_OUT_OF_DOMAIN
    return EXIT_OK


#: The Click command built from :data:`app`, with what it was built from (see build_command).
_BUILT: list[tuple[tuple[Any, ...], Any]] = []


def build_command() -> Any:
    """The Click command of :data:`app` with the option gate installed
    (:func:`skisnow.cli._options.install_gate`: every numeric option checked before any command
    runs).

    Built once per process and reused while :data:`app`'s registered commands, groups and
    callback are the same objects (a command registered later gets a new build): building it
    costs ~30 ms of CPU, once per ``skisnow`` process but at every :func:`main` of a program
    that calls it many times (the test suite's fuzz corpus: 461 runs). Click keeps the state of
    a run in its ``Context``, never in the command, and the gate's callbacks are pure."""
    from skisnow.cli._options import install_gate

    key = (tuple(app.registered_commands), tuple(app.registered_groups), app.registered_callback)
    if not _BUILT or _BUILT[0][0] != key:
        _BUILT[:] = [(key, _literal_help(install_gate(typer.main.get_command(app))))]
    return _BUILT[0][1]


def _literal_help(group: Any) -> Any:
    """Escape the help texts of ``group``'s commands and options for Rich, which Typer renders
    them with: a unit in brackets (``"Load mass [kg]"``) would otherwise be read as a markup tag
    and vanish from ``--help``. skisnow's help texts hold no markup of their own."""
    from rich.markup import escape

    for command in group.commands.values():
        if command.help:
            command.help = escape(command.help)
        for param in command.params:
            if getattr(param, "help", None):
                param.help = escape(param.help)
    return group


def _run(args: list[str]) -> int:
    try:
        # In non-standalone mode Click returns the code of a `typer.Exit(code)` / Ctrl-C (130)
        # instead of raising it: pass it on, or an interrupted command would report success.
        code = build_command()(args=args, prog_name="skisnow", standalone_mode=False)
    except typer.Exit as exc:
        return exc.exit_code
    except typer.Abort:
        typer.echo("skisnow: aborted", err=True)
        return EXIT_INTERRUPTED
    except KeyboardInterrupt:
        typer.echo("skisnow: interrupted", err=True)
        return EXIT_INTERRUPTED
    except Exception as exc:  # the one place where every error is turned into a message
        if interrupted_by_user(exc):
            typer.echo("skisnow: interrupted", err=True)
            return EXIT_INTERRUPTED
        if _state["debug"]:
            raise
        # Click's exceptions, whether from click itself or the copy Typer vendors: by name
        classes = {c.__name__ for c in type(exc).__mro__}
        if "ClickException" in classes:
            exc.show()  # type: ignore[attr-defined]
            return EXIT_INPUT if "UsageError" in classes else int(exc.exit_code)  # type: ignore[attr-defined]
        name = type(exc).__name__
        code = _exit_code_of(exc)
        what = "internal error" if code == EXIT_INTERNAL else "error"
        from skisnow._names import printable

        typer.echo(f"skisnow: {what}: {printable(exc)} [{name}]", err=True)
        return code
    return code if isinstance(code, int) else EXIT_OK
