"""Golden outputs: a representative set of solver results through the public names, to an .npz.

For refactorings that must not change a number: run it before and after, then compare bitwise::

    uv run python tools/golden_outputs.py /tmp/golden_before.npz       # on the old tree
    uv run python tools/golden_outputs.py /tmp/golden_after.npz        # on the new tree
    uv run python tools/golden_outputs.py --compare /tmp/golden_before.npz /tmp/golden_after.npz

It imports only names that users import (``skisnow.ski``, ``skisnow.pipeline``,
``skisnow.sweep``, ``skisnow.micro``), so it runs on a tree before and after a move of their
homes. Every number of every result (dataclass fields, dicts, arrays, a sweep's variables) is
stored under a dotted key; ``--compare`` checks each key with :func:`numpy.array_equal`
(``equal_nan``), i.e. bitwise for floats, and exits 1 on any difference or missing key. Takes
about a minute.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

# the rigid and flexible load cases (mass [kg], load position [m], snow modulus [Pa])
CASES = ((30.0, -0.12, 60e6), (65.0, -0.08, 100e6), (90.0, -0.16, 30e6))
N_POINTS = 1024


def _flatten(prefix: str, value: Any, out: dict[str, np.ndarray], depth: int = 0) -> None:
    """Every number below ``value`` into ``out`` under dotted keys (strings as 0-d arrays)."""
    if depth > 6 or value is None:
        return
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            _flatten(f"{prefix}.{f.name}", getattr(value, f.name), out, depth + 1)
    elif isinstance(value, dict):
        for k, v in value.items():
            _flatten(f"{prefix}.{k}", v, out, depth + 1)
    elif isinstance(value, list | tuple) and not all(
        isinstance(v, int | float | np.number) for v in value
    ):
        for i, v in enumerate(value):
            _flatten(f"{prefix}[{i}]", v, out, depth + 1)
    elif isinstance(value, str | bool | int | float | np.number | np.ndarray | list | tuple):
        out[prefix] = np.asarray(value)
    elif hasattr(value, "to_numpy") and hasattr(value, "columns"):  # a pandas table
        for c in value.columns:
            out[f"{prefix}.{c}"] = value[c].to_numpy()


def compute(progress: Callable[[str], None] = print) -> dict[str, np.ndarray]:
    """The golden outputs (see the module docstring)."""
    from skisnow.micro import bearing_area, grind_preset, ice_hardness
    from skisnow.pipeline import solve_case
    from skisnow.ski import (
        camber_profile,
        closing_load,
        get_ski,
        identify_ski,
        predict_identification_uncertainty,
        run_bench,
        shipped_network,
        ski_metrics,
        ski_passport,
        solve_beam,
    )
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep

    out: dict[str, np.ndarray] = {}
    for ski in ("classic", "skate"):
        progress(f"solve_case {ski}")
        for i, (m, xm, e) in enumerate(CASES):
            for source in ("network", "beam"):
                case = solve_case(ski, mass=m, load_position=xm, snow_modulus=e,
                                  n_points=N_POINTS, profile_source=source)  # fmt: skip
                _flatten(f"case.{ski}.{i}.rigid.{source}", case, out)
            case = solve_case(ski, mass=m, load_position=xm, snow_modulus=e,
                              n_points=N_POINTS, ski_model="flexible")  # fmt: skip
            _flatten(f"case.{ski}.{i}.flexible", case, out)
            sol = solve_beam(get_ski(ski), mass=m, load_position=xm)
            _flatten(f"beam.{ski}.{i}", sol, out)
        progress(f"camber_profile, network, metrics {ski}")
        for source in ("beam", "network"):
            x, h = camber_profile(ski, mass=np.array([20.0, 60.0]), load_position=-0.1,
                                  source=source)  # fmt: skip
            out[f"camber_profile.{ski}.{source}.x"], out[f"camber_profile.{ski}.{source}.h"] = x, h
        xs = np.linspace(-0.9, 0.9, 301)
        out[f"network.{ski}.predict"] = np.asarray(
            shipped_network(ski).predict(xs, np.array([10.0, 50.0, 110.0]), -0.14)
        )
        _flatten(f"metrics.{ski}", ski_metrics(ski), out)
        out[f"closing_load.{ski}"] = np.asarray(closing_load(ski))
        _flatten(f"passport.{ski}", ski_passport(get_ski(ski)), out)

    progress("run_bench")
    bench = run_bench("classic", masses=(20.0, 50.0, 80.0), load_positions=(-0.12, -0.16))
    _flatten("bench.clean", bench, out)
    noisy = run_bench("classic", masses=(30.0, 60.0), load_positions=(-0.12,), noise=1e-5, seed=7)
    _flatten("bench.noisy", noisy, out)

    progress("identify_ski")
    res = identify_ski(noisy, n_stiffness=8, n_camber=30, n_camber_max=60, max_nfev=40,
                       lambdas=(10.0, 1e3))  # fmt: skip
    _flatten("identify", dataclasses.replace(res, seconds=0.0), out)
    # what the clock writes into the provenance (when, how long) is not an output
    prov = "identify.ski.provenance"
    del out[f"{prov}.created"]
    for k in [k for k in out if k.startswith(f"{prov}.details[") and k.endswith("[0]")]:
        if str(out[k]) == "seconds":
            del out[k], out[k.removesuffix("[0]") + "[1]"]
    _flatten("identify.ski_arrays", {
        "stiffness": res.ski.stiffness(xs), "camber": res.ski.free_camber(xs)}, out)  # fmt: skip

    progress("predict_identification_uncertainty")
    plan = predict_identification_uncertainty(get_ski("classic"), (30.0, 60.0), (-0.12,), 1e-5,
                                              n_stiffness=8, n_camber=30,
                                              max_nfev=6)  # fmt: skip
    _flatten("bench_plan", plan, out)

    progress("sweep 2x2")
    spec = SweepSpec(skis=("skate",), masses=(40.0, 70.0), load_positions=(-0.1,),
                     snow_moduli=(50e6, 120e6), n_points=512)  # fmt: skip
    with tempfile.TemporaryDirectory() as tmp:
        run_sweep(spec, Path(tmp) / "s.zarr", workers=0)
        ds = open_sweep(Path(tmp) / "s.zarr")
        for name in sorted(ds.data_vars):
            out[f"sweep.{name}"] = np.asarray(ds[name].values)
        ds.close()

    progress("bearing model")
    topo = grind_preset("S2", size=2e-4, dx=1e-6, seed=3)
    bm = bearing_area(topo, diameter=40e-6, pressure=20e3, hardness=ice_hardness(-5.0))
    _flatten("bearing", bm, out)
    return {k: v for k, v in out.items() if v.dtype != object}


def compare(before: Path, after: Path) -> int:
    """Print the keys that differ (bitwise) or are missing; 0 when all are equal."""
    a, b = np.load(before), np.load(after)
    bad = 0
    for k in sorted(set(a.files) | set(b.files)):
        if k not in a.files or k not in b.files:
            print(f"missing in {'after' if k in a.files else 'before'}: {k}")
            bad += 1
        elif a[k].dtype.kind in "fc":
            if not np.array_equal(a[k], b[k], equal_nan=True):
                print(f"differs: {k}")
                bad += 1
        elif a[k].shape != b[k].shape or not np.array_equal(a[k], b[k]):
            print(f"differs: {k}")
            bad += 1
    n = len(set(a.files) | set(b.files))
    print(f"{n} keys, {sum(a[k].size for k in a.files)} numbers: {bad} differ or are missing")
    return 1 if bad else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="+", type=Path, help="OUT.npz, or BEFORE AFTER")
    parser.add_argument("--compare", action="store_true", help="compare two saved files")
    args = parser.parse_args(argv)
    if args.compare:
        if len(args.paths) != 2:
            parser.error("--compare takes two files")
        return compare(*args.paths)
    out = compute()
    np.savez(args.paths[0], **out)
    print(f"{len(out)} arrays -> {args.paths[0]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
