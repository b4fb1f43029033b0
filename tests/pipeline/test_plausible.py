"""The apparent pressure checked where it is computed (:mod:`skisnow.pipeline._plausible`).

The bound on snow is the hardness of ice, Poirier's H(T) = −0.6·T + 14.7 MPa (Scherge et al.
2021, eq. 2), written out here independently of :func:`skisnow.micro.ice_hardness`; the
shipped skis over the paper's loads and snows (Kalliorinne et al. 2023: 5–130 kg, 20–400 MPa,
and the 70 GPa stone bench) must raise nothing, and a width typed in metres must be named.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from skisnow import allow_implausible
from skisnow.cli import main
from skisnow.pipeline import recording_implausible, solve_case
from skisnow.pipeline._plausible import SMALL_STRAIN, pressure_notes
from skisnow.snow import Snow

N = 256
BEARS = "more than snow can bear"
STRAIN = "not a small strain"


def _poirier(t_c: float) -> float:
    return (-0.6 * t_c + 14.7) * 1e6


@pytest.fixture(scope="module")
def case():
    return solve_case("skate", mass=60.0, load_position=-0.12, snow_modulus=100e6, n_points=N)


def _scaled(case, peak: float) -> np.ndarray:
    p = case.solution.pressure
    return p * (peak / p.max())


@pytest.mark.parametrize("ski", ["classic", "skate"])
@pytest.mark.parametrize(("mass", "modulus"), [(5.0, 20e6), (130.0, 20e6), (130.0, 400e6),
                                               (130.0, 70e9)])  # fmt: skip
def test_the_papers_cases_are_plausible(ski, mass, modulus) -> None:
    with recording_implausible() as log:
        c = solve_case(ski, mass=mass, load_position=-0.12, snow_modulus=modulus, n_points=N)
    assert not [w for w in c.warnings if BEARS in w or STRAIN in w]
    assert log == []


def test_the_bound_on_snow_is_the_hardness_of_ice(case) -> None:
    h = _poirier(-2.0)  # a snow given only its modulus: Snow's default temperature
    stiff = 1e15  # E' so large that the strain check stays silent
    below = pressure_notes(_scaled(case, 0.99 * h), case.zones, modulus=stiff, snow=100e6)
    above = pressure_notes(_scaled(case, 1.01 * h), case.zones, modulus=stiff, snow=100e6)
    assert below == []
    assert len(above) == 1 and BEARS in above[0] and f"{h / 1e6:.3g} MPa" in above[0]


def test_colder_snow_bears_more(case) -> None:
    peak = 0.5 * (_poirier(-2.0) + _poirier(-20.0))  # between H(-2 °C) and H(-20 °C)
    cold = Snow(name="cold", modulus=100e6, temperature_c=-20.0)
    warm = Snow(name="warm", modulus=100e6, temperature_c=-2.0)
    p = _scaled(case, peak)
    assert pressure_notes(p, case.zones, modulus=1e15, snow=cold) == []
    assert BEARS in pressure_notes(p, case.zones, modulus=1e15, snow=warm)[0]


def test_a_bench_is_not_snow_but_keeps_the_strain_check(case) -> None:
    e_eq = 1.95e9  # stone 70 GPa against the 900 MPa base (Kalliorinne et al. 2023, §3.1)
    p = _scaled(case, 0.9 * SMALL_STRAIN * e_eq)  # 88 MPa: far beyond snow, fine for stone
    assert pressure_notes(p, case.zones, modulus=e_eq, snow=70e9) == []
    p = _scaled(case, 1.1 * SMALL_STRAIN * e_eq)
    (note,) = pressure_notes(p, case.zones, modulus=e_eq, snow=70e9)
    assert STRAIN in note


def test_a_snow_as_stiff_as_stone_is_named(case) -> None:
    stone_snow = Snow(name="fine-grained", modulus=70e9)
    notes = pressure_notes(case.solution.pressure, case.zones, modulus=1.95e9, snow=stone_snow)
    assert len(notes) == 1 and "70000 MPa" in notes[0] and "ice" in notes[0]


def _slip(tmp_path):
    from skisnow.ski import shipped_ski_path

    doc = json.loads(shipped_ski_path("skate").read_text())
    doc["name"] = "slip"
    doc["width_mm"] *= 1e-3  # metres typed into the millimetre field
    if doc.get("width_profile"):
        doc["width_profile"]["width_mm"] = [w * 1e-3 for w in doc["width_profile"]["width_mm"]]
    path = tmp_path / "slip.json"
    path.write_text(json.dumps(doc))
    return path


def test_a_width_in_metres_is_named_where_computed(tmp_path) -> None:
    from skisnow.ski import read_ski

    with allow_implausible():
        ski = read_ski(_slip(tmp_path))
        with recording_implausible() as log:
            c = solve_case(ski, mass=60.0, load_position=-0.12, snow_modulus=100e6, n_points=N)
    bears = [w for w in c.warnings if BEARS in w]
    assert len(bears) == 1 and " zone (its mean " in bears[0]
    assert any(STRAIN in w for w in c.warnings)
    assert len(log) == 2 and all(e.startswith("slip 60 kg at -120 mm on 100 MPa: ") for e in log)


def test_cli_exit_4_and_json_warnings(tmp_path, capsys) -> None:
    slip = str(_slip(tmp_path))
    common = ["--snow-modulus-mpa", "100", "--points", str(N), "--json"]
    code = main(["--allow-implausible", "contact", "--ski", slip, "--mass-kg", "60",
                 "--load-position-mm", "-120", *common])  # fmt: skip
    doc = json.loads(capsys.readouterr().out)
    assert code == 4
    assert sum(BEARS in w for w in doc["warnings"]) == 1  # listed once, not again as a summary
    code = main(["--allow-implausible", "compare", slip, "skate", "--body-mass-kg", "60",
                 "--snow-range-mpa", "100,200", *common])  # fmt: skip
    out = capsys.readouterr()
    doc = json.loads(out.out)
    assert code == 4
    (summary,) = [w for w in doc["warnings"] if BEARS in w]
    assert "implausible results of the run's solves (first: slip " in summary
    assert "implausible results" in out.err
