"""The apparent pressure of the shipped skis against the bounds it is checked against.

For the classic and the skate ski loaded 120 mm behind the balance point, over the paper's
masses and snows (Kalliorinne et al. 2023: 5–130 kg, 20–400 MPa), 300 kg, a modulus between
snow and ice (2 GPa), ice (9.5 GPa) and the stone bench (70 GPa): the peak apparent pressure,
p_peak / E' (the strain the linear half-space must keep small, bound 5 %), and what
:func:`skisnow.pipeline._plausible.pressure_notes` finds (nothing is expected: the bound on snow
is the hardness of ice, 15.9 MPa at −2 °C). Then a ski file with its width in metres. Prints a
table::

    uv run python benchmarks/pressure_bounds.py [--points 1024]
"""

import json
import sys
import tempfile
import warnings
from pathlib import Path

from skisnow import allow_implausible
from skisnow.pipeline import recording_implausible, solve_case
from skisnow.ski import read_ski, shipped_ski_path

N = int(sys.argv[sys.argv.index("--points") + 1]) if "--points" in sys.argv else 1024
MASSES = (5.0, 30.0, 60.0, 130.0, 300.0)
MODULI_MPA = (20.0, 100.0, 400.0, 2000.0, 9500.0, 70000.0)


def row(ski, mass, e_mpa):
    with warnings.catch_warnings(), recording_implausible() as found:
        warnings.simplefilter("ignore")  # the network's domain: not what is measured here
        c = solve_case(ski, mass=mass, load_position=-0.12, snow_modulus=e_mpa * 1e6,
                       n_points=N)  # fmt: skip
    peak = float(c.solution.pressure.max())
    name = ski if isinstance(ski, str) else ski.name
    print(f"| {name} | {mass:g} | {e_mpa:g} | {peak / 1e3:.1f} | {100 * peak / c.modulus:.3f} | "
          f"{len(found)} |")  # fmt: skip


print("| ski | mass [kg] | E_counter [MPa] | peak p [kPa] | p_peak/E' [%] | findings |")
print("| --- | --- | --- | --- | --- | --- |")
for ski in ("classic", "skate"):
    for m in MASSES:
        for e in MODULI_MPA:
            row(ski, m, e)
doc = json.loads(shipped_ski_path("skate").read_text())
doc["name"], doc["width_mm"] = "skate, width in m", doc["width_mm"] * 1e-3
with tempfile.TemporaryDirectory() as tmp, allow_implausible():
    path = Path(tmp) / "slip.json"
    path.write_text(json.dumps(doc))
    row(read_ski(path), 60.0, 100.0)
