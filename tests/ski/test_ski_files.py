"""Ski files: exact round trips, validation messages, the shipped skis as files, --ski FILE."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from skisnow import FileFormatError, InputError
from skisnow.ski import (
    SHIPPED_SKIS,
    Provenance,
    Ski,
    get_ski,
    read_ski,
    shipped_ski_path,
    ski_from_json,
    ski_to_document,
    ski_to_json,
    solve_beam,
    write_ski,
)


def _odd_ski() -> Ski:
    """A ski with awkward doubles everywhere (random stations, a width profile, bands)."""
    rng = np.random.default_rng(7)
    x_tail, x_tip = -0.9123456789012345, 1.0000000000000002
    ex = np.sort(np.concatenate([[x_tail, x_tip], rng.uniform(x_tail, x_tip, 30)]))
    cx = np.sort(np.concatenate([[x_tail - 1e-3, x_tip], rng.uniform(x_tail, x_tip, 50)]))
    return Ski(
        name="odd ski ü",
        kind="classic",
        x_tail=x_tail,
        x_tip=x_tip,
        width=0.04412345678901,
        stiffness_x=ex,
        stiffness_values=rng.uniform(100, 5000, ex.size),
        camber_x=cx,
        camber_values=rng.uniform(0, 3e-3, cx.size) * rng.choice([1e-9, 1.0], cx.size),
        kick_zone=(-0.2654321, 0.25),
        boot_plate=(-0.3, 1e-17),
        width_x=(x_tail, 0.0, x_tip),
        width_values=(0.043, 0.0441, 0.046),
        stiffness_log_sd=rng.uniform(0, 0.1, ex.size),
        camber_sd=rng.uniform(0, 1e-5, cx.size),
        description="made for the test",
        provenance=Provenance(
            method="test",
            data="random",
            sources=("nobody (2026)",),
            created="2026-11-23T00:00:00Z",
            software="skisnow",
            details=(("noise_mm", 0.01), ("n", 3), ("ok", True), ("none", None)),
        ),
    )


def _fields(ski: Ski) -> dict:
    return {f: getattr(ski, f) for f in Ski.__dataclass_fields__}


def test_round_trip_is_exact(tmp_path: Path) -> None:
    ski = _odd_ski()
    path = write_ski(ski, tmp_path / "odd.json")
    back = read_ski(path)
    assert _fields(back) == _fields(ski)  # every field, bit for bit, provenance included
    assert back.provenance.detail("n") == 3
    # and file -> Ski -> file gives the same text
    assert ski_to_json(back) == path.read_text(encoding="utf-8")


@pytest.mark.parametrize("name", SHIPPED_SKIS)
def test_shipped_skis_are_files_reproduced_by_their_generator(name: str) -> None:
    from skisnow.ski._shipped import GENERATOR, build_shipped

    ski = get_ski(name)
    assert shipped_ski_path(name).is_file()
    assert ski.provenance.sources and ski.provenance.method
    if ski.provenance.method == GENERATOR:  # re-made skis say so and are not generated here
        assert ski_to_json(build_shipped(name)) == shipped_ski_path(name).read_text("utf-8")
    # The same beam answer from the name and from a copy of the file elsewhere.
    assert get_ski(str(shipped_ski_path(name))) == ski


def test_get_ski_accepts_a_path_and_rereads_a_changed_file(tmp_path: Path) -> None:
    ski = get_ski("classic")
    path = write_ski(ski, tmp_path / "mine.json")
    assert get_ski(path) == ski and get_ski(str(path)) == ski
    doc = json.loads(path.read_text())
    doc["name"] = "mine"
    path.write_text(json.dumps(doc) + "\n" * 3)  # a different size: a new cache key
    assert get_ski(path).name == "mine"
    with pytest.raises(InputError, match="neither a shipped ski"):
        get_ski(tmp_path / "absent.json")


def _break(doc: dict, path: str, value: object) -> dict:
    keys = path.split(".")
    d = doc
    for k in keys[:-1]:
        d = d[k]
    if value is _DELETE:
        del d[keys[-1]]
    else:
        d[keys[-1]] = value
    return doc


_DELETE = object()


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("format", "other", r"format: must be 'skisnow-ski'"),
        ("format_version", 99, r"format_version: this skisnow reads versions 1\.\.2"),
        ("kind", "alpine", r"kind: must be 'classic' or 'skate'"),
        ("name", "", r"name: must be non-empty text"),
        ("x_tail_mm", 10.0, r"x_tail_mm: must be < 0"),
        ("width_mm", -4, r"width_mm: must be > 0 mm"),
        ("width_mm", "44", r"width_mm: must be a number"),
        ("stiffness", _DELETE, r"stiffness: missing \(required\)"),
        ("stiffness.ei_nm2", [1.0], r"stiffness.ei_nm2: must be a list of at least 2 numbers"),
        ("stiffness.units", "x", r"stiffness.units: unknown key; valid keys are x_mm, ei_nm2"),
        ("kick_zone_mm", [100.0, -100.0], r"kick_zone_mm: start must be < end"),
        ("kick_zone_mm", [-5000.0, 0.0], r"kick_zone_mm: must lie on the ski"),
        ("boot_plate_mm", [1.0], r"boot_plate_mm: must be \[start, end\] in mm or null"),
        ("colour", "red", r"colour: unknown key"),
        ("provenance.details", {"a": [1]}, r"provenance.details.a: must be a number, text"),
    ],
)
def test_bad_files_name_the_field(tmp_path: Path, field: str, value: object, message: str) -> None:
    doc = _break(ski_to_document(get_ski("classic")), field, value)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match=message) as info:
        read_ski(path)
    assert str(path) in str(info.value)


def test_bad_values_in_lists_name_the_index(tmp_path: Path) -> None:
    doc = ski_to_document(get_ski("classic"))
    doc["stiffness"]["ei_nm2"][3] = -1.0
    with pytest.raises(FileFormatError, match=r"stiffness.ei_nm2\[3\]: EI must be > 0 N m²"):
        ski_from_json(json.dumps(doc))
    doc = ski_to_document(get_ski("classic"))
    doc["camber"]["x_mm"][5] = doc["camber"]["x_mm"][4]
    with pytest.raises(FileFormatError, match=r"camber.x_mm\[5\]: stations must strictly"):
        ski_from_json(json.dumps(doc))
    doc = ski_to_document(get_ski("classic"))
    doc["camber"]["x_mm"] = doc["camber"]["x_mm"][1:]
    doc["camber"]["z0_mm"] = doc["camber"]["z0_mm"][1:]
    with pytest.raises(FileFormatError, match=r"camber.x_mm: stations must cover"):
        ski_from_json(json.dumps(doc))
    with pytest.raises(FileFormatError, match="not valid JSON at line 1"):
        ski_from_json("{")
    with pytest.raises(FileFormatError, match="Infinity is not a valid number"):
        ski_from_json('{"format": Infinity}')
    with pytest.raises(FileFormatError, match=r"x_tip_mm: must be a finite number"):
        text = json.dumps(ski_to_document(get_ski("skate")))
        ski_from_json(text.replace('"x_tip_mm": 940.0', '"x_tip_mm": 1e999'))


def test_a_ski_file_solves_like_the_shipped_ski(tmp_path: Path) -> None:
    # Balance law through a file ski: the reactions carry m g (Kalliorinne et al. 2023, eq. 1).
    path = write_ski(get_ski("skate"), tmp_path / "s.json")
    sol = solve_beam(get_ski(path), mass=40.0, load_position=-0.1)
    ref = solve_beam(get_ski("skate"), mass=40.0, load_position=-0.1)
    np.testing.assert_array_equal(sol.height, ref.height)
    assert sol.reactions.sum() == pytest.approx(40.0 * 9.80665, rel=1e-12)


def test_sweep_spec_carries_the_ski_definition(tmp_path: Path) -> None:
    from skisnow.sweep import SweepSpec

    path = write_ski(get_ski("classic"), tmp_path / "c.json")
    spec = SweepSpec(
        skis=(str(path),), masses=(30.0,), load_positions=(-0.12,), snow_moduli=(1e8,),
        profile_source="beam",
    )  # fmt: skip
    assert spec.ski_files and spec.ski_files[0][0] == str(path)
    path.unlink()  # the workers need only the spec
    again = SweepSpec.from_json(spec.to_json())
    assert again == spec and again.ski(str(path)) == get_ski("classic")
    # the network route is found by content: a copy of a shipped ski may use its network, a
    # changed ski may not (issue 26: a ski's name never changes its answer)
    SweepSpec(skis=(str(path),), masses=(30.0,), load_positions=(-0.12,), snow_moduli=(1e8,),
              ski_files=spec.ski_files, profile_source="network")  # fmt: skip
    from dataclasses import replace

    other = write_ski(replace(get_ski("classic"), width=0.045), tmp_path / "wide.json")
    with pytest.raises(InputError, match="camber network exists only for the shipped skis"):
        SweepSpec(skis=(str(other),), masses=(30.0,), load_positions=(-0.12,),
                  snow_moduli=(1e8,), profile_source="network")  # fmt: skip
