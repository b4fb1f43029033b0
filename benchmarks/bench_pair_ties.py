"""Is a ski a tie with its own identification? The "same ski?" test of pairs measured by coverage
and power (issue 25, item 4).

Run:  uv run python benchmarks/bench_pair_ties.py [--skis classic 1001 1002 1003]
      [--seeds 1-6] [--noise-um 5] [--bootstrap 0] [--bands laplace] [--jobs 2] [--cache DIR]
      [--out rows.jsonl]
      then ``--table --out rows.jsonl`` prints the table of the rows written.

For each true ski × noise seed:

* the true ski: the shipped ``classic`` (its definition), or a held-out plausible synthetic ski
  ``skisnow.bench.random_ski(seed)`` (1001-1003: fixed after the identification's development,
  as in ``bench_identify_coverage.py``);
* its bench by an implementation independent of the fit's forward model,
  ``skisnow.bench.reference_bench`` (finite differences, contact at every node of a 1 mm grid),
  on the shop plan (20, 40, ..., 120 kg at -40 and -120 mm, stations every 10 mm); the noise-free
  bench cached in ``--cache``, seeded Gaussian noise added (seed = the row's seed);
* ``skisnow.identify.identify_ski`` (defaults, BLAS on one thread) → the identified ski (with
  ``--bootstrap B`` also its bands widened by ``bootstrap_bands(replicates=B)``, as
  ``skisnow identify --bootstrap B``; with ``--discrepancy-bands`` the opt-in bands with the
  model discrepancy of the fit's own excess, ``identify_ski(discrepancy_bands=True)``; with
  ``--bands conformal`` the Laplace bands' conformal widths, ``identify_ski(bands='conformal')``);
* **coverage**: the identified ski paired with the truth, ``skisnow.workflows.same_ski``: a tie?
  (target: 95 % of the rows, the test's level), and the rule before (differences within the
  pointwise combined 95 % band at >= 95 % of the compared stations) on the same pair;
* **power**: the truth changed — EI × 1.10 everywhere; a 50 µm camber bump (Gaussian, sd 40 mm,
  rested again) at +100 mm (the kick zone of a classic, where the bench's z0 band is widest) or
  at -400 mm (the rear glide zone) — paired with the same identified ski: how often *not* a
  tie.

Prints one row per run and the table pooled per ski. Report the load average with the CPU.

``--calibrated-null SKI_FILE [--draws 400]``: the design check of the rule itself, no
identification — differences drawn from the identified ski's posterior (its modes, rescaled per
station to its bands: bands calibrated by construction) and judged by the new test and by the
rule before; a calibrated test ties at its level (95 %).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import dataclasses
import json
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

SHOP = dict(masses=(20, 40, 60, 80, 100, 120), load_positions=(-0.04, -0.12), station_step=0.010)


def true_ski(name: str):
    from skisnow.bench import random_ski
    from skisnow.ski import get_ski

    return get_ski(name) if not name.isdigit() else random_ski(int(name))


def bench_of(name: str, seed: int, noise_um: float, cache: Path):
    import pandas as pd

    from skisnow.bench import BenchData, read_bench, reference_bench, write_bench

    cache.mkdir(parents=True, exist_ok=True)
    path = cache / f"ref_{name}_shop_1mm.csv"
    if path.exists():
        clean = read_bench(path)
    else:
        clean = reference_bench(true_ski(name), **SHOP, dx=1e-3)
        write_bench(clean, path)
    t = clean.table.copy()
    t["height_mm"] = t["height_mm"] + np.random.default_rng(seed).normal(
        0.0, noise_um * 1e-3, len(t)
    )
    return BenchData(table=pd.DataFrame(t), metadata={**clean.metadata,
                     "noise_mm": noise_um * 1e-3, "seed": seed})  # fmt: skip


def stiffer(ski, factor: float = 1.10):
    ei = tuple(factor * np.asarray(ski.stiffness_values))
    return dataclasses.replace(ski, name=f"{ski.name} EI x{factor:g}", stiffness_values=ei)


def bumped(ski, height: float = 50e-6, at: float = 0.10, sd: float = 0.04):
    from skisnow.ski import lower_hull_bracket

    x = np.asarray(ski.camber_x)
    if x.size < 200:  # resolve the bump: the camber on a 5 mm grid
        x = np.arange(ski.camber_x[0], ski.camber_x[-1] + 1e-9, 0.005)
    z = ski.free_camber(x) + height * np.exp(-0.5 * ((x - at) / sd) ** 2)
    i, j = lower_hull_bracket(x, z, 0.0)
    z = z - (z[i] + (z[j] - z[i]) * (x - x[i]) / (x[j] - x[i]))
    return dataclasses.replace(ski, name=f"{ski.name} bump", camber_x=tuple(x),
                               camber_values=tuple(np.maximum(z, 0.0)), camber_sd=None)  # fmt: skip


def old_rule(a, b) -> bool:
    """The rule before: within the pointwise combined 95 % band at >= 95 % of the stations."""
    from types import SimpleNamespace

    from skisnow.workflows._pairs import _shape

    sa, sb = SimpleNamespace(**_shape(a)), SimpleNamespace(**_shape(b))
    # the identified ski b carries the bands; the truth a none; same grid (same x_tail, x_tip)
    n = min(sa.x.size, sb.x.size)
    both = sa.determined[:n] & sb.determined[:n]
    dz = (sa.z0[:n] - sb.z0[:n])[both]
    dk = (sa.log_ei[:n] - sb.log_ei[:n])[both]
    return bool(np.mean(np.abs(dz) <= 2 * sb.sd_z0[:n][both]) >= 0.95
                and np.mean(np.abs(dk) <= 2 * sb.sd_log_ei[:n][both]) >= 0.95)  # fmt: skip


def run_one(args: tuple) -> dict:
    name, seed, noise_um, cache, boot, disc, bands = args
    from skisnow.identify import identify_ski
    from skisnow.workflows import same_ski

    true = true_ski(name)
    bench = bench_of(name, seed, noise_um, Path(cache))
    t0 = time.process_time()
    res = identify_ski(bench, discrepancy_bands=disc, bands=bands)
    cpu = time.process_time() - t0
    if boot:
        from skisnow.identify import bootstrap_bands

        res = bootstrap_bands(res, bench, replicates=boot)
    ident = res.ski
    row = {"ski": name, "seed": seed, "noise_um": noise_um, "bootstrap": boot, "cpu": cpu,
           "discrepancy_bands": disc, "bands": bands,
           "cpu_total": time.process_time() - t0, "exit": 0 if res.converged else 3}  # fmt: skip
    for key, other in (("same", true), ("ei110", stiffer(true)), ("bump50", bumped(true)),
                       ("bump50r", bumped(true, at=-0.40))):  # fmt: skip
        t = same_ski(other, ident)
        row[f"{key}_tie"] = t.tie
        row[f"{key}_T"] = t.statistic
        row[f"{key}_c"] = t.critical
        row[f"{key}_worst"] = f"{t.worst[0]}@{t.worst[1] * 1e3:+.0f}"
    row["same_tie_old"] = old_rule(true, ident)
    return row


def calibrated_null(path: str, draws: int) -> None:
    from types import SimpleNamespace

    from skisnow.ski import read_ski
    from skisnow.workflows import same_ski_test
    from skisnow.workflows._pairs import _shape

    c = SimpleNamespace(**_shape(read_ski(path)))
    m = c.determined
    x, sz, sk, mz, mk = c.x[m], c.sd_z0[m], c.sd_log_ei[m], c.modes_z0[:, m], c.modes_log_ei[:, m]
    rng = np.random.default_rng(7)
    new = old = 0
    t0 = time.process_time()
    for _ in range(draws):
        xi = rng.standard_normal(mz.shape[0])
        dz = (xi @ mz) * sz / np.sqrt(np.sum(mz**2, axis=0)).clip(1e-12)
        dk = (xi @ mk) * sk / np.sqrt(np.sum(mk**2, axis=0)).clip(1e-12)
        old += np.mean(np.abs(dz) <= 2 * sz) >= 0.95 and np.mean(np.abs(dk) <= 2 * sk) >= 0.95
        new += same_ski_test(x=x, dz=dz, dk=dk, sd_z=sz, sd_k=sk, modes_z=mz, modes_k=mk).tie
    print(
        f"{path}: {draws} differences under 'same ski' with calibrated bands, {x.size} "
        f"stations, {mz.shape[0]} modes: a tie by the simultaneous test {new / draws:.3f}, "
        f"by the pointwise rule before {old / draws:.3f} ({time.process_time() - t0:.1f} s CPU)"
    )


def table(rows: list[dict]) -> None:
    print(
        "| ski | noise µm | bootstrap | runs | same ski: tie (new) | tie (old rule) | "
        "EI x1.10: not a tie | 50 µm bump at +100 / -400 mm: not a tie | "
        "median T / c (same) | CPU s (median) |"
    )
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: |")

    def key(r: dict) -> tuple:
        bands = f"{r['bootstrap']}" + (" + discrepancy" if r.get("discrepancy_bands") else "")
        bands += " + conformal" if r.get("bands") == "conformal" else ""
        return (r["ski"], r["noise_um"], bands)

    keys = sorted({key(r) for r in rows}, key=str)
    groups = [[r for r in rows if key(r) == k] for k in keys]
    pooled = {}
    for k, g in zip(keys, groups, strict=True):
        pooled.setdefault((k[1], k[2]), []).extend(g)
    for label, g in [*zip(keys, groups, strict=True),
                     *(((("all", *k)), g) for k, g in pooled.items())]:  # fmt: skip
        n = len(g)
        print(f"| {label[0]} | {label[1]:g} | {label[2]} | {n} "
              f"| {sum(r['same_tie'] for r in g)}/{n} | {sum(r['same_tie_old'] for r in g)}/{n} "
              f"| {sum(not r['ei110_tie'] for r in g)}/{n} "
              f"| {sum(not r['bump50_tie'] for r in g)}/{n}, "
              f"{sum(not r['bump50r_tie'] for r in g)}/{n} "
              f"| {np.median([r['same_T'] for r in g]):.2f} / "
              f"{np.median([r['same_c'] for r in g]):.2f} "
              f"| {np.median([r['cpu_total'] for r in g]):.1f} |")  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--skis", nargs="+", default=["classic", "1001", "1002", "1003"])
    ap.add_argument("--seeds", default="1-6", help="noise seeds a-b")
    ap.add_argument("--noise-um", type=float, default=5.0)
    ap.add_argument("--bootstrap", type=int, default=0)
    ap.add_argument("--discrepancy-bands", action="store_true",
                    help="identify_ski(discrepancy_bands=True): the bands with the model "
                    "discrepancy of the fit's own excess (opt-in)")  # fmt: skip
    ap.add_argument("--bands", default="laplace", choices=["laplace", "conformal"],
                    help="identify_ski(bands=...)")  # fmt: skip
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--cache", default=str(Path.home() / ".cache" / "skisnow-identify-bench"))
    ap.add_argument("--out", default=None, help="append every row as a JSON line")
    ap.add_argument("--table", action="store_true", help="only print the table of --out")
    ap.add_argument("--calibrated-null", default=None, help="an identified ski file (see above)")
    ap.add_argument("--draws", type=int, default=400)
    a = ap.parse_args()
    if a.calibrated_null:
        calibrated_null(a.calibrated_null, a.draws)
        return
    if a.table:
        table([json.loads(line) for line in Path(a.out).read_text().splitlines() if line])
        return
    lo, _, hi = a.seeds.partition("-")
    seeds = range(int(lo), int(hi or lo) + 1)
    jobs = [(s, k, a.noise_um, a.cache, a.bootstrap, a.discrepancy_bands, a.bands)
            for s in a.skis for k in seeds]  # fmt: skip
    print(f"load average at start: {os.getloadavg()}", flush=True)
    rows = []
    with ProcessPoolExecutor(max_workers=a.jobs) as ex:
        for row in ex.map(run_one, jobs):
            rows.append(row)
            print(json.dumps(row), flush=True)
            if a.out:
                with open(a.out, "a") as f:
                    f.write(json.dumps(row) + "\n")
    print(f"load average at end: {os.getloadavg()}")
    table(rows)


if __name__ == "__main__":
    main()
