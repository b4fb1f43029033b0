"""The S1–S5 table of seed paper 001 on skisnow's synthetic grinding presets.
==========================================================================

For each preset: roughness (plane removed, 33 µm low-pass); the bearing model's mean fractional
real contact area A_fr(D) over grain diameters 450–750 µm (eq. 5–9) and its grain average
⟨A_fr⟩ (eq. 12–13, the seed's fitted f(D)); the elastic–perfectly-plastic contact with a flat
ice counter surface (the seed's Fig. 3 check). Both contact models see the plane-removed,
33 µm low-passed map, as ``skisnow bearing`` prepares a file. Then the ranks under both models
and the Pearson r of ⟨A_fr⟩ against the seed's Table 3 glide times (eq. 10). Ice at the given
temperature (Poirier, eq. 2), nominal pressure 20 kPa.

    uv run python examples/micro_s1_s5.py                 # 1 mm², 1 µm; EP at 2 µm (~4 min)
    uv run python examples/micro_s1_s5.py --small         # a quick look (0.3 mm², coarse)

The presets are skisnow's stand-ins built to the seed's Table 1 ranges, not the seed's surfaces.
"""

from __future__ import annotations

import argparse
import os

import numpy as np
from scipy.stats import rankdata


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--small", action="store_true", help="0.3 mm maps, 3 µm EP pixels, stride 4")
    p.add_argument("--temperature-c", type=float, default=-2.0)
    p.add_argument("--pressure-kpa", type=float, default=20.0)
    p.add_argument("--stride", type=int, default=None, help="raster stride of the bearing model")
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args()
    os.environ.setdefault("COLUMNS", "220")  # a wide table: let Rich print it whole

    from skisnow.cli._render import print_table
    from skisnow.micro import (
        bearing_sweep,
        elastoplastic_contact,
        grain_average,
        grind_preset,
        ice_hardness,
        pearson,
        prepare,
        roughness,
        scherge2021,
    )

    def prepared(name: str, dx: float) -> object:
        """The preset as both contact models see it (skisnow.micro.prepare, as the CLI prepares
        a file): plane removed, then the seed's 33 µm Fourier low-pass."""
        return prepare(grind_preset(name, size=size, dx=dx, seed=0))

    size = 0.3e-3 if args.small else 1e-3
    ep_dx = 3e-6 if args.small else 2e-6
    stride = args.stride or (4 if args.small else 1)
    pressure = args.pressure_kpa * 1e3
    hardness = ice_hardness(args.temperature_c)
    diameters = np.arange(450e-6, 750e-6 + 1e-9, 10e-6)
    if args.small:
        diameters = np.array([100e-6, 150e-6, 200e-6])  # grains that fit a 0.3 mm map

    names = ["S1", "S2", "S3", "S4", "S5"]
    rows, mean_afr, ep_afr = [], [], []
    for name in names:
        r = roughness(grind_preset(name, size=size, dx=1e-6, seed=0))
        topo = prepared(name, 1e-6)
        sweep = bearing_sweep(
            topo,
            diameters=diameters,
            pressure=pressure,
            hardness=hardness,
            stride=stride,
            workers=args.workers,
        )
        afr = sweep.fractional_area
        avg = grain_average(diameters, afr) if not args.small else float(np.mean(afr))
        ep = elastoplastic_contact(prepared(name, ep_dx), pressure=pressure, hardness=hardness)
        at = {d: float(np.interp(d, diameters, afr)) for d in (500e-6, 600e-6, 700e-6)}
        mean_afr.append(avg)
        ep_afr.append(ep.real_fractional_area)
        rows.append(
            [name, r.Sa * 1e6, r.Sq * 1e6, r.Sdq, r.Ssk, r.Sku, r.Ra * 1e6, r.Rz * 1e6]
            + [1e3 * v for v in at.values()]
            + [1e3 * avg, 1e3 * ep.real_fractional_area, ep.converged]
        )
    # rank 1 = smallest real contact area (the seed: less area, faster ski)
    rank_bearing = rankdata(mean_afr, method="min").astype(int)
    rank_ep = rankdata(ep_afr, method="min").astype(int)
    for row, rb, re in zip(rows, rank_bearing, rank_ep, strict=True):
        row += [int(rb), int(re)]
    print_table(
        f"S1–S5 at {args.temperature_c} °C (H_ice {hardness / 1e6:.3g} MPa), "
        f"{args.pressure_kpa} kPa; A_fr in 1e-3 (flat base: {1e3 * pressure / hardness:.5g})",
        ["preset", "Sa_um", "Sq_um", "Sdq", "Ssk", "Sku", "Ra_um", "Rz_um", "A_fr_500um",
         "A_fr_600um", "A_fr_700um", "<A_fr>", "EP_A_fr", "EP_converged", "rank_bearing",
         "rank_EP"],
        rows,
    )  # fmt: skip
    times = [scherge2021.TABLE3_AVERAGE_S[n] for n in names]
    same = bool(np.array_equal(rank_bearing, rank_ep))
    print(f"ranking bearing model {rank_bearing.tolist()}, elastic-plastic {rank_ep.tolist()}: "
          f"{'the same' if same else 'different'}")  # fmt: skip
    print(f"Pearson r of <A_fr> vs seed Table 3 glide times: {pearson(mean_afr, times)}")


if __name__ == "__main__":
    main()
