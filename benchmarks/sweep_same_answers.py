"""Same answers: the Figure 8/9 sweep's store made by two checkouts, compared array by array.

    uv run python benchmarks/sweep_same_answers.py make /tmp/new.zarr --workers 2
    PYTHONPATH=<main>/src uv run python benchmarks/sweep_same_answers.py make /tmp/old.zarr
    uv run python benchmarks/sweep_same_answers.py compare /tmp/old.zarr /tmp/new.zarr

``make`` runs the sweep of ``bench_speed.py --rows sweep`` (skate, 126 masses × 20 moduli, beam
profiles, 4096 stations) into a new store, in this process (``--workers 0``) or on a local
cluster. ``compare`` prints, for every array of the two stores, whether it is bitwise equal
(``np.array_equal``, NaN equal to NaN) and otherwise its largest relative difference, then the
attributes that differ. Exit status 0 when every array is equal, 1 otherwise.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np


def make(out: Path, workers: int) -> None:
    from sweep_phases import spec

    import skisnow
    from skisnow.sweep import run_sweep

    run = run_sweep(spec(), out, workers=workers)
    print(f"skisnow at {Path(skisnow.__file__).parent}: {out}, compute {run.compute_time:.2f} s")


def compare(a_path: Path, b_path: Path) -> int:
    import zarr

    a, b = zarr.open_group(str(a_path), mode="r"), zarr.open_group(str(b_path), mode="r")
    names = sorted(set(a.array_keys()) | set(b.array_keys()))
    bad = 0
    for name in names:
        if name not in a or name not in b:
            print(f"  {name}: only in one store")
            bad += 1
            continue
        x, y = a[name][...], b[name][...]
        if x.shape == y.shape and np.array_equal(x, y, equal_nan=x.dtype.kind in "fc"):
            continue
        bad += 1
        if x.shape != y.shape:
            print(f"  {name}: shapes {x.shape} and {y.shape}")
            continue
        xf, yf = x.astype(float), y.astype(float)
        with np.errstate(all="ignore"):
            rel = np.nanmax(np.abs(xf - yf) / np.maximum(np.abs(xf), np.finfo(float).tiny))
        print(f"  {name}: differs, largest relative difference {rel:.3g}")
    ad, bd = dict(a.attrs), dict(b.attrs)
    attrs = sorted(k for k in set(ad) | set(bd) if ad.get(k) != bd.get(k))
    print(f"{len(names)} arrays, {len(names) - bad} bitwise equal; attributes that differ: "
          f"{attrs or 'none'}")  # fmt: skip
    return 0 if bad == 0 else 1


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    m = sub.add_parser("make")
    m.add_argument("out", type=Path)
    m.add_argument("--workers", type=int, default=0)
    c = sub.add_parser("compare")
    c.add_argument("a", type=Path)
    c.add_argument("b", type=Path)
    args = ap.parse_args()
    if args.cmd == "make":
        make(args.out, args.workers)
    else:
        sys.exit(compare(args.a, args.b))


if __name__ == "__main__":  # required: Dask workers re-import the main module
    main()
