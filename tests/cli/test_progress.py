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
