"""Largest jump of each zone and region metric over a load sweep in 1 kg steps (issue 26).

    uv run python benchmarks/zone_continuity.py              # the full table (≈ 10 min)
    uv run python benchmarks/zone_continuity.py --quick      # 256 stations, fewer cases

Sweeps m = 20…130 kg in 1 kg steps for the shipped classic and skate, several load positions
and snow moduli, the rigid ski (beam profile) and the flexible ski, and prints per zone (the
paper's rear / middle / front of :func:`skisnow.contact.contact_zones`) and per region (rear
glide / kick zone / front glide of :func:`skisnow.contact.footprint`, where this version of
skisnow has it) the largest change of the contact length [mm] and of the load share [%]
between neighbouring loads, and at that step the footprint's own change (the cells that came
into or left contact, as a length): a region can never move more than that.
Run it on an older checkout (``main`` before issue 26) for the "before" column: the script
only reads ``zones[name]`` and, when present, ``zones.footprint``.
"""

from __future__ import annotations

import argparse
import itertools
import os
import time

import numpy as np

from skisnow.pipeline import solve_case

ZONES = ("rear", "middle", "front")
REGIONS = ("rear_glide", "kick_zone", "front_glide")


def sweep(ski, position_mm, modulus_mpa, ski_model, n_points, masses):
    rows = []
    for m in masses:
        try:
            c = solve_case(
                ski, mass=float(m), load_position=position_mm * 1e-3,
                snow_modulus=modulus_mpa * 1e6, profile_source="beam", n_points=n_points,
                ski_model=ski_model,
            )  # fmt: skip
        except Exception:  # a load the ski cannot carry: a gap in the sweep
            rows.append(None)
            continue
        z = c.zones
        row = {f"zone {n}": (z[n].length, z[n].load_share) for n in ZONES}
        fp = getattr(z, "footprint", None)
        if fp is not None:
            for r in fp.regions:
                row[f"region {r.name}"] = (r.length, r.load_share)
        row["total"] = (z.total.length, 1.0)
        row["dx"] = c.solution.dx
        row["mask"] = c.solution.pressure > 0
        rows.append(row)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    n_points = 256 if args.quick else 1024
    masses = np.arange(20, 131, 1)
    cases = [
        ("classic", pos, e, model)
        for pos, e, model in itertools.product(
            (-120, -70, 0), (20, 50, 300) if not args.quick else (20, 300), ("rigid", "flexible")
        )
    ] + [("skate", pos, e, "rigid") for pos in (-120, 0) for e in (20, 300)]
    worst: dict[str, list[float]] = {}
    t0 = time.process_time()
    for ski, pos, e, model in cases:
        rows = sweep(ski, pos, e, model, n_points, masses)
        for a, b in itertools.pairwise(rows):
            if a is None or b is None:
                continue
            # the footprint's own change: cells that came into or left contact, as a length
            dtot = float((a["mask"] != b["mask"]).sum()) * b["dx"]
            for key, value in b.items():
                if key in ("total", "dx", "mask"):
                    continue
                length, share = value
                dl = abs(length - a[key][0])
                ds = abs(share - a[key][1]) if np.isfinite(share) and np.isfinite(a[key][1]) else 0
                w = worst.setdefault(f"{ski} {key}", [0.0, 0.0, 0.0, 0.0])
                if dl > w[0]:
                    w[0], w[2] = dl, dtot
                    w[3] = b["dx"]
                w[1] = max(w[1], ds)
    cpu = time.process_time() - t0
    print(f"load sweep 20–130 kg in 1 kg steps, {len(cases)} cases, {n_points} stations; "
          f"CPU {cpu:.0f} s, load average {os.getloadavg()[0]:.2f}")  # fmt: skip
    print(f"{'ski / view':32s} {'max Δlength mm':>15s} {'cells changed mm':>16s} "
          f"{'cell mm':>8s} {'max Δshare %':>13s}")  # fmt: skip
    for key, (dl, ds, dtot, dx) in worst.items():
        print(f"{key:32s} {dl * 1e3:15.1f} {dtot * 1e3:16.1f} {dx * 1e3:8.2f} {ds * 100:13.1f}")


if __name__ == "__main__":
    main()
