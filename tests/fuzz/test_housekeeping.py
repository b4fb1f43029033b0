"""Housekeeping after kills: no temporary file or folder survives the next run of the same
command. The temporaries are found with :func:`skisnow._atomic.temporary_siblings`, whose
pattern is made by the one function that makes their names, so these tests look for exactly
what the code can leave (the sweep's own kill points: tests/sweep/test_kill_points.py)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import skisnow._atomic as atomic
from skisnow._atomic import (
    atomic_path,
    atomic_write,
    remove_stale_siblings,
    scratch_directory,
    temporary_sibling,
    temporary_siblings,
)


def _dead_pid() -> int:
    """The id of a process that has ended."""
    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    return int(proc.stdout)


def _sibling_of(pid: int, target: Path, tag: str = "tmp") -> Path:
    """A temporary sibling of ``target`` as process ``pid`` would have named it."""
    mine = temporary_sibling(target, tag=tag)
    return mine.with_name(mine.name.replace(f"-{os.getpid()}-", f"-{pid}-", 1))


def test_the_pattern_finds_every_name_the_maker_makes_and_nothing_else(tmp_path) -> None:
    target = tmp_path / "cycle_a.b.csv"
    made = [temporary_sibling(target, tag=t) for t in atomic.TEMPORARY_TAGS]
    others = [
        temporary_sibling(tmp_path / "cycle_a.csv"),  # another target's
        temporary_sibling(tmp_path / "cycle_a.b.nc"),
        tmp_path / ".cycle_a.b.csv.tmp-1-ab",  # the pattern the old clean-up looked for
        tmp_path / "cycle_a.b.csv",
    ]
    for p in made + others:
        p.write_text("x")
    assert [s.path for s in temporary_siblings(target)] == sorted(made)
    assert {s.tag for s in temporary_siblings(target)} == set(atomic.TEMPORARY_TAGS)


def test_a_dead_writers_temporary_is_removed_by_the_next_write(tmp_path) -> None:
    target = tmp_path / "report.html"
    dead = _sibling_of(_dead_pid(), target)
    dead.write_text("half a page")
    alive = _sibling_of(1, target)  # process 1 runs: its write may be in progress
    alive.write_text("being written")
    atomic_write(target, "whole page")
    assert target.read_text() == "whole page"
    assert [s.path for s in temporary_siblings(target)] == [alive]


def test_a_folder_moved_aside_by_a_killed_replace_is_put_back(tmp_path) -> None:
    target = tmp_path / "store"
    old = _sibling_of(_dead_pid(), target, tag="old")
    old.mkdir()
    (old / "data").write_text("previous complete version")
    remove_stale_siblings(target)
    assert (target / "data").read_text() == "previous complete version"
    assert temporary_siblings(target) == []


def test_a_kill_before_the_rename_leaves_a_temporary_that_the_next_run_removes(
    tmp_path, monkeypatch
) -> None:
    target = tmp_path / "a.csv"

    class Killed(BaseException):
        pass

    def killed(*_):
        raise Killed

    with monkeypatch.context() as m:
        m.setattr(atomic.os, "replace", killed)
        m.setattr(atomic, "_remove", lambda p: None)  # a SIGKILL runs no clean-up
        with pytest.raises(Killed), atomic_path(target) as tmp:
            tmp.write_text("new")
    assert len(temporary_siblings(target)) == 1  # what the kill left (this process's own)
    atomic_write(target, "new")
    assert temporary_siblings(target) == []


def test_scratch_folders_of_killed_runs_are_removed(tmp_path, monkeypatch) -> None:
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    stale = tmp_path / f"skisnow-explore-{_dead_pid()}-abc"
    stale.mkdir()
    live = tmp_path / "skisnow-explore-1-abc"
    live.mkdir()
    with scratch_directory("explore") as d:
        assert d.is_dir() and d.name.startswith(f"skisnow-explore-{os.getpid()}-")
    assert not stale.exists() and live.exists() and not d.exists()


def test_scratch_folder_in_memory_is_cleaned_and_falls_back(tmp_path, monkeypatch) -> None:
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    ram = atomic._ram_disk()
    with scratch_directory("explore", in_memory=True) as d:
        assert d.is_dir() and d.parent == (Path(ram) if ram else tmp_path)
    assert not d.exists()
    monkeypatch.setattr(atomic, "_ram_disk", lambda: None)  # no RAM disk: the temporary dir
    with scratch_directory("explore", in_memory=True) as d:
        assert d.parent == tmp_path
    assert not d.exists()


CYCLE = ["cycle", "skate", "--template", "diagonal", "--body-mass-kg", "70", "--frames", "3",
         "--points", "256", "--snow-modulus-mpa", "100"]  # fmt: skip


@pytest.mark.slow
def test_cycle_killed_before_each_rename_leaves_nothing_after_the_next_run(
    tmp_path, monkeypatch, capsys
) -> None:
    from skisnow.cli import main

    class Killed(BaseException):
        """Stands for SIGKILL just before a rename: no clean-up runs."""

    real_replace, real_remove = atomic.os.replace, atomic._remove
    state = {"n": 0, "k": 0}

    def replace(src, dst):
        state["n"] += 1
        if state["n"] == state["k"]:
            raise Killed(f"killed before rename {state['n']} ({dst})")
        return real_replace(src, dst)

    monkeypatch.setattr(atomic.os, "replace", replace)
    out = tmp_path / "reference"
    assert main([*CYCLE, "--out", str(out)]) == 0
    n_renames = state["n"]
    outputs = sorted(p.name for p in out.iterdir())
    assert n_renames >= len(outputs) >= 5
    left_by_kills = 0
    for k in range(1, n_renames + 1):
        out = tmp_path / f"k{k}"
        state.update(n=0, k=k)
        monkeypatch.setattr(atomic, "_remove", lambda p: None)
        with pytest.raises(Killed):
            main([*CYCLE, "--out", str(out)])
        monkeypatch.setattr(atomic, "_remove", real_remove)
        left_by_kills += sum(len(temporary_siblings(out / name)) for name in outputs)
        state.update(n=0, k=0)
        assert main([*CYCLE, "--out", str(out)]) == 0
        assert sorted(p.name for p in out.iterdir()) == outputs, f"kill point {k}"
        assert all(temporary_siblings(out / name) == [] for name in outputs), f"kill point {k}"
    assert left_by_kills == n_renames  # each kill left its temporary; none survived the rerun
    capsys.readouterr()
