"""The package's own contract: version, error hierarchy, CLI error handling."""

from __future__ import annotations

import pytest

import skisnow
from skisnow.cli import main


def test_error_hierarchy_refines_builtins() -> None:
    assert issubclass(skisnow.InputError, ValueError)
    assert issubclass(skisnow.FileFormatError, skisnow.InputError)
    assert issubclass(skisnow.ConvergenceError, RuntimeError)
    for cls in (skisnow.InputError, skisnow.ConvergenceError, skisnow.UnsupportedLoadError):
        assert issubclass(cls, skisnow.SkisnowError)


def test_convergence_error_carries_result() -> None:
    err = skisnow.ConvergenceError("not converged", result={"residual": 1.0})
    assert err.result == {"residual": 1.0}


def test_cli_version(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert skisnow.__version__ in capsys.readouterr().out


def test_cli_unknown_command_is_an_error_not_a_traceback(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert main(["no-such-command"]) != 0
    assert "Traceback" not in capsys.readouterr().err


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (2000.0, "2000"),
        (1860.0, "1860"),
        (7.38, "7.38"),
        (0.0874, "0.0874"),
        (0.0, "0"),
        (-120.0, "-120"),
        (1.5e-5, "1.500e-05"),
        (2.5e7, "2.500e+07"),
    ],
)
def test_table_numbers_are_plain(value: float, text: str) -> None:
    from skisnow.cli._render import format_number

    assert format_number(value) == text


def test_cli_passes_on_the_exit_code_of_a_command() -> None:
    import typer

    from skisnow.cli import app

    @app.command("_exit-with-3", hidden=True)
    def _exit_with_3() -> None:
        raise typer.Exit(3)

    try:
        assert main(["_exit-with-3"]) == 3
    finally:
        app.registered_commands[:] = [
            c for c in app.registered_commands if c.name != "_exit-with-3"
        ]
