"""Kill points of a sweep, counted: a kill after each file write of a two-chunk sweep (zarr's
LocalStore stops writing, as after SIGKILL), then the same sweep again; prints how many kills
left a temporary sibling (``.STEM.TAG-PID-RAND.SUFFIX``, the names ``skisnow._atomic`` makes) and
how many survived the next run. Runs against any checkout (``PYTHONPATH=<checkout>/src``), so the
figure before a change can be measured too::

    uv run python benchmarks/kill_points.py
"""

import contextlib
import tempfile
from pathlib import Path

import numpy as np
import zarr.storage

from skisnow.sweep import VARIABLES, SweepSpec, run_sweep


class Killed(Exception):
    pass


def chunk(spec, ski, position, modulus):
    n_m, n_z = len(spec.masses), len(spec.zones)
    base = np.outer(np.asarray(spec.masses), np.arange(1, n_z + 1)) * (modulus / 1e8)
    out = {}
    for name, var in VARIABLES.items():
        shape = (n_m, n_z) if "zone" in var.dims else (n_m,)
        value = base if "zone" in var.dims else base[:, 0] + position
        out[name] = np.asarray(value, dtype=float).reshape(shape).astype(var.dtype)
    return out


SPEC = SweepSpec(
    skis=("skate",),
    masses=(20.0, 60.0),
    load_positions=(-0.12,),
    snow_moduli=(50e6, 100e6),
    n_points=64,
    profile_source="beam",
)
orig = zarr.storage.LocalStore._set
st = {"n": 0, "k": None, "dead": False}


async def _set(self, key, value, exclusive=False):
    if st["dead"]:
        raise Killed
    await orig(self, key, value, exclusive=exclusive)
    st["n"] += 1
    if st["k"] is not None and st["n"] == st["k"]:
        st["dead"] = True
        raise Killed


zarr.storage.LocalStore._set = _set
d = Path(tempfile.mkdtemp())
run_sweep(SPEC, d / "ref.zarr", chunk_function=chunk, workers=0)
n = st["n"]
after_kill = survived = 0
for k in range(1, n + 1):
    st.update(n=0, k=k, dead=False)
    with contextlib.suppress(Killed):
        run_sweep(SPEC, d / f"k{k}.zarr", chunk_function=chunk, workers=0)
    st.update(n=0, k=None, dead=False)
    after_kill += bool(list(d.glob(f".k{k}.*-*.zarr")))
    run_sweep(SPEC, d / f"k{k}.zarr", chunk_function=chunk, workers=0)
    survived += bool(list(d.glob(f".k{k}.*-*.zarr")))
print(f"{n} kill points; {after_kill} kills left a temporary; {survived} survived the next run")
