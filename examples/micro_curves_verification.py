"""Micro curves: verification against analytic limits
=====================================================

The verification table of the micro curves (issue 28, point 3): the elastic–plastic flat-ice
contact (:func:`skisnow.micro.elastoplastic_curve`, mirror-continued half-space) against its
analytic limits and under refinement of the topography grid.

    uv run python examples/micro_curves_verification.py [--out DIR]    # ~1 min

Rows: (1) light load, purely elastic: Westergaard's wavy surface (contact width, mean gap);
(2) full plastic flow, rigid body: the truncated sinusoid (A = F/H, mean and reciprocal
separation in closed form); (3) A = F/H on a grind with a stiff body, and the excess of the
ice/UHMWPE contact over it; (4) the S3 stand-in (33 µm low-pass) sampled every 8, 4, 2, 1 µm.
The references are in :mod:`skisnow.micro.reference`; the tests assert the same comparisons.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np


def main() -> None:
    import argparse

    ap = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])
    ap.add_argument("--small", action="store_true", help="refinement down to 2 µm only")
    ap.add_argument("--out", type=Path, default=None, help="folder for the two tables (CSV)")
    args = ap.parse_args()
    os.environ.setdefault("COLUMNS", "160")
    from skisnow.cli._render import print_table
    from skisnow.micro import (
        elastoplastic_curve,
        grind_preset,
        ice_base_modulus,
        ice_hardness,
        make_topography,
        prepare,
    )
    from skisnow.micro.reference import plastic_sinusoid, westergaard

    def sinusoid(delta: float, lam: float, periods: float, dx: float):
        n = round(periods * lam / dx)
        x = (np.arange(n) + 0.5) * dx
        return make_topography(np.repeat((delta * np.cos(2 * np.pi * x / lam))[:, None], 4, 1),
                               dx=dx)  # fmt: skip

    rows = []
    e, delta, lam, dx = 1e9, 1e-6, 200e-6, 0.5e-6
    pstar = math.pi * (e / 2) * delta / lam
    loads = np.array([0.02, 0.1, 0.3]) * pstar
    c = elastoplastic_curve(sinusoid(delta, lam, 2, dx), pressures=loads, hardness=np.inf,
                            modulus=e)  # fmt: skip
    for i, p in enumerate(loads):
        ref = westergaard(p, amplitude=delta, wavelength=lam, contact_modulus=e / 2)
        rows.append([f"elastic, Westergaard, p/p* = {p / pstar:g} (0.5 µm px)",
                     "contact fraction", c.fractional_area[i], ref.contact_fraction,
                     c.fractional_area[i] / ref.contact_fraction - 1])  # fmt: skip
        rows.append(["", "mean gap [µm]", c.mean_separation[i] * 1e6, ref.mean_gap * 1e6,
                     c.mean_separation[i] / ref.mean_gap - 1])  # fmt: skip
    delta, lam, dx, hard = 2e-6, 100e-6, 0.05e-6, 10e6
    loads = np.array([0.05, 0.2, 0.5]) * hard
    uc = 10 ** (-7.5)
    c = elastoplastic_curve(sinusoid(delta, lam, 0.5, dx), pressures=loads, hardness=hard,
                            modulus=1e14, tol=1e-11)  # fmt: skip
    recip = c.reciprocal_separation(uc)
    for i, p in enumerate(loads):
        ref = plastic_sinusoid(p / hard, amplitude=delta, film_cutoff=uc)
        rows.append([f"rigid-plastic sinusoid, p/H = {p / hard:g} (0.05 µm px)", "A/A₀ (= p/H)",
                     c.fractional_area[i], ref.contact_fraction,
                     c.fractional_area[i] / ref.contact_fraction - 1])  # fmt: skip
        du = c.mean_separation[i] / ref.mean_separation - 1
        rows.append(["", "mean separation [µm]", c.mean_separation[i] * 1e6,
                     ref.mean_separation * 1e6, du])  # fmt: skip
        dr = recip[i] / ref.reciprocal_separation - 1
        rows.append(["", f"⟨1/u⟩ [1/µm], u_c = {uc * 1e9:.3g} nm", recip[i] * 1e-6,
                     ref.reciprocal_separation * 1e-6, dr])  # fmt: skip
    hard = ice_hardness(-2.0)
    topo = prepare(grind_preset("S3", size=400e-6, dx=1e-6, seed=3))
    t3 = make_topography(np.asarray(topo.heights)[::2, ::2], dx=2e-6)
    loads = np.array([20e3, 500e3])
    stiff = elastoplastic_curve(t3, pressures=loads, hardness=hard, modulus=1e13, tol=1e-11)
    soft = elastoplastic_curve(t3, pressures=loads, hardness=hard, modulus=ice_base_modulus())
    for i, p in enumerate(loads):
        rows.append([f"S3, stiff body (E' = 1e13 Pa), {p / 1e3:g} kPa", "A/(A₀·p/H)",
                     stiff.fractional_area[i] / (p / hard), 1.0,
                     stiff.fractional_area[i] / (p / hard) - 1])  # fmt: skip
        rows.append([f"S3, ice on UHMWPE (E' = {ice_base_modulus() / 1e9:.3g} GPa)",
                     "A/(A₀·p/H)", soft.fractional_area[i] / (p / hard), 1.0,
                     soft.fractional_area[i] / (p / hard) - 1])  # fmt: skip
    print_table(
        "Micro curves against their references",
        ["case", "quantity", "skisnow", "reference", "relative difference"],
        rows,
    )
    ref_rows = []
    for k in (8, 4, 2) if args.small else (8, 4, 2, 1):
        t = make_topography(np.asarray(topo.heights)[::k, ::k], dx=k * 1e-6)
        c = elastoplastic_curve(t, pressures=loads, hardness=hard, modulus=ice_base_modulus())
        r = c.reciprocal_separation(1e-7)
        for i, p in enumerate(loads):
            ref_rows.append([k, f"{p / 1e3:g}", t.shape[0], c.mean_separation[i] * 1e6,
                             c.fractional_area[i] / (p / hard), c.plastic_fraction[i],
                             r[i] * 1e-6, int(c.iterations[i])])  # fmt: skip
    if args.out is not None:
        from skisnow.cli._workflows import write_csv

        hdr = ["case", "quantity", "skisnow", "reference", "relative_difference"]
        write_csv(args.out / "references.csv", [dict(zip(hdr, r, strict=True)) for r in rows])
        hdr = ["pixel_um", "p_kpa", "grid", "mean_separation_um", "area_over_p_over_h",
               "plastic_share", "reciprocal_per_um", "iterations"]  # fmt: skip
        write_csv(args.out / "refinement.csv", [dict(zip(hdr, r, strict=True)) for r in ref_rows])
        print(f"wrote {args.out / 'references.csv'}, {args.out / 'refinement.csv'}")
    print_table(
        "Refinement: S3 stand-in, 0.4 mm map after the 33 µm low-pass, ice on UHMWPE at -2 °C",
        ["pixel [µm]", "p [kPa]", "grid", "ū [µm]", "A/(A₀·p/H)", "plastic share",
         "⟨1/u⟩ [1/µm] (100 nm)", "iterations"],
        ref_rows,
    )  # fmt: skip


if __name__ == "__main__":
    main()
