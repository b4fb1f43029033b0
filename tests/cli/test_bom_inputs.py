"""A file saved "UTF-8 with BOM" (Windows Notepad, Excel's "CSV UTF-8") reads exactly as the same
file without it: ski and snow files, bench tables and load histories with ``#`` comment lines,
profile CSVs and text topographies. Before, the BOM hid the first ``#`` line from the comment
rule (bench: "not a valid CSV table (Error tokenizing data ...)", load history: "give exactly one
load column ... header has # a stride") and JSON refused it ("Unexpected UTF-8 BOM")."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from skisnow.bench import read_bench, run_bench, write_bench
from skisnow.contact import read_profile
from skisnow.micro import read_topography
from skisnow.ski import get_ski, read_ski, write_ski
from skisnow.snow import get_snow, read_snow, write_snow
from skisnow.workflows import read_load_history

BOM = "\ufeff"


def _twins(tmp_path: Path, name: str, text: str) -> tuple[Path, Path]:
    plain, bom = tmp_path / name, tmp_path / f"bom_{name}"
    plain.write_text(text, encoding="utf-8")
    bom.write_text(BOM + text, encoding="utf-8")
    return plain, bom


def test_ski_and_snow_files(tmp_path: Path) -> None:
    ski = write_ski(get_ski("classic"), tmp_path / "ski.json")
    plain, bom = _twins(tmp_path, "ski.json", ski.read_text(encoding="utf-8"))
    a, b = read_ski(plain), read_ski(bom)
    for field in ("stiffness_x", "stiffness_values", "camber_x", "camber_values"):
        assert np.array_equal(getattr(a, field), getattr(b, field))
    assert (a.x_tail, a.x_tip, a.kick_zone) == (b.x_tail, b.x_tip, b.kick_zone)
    snow = write_snow(get_snow("fine-grained"), tmp_path / "snow.json")
    plain, bom = _twins(tmp_path, "snow.json", snow.read_text(encoding="utf-8"))
    a, b = read_snow(plain), read_snow(bom)
    for f in dataclasses.fields(a):
        if f.name != "modulus_source":  # names the file read
            assert np.array_equal(getattr(a, f.name), getattr(b, f.name)), f.name


def test_bench_with_metadata_comments(tmp_path: Path) -> None:
    data = run_bench("classic", masses=[20.0, 60.0], load_positions=[-0.12], dx=0.01)
    path = write_bench(data, tmp_path / "b.csv")
    text = path.read_text(encoding="utf-8")
    assert text.startswith("#")  # the comment lines the BOM used to hide
    plain, bom = _twins(tmp_path, "b.csv", text)
    assert read_bench(bom).equals(read_bench(plain))


def test_load_history_with_a_comment(tmp_path: Path) -> None:
    text = "# a stride\nt_s,mass_kg,load_position_mm\n0,30,-100\n0.5,60,-80\n1.0,40,-60\n"
    plain, bom = _twins(tmp_path, "h.csv", text)
    a, b = read_load_history(plain), read_load_history(bom)
    assert np.array_equal(a.force, b.force) and a.lines == b.lines == (3, 4, 5)


def test_profile_and_text_topography(tmp_path: Path) -> None:
    x = np.linspace(-500, 500, 64)
    rows = "\n".join(f"{xi:.6g},{1e-5 * xi**2:.6g}" for xi in x)
    plain, bom = _twins(tmp_path, "p.csv", "# profile\nx_mm,height_mm\n" + rows + "\n")
    for u, v in zip(read_profile(plain), read_profile(bom), strict=True):
        assert np.array_equal(u, v)
    h = np.random.default_rng(0).normal(size=(16, 16))
    matrix = "# heights\n" + "\n".join(" ".join(f"{v:.6g}" for v in r) for r in h) + "\n"
    plain, bom = _twins(tmp_path, "t.txt", matrix)
    a = read_topography(plain, pixel_size=1e-6, height_unit="um")
    b = read_topography(bom, pixel_size=1e-6, height_unit="um")
    assert np.array_equal(a.heights, b.heights)
