"""`skisnow pairs` with a ski carrying its posterior: the simultaneous "same ski?" test in the
JSON document (``tie_test``), a tie for the ski's own definition, not a tie for a ski 10 %
stiffer than its bands allow (issue 25, item 4)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from skisnow.cli import main
from skisnow.ski import get_ski, write_ski


def _with_posterior(ski, *, k: int = 12, sd_log_ei: float = 0.02, sd_z0: float = 5e-6):
    """``ski`` with smooth posterior modes (Gaussian bumps) and the bands they imply."""
    ex, cx = np.asarray(ski.stiffness_x), np.asarray(ski.camber_x)
    centres = np.linspace(ski.x_tail, ski.x_tip, k)
    me = np.exp(-0.5 * ((ex[None, :] - centres[:, None]) / 0.15) ** 2)
    mz = np.exp(-0.5 * ((cx[None, :] - centres[:, None]) / 0.15) ** 2)
    me *= sd_log_ei / np.sqrt(np.sum(me**2, axis=0))
    mz *= sd_z0 / np.sqrt(np.sum(mz**2, axis=0))
    return dataclasses.replace(
        ski, name=f"{ski.name} identified", stiffness_log_sd=tuple(np.full(ex.size, sd_log_ei)),
        camber_sd=tuple(np.full(cx.size, sd_z0)), stiffness_modes=tuple(map(tuple, me)),
        camber_modes=tuple(map(tuple, mz)),
    )  # fmt: skip


def test_pairs_reports_the_simultaneous_tie_test(capsys, tmp_path: Path) -> None:
    classic = get_ski("classic")
    same = write_ski(_with_posterior(classic), tmp_path / "same.json")
    stiff = dataclasses.replace(
        classic, stiffness_values=tuple(1.10 * np.asarray(classic.stiffness_values))
    )
    stiffer = write_ski(_with_posterior(stiff), tmp_path / "stiffer.json")
    for path, tie in ((same, True), (stiffer, False)):
        code = main(["pairs", "classic", str(path), "--body-mass-kg", "70",
                     "--snow-modulus-mpa", "100", "--points", "512", "--json"])  # fmt: skip
        doc = json.loads(capsys.readouterr().out)
        assert code == 0
        (pair,) = doc["pairs"]
        test = pair["tie_test"]
        assert pair["tie_within_uncertainty"] is tie and test["method"] == "sup-t"
        assert test["level"] == 0.95 and test["draws"] == 4000
        assert (test["statistic"] <= test["critical_value"]) is tie
        assert 2.0 < test["critical_value"] < 4.5
        if not tie:  # ln 1.10 / 0.02 = 4.8 band sd everywhere
            assert test["worst"] == "stiffness"
            assert test["statistic"] == pytest.approx(np.log(1.10) / 0.02, rel=1e-6)
    assert "sup-t" in doc["distance"]
