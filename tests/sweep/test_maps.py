"""The maps of a sweep (Figures 8–9 layout): the lines drawn are the dataset's values, one per
snow modulus plus the Breitschädel line, and the files are valid PNG and SVG."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from _hertz_chunk import hertz_chunk
from skisnow import InputError
from skisnow.sweep import SweepSpec, open_sweep, run_sweep


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory):
    spec = SweepSpec(
        skis=("skate",),
        masses=np.arange(5.0, 131.0, 25.0),
        load_positions=(-0.12, -0.07),
        snow_moduli=(20e6, 200e6, 400e6),
    )
    path = tmp_path_factory.mktemp("maps") / "s.zarr"
    run_sweep(spec, path, chunk_function=hertz_chunk, workers=0)
    return open_sweep(path)


def test_zone_map_draws_the_data(dataset) -> None:
    from skisnow.plot import plot_zone_map

    fig = plot_zone_map(dataset, variable="area_cm2", ski="skate", load_position_mm=-120)
    rear, front = fig.axes[:2]
    # 3 moduli + the Breitschädel line per panel
    assert len(rear.lines) == 4 and len(front.lines) == 4
    want = dataset.area_cm2.sel(ski="skate", load_position_mm=-120, zone="front")
    for line, e in zip(front.lines[:3], (20.0, 200.0, 400.0), strict=True):
        np.testing.assert_array_equal(line.get_xdata(), dataset.mass_kg.values)
        np.testing.assert_array_equal(line.get_ydata(), want.sel(snow_modulus_mpa=e).values)
    breit = dataset.breitschaedel_area_cm2.sel(ski="skate", load_position_mm=-120, zone="rear")
    np.testing.assert_array_equal(rear.lines[3].get_ydata(), breit.values)
    with pytest.raises(InputError, match="load position"):
        plot_zone_map(dataset, load_position_mm=-999)
    with pytest.raises(InputError, match="ski"):
        plot_zone_map(dataset, ski="nope")


def test_sweep_figures_save_as_valid_png_and_svg(dataset, tmp_path: Path) -> None:
    from skisnow.plot import save_figure, sweep_figures

    figures = sweep_figures(dataset, load_positions_mm=[-70.0])
    paths = [p for stem, fig in figures.items() for p in save_figure(fig, tmp_path / stem)]
    # 1 position × (area, mean pressure, length, load share) × (png, svg)
    assert len(paths) == 8 and all(p.stat().st_size > 1000 for p in paths)
    for p in paths:
        if p.suffix == ".png":
            assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        else:
            root = ET.parse(p).getroot()
            assert root.tag.endswith("svg")
    names = {p.name for p in paths}
    assert "skate_x-70mm_area.svg" in names and "skate_x-70mm_load_share.png" in names
    # a suffix picks the one format (the CLI's --figure contact.png)
    fig = figures["skate_x-70mm_area"]
    assert save_figure(fig, tmp_path / "one" / "map.svg") == [tmp_path / "one" / "map.svg"]
