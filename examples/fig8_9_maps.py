"""Figures 8 and 9: contact area and mean pressure over load and snow
==================================================================

Figures 8 and 9 of Kalliorinne et al. (2023): apparent contact area (8) and mean pressure (9) of
the rear and front zones versus load (5-130 kg) at x_m = -120 mm, one line per snow modulus
20-400 MPa in 20 MPa steps, with the Breitschädel (50 µm) estimate; for both shipped skis.

The sweep runs on a local Dask cluster (or ``--scheduler ADDRESS``) into a resumable Zarr store:
interrupt it and run the same command again to finish it.

    uv run python examples/fig8_9_maps.py [--small] [--out DIR] [--workers N] [--scheduler ADDR]
"""

import numpy as np
from _cases import parser

if __name__ == "__main__":  # required: the Dask workers re-import this module
    p = parser(__doc__)
    p.add_argument("--workers", type=int, default=None, help="local Dask workers (0: none)")
    p.add_argument("--scheduler", default=None, help="existing dask.distributed scheduler")
    p.add_argument("--skis", default="skate,classic")
    args = p.parse_args()

    from skisnow.plot import save_figure, sweep_figures
    from skisnow.sweep import SweepSpec, open_sweep, run_sweep

    if args.small:
        masses, moduli, n = np.arange(5.0, 131.0, 25.0), np.array([20.0, 200.0, 400.0]), 1024
    else:
        masses, moduli, n = np.arange(5.0, 131.0, 1.0), np.arange(20.0, 401.0, 20.0), 4096
    spec = SweepSpec(
        skis=tuple(args.skis.split(",")), masses=masses, load_positions=(-0.120,),
        snow_moduli=moduli * 1e6, profile_source=args.profile_source, n_points=n,
    )  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    store = args.out / f"fig8_9_{'small' if args.small else 'full'}_{args.profile_source}.zarr"
    run = run_sweep(spec, store, workers=args.workers, scheduler=args.scheduler)
    print(f"sweep: {len(run.computed)} chunks computed, {len(run.skipped)} already done, "
          f"{run.wall_time:.1f} s -> {store}")  # fmt: skip
    ds = open_sweep(store)
    formats = args.formats.split(",")
    # Figure 8: {ski}_x-120mm_area, Figure 9: {ski}_x-120mm_mean_pressure, and the load share
    kinds = ("area", "mean_pressure", "load_share")
    for stem, fig in sweep_figures(ds, load_positions_mm=[-120.0], kinds=kinds).items():
        for f in save_figure(fig, args.out / stem, formats=formats):
            print(f"  wrote {f}")
    for ski in spec.skis:
        half = ds.sel(ski=ski, zone=["rear", "front"]).sel(mass_kg=30.0, method="nearest")
        print(f"{ski} at ~30 kg: area [cm²] rear/front over snows "
              f"{half.area_cm2.min().item():.1f}-{half.area_cm2.max().item():.1f}")  # fmt: skip
