"""The Figure 8–9 findings of Kalliorinne et al. (2023), §4, checked on the shipped skate's maps.
==============================================================================================

The skate's rear and front maps (apparent contact area, mean pressure, patches, Breitschädel
area) over load 5–80 kg (5 kg steps) at x_m = -120 mm and snow 20–400 MPa (20 MPa steps) are
computed with the paper's pipeline (beam on the rigid plane → rigid profile → strip
half-space), and every finding the paper reads off its Figures 8–9 is evaluated with the
criterion printed next to it.
The skis are fitted to the captions of Figures 4–7 only: these findings are the validation.

    uv run python examples/paper_fig8_9_findings.py [--small] [--out DIR] [--json]
"""

import json

import numpy as np
from _cases import parser

if __name__ == "__main__":
    p = parser(__doc__)
    p.add_argument("--json", action="store_true", help="also write fig8_9_findings.json")
    args = p.parse_args()

    from skisnow.paper import figure89_findings, zone_maps
    from skisnow.ski import get_ski

    if args.small:
        masses, moduli, n = np.arange(5.0, 81.0, 5.0), np.array([20.0, 100.0, 280.0, 400.0]), 1024
    else:
        masses, moduli, n = np.arange(5.0, 81.0, 5.0), np.arange(20.0, 401.0, 20.0), 2048
    maps = zone_maps(get_ski("skate"), masses, moduli, n_points=n)
    findings = figure89_findings(maps)
    print("| finding | Fig. | paper | criterion | shown | measured |")
    print("| --- | --- | --- | --- | --- | --- |")
    for f in findings:
        shown = "yes" if f.shown else "no"
        print(f"| {f.key} | {f.figure} | {f.statement} | {f.criterion} | {shown} | {f.measured} |")
    print(f"{sum(f.shown for f in findings)}/{len(findings)} findings shown on the skate's maps")
    if args.json:
        args.out.mkdir(parents=True, exist_ok=True)
        path = args.out / "fig8_9_findings.json"
        path.write_text(json.dumps([f.__dict__ for f in findings], indent=1))
        print(f"  wrote {path}")
