"""skisnow reads every topography file it writes: `grind --out` then `topo` with no extra option
(the pixel size travels with the file: .npy sidecar, .npz, the text header, .x3p)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from skisnow import micro
from skisnow.cli import main


@pytest.mark.parametrize("suffix", [".npy", ".npz", ".txt", ".csv", ".x3p"])
def test_grind_then_topo_reads_it_back(tmp_path, capsys, suffix) -> None:
    out = tmp_path / f"s3{suffix}"
    args = ["grind", "S3", "--out", str(out), "--size-um", "96", "--pixel-um", "1.5", "--json"]
    assert main(args) == 0
    capsys.readouterr()
    assert main(["topo", str(out), "--json"]) == 0  # no --pixel-um needed
    doc = json.loads(capsys.readouterr().out)
    assert doc["pixel_um"] == pytest.approx([1.5, 1.5], rel=1e-12)
    assert doc["grid"] == [64, 64]
    original = micro.grind_preset("S3", size=96e-6, dx=1.5e-6)
    back = micro.read_topography(out)
    if suffix == ".x3p":  # stored as float64 by SurfaceTopography, re-read through its reader
        np.testing.assert_allclose(back.heights, original.heights, rtol=0, atol=1e-15)
    else:
        np.testing.assert_array_equal(back.heights, original.heights)  # exact
    assert (back.dx, back.dy) == pytest.approx((1.5e-6, 1.5e-6), rel=1e-12)
