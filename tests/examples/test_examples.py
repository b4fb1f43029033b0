"""The examples run (on small grids) and write the figures they promise.

They are executed in this interpreter with ``runpy`` (as ``__main__``, with their own argv) so the
suite pays the imports once; ``fig8_9_maps.py`` runs its sweep in process (``--workers 0``).
"""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CASES = {
    "fig4_stone.py": ["fig4_classic_stone", "fig4_skate_stone"],
    "fig5_load.py": ["fig5_skate_30kg", "fig5_skate_60kg"],
    "fig6_position.py": ["fig6_classic_x-210mm", "fig6_classic_x-70mm"],
    "fig7_snow.py": ["fig7_classic_50MPa", "fig7_classic_200MPa"],
    "fig8_9_maps.py": ["skate_x-120mm_area", "skate_x-120mm_mean_pressure",
                       "skate_x-120mm_load_share"],
}  # fmt: skip


def _run(script: str, args: list[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "argv", [str(EXAMPLES / script), *args])
    monkeypatch.syspath_prepend(str(EXAMPLES))
    runpy.run_path(str(EXAMPLES / script), run_name="__main__")


@pytest.mark.parametrize("script", sorted(CASES))
def test_example_runs_on_a_small_grid(
    script: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    args = ["--small", "--out", str(tmp_path), "--profile-source", "beam", "--formats", "png,svg"]
    if script == "fig8_9_maps.py":
        args += ["--workers", "0", "--skis", "skate"]  # one ski is enough to test the script
    _run(script, args, monkeypatch)
    out = capsys.readouterr().out
    for stem in CASES[script]:
        for fmt in ("png", "svg"):
            f = tmp_path / f"{stem}.{fmt}"
            assert f.is_file() and f.stat().st_size > 1000, f
            assert str(f) in out  # the script says what it wrote where
    assert "converged': False" not in out


def test_every_example_is_tested() -> None:
    scripts = {p.name for p in EXAMPLES.glob("fig*.py")}
    assert scripts == set(CASES)
