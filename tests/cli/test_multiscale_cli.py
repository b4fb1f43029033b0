"""The real contact at the command line: contact, sweep, cycle, compare; the snow options' rule
(a preset or a file, --snow-modulus-mpa overrides) and their errors (exit 2) and domains (4)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from skisnow.cli import main
from skisnow.constants import STANDARD_GRAVITY
from skisnow.micro import grind_preset, write_topography

CONTACT = ["contact", "--ski", "skate", "--mass-kg", "60", "--load-position-mm", "-120",
           "--points", "1024"]  # fmt: skip


@pytest.fixture(scope="module")
def texture(tmp_path_factory) -> str:
    """A small S3 map (0.3 mm) as a topography file: cheap micro curves."""
    d = tmp_path_factory.mktemp("tex")
    return str(write_topography(grind_preset("S3", size=0.3e-3, seed=1), d / "s3.npz"))


def _json(capsys, args: list[str], code: int = 0) -> dict:
    got = main([*args, "--json"])
    out = capsys.readouterr()
    assert got == code, out.err
    return json.loads(out.out)


def test_contact_prints_the_real_contact_beside_the_apparent(capsys, texture) -> None:
    doc = _json(capsys, [*CONTACT, "--snow", "machine-made", "--base", texture])
    assert doc["snow_modulus_mpa"] == pytest.approx(175.0)
    real = doc["real"]
    assert {"total", "rear_glide", "front_glide", "patch 1"} <= set(real)
    total = real["total"]
    assert total["load_n"] == pytest.approx(60 * STANDARD_GRAVITY, rel=1e-6)
    assert total["apparent_area_cm2"] == pytest.approx(doc["total"]["area_cm2"], rel=1e-9)
    f = doc["friction"]
    assert f["mu"] == pytest.approx(
        (f["dry_force_n"] + f["viscous_force_n"]) / f["load_n"], rel=1e-9
    )
    assert "τ =" in f["assumptions"] and f["parameters"]["film_cutoff_nm"] == pytest.approx(100)
    # human output: both tables and the µ line with its assumptions
    assert main([*CONTACT, "--snow", "machine-made", "--base", texture]) == 0
    out = capsys.readouterr().out
    assert "Apparent and real contact" in out and "assumptions:" in out


def test_friction_options_in_field_units_change_their_terms(capsys, texture) -> None:
    base = [*CONTACT, "--snow", "machine-made", "--base", texture]
    ref = _json(capsys, base)["friction"]
    fast = _json(capsys, [*base, "--sliding-speed-m-s", str(2 * 10 / 3.6)])["friction"]
    assert fast["viscous_force_n"] == pytest.approx(2 * ref["viscous_force_n"], rel=1e-9)
    tau = _json(capsys, [*base, "--shear-strength-mpa", "1"])["friction"]
    assert tau["parameters"]["shear_strength_mpa"] == 1.0
    assert tau["dry_force_n"] < ref["dry_force_n"]
    assert main([*base, "--film-cutoff-nm", "-5"]) == 2
    assert "--film-cutoff-nm" in capsys.readouterr().err
    assert main([*base, "--sliding-speed-m-s", "90"]) == 2  # implausible: km/h?
    assert "km/h" in capsys.readouterr().err


def test_snow_options_follow_one_rule(capsys, tmp_path: Path, texture) -> None:
    doc = _json(capsys, [*CONTACT, "--snow", "fine-grained", "--snow-modulus-mpa", "150"])
    assert doc["snow_modulus_mpa"] == 150.0 and doc["snow"]["modulus_mpa"] == 150.0
    snow = tmp_path / "track.json"
    snow.write_text(json.dumps({"modulus_mpa": 90, "temperature_c": -6, "grain_mode_um": 400}))
    doc = _json(capsys, [*CONTACT, "--snow", str(snow), "--base", texture])
    assert doc["snow_modulus_mpa"] == 90.0 and doc["snow"]["temperature_c"] == -6
    for args, needle in (
        (CONTACT, "--snow"),  # no snow at all
        ([*CONTACT, "--snow-modulus-mpa", "100", "--base", texture], "--snow"),
        ([*CONTACT, "--snow", "slush"], "slush"),
        ([*CONTACT, "--snow-modulus-mpa", "100", "--sliding-speed-m-s", "3"], "--base"),
        ([*CONTACT, "--snow-modulus-mpa", "100", "--snow-temperature-c", "-3"], "--snow"),
        ([*CONTACT, "--snow", "wet", "--base", "S9"], "--base"),
    ):
        assert main(args) == 2, args
        assert needle in capsys.readouterr().err


def test_wet_snow_lies_outside_the_hardness_relation(capsys, texture) -> None:
    doc = _json(capsys, [*CONTACT, "--snow", "wet", "--base", texture], code=4)
    assert any("-1 °C" in w for w in doc["warnings"])
    assert doc["real"]["total"]["real_area_mm2"] > 0


def test_sweep_stores_the_real_contact(capsys, tmp_path: Path, texture) -> None:
    from skisnow.sweep import open_sweep

    out = tmp_path / "s.zarr"
    args = ["sweep", "--ski", "skate", "--out", str(out), "--mass-kg", "40,70", "--snow",
            "machine-made", "--base", texture, "--workers", "0", "--points", "1024"]  # fmt: skip
    assert main(args) == 0
    capsys.readouterr()
    ds = open_sweep(out)
    assert list(ds["snow_modulus_mpa"].values) == [175.0]  # --snow alone: its modulus
    area = ds["real_area_grains_mm2"].sel(zone="total").values.ravel()
    w = ds["mass_kg"].values * STANDARD_GRAVITY
    hard = 15.9e6  # machine-made: −2 °C, eq. 2
    assert area == pytest.approx(w / hard * 1e6, rel=0.03)  # W·s/H, s ≈ 1.01
    assert ds["mu"].notnull().all()


def test_cycle_and_compare_carry_the_proxies(capsys, texture) -> None:
    doc = _json(capsys, ["cycle", "classic", "--template", "diagonal", "--body-mass-kg", "70",
                         "--frames", "8", "--points", "1024", "--snow", "machine-made",
                         "--base", texture])  # fmt: skip
    (real,) = doc["real_contact"]
    assert 0 < real["mu_lubricated"] < real["mu"]
    assert doc["frames"]["diagonal"][0].keys() >= {"viscous_force_n", "real_area_mm2"}
    doc = _json(capsys, ["compare", "skate", "classic", "--body-mass-kg", "70", "--points",
                         "1024", "--snow", "machine-made", "--base", texture, "--base",
                         "smooth", "--proxy", "viscous"])  # fmt: skip
    ranking = doc["real_ranking"]["ranking"]
    assert len(ranking) == 4 and [r["rank"] for r in ranking] == [1, 2, 3, 4]
    values = [r["viscous_force_n"] for r in ranking]
    assert values == sorted(values)
    assert main(["compare", "skate", "--body-mass-kg", "70", "--snow", "wet",
                 "--proxy", "speed"]) == 2  # fmt: skip
    assert "--proxy" in capsys.readouterr().err


def test_micro_curves_command(capsys, tmp_path: Path, texture) -> None:
    doc = _json(capsys, ["micro-curves", "--base", texture, "--base", "smooth", "--snow",
                         "machine-made", "--figure", str(tmp_path / "c.png")])  # fmt: skip
    textured, smooth = doc["curves"]
    assert smooth["real_fraction"] == [1.0] * len(smooth["real_fraction"])
    p = np.array(textured["pressure_kpa"]) * 1e3
    assert np.all(np.array(textured["real_fraction"]) >= p / 15.9e6)  # at least F/H
    assert (tmp_path / "c.png").is_file()
    assert main(["micro-curves", "--base", "S3"]) == 2
    assert "--snow" in capsys.readouterr().err
