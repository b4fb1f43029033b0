"""Every command and every numeric option, listed FROM THE CLI APPLICATION ITSELF (the Click
command Typer builds from ``skisnow.cli.app``), fed the same bad values: NaN, ±inf, negative,
zero, huge, a unit slip both ways (the quantity's typical value ×1000 and ÷1000) and text.

A new command or option is enumerated without editing this file. Each value must be refused with
exit 2 by the option gate (``skisnow.cli._options``), naming the option, unless the option's
quantity (``skisnow._quantities``) says the value is possible and plausible (a negative load
position, a seed of 0): then it must be accepted. Never exit 1, never a silent acceptance. The
commands' bodies are replaced by a recorder (what is under test is the gate every command
passes before it computes or writes anything), so the test runs in a few seconds.
"""

from __future__ import annotations

import functools
import math
from collections import Counter

import pytest
import typer

from skisnow._quantities import QUANTITIES
from skisnow.cli import _app as cli_app
from skisnow.cli import app
from skisnow.cli._options import install_gate, numeric_kind, quantity_of

BAD = ("nan", "inf", "-inf", "negative", "zero", "huge", "x1000", "/1000", "abc")


@functools.cache
def _group():
    return typer.main.get_command(app)


def _options() -> list[tuple[str, object, str]]:
    group = _group()
    return [(name, p, kind) for name, cmd in group.commands.items() for p in cmd.params
            if (kind := numeric_kind(p)) is not None]  # fmt: skip


def _text(value: float, integer: bool) -> str:
    if integer and math.isfinite(value) and value == int(value):
        return str(int(value))
    return repr(float(value))


def _value(bad: str, typical: float, integer: bool) -> str:
    return {
        "nan": "nan", "inf": "inf", "-inf": "-inf", "abc": "abc", "zero": "0",
        "negative": _text(-abs(typical) or -1.0, integer),
        "huge": "1" + "0" * 30 if integer else "1e30",
        "x1000": _text((typical or 1.0) * 1000, integer),
        "/1000": _text((typical or 1.0) / 1000, integer),
    }[bad]  # fmt: skip


def _acceptable(text: str, key: str, integer_option: bool) -> bool:
    """What the quantity says of a value: possible and plausible."""
    q = QUANTITIES[key]
    try:
        v = float(text)
    except ValueError:
        return False
    if (q.integer or integer_option) and not (math.isfinite(v) and v.is_integer()):
        return False
    import numpy as np

    lo, hi = q.plausible
    return bool(q.possible(np.array([v]))[0]) and lo <= v <= hi


@functools.cache
def _base_argv(command: str) -> tuple[str, ...]:
    """A command line that parses: every required parameter with a typical value (numbers) or
    a placeholder (names and files; the command's body does not run)."""
    group = _group()
    argv = [command]
    for p in group.commands[command].params:
        if not p.required:
            continue
        kind, key = numeric_kind(p), quantity_of(command, p.opts[0]) if p.opts else None
        value = _text(QUANTITIES[key].typical, QUANTITIES[key].integer) if kind and key else "skate"
        if p.opts and p.opts[0].startswith("-"):
            argv += [p.opts[0]] + [value] * (p.nargs if p.nargs > 1 else 1)
        else:
            argv += [value] * (p.nargs if p.nargs > 1 else 1)
    return tuple(argv)


@pytest.fixture(scope="module")
def gated():
    """The gated command with every command's body replaced by a recorder."""
    group = install_gate(typer.main.get_command(app))
    ran: list[str] = []
    for name, cmd in group.commands.items():
        cmd.callback = lambda *a, _name=name, **k: ran.append(_name)
    return group, ran


def test_every_numeric_option_is_in_the_table_of_quantities() -> None:
    missing = [f"{c} {p.opts[0]}" for c, p, _ in _options() if quantity_of(c, p.opts[0]) is None]
    assert missing == [], "numeric options with no quantity in skisnow.cli._options"
    unknown = {quantity_of(c, p.opts[0]) for c, p, _ in _options()} - set(QUANTITIES)
    assert unknown == set()


def test_every_command_and_numeric_option_refuses_every_bad_value(
    gated, monkeypatch, capsys
) -> None:
    from skisnow.cli import main

    group, ran = gated
    monkeypatch.setattr(cli_app, "build_command", lambda: group)
    tally: Counter[str] = Counter()
    problems = []
    commands = set()
    for command, param, _kind in _options():
        option = param.opts[0]
        key = quantity_of(command, option)
        q = QUANTITIES[key]
        integer = "int" in str(param.type_descriptor.annotation)
        commands.add(command)
        base = list(_base_argv(command))
        assert main(base) == 0, f"{base}: the base command line must parse"
        capsys.readouterr()
        for bad in BAD:
            text = _value(bad, q.typical, integer)
            ran.clear()
            argv = [*base, option, *[text] * max(param.nargs, 1)]
            code = main(argv)
            err = capsys.readouterr().err
            ok = _acceptable(text, key, integer)
            if code == 1:
                tally["exit 1"] += 1
                problems.append(f"exit 1: {argv}: {err}")
            elif ok and code == 0 and ran == [command]:
                tally["accepted (valid)"] += 1
            elif not ok and code == 2 and not ran:
                tally["refused"] += 1
                tally["names the option"] += option in err
                if option not in err:
                    problems.append(f"does not name {option}: {argv}: {err}")
            elif not ok and code == 0:
                tally["silent"] += 1
                problems.append(f"silently accepted: {argv}")
            else:
                tally["other"] += 1
                problems.append(f"exit {code} (acceptable {ok}): {argv}: {err}")
    n = len(_options())
    with capsys.disabled():
        print(f"\noption enumeration: {len(commands)} commands, {n} numeric options x "
              f"{len(BAD)} values = {n * len(BAD)} runs: {dict(tally)}")  # fmt: skip
    assert not problems, "\n".join(problems[:40])
    assert tally["refused"] == tally["names the option"] > 0


def test_the_override_accepts_an_implausible_value_but_never_an_impossible_one(
    gated, monkeypatch, capsys
) -> None:
    from skisnow.cli import main

    group, _ = gated
    monkeypatch.setattr(cli_app, "build_command", lambda: group)
    argv = ["contact", "--ski", "skate", "--mass-kg", "60", "--load-position-mm", "-120"]
    assert main([*argv, "--snow-modulus-mpa", "1e8"]) == 2  # in Pa: refused
    assert main(["--allow-implausible", *argv, "--snow-modulus-mpa", "1e8"]) == 0
    assert main(["--allow-implausible", *argv, "--snow-modulus-mpa", "nan"]) == 2
    assert "--snow-modulus-mpa" in capsys.readouterr().err
