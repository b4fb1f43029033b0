"""Shared by the figure scripts: solve one load case and draw it like the paper's Figures 4–7.

Not part of the library: a few lines of glue that each example would otherwise repeat.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from skisnow.constants import MPA
from skisnow.pipeline import solve_case
from skisnow.plot import plot_contact, save_figure


def parser(description: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--out", type=Path, default=Path("skisnow-examples"), help="output directory")
    p.add_argument("--small", action="store_true", help="coarse grid (fast; for tests)")
    p.add_argument("--profile-source", default="network", choices=("network", "beam"))
    p.add_argument("--formats", default="png,svg", help="figure formats")
    return p


def case(
    args: argparse.Namespace,
    *,
    ski: str,
    mass_kg: float,
    load_position_mm: float,
    snow_modulus_mpa: float,
    stem: str,
) -> dict:
    """Solve one case, save its picture, return its zone numbers (field units)."""
    case_ = solve_case(
        ski,
        mass=mass_kg,
        load_position=load_position_mm * 1e-3,
        snow_modulus=snow_modulus_mpa * MPA,
        profile_source=args.profile_source,
        n_points=1024 if args.small else 4096,
    )
    solution, zones = case_.solution, case_.zones
    title = (
        f"{ski}: m = {mass_kg:g} kg at x_m = {load_position_mm:g} mm, "
        f"E_counter = {snow_modulus_mpa:g} MPa"
    )
    fig = plot_contact(solution, zones, title=title)
    files = save_figure(fig, args.out / stem, formats=args.formats.split(","))
    row = {"case": stem, "converged": solution.converged}
    for name in ("rear", "middle", "front"):
        z = zones[name]
        if z.patches:
            row[f"{name}_length_mm"] = round(z.length * 1e3, 1)
            row[f"{name}_mean_kpa"] = round(z.mean_pressure / 1e3, 1)
            row[f"{name}_share_pct"] = round(z.load_share * 100, 1)
    row["files"] = [str(f) for f in files]
    return row


def report(rows: list[dict], paper: str) -> None:
    for row in rows:
        numbers = {k: v for k, v in row.items() if k not in ("files", "case")}
        print(f"{row['case']}: {numbers}")
        for f in row["files"]:
            print(f"  wrote {f}")
    print(f"paper (measured Fischer skis, not these virtual ones): {paper}")
