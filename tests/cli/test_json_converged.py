"""``converged`` of a ``--json`` document says what the run's solves did: ``true`` when every
solve converged, ``false`` when one did not, ``null`` only when the command solved nothing
(docs/user-guide/units-and-robustness.md). Before, ``sweep`` and ``report`` said ``null`` after
hundreds of solves, and a document printed before the run's record was read could say ``null``
while the run exited 3."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from skisnow.cli import main

REPORT = ["report", "skate", "--mass-kg", "60", "--snow-modulus-mpa", "100", "--points", "256",
          "--stride", "none", "--json"]  # fmt: skip


def _doc(capsys: pytest.CaptureFixture[str], args: list[str]) -> tuple[int, dict]:
    code = main(args)
    return code, json.loads(capsys.readouterr().out)


def test_a_sweep_says_its_solves_converged(capsys, tmp_path: Path) -> None:
    code, doc = _doc(capsys, ["sweep", "--ski", "skate", "--mass-kg", "30,60",
                              "--load-position-mm", "-120", "--snow-modulus-mpa", "100",
                              "--points", "256", "--workers", "0",
                              "--out", str(tmp_path / "s.zarr"), "--json"])  # fmt: skip
    assert code == 0 and doc["converged"] is True
    code, doc = _doc(capsys, ["skis", "--json"])  # solves nothing
    assert code == 0 and doc["converged"] is None


def test_a_report_says_whether_its_solves_converged(capsys, tmp_path: Path, monkeypatch) -> None:
    code, doc = _doc(capsys, [*REPORT, "--out", str(tmp_path / "a")])
    assert code == 0 and doc["converged"] is True
    import skisnow.contact

    original = skisnow.contact.solve_contact

    def starved(*args, **kwargs):  # the same solve with 2 iterations: it cannot converge
        return original(*args, **{**kwargs, "max_iter": 2})

    monkeypatch.setattr(skisnow.contact, "solve_contact", starved)
    code, doc = _doc(capsys, [*REPORT, "--out", str(tmp_path / "b")])
    assert code == 3 and doc["converged"] is False


def test_metrics_say_their_beam_solves_converged(capsys, tmp_path: Path) -> None:
    """``metrics`` of a ski solves the beam on the stone (solve_beam raises unless each solve
    converged): ``true``; of a bench file it interpolates the bench and solves nothing:
    ``null``."""
    code, doc = _doc(capsys, ["metrics", "classic", "--json"])
    assert code == 0 and doc["converged"] is True
    bench = tmp_path / "b.csv"
    assert main(["bench", "classic", "--mass-kg", "20,30,40,60,70",
                 "--load-position-mm", "-80", "--out", str(bench)]) == 0  # fmt: skip
    capsys.readouterr()
    code, doc = _doc(capsys, ["metrics", str(bench), "--json"])
    assert code == 0 and doc["converged"] is None
