"""The Typer application shared by all command modules, and its error handling.

The CLI only parses, calls the library and renders. Each command module (``_ski.py``,
``_contact.py``, ...) adds its commands to :data:`app`; :func:`main` runs it and turns
:class:`~skisnow.SkisnowError` (and any other exception) into a one-line message and a non-zero
exit, unless ``--debug`` is given.
"""

from __future__ import annotations

import sys

import typer

from skisnow import __version__

app = typer.Typer(
    name="skisnow",
    help="How a cross-country ski meets the snow: camber, apparent contact, real contact.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

_state = {"debug": False}


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


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; return the exit code (errors: one line on stderr, exit 1)."""
    args = sys.argv[1:] if argv is None else argv
    _state["debug"] = "--debug" in args
    from skisnow._checks import _ALLOW

    token = _ALLOW.set(None)  # each run starts strict (or as SKISNOW_ALLOW_IMPLAUSIBLE says)
    try:
        # In non-standalone mode Click returns the code of a `typer.Exit(code)` / Ctrl-C (130)
        # instead of raising it: pass it on, or an interrupted command would report success.
        code = app(args=args, prog_name="skisnow", standalone_mode=False)
    except typer.Exit as exc:
        return exc.exit_code
    except typer.Abort:
        typer.echo("skisnow: aborted", err=True)
        return 130
    except KeyboardInterrupt:
        typer.echo("skisnow: interrupted", err=True)
        return 130
    except Exception as exc:  # the one place where every error is turned into a message
        import click

        if _state["debug"]:
            raise
        if isinstance(exc, click.ClickException):
            exc.show()
            return exc.exit_code
        name = type(exc).__name__
        typer.echo(f"skisnow: error: {exc} [{name}]", err=True)
        return 1
    finally:
        _ALLOW.reset(token)
    return code if isinstance(code, int) else 0
