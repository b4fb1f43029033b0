"""Figure 4: both skis on the bench stone
======================================

Figure 4 of Kalliorinne et al. (2023): both skis on the stone of the bench (E_counter = 70 GPa),
m = 30 kg at x_m = -120 mm. The stiff counter surface gives short contacts with spiky pressure.

    uv run python examples/fig4_stone.py [--small] [--out DIR] [--profile-source beam]
"""

from _cases import case, parser, report

if __name__ == "__main__":
    args = parser(__doc__).parse_args()
    rows = [
        case(args, ski=ski, mass_kg=30, load_position_mm=-120, snow_modulus_mpa=70_000,
             stem=f"fig4_{ski}_stone")
        for ski in ("classic", "skate")
    ]  # fmt: skip
    report(rows, "classic rear/front 28.1/14.9 mm, 169/137 kPa; skate 52.7/45.7 mm, 83.7/48.1 kPa")
