"""Figure 6: the classic ski loaded on the heel and on the forefoot
================================================================

Figure 6 of Kalliorinne et al. (2023): the classic ski under 60 kg at x_m = -210 mm (on the heel)
and -70 mm (collapsing the camber onto the kick zone: a middle zone appears), snow 100 MPa.

    uv run python examples/fig6_position.py [--small] [--out DIR] [--profile-source beam]
"""

from _cases import case, parser, report

if __name__ == "__main__":
    args = parser(__doc__).parse_args()
    rows = [
        case(args, ski="classic", mass_kg=60, load_position_mm=x, snow_modulus_mpa=100,
             stem=f"fig6_classic_x{x}mm")
        for x in (-210, -70)
    ]  # fmt: skip
    report(rows, "-210 mm: rear/front 200/51 mm, 56.4/40.9 kPa, 84/16 %; -70 mm: rear/middle/"
                 "front 146/80.9/105 mm, 41.1/46.6/34.3 kPa, 45/28/27 %")  # fmt: skip
