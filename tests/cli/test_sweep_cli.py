"""CLI of the maps: sweep (in process, resume, mismatch, --scheduler), plot, report, the contact
part of the demo. The real-subprocess smoke test of ``skisnow sweep`` is the SIGKILL/resume test
in ``tests/sweep/test_kill_resume.py``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from skisnow.cli import main
from skisnow.sweep import open_sweep

SMALL = [
    "--ski", "skate", "--ski", "classic", "--mass-kg", "30,60", "--load-position-mm", "-120",
    "--snow-modulus-mpa", "50,200", "--points", "512", "--profile-source", "beam",
]  # fmt: skip


def _json(capsys: pytest.CaptureFixture[str]) -> dict:
    return json.loads(capsys.readouterr().out)


def test_sweep_resume_and_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "s.zarr"
    assert main(["sweep", *SMALL, "--workers", "0", "--out", str(store), "--json"]) == 0
    doc = _json(capsys)
    assert doc["points"] == 8 and doc["computed_chunks"] == 4 and doc["skipped_chunks"] == 0
    ds = open_sweep(store)
    assert ds.sizes == {"ski": 2, "mass_kg": 2, "load_position_mm": 1, "snow_modulus_mpa": 2,
                        "zone": 7}  # fmt: skip
    assert ds.snow_modulus_mpa.values.tolist() == [50.0, 200.0]
    assert bool(ds.converged.all())
    np.testing.assert_allclose(ds.load_share.sel(zone="total"), 1.0, atol=1e-6)  # force balance
    # the regions (rear glide, kick zone, front glide) carry the whole load
    regions = ds.load_share.sel(zone=["rear_glide", "kick_zone", "front_glide"]).sum("zone")
    np.testing.assert_allclose(regions, 1.0, atol=1e-6)
    # the same command again: nothing to compute
    assert main(["sweep", *SMALL, "--workers", "0", "--out", str(store), "--json"]) == 0
    again = _json(capsys)
    assert again["computed_chunks"] == 0 and again["skipped_chunks"] == 4
    # plot: every figure promised (SVG here; PNG and SVG are checked in tests/sweep/test_maps.py)
    figs_dir = tmp_path / "figs"
    assert main(["plot", str(store), "--out", str(figs_dir), "--formats", "svg", "--json"]) == 0
    figs = [Path(p) for p in _json(capsys)["figures"]]
    assert len(figs) == 2 * 4 and all(p.is_file() and p.suffix == ".svg" for p in figs)


def test_sweep_errors_are_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "s.zarr"
    assert main(["sweep", *SMALL[:4], "--mass-kg", "30", "--snow-modulus-mpa", "50",
                 "--points", "512", "--profile-source", "beam", "--workers", "0",
                 "--out", str(store)]) == 0  # fmt: skip
    capsys.readouterr()
    # a different grid into the same store
    code = main(["sweep", *SMALL[:4], "--mass-kg", "30", "--snow-modulus-mpa", "80",
                 "--points", "512", "--profile-source", "beam", "--workers", "0",
                 "--out", str(store)])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "different sweep" in err and "snow_moduli" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert (
        main(["sweep", "--ski", "skate", "--mass-kg", "5:1:1", "--out", str(tmp_path / "x")]) == 2
    )
    assert "--mass-kg" in capsys.readouterr().err
    assert (
        main(
            [
                "sweep",
                "--ski",
                "nope",
                "--mass-kg",
                "30",
                "--snow-modulus-mpa",
                "50",
                "--workers",
                "0",
                "--out",
                str(tmp_path / "y"),
                "--profile-source",
                "beam",
            ]
        )
        == 2
    )
    assert "nope" in capsys.readouterr().err


def test_sweep_on_an_existing_scheduler(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as cluster:  # fmt: skip
        args = ["sweep", *SMALL, "--scheduler", cluster.scheduler_address, "--json"]
        assert main([*args, "--out", str(tmp_path / "s.zarr")]) == 0
    doc = _json(capsys)
    assert doc["workers"] == 2 and doc["computed_chunks"] == 4
    main(["sweep", *SMALL, "--workers", "0", "--out", str(tmp_path / "ref.zarr"), "--json"])
    a, b = open_sweep(tmp_path / "s.zarr"), open_sweep(tmp_path / "ref.zarr")
    assert a.identical(b)  # same numbers whichever engine ran the chunks


def test_report_command(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["report", "classic", "--out", str(tmp_path), "--profile-source", "beam",
                 "--mass-kg", "20,40,60", "--snow-modulus-mpa", "50,200", "--points", "512",
                 "--json"])  # fmt: skip
    assert code == 0
    path = Path(_json(capsys)["report"])
    text = path.read_text(encoding="utf-8")
    assert path.name == "classic_report.html" and "<svg" in text and "<script" not in text
    assert (tmp_path / "classic_maps_beam.zarr").is_dir()


@pytest.mark.slow
def test_contact_part_of_the_demo_writes_every_figure(tmp_path: Path) -> None:
    from skisnow.cli._demo import PAPER_CASES, run_contact_demo

    doc = run_contact_demo(
        tmp_path, profile_source="beam", n_points=512, masses=(30.0, 60.0),
        snow_moduli=(50e6, 200e6), progress=False,
    )  # fmt: skip
    files = [Path(f) for f in doc["files"]]
    assert all(f.exists() for f in files)
    names = {f.name for f in files}
    cases = [n for n in names if n.startswith(("fig4", "fig5", "fig6", "fig7"))]
    assert len(cases) == len(PAPER_CASES) and all(n.endswith(".png") for n in cases)
    for ski in ("classic", "skate"):
        # Figure 8 (area), Figure 9 (mean pressure), load share: skisnow.plot.sweep_figures
        for kind in ("area", "mean_pressure", "load_share"):
            assert f"{ski}_x-120mm_{kind}.png" in names
        assert f"{ski}_report.html" in names
        # the report links the explorer page written beside it
        assert 'href="explore.html"' in (tmp_path / f"{ski}_report.html").read_text("utf-8")
    assert "explore.html" in names
    assert all(c["converged"] for c in doc["cases"])
    # one sweep feeds the maps, the reports and the explorer: the page shows the maps' grid
    page = (tmp_path / "explore.html").read_text("utf-8")
    assert doc["sweep"]["points"] == 2 * 2 * 2 and "skisnow explorer" in page


def test_the_old_station_option_name_still_works(tmp_path, capsys) -> None:
    """One option name per concept: --points everywhere; --n-points stays as a hidden alias."""
    from skisnow.cli import main

    args = ["sweep", "--ski", "skate", "--mass-kg", "30", "--load-position-mm", "-120",
            "--snow-modulus-mpa", "100", "--profile-source", "beam", "--workers", "0",
            "--json"]  # fmt: skip
    assert main([*args, "--n-points", "256", "--out", str(tmp_path / "a.zarr")]) == 0
    old = capsys.readouterr()
    assert "--n-points is now --points" in old.err
    assert main([*args, "--points=256", "--out", str(tmp_path / "b.zarr")]) == 0
    assert "--n-points" not in capsys.readouterr().err
    from typer.testing import CliRunner

    from skisnow.cli._app import app

    help_text = CliRunner().invoke(app, ["sweep", "--help"]).output
    assert "--points" in help_text and "--n-points" not in help_text
