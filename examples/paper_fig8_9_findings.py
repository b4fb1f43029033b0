"""The twelve Figure 8–9 statements of Kalliorinne et al. (2023), §4, read on a ski's maps.
========================================================================================

The ski's rear and front maps (apparent contact area, mean pressure, patches, Breitschädel
area) over load 5–130 kg in 1 kg steps at x_m = -120 mm and snow 20–400 MPa in 20 MPa steps
are computed with the paper's pipeline (loaded profile from the camber network or the beam →
rigid profile → strip half-space), and every statement the paper reads off its Figures 8–9 is
evaluated with the criterion printed next to it, on the 1 kg grid and on the 2 kg grid (every
other mass); "yes" needs both. The skis are fitted to the captions of Figures 4–7 only: these
are predictions. The table of every shipped ski is ``benchmarks/figure89_table.py``.

    uv run python examples/paper_fig8_9_findings.py [--ski skate-k22] [--small] [--json]
"""

import json

from _cases import parser

if __name__ == "__main__":
    p = parser(__doc__)
    p.add_argument("--ski", default="skate", help="a shipped ski or a ski file")
    p.add_argument("--json", action="store_true", help="also write fig8_9_findings.json")
    args = p.parse_args()

    from skisnow.paper import FIGURE89_MODULI_MPA, figure89_findings, figure89_masses, zone_maps

    if args.small:  # a coarse look: 5 kg steps (and 10 kg), four snows
        masses, moduli, n = figure89_masses(5.0), (20.0, 100.0, 280.0, 400.0), 1024
    else:
        masses, moduli, n = figure89_masses(1.0), FIGURE89_MODULI_MPA, 2048
    maps = zone_maps(args.ski, masses, moduli, route=args.profile_source, n_points=n)
    findings = figure89_findings(maps, maps.every(2))
    print(f"{args.ski}, {args.profile_source} route, grids {maps.step_kg:g} and "
          f"{2 * maps.step_kg:g} kg over {masses[0]:g}-{masses[-1]:g} kg")  # fmt: skip
    print("| statement | Fig. | the paper | criterion | verdict | measured |")
    print("| --- | --- | --- | --- | --- | --- |")
    for f in findings:
        print(f"| {f.key} | {f.figure} | {f.statement} | {f.criterion} | {f.verdict} | "
              f"{f.measured} |")  # fmt: skip
    n_yes = sum(f.verdict == "yes" for f in findings)
    n_partly = sum(f.verdict == "partly" for f in findings)
    print(f"{n_yes} yes, {n_partly} partly, {len(findings) - n_yes - n_partly} no of "
          f"{len(findings)}")  # fmt: skip
    if args.json:
        args.out.mkdir(parents=True, exist_ok=True)
        path = args.out / "fig8_9_findings.json"
        path.write_text(json.dumps([f.__dict__ for f in findings], indent=1))
        print(f"  wrote {path}")
