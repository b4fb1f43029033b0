"""The Figure 8–9 statements of Kalliorinne et al. (2023) on every shipped ski (issue 30).

    uv run python benchmarks/figure89_table.py            # compute, store, print (≈ 25 min CPU)
    uv run python benchmarks/figure89_table.py --reuse    # re-read the stored maps, print

For every shipped ski (plausible and reproduction) and both profile routes (the paper's camber
network, and the beam it emulates) the rear/front maps over 5–130 kg in 1 kg steps at
x_m = -120 mm and 20–400 MPa in 20 MPa steps (:func:`skisnow.paper.zone_maps`, 2048 stations)
are stored in ``docs/validation/data/fig89_<ski>_<route>.npz`` (+ ``.json``: what was computed),
the twelve statements read on the 1 kg grid and on the 2 kg grid (every other mass) by
:func:`skisnow.paper.figure89_findings`, the verdicts written to
``docs/validation/data/fig89_findings.json`` and printed as the markdown table of
``docs/validation/figures-8-9.md``. Nothing of Figures 8–9 is fitted: these are predictions.
``tests/paper/test_figure89_table.py`` checks the stored maps against fresh solves and the table
against the criteria.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[1] / "docs" / "validation" / "data"
ROUTES = ("network", "beam")


def maps_path(ski: str, route: str, folder: Path = DATA) -> Path:
    return folder / f"fig89_{ski}_{route}.npz"


def load_maps(ski: str, route: str, folder: Path = DATA):  # -> ZoneMaps
    from skisnow.paper import ZoneMaps

    meta = json.loads(maps_path(ski, route, folder).with_suffix(".json").read_text())
    with np.load(maps_path(ski, route, folder)) as z:
        arrays = {k: z[k] for k in z.files}
    return ZoneMaps.from_arrays(
        arrays, ski=meta["ski"], route=meta["route"],
        load_position_mm=meta["load_position_mm"], n_points=meta["n_points"],
    )  # fmt: skip


def save_maps(maps, folder: Path = DATA) -> Path:  # type: ignore[no-untyped-def]
    from skisnow import __version__

    folder.mkdir(parents=True, exist_ok=True)
    path = maps_path(maps.ski, maps.route, folder)
    np.savez_compressed(path, **maps.arrays())
    meta = {
        "ski": maps.ski, "route": maps.route, "load_position_mm": maps.load_position_mm,
        "n_points": maps.n_points, "masses_kg": [maps.masses_kg[0], maps.masses_kg[-1],
                                                 maps.step_kg],
        "moduli_mpa": maps.moduli_mpa.tolist(), "skisnow_version": __version__,
        "created_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }  # fmt: skip
    path.with_suffix(".json").write_text(json.dumps(meta, indent=1) + "\n")
    return path


def findings_table(skis: list[str], routes: list[str], folder: Path = DATA) -> dict:
    """{"columns": [...], "rows": {key: {"ski/route": [verdict, measured]}}} of stored maps."""
    from skisnow.paper import STATEMENTS, figure89_findings

    rows: dict[str, dict[str, list[str]]] = {key: {} for key in STATEMENTS}
    columns = []
    for ski in skis:
        for route in routes:
            maps = load_maps(ski, route, folder)
            col = f"{ski}/{route}"
            columns.append(col)
            for f in figure89_findings(maps, maps.every(2)):
                rows[f.key][col] = [f.verdict, f.measured]
    return {"columns": columns, "rows": rows}


def markdown(table: dict) -> str:
    from skisnow.paper import STATEMENTS

    cols = table["columns"]
    lines = [
        "| # | statement (Fig.) | " + " | ".join(cols) + " |",
        "| --- | --- | " + " | ".join("---" for _ in cols) + " |",
    ]
    for i, (key, (fig, _, _)) in enumerate(STATEMENTS.items(), 1):
        cells = [table["rows"][key][c][0] for c in cols]
        lines.append(f"| {i} | {key} ({fig}) | " + " | ".join(cells) + " |")
    counts = []
    for c in cols:
        v = [table["rows"][k][c][0] for k in STATEMENTS]
        counts.append(f"{v.count('yes')} / {v.count('partly')} / {v.count('no')}")
    lines.append("| | yes / partly / no | " + " | ".join(counts) + " |")
    return "\n".join(lines)


def main() -> None:
    from skisnow.paper import FIGURE89_MODULI_MPA, figure89_masses, zone_maps
    from skisnow.ski import SHIPPED_SKIS

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--skis", default=",".join(SHIPPED_SKIS))
    ap.add_argument("--routes", default=",".join(ROUTES))
    ap.add_argument("--reuse", action="store_true", help="read the stored maps, compute none")
    ap.add_argument("--out", type=Path, default=DATA)
    args = ap.parse_args()
    skis, routes = args.skis.split(","), args.routes.split(",")
    print(f"load average {os.getloadavg()[0]:.2f}")
    if not args.reuse:
        for ski in skis:
            for route in routes:
                t0 = time.process_time()
                maps = zone_maps(ski, figure89_masses(1.0), FIGURE89_MODULI_MPA, route=route)
                path = save_maps(maps, args.out)
                print(f"{ski} {route}: {time.process_time() - t0:.0f} s CPU -> {path}",
                      flush=True)  # fmt: skip
    table = findings_table(skis, routes, args.out)
    (args.out / "fig89_findings.json").write_text(json.dumps(table, indent=1) + "\n")
    print(markdown(table))
    print()
    for key, cells in table["rows"].items():
        for col, (verdict, measured) in cells.items():
            print(f"{key} [{col}] {verdict}: {measured}")
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
