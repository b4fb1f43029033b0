"""Figure 7: the classic ski on soft and on stiff snow
===================================================

Figure 7 of Kalliorinne et al. (2023): the classic ski under 30 kg at x_m = -120 mm on soft
(50 MPa) and stiff (200 MPa) snow: the same rigid profile, rotated differently by moment balance.

    uv run python examples/fig7_snow.py [--small] [--out DIR] [--profile-source beam]
"""

from _cases import case, parser, report

if __name__ == "__main__":
    args = parser(__doc__).parse_args()
    rows = [
        case(args, ski="classic", mass_kg=30, load_position_mm=-120, snow_modulus_mpa=e,
             stem=f"fig7_classic_{e}MPa")
        for e in (50, 200)
    ]  # fmt: skip
    report(rows, "50 MPa: rear/front 141/74 mm, 33.3/27.2 kPa; 200 MPa: 98/37 mm, 48.2/52.7 kPa")
