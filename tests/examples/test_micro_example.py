"""The S1–S5 micro example runs on a small map and prints its table and the two rankings."""

from __future__ import annotations

import runpy
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "examples" / "micro_s1_s5.py"


def test_micro_s1_s5_small(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture) -> None:
    monkeypatch.setattr(sys, "argv", [str(SCRIPT), "--small", "--workers", "1"])
    runpy.run_path(str(SCRIPT), run_name="__main__")
    out = capsys.readouterr().out
    for name in ("S1", "S2", "S3", "S4", "S5"):
        assert name in out
    assert "ranking bearing model" in out and "Pearson r" in out
    assert "False" not in out  # every elastic-plastic solve converged
