"""The real-contact examples run on small maps and print their tables."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _run(script: str, args: list[str], monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(sys, "argv", [str(EXAMPLES / script), *args])
    runpy.run_path(str(EXAMPLES / script), run_name="__main__")


@pytest.mark.slow
def test_findings_example(monkeypatch, capsys, tmp_path: Path) -> None:
    _run("multiscale_findings.py", ["--small", "--out", str(tmp_path)], monkeypatch)
    out = capsys.readouterr().out
    assert "Shares of the variation" in out and "Pearson r" in out
    assert (tmp_path / "camber_vs_texture.csv").is_file()
    assert (tmp_path / "s1_s5_ranking.csv").is_file()


@pytest.mark.slow
def test_verification_example(monkeypatch, capsys, tmp_path: Path) -> None:
    # the arguments the documentation's gallery passes (docs/conf.py, _example_argv)
    _run("micro_curves_verification.py", ["--out", str(tmp_path), "--small"], monkeypatch)
    out = capsys.readouterr().out
    assert "Westergaard" in out and "Refinement" in out
    assert (tmp_path / "references.csv").is_file() and (tmp_path / "refinement.csv").is_file()
