"""The CLI's one progress bar: a library progress callback, shown on stderr, silent with --json."""

from __future__ import annotations

from skisnow.cli._render import progress_bar


def test_callback_signatures_and_silence(capsys) -> None:
    # run_bench/bearing_sweep call progress(done, total); run_sweep on_progress(done, total, key)
    with progress_bar("quiet", disable=True) as bar:
        bar(1, 4)
        bar(2, 4, (0, 0, 1))
        bar(3, None, status="x", label="y")
    assert bar.completed == 3 and bar.total == 4
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""


def test_shown_on_stderr_only(capsys) -> None:
    with progress_bar("bench skate", transient=False) as bar:
        for done in range(1, 4):
            bar(done, 3)
    captured = capsys.readouterr()
    assert captured.out == ""  # stdout stays free for tables and the one JSON document
    assert "bench skate" in captured.err and "3/3" in captured.err


def test_ctrl_c_while_the_bar_starts_leaves_it_closable(monkeypatch) -> None:
    # A Ctrl-C between rich's Live marking itself started and pushing itself on the console's
    # live stack (the moment the first chunk of a sweep reports progress) must still end as an
    # interrupt: the KeyboardInterrupt comes once the bar has started, and closing the bar
    # afterwards works (before: IndexError 'pop from empty list', an "internal error").
    import signal

    from rich.console import Console

    from skisnow.cli._render import err_console

    real = Console.set_live

    def set_live(self, live):
        signal.raise_signal(signal.SIGINT)  # Ctrl-C in the middle of Live.start
        return real(self, live)

    monkeypatch.setattr(Console, "set_live", set_live)
    # Python's own Ctrl-C handler even where the test runner was started with SIGINT ignored
    # (a background job of a shell without job control, nohup)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    bar = progress_bar("interrupted", transient=True)
    try:
        bar(1, 10)
    except KeyboardInterrupt:
        interrupted = True
    else:
        interrupted = False
    finally:
        signal.signal(signal.SIGINT, previous)
    monkeypatch.undo()
    bar.close()
    assert interrupted
    assert not bar._bar.live.is_started and not err_console._live_stack
