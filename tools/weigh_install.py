"""Weigh skisnow's install: what each direct dependency costs and what it buys.

For every requirement of ``pyproject.toml`` (the default dependencies, each extra, the ``dev``
group) it prints the distributions that requirement brings in *alone* (not needed by any other
requirement of the same set), their size in the venv [MB], the size of their wheels in
``uv.lock`` [MB] (what an empty package cache downloads), and the time to import the module
with bytecode compiled (warm) and without (cold: the first run after an install, when every
``.py`` is compiled). Run it in the environment to weigh::

    uv run python tools/weigh_install.py                 # the default environment
    uv sync --all-extras && uv run python tools/weigh_install.py --markdown

Shared distributions (numpy, pandas, ...) are listed once, under "shared".
"""

from __future__ import annotations

import argparse
import importlib.metadata as md
import os
import re
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

from packaging.requirements import Requirement
from packaging.tags import sys_tags
from packaging.utils import canonicalize_name, parse_wheel_filename

#: The project whose pyproject.toml and uv.lock are read (default: this repository).
ROOT = Path(os.environ.get("WEIGH_ROOT", Path(__file__).resolve().parents[1]))
#: Requirements weighed as one unit (they serve one feature and share most of what they bring).
UNITS = {"jax": "camber network", "equinox": "camber network", "optax": "camber network",
         "optimistix": "camber network"}  # fmt: skip
#: The module a distribution is imported as, where the names differ.
MODULES = {
    "dask": "dask.array",
    "pyyaml": "yaml",
    "surfacetopography": "SurfaceTopography",
    "pillow": "PIL",
    "scipy": "scipy.sparse.linalg",
}


def _size_mb(dist: md.Distribution) -> float:
    total = 0
    for f in dist.files or ():
        p = Path(dist.locate_file(f))
        if p.is_file():
            total += p.stat().st_size
    return total / 1e6


def _installed() -> dict[str, md.Distribution]:
    return {canonicalize_name(d.metadata["Name"]): d for d in md.distributions()}


def _closure(name: str, dists: dict[str, md.Distribution], extras=()) -> set[str]:
    """Every installed distribution ``name`` (with ``extras``) pulls in, itself included."""
    seen, todo = set(), [(canonicalize_name(name), tuple(extras))]
    while todo:
        n, ex = todo.pop()
        if n in seen or n not in dists:
            continue
        seen.add(n)
        for r in dists[n].requires or ():
            req = Requirement(r)
            env = [{"extra": e} for e in ex] or [{"extra": ""}]
            if req.marker is None or any(req.marker.evaluate(e) for e in env):
                todo.append((canonicalize_name(req.name), tuple(req.extras)))
    return seen


def _wheel_mb() -> dict[str, float]:
    """Size of the wheel of each locked distribution that this interpreter would install."""
    lock = tomllib.loads((ROOT / "uv.lock").read_text(encoding="utf-8"))
    tags = {str(t): i for i, t in enumerate(sys_tags())}
    out = {}
    for pkg in lock["package"]:
        best = None
        for w in pkg.get("wheels", ()):
            fname = w["url"].rsplit("/", 1)[-1]
            _, ver, _, wtags = parse_wheel_filename(fname)
            if str(ver) != pkg["version"]:
                continue
            rank = min((tags.get(str(t), 10**9) for t in wtags), default=10**9)
            if rank < 10**9 and (best is None or rank < best[0]):
                best = (rank, w.get("size", 0))
        if best is not None:
            out[canonicalize_name(pkg["name"])] = max(out.get(pkg["name"], 0), best[1] / 1e6)
    return out


