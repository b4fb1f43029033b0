"""A Ctrl-C is reported as an interruption (exit 130) wherever it lands, even in a kernel.

A ``KeyboardInterrupt`` raised while a numba kernel runs reaches Python as ``SystemError:
CPUDispatcher(...) returned a result with an exception set``, chained from the interrupt; the
sweep's kill-and-resume test once saw it reported as an internal error (exit 1).
"""

from __future__ import annotations

import numba
import pytest

from skisnow.cli import _app


@numba.njit(cache=False)
def _kernel(x: float) -> float:
    return x * 2.0


def _systemerror_from_ctrl_c() -> SystemError:
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as ki:
            raise SystemError(
                "CPUDispatcher(<function pk_dense>) returned a result with an exception set"
            ) from ki
    except SystemError as exc:
        return exc


def test_the_chain_is_searched_for_the_interrupt() -> None:
    assert _app.interrupted_by_user(KeyboardInterrupt())
    assert _app.interrupted_by_user(_systemerror_from_ctrl_c())
    assert not _app.interrupted_by_user(SystemError("a real bug"))
    assert not _app.interrupted_by_user(ValueError("bad"))
    # a cycle in the chain ends the search instead of looping
    a, b = ValueError("a"), ValueError("b")
    a.__context__, b.__context__ = b, a
    assert not _app.interrupted_by_user(a)


@pytest.mark.parametrize(
    ("raised", "code", "said"),
    [
        ("chained", 130, "interrupted"),
        ("plain", 130, "interrupted"),
        ("bug", 1, "internal error"),
    ],
)
def test_run_maps_the_interrupt_to_exit_130(
    monkeypatch, capsys, raised: str, code: int, said: str
) -> None:
    def command(**_kw):
        _kernel(1.0)  # a compiled kernel ran, as in the sweep
        if raised == "chained":
            raise _systemerror_from_ctrl_c()
        if raised == "plain":
            raise KeyboardInterrupt
        raise SystemError("a real bug")

    monkeypatch.setattr(_app, "build_command", lambda: command)
    assert _app._run(["contact"]) == code
    assert said in capsys.readouterr().err
