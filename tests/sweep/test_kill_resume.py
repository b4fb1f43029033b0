"""No work lost: a REAL sweep process (the CLI on a local Dask cluster) is killed with SIGKILL
mid-way, then the same command is run again. It must compute exactly the chunks that were not
finished (0 finished chunks recomputed) and end with the same dataset as an uninterrupted run."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from skisnow.cli import main
from skisnow.sweep import SweepSpec, open_sweep, run_sweep
from skisnow.sweep._store import done_chunks

MASSES, MODULI = "5:60:5", "20:200:20"  # 12 masses × 10 moduli = 10 chunks of 12 solves
ARGS = [
    "sweep", "--ski", "skate", "--mass-kg", MASSES, "--load-position-mm", "-120",
    "--snow-modulus-mpa", MODULI, "--n-points", "2048", "--profile-source", "beam",
    "--workers", "1",
]  # fmt: skip
CMD = [sys.executable, "-c", "from skisnow.cli import main; raise SystemExit(main())"]


def _spec() -> SweepSpec:
    return SweepSpec(
        skis=("skate",),
        masses=np.arange(5.0, 61.0, 5.0),
        load_positions=(-0.12,),
        snow_moduli=np.arange(20.0, 201.0, 20.0) * 1e6,
        n_points=2048,
        profile_source="beam",
    )


@pytest.mark.slow
def test_sigkill_mid_sweep_then_resume(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    store = tmp_path / "fig8.zarr"
    spec = _spec()
    n_chunks = len(spec.chunks())
    proc = subprocess.Popen(
        [*CMD, *ARGS, "--out", str(store)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,  # its own process group: the kill takes its Dask workers too
    )
    try:
        deadline = time.monotonic() + 90
        while time.monotonic() < deadline:
            if (store / "chunk_done").exists() and len(done_chunks(store, spec)) >= 2:
                break
            if proc.poll() is not None:
                pytest.fail(f"sweep ended before it could be killed: {proc.stderr.read()!r}")
            time.sleep(0.05)
        else:
            pytest.fail("no chunk finished within 90 s")
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        proc.stderr.close()
    finished = done_chunks(store, spec)
    assert 2 <= len(finished) < n_chunks, f"killed too late: {len(finished)} of {n_chunks} done"
    with pytest.raises(Exception, match="not computed yet"):
        open_sweep(store)

    # The same command again (in this process, to save an interpreter start-up; it still starts
    # its own local cluster of one worker process).
    capsys.readouterr()
    assert main([*ARGS, "--out", str(store), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    recomputed = {tuple(k) for k in doc["computed"]}
    assert recomputed.isdisjoint(finished), "a finished chunk was recomputed"
    assert recomputed | finished == set(spec.chunks())
    assert doc["skipped_chunks"] == len(finished)

    # the same dataset as an uninterrupted run (computed here, in process, without Dask)
    reference = tmp_path / "reference.zarr"
    run_sweep(spec, reference, workers=0)
    xr.testing.assert_identical(open_sweep(store), open_sweep(reference))