def _import_s(module: str, *, cold: bool) -> float | None:
    """Import time [s] of ``module`` in a fresh interpreter (median of 3 warm runs, or one cold
    run with no bytecode cache)."""
    env = dict(os.environ)
    times = []
    for _ in range(1 if cold else 3):
        with tempfile.TemporaryDirectory() as tmp:
            if cold:
                env["PYTHONPYCACHEPREFIX"] = tmp  # an empty bytecode cache, not written back
                env["PYTHONDONTWRITEBYTECODE"] = "1"
            else:
                env.pop("PYTHONDONTWRITEBYTECODE", None)
            code = f"import time; t = time.perf_counter(); import {module}; "
            code += "print(time.perf_counter() - t)"
            proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                                  text=True, check=False)  # fmt: skip
            if proc.returncode:
                return None
            times.append(float(proc.stdout.strip().splitlines()[-1]))
    times.sort()
    return times[len(times) // 2]


def requirement_sets() -> dict[str, list[Requirement]]:
    py = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    sets = {"default": [Requirement(r) for r in py["project"]["dependencies"]]}
    for extra, reqs in py["project"].get("optional-dependencies", {}).items():
        sets[f"extra {extra}"] = [Requirement(r) for r in reqs if not r.startswith("skisnow")]
    dev = py.get("dependency-groups", {}).get("dev", [])
    sets["group dev"] = [Requirement(r) for r in dev if isinstance(r, str)]
    sets["group dev"] = [r for r in sets["group dev"] if canonicalize_name(r.name) != "skisnow"]
    return sets


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--no-import", action="store_true", help="skip the import timings")
    p.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = p.parse_args()
    dists, wheels = _installed(), _wheel_mb()
    rows, claimed = [], {}
    units: dict[tuple[str, str], list[Requirement]] = {}
    for s, reqs in requirement_sets().items():
        for r in reqs:
            name = UNITS.get(canonicalize_name(r.name), r.name) if s == "default" else r.name
            units.setdefault((s, name), []).append(r)
    closures = {
        key: set().union(*(_closure(r.name, dists, r.extras) for r in reqs))
        for key, reqs in units.items()
    }
    for key, clo in closures.items():
        for d in clo:
            claimed.setdefault(d, set()).add(key)
    for key, reqs in units.items():
        s, _ = key
        own = sorted(d for d in closures[key] if claimed[d] == {key})
        installed = all(canonicalize_name(r.name) in dists for r in reqs)
        mb = sum(_size_mb(dists[d]) for d in own)
        wmb = sum(wheels.get(d, 0.0) for d in own)
        warm = cold = None
        if installed and not args.no_import:
            mods = [MODULES.get(canonicalize_name(r.name), re.sub(r"[-.]", "_", r.name).lower())
                    for r in reqs]  # fmt: skip
            warm = _import_s("; import ".join(mods), cold=False)
            cold = _import_s("; import ".join(mods), cold=True)
        label = " + ".join(str(r) for r in reqs)
        rows.append((s, label, installed, mb, wmb, warm, cold, own))
    shared = sorted(d for d, owners in claimed.items() if len(owners) > 1)
    rows.append(("shared", "(needed by several)", True, sum(_size_mb(dists[d]) for d in shared),
                 sum(wheels.get(d, 0.0) for d in shared), None, None, shared))  # fmt: skip
    total = sum(_size_mb(d) for d in dists.values())
    fmt = lambda v: "—" if v is None else f"{v:.2f}"  # noqa: E731
    if args.markdown:
        print("| set | requirement | venv MB | wheels MB | import warm s | import cold s "
              "| brings |")  # fmt: skip
        print("| --- | --- | ---: | ---: | ---: | ---: | --- |")
    for s, req, inst, mb, wmb, warm, cold, own in rows:
        brings = ", ".join(own) if inst else "(not installed)"
        if args.markdown:
            print(f"| {s} | `{req}` | {mb:.0f} | {wmb:.0f} | {fmt(warm)} | {fmt(cold)} "
                  f"| {brings} |")  # fmt: skip
        else:
            print(f"{s:18} {req:32} {mb:7.0f} MB {wmb:6.0f} MB  {fmt(warm):>5} {fmt(cold):>5} s"
                  f"  {brings}")  # fmt: skip
    print(f"\nvenv site-packages: {total:.0f} MB in {len(dists)} distributions")


if __name__ == "__main__":
    main()
