"""No work lost: a REAL sweep process (the CLI) is interrupted with Ctrl-C (SIGINT to its process
group, as a terminal does), restarted on a local Dask cluster and killed with SIGKILL (workers
included), then the same sweep is run again. Each restart must compute only chunks that were not
finished (0 finished chunks recomputed) and the end result must be the dataset of an
uninterrupted run."""

from __future__ import annotations

import contextlib
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

from skisnow import InputError
from skisnow.cli import main
from skisnow.sweep import SweepSpec, open_sweep, run_sweep
from skisnow.sweep._store import done_chunks

# 25 masses × 77 moduli = 77 chunks of 25 solves each (with 6 solves a chunk the faster solver
# and store finished all 20 chunks between the first one marked done and the Ctrl-C, at load 10;
# with 20 chunks of 25 solves, once the workers wrote their own chunks, the last chunks finished
# between the poll that saw enough of them done and the SIGKILL in 3 of ~10 runs at load 2-8:
# 77 chunks leave dozens undone whatever the poll's delay)
ARGS = [
    "sweep", "--ski", "skate", "--mass-kg", "5:125:5", "--load-position-mm", "-120",
    "--snow-modulus-mpa", "20:400:5", "--points", "512", "--profile-source", "beam",
]  # fmt: skip
#: The CLI in a child that takes Ctrl-C as a terminal job does, even where the test runner itself
#: was started ignoring SIGINT (a background job of a shell without job control, nohup: ignored
#: signals are inherited). Not a preexec_fn: that forces a fork, which JAX (imported by other
#: tests in the same run) warns against.
CMD = [
    sys.executable,
    "-c",
    "import signal; signal.signal(signal.SIGINT, signal.default_int_handler); "
    "from skisnow.cli import main; raise SystemExit(main())",
]


def _spec() -> SweepSpec:
    return SweepSpec(
        skis=("skate",),
        masses=np.arange(5.0, 126.0, 5.0),
        load_positions=(-0.12,),
        snow_moduli=np.arange(20.0, 401.0, 5.0) * 1e6,
        n_points=512,
        profile_source="beam",
    )


def _interrupt(
    store: Path, spec: SweepSpec, sig: int, at_least: int, workers: str
) -> tuple[int, str]:
    """Start the sweep, wait until ``at_least`` chunks are marked done, send ``sig`` to its
    process group; return (exit code, stderr)."""
    proc = subprocess.Popen(
        [*CMD, *ARGS, "--workers", workers, "--out", str(store)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, like a terminal job with its workers
    )
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            if (store / "chunk_done").exists() and len(done_chunks(store, spec)) >= at_least:
                break
            if proc.poll() is not None:
                pytest.fail(f"sweep ended before it could be interrupted: {proc.stderr.read()}")
            time.sleep(0.02)
        else:
            pytest.fail("the sweep made no progress within 120 s")
    finally:
        os.killpg(proc.pid, sig)
        try:
            code = proc.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            code = proc.wait()
        err = proc.stderr.read()
        proc.stderr.close()
        if sig != signal.SIGKILL:  # workers that outlived the interrupted client
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGKILL)
    return code, err


@pytest.mark.slow
def test_ctrl_c_then_sigkill_then_resume(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    store = tmp_path / "fig8.zarr"
    spec = _spec()
    everything = set(spec.chunks())

    # 1. Ctrl-C (sweep computing in its own process): a clean, non-zero exit saying what was kept
    code, err = _interrupt(store, spec, signal.SIGINT, at_least=1, workers="0")
    after_ctrl_c = done_chunks(store, spec)
    assert code != 0 and "interrupted" in err, err[-500:]
    assert 1 <= len(after_ctrl_c) < len(everything)

    # 2. restarted on a local Dask cluster, then SIGKILLed (no clean-up, workers included)
    code, _ = _interrupt(store, spec, signal.SIGKILL, at_least=len(after_ctrl_c) + 2, workers="1")
    after_kill = done_chunks(store, spec)
    assert code == -signal.SIGKILL
    assert after_ctrl_c < after_kill < everything, "killed too late to test resuming"
    with pytest.raises(InputError, match="not computed yet"):
        open_sweep(store)

    # 3. the same command again (in this process, to save an interpreter start-up; it starts
    # its own local cluster): exactly the missing chunks are computed
    capsys.readouterr()
    assert main([*ARGS, "--workers", "1", "--out", str(store), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    recomputed = {tuple(k) for k in doc["computed"]}
    assert recomputed.isdisjoint(after_kill), "a finished chunk was recomputed"
    assert recomputed | after_kill == everything
    assert doc["skipped_chunks"] == len(after_kill)

    # the same dataset as an uninterrupted run (computed here, in process, without Dask)
    reference = tmp_path / "reference.zarr"
    run_sweep(spec, reference, workers=0)
    xr.testing.assert_identical(open_sweep(store), open_sweep(reference))
