"""Every unit a help text names in brackets reaches ``--help`` (Rich would read ``[kg]`` as a
markup tag and drop it: "Skier's body mass ." instead of "Skier's body mass [kg].")."""

from __future__ import annotations

import re

import pytest
import typer
from rich.text import Text

from skisnow.cli import app, main
from skisnow.cli._app import build_command


def _help_texts(group) -> dict[tuple[str, str], str]:
    out = {}
    for name, command in group.commands.items():
        out[(name, "(command)")] = command.help or ""
        for param in command.params:
            out[(name, param.opts[0])] = getattr(param, "help", None) or ""
    return out


def test_every_help_text_is_shown_as_written() -> None:
    written = _help_texts(typer.main.get_command(app))
    shown = {k: Text.from_markup(v).plain for k, v in _help_texts(build_command()).items()}
    assert any("[kg]" in v for v in written.values())  # the case this guards exists
    lost = {k: (v, shown[k]) for k, v in written.items() if shown[k] != v}
    assert not lost, lost


@pytest.mark.parametrize(("command", "unit"), [("metrics", "[kg]"), ("bearing", "[kPa]")])
def test_units_in_rendered_help(capsys, monkeypatch, command: str, unit: str) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    main([command, "--help"])
    out = capsys.readouterr().out
    assert unit in out, re.sub(r"\s+", " ", out)[:2000]
