"""Figure 5: the skate ski under 30 and 60 kg
==========================================

Figure 5 of Kalliorinne et al. (2023): the skate ski under 30 kg and 60 kg at x_m = -120 mm on
snow of 100 MPa. Doubling the load changes the profile, not only the force.

    uv run python examples/fig5_load.py [--small] [--out DIR] [--profile-source beam]
"""

from _cases import case, parser, report

if __name__ == "__main__":
    args = parser(__doc__).parse_args()
    rows = [
        case(args, ski="skate", mass_kg=m, load_position_mm=-120, snow_modulus_mpa=100,
             stem=f"fig5_skate_{m}kg")
        for m in (30, 60)
    ]  # fmt: skip
    report(rows, "30 kg: rear/front 146/162 mm, 30.6/13.8 kPa, 67/33 %; "
                 "60 kg: 288/132 mm (front in two patches), 33.2/28.9 kPa, 71/29 %")  # fmt: skip
