"""How far is the paper's rigid-profile method from the flexible ski? (one command)
================================================================================

Kalliorinne et al. (2023, §3.2) press the profile loaded on the stone, as a rigid body, into the
snow and call the soft-snow results "more approximate due to the error inherited from the BEM
simulation with a rigid ski-camber profile". This script measures that error on the shipped
skis: every load case of the paper's Figures 4–7 (and the classic's half/full 60 kg at the three
positions of Figure 6), on snow of 20, 50, 100, 200 and 400 MPa and on the stone (70 GPa), solved
both ways on the same ski and grid:

* rigid: the beam's loaded profile on the stone (``profile_source='beam'``: the ground-truth
  profile of the same ski, so the difference is the rigid assumption alone, not the network);
* flexible: the beam and the half-space solved together (``ski_model='flexible'``).

It writes ``flexible_vs_rigid.csv`` (one row per case and snow: zone lengths, mean and peak
pressures, load shares, penetration, both ways) and ``flexible_vs_rigid.png/svg`` (the
differences against the snow modulus), and prints the table.

    uv run python examples/flexible_vs_rigid.py [--out DIR] [--small]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from skisnow.pipeline import solve_case
from skisnow.plot import save_figure

#: (ski, m [kg], x_m [mm]): the paper's load cases (Figures 4–7) and the classic's kick cases
CASES: tuple[tuple[str, float, float], ...] = (
    ("skate", 30, -120),
    ("skate", 60, -120),
    ("classic", 30, -120),
    ("classic", 60, -120),
    ("classic", 60, -70),
    ("classic", 60, -210),
)
#: snow moduli [MPa]; 70 000 is the bench stone
SNOWS: tuple[float, ...] = (20, 50, 100, 200, 400, 70_000)


def _row(case) -> dict:
    z = case.zones
    pen = (
        case.flexible.penetration
        if case.flexible is not None
        else float(np.max(case.solution.displacement))
    )
    return {
        "total_mm": z.total.length * 1e3,
        "kick_mm": z.kick.length * 1e3,
        "rear_mm": z.rear.length * 1e3,
        "front_mm": z.front.length * 1e3,
        "mean_kpa": z.total.mean_pressure * 1e-3,
        "peak_kpa": z.total.max_pressure * 1e-3,
        "kick_share_pct": z.kick.load_share * 100,
        "rear_share_pct": z.rear.load_share * 100,
        "penetration_um": pen * 1e6,
    }


def run(n_points: int) -> pd.DataFrame:
    """Both ski models on every case × snow; one row each with both results."""
    rows = []
    for ski, m, x_mm in CASES:
        for e in SNOWS:
            common = dict(mass=m, load_position=x_mm * 1e-3, snow_modulus=e * 1e6,
                          n_points=n_points)  # fmt: skip
            rigid = _row(solve_case(ski, profile_source="beam", **common))
            flex = _row(solve_case(ski, ski_model="flexible", **common))
            row = {"ski": ski, "mass_kg": m, "load_position_mm": x_mm, "snow_mpa": e}
            for k in rigid:
                row[f"{k}_rigid"] = rigid[k]
                row[f"{k}_flexible"] = flex[k]
            rows.append(row)
    return pd.DataFrame(rows)


def figure(table: pd.DataFrame):
    """Relative differences (flexible − rigid)/rigid against the snow modulus, per case."""
    from matplotlib.figure import Figure

    panels = (
        ("total_mm", "total contact length"),
        ("mean_kpa", "mean pressure"),
        ("peak_kpa", "peak pressure"),
        ("kick_share_pct", "kick-zone load share [points]"),
    )
    fig = Figure(figsize=(13.0, 3.6), layout="constrained")
    axes = fig.subplots(1, len(panels))
    if True:
        for ax, (key, title) in zip(axes, panels, strict=True):
            for (ski, m, x_mm), grp in table.groupby(["ski", "mass_kg", "load_position_mm"]):
                if key == "kick_share_pct" and ski != "classic":
                    continue
                e = grp["snow_mpa"].to_numpy().astype(float)
                e_plot = np.where(e > 1000, 1000.0, e)  # the stone drawn at the right edge
                r, f = grp[f"{key}_rigid"].to_numpy(), grp[f"{key}_flexible"].to_numpy()
                y = f - r if key == "kick_share_pct" else 100 * (f - r) / r
                ls = "-" if ski == "classic" else "--"
                ax.plot(e_plot, y, ls, marker="o", ms=3, label=f"{ski} {m:g} kg, {x_mm:g} mm")
            ax.axhline(0.0, color="black", lw=0.6)
            ax.set_xscale("log")
            ax.set_xticks([20, 50, 100, 200, 400, 1000])
            ax.set_xticklabels(["20", "50", "100", "200", "400", "stone"])
            ax.set_xlabel("snow modulus [MPa]")
            ax.set_title(title)
            ax.set_ylabel("flexible − rigid " + ("[% points]" if "share" in key else "[%]"))
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.suptitle(
            "The flexible ski against the paper's rigid profile (Kalliorinne et al. 2023, §3.2)"
        )
    return fig


def main() -> None:
    p = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])
    p.add_argument("--out", type=Path, default=Path("skisnow-examples"), help="output directory")
    p.add_argument("--small", action="store_true", help="1024 stations (fast; for tests)")
    p.add_argument("--formats", default="png,svg", help="figure formats")
    args = p.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    table = run(1024 if args.small else 4096)
    csv = args.out / "flexible_vs_rigid.csv"
    table.round(3).to_csv(csv, index=False)
    files = save_figure(figure(table), args.out / "flexible_vs_rigid",
                        formats=args.formats.split(","))  # fmt: skip
    show = table[["ski", "mass_kg", "load_position_mm", "snow_mpa"]].copy()
    for key, fmt in (("total_mm", "{:.0f}"), ("kick_mm", "{:.0f}"), ("mean_kpa", "{:.1f}"),
                     ("peak_kpa", "{:.1f}"), ("kick_share_pct", "{:.0f}"),
                     ("penetration_um", "{:.0f}")):  # fmt: skip
        show[key.rsplit("_", 1)[0] + " r/f"] = [
            f"{fmt.format(r)}/{fmt.format(f)}"
            for r, f in zip(table[f"{key}_rigid"], table[f"{key}_flexible"], strict=True)
        ]
    show["snow_mpa"] = show["snow_mpa"].map(lambda e: "stone" if e > 1000 else f"{e:g}")
    print("| " + " | ".join(show.columns) + " |")
    print("|" + "---|" * len(show.columns))
    for rec in show.itertuples(index=False):
        print("| " + " | ".join(str(v) for v in rec) + " |")
    print(f"wrote {csv} and {', '.join(str(f) for f in files)}")


if __name__ == "__main__":
    main()
